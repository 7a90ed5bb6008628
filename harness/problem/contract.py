"""The case contract's checks (``case``'s docstring says what a case module declares): the
plain values of a module, each of the type and range it must have, refused in one line before
anything is built from them; the optional fields as the ``Case`` record takes them; a case
file imported with its failure in one line."""
from __future__ import annotations

import math
from pathlib import Path

import ngsolve as ngs

from ..core import plugins
from .geometry import geometry_dimension
from .physics import PHYSICS, SCALAR, Elasticity

REQUIRED = ("name", "description", "geometry", "maxh", "u", "nu", "expected_rate", "theorem")
# a reference case replaces u by its data; it may leave its regularity and rate unknown
# the report profiles from the cheapest (``study.chain.PROFILES`` has these keys)
REPORT_PROFILES = ("default", "fine")
REFERENCE_REQUIRED = ("name", "description", "geometry", "maxh", "f", "dirichlet", "neumann")
REFERENCE_OPTIONAL = {"nu": float("nan"), "expected_rate": float("nan"), "theorem": ""}
DEFAULT_REFERENCE_LEVELS = 2


class CaseError(ValueError):
    """A case that cannot be loaded or does not satisfy the Signorini conditions."""


def import_file(path: Path):
    """The case module of the file ``path``, run afresh (a case file edited between two loads
    is read again); CaseError in one line if it fails (``harness.core.plugins.import_file``)."""
    try:
        return plugins.import_file(Path(path), "case", cached=False)
    except plugins.PluginError as exc:
        raise CaseError(str(exc)) from exc.__cause__


def check_declared(module, source: str) -> None:
    """The plain values of the contract, each of the type and range it must have, refused in
    one line (wrong type, NaN or infinite where a finite number is meant, wrong sign), before
    anything is built from them. The checks run in this order: of several faults, the first
    is the one reported."""
    _check_strings(module, source)
    _check_number(module, source, "maxh", 0.0)
    _check_level_counts(module, source)
    _check_predictions(module, source)
    if getattr(module, "report_profile", REPORT_PROFILES[0]) not in REPORT_PROFILES:
        raise CaseError(f"case {source}: report_profile must be one of {', '.join(REPORT_PROFILES)}, "
                        f"got {module.report_profile!r}")
    if hasattr(module, "reference_levels"):
        reference_levels(module, source)
    reference = not hasattr(module, "u")
    _check_number(module, source, "nu", 1.0, finite=False, optional_nan=reference)       # u in H^{nu - eps}, nu > 1
    _check_number(module, source, "expected_rate", 0.0, optional_nan=reference)
    _check_number(module, source, "expected_log_exponent", -math.inf)
    if hasattr(module, "geometry") and not hasattr(module.geometry, "GenerateMesh"):
        raise CaseError(f"case {source}: geometry must be a netgen geometry (harness.problem.geometry.polygon builds one), "
                        f"got {type(module.geometry).__name__}")
    _check_coefficients(module, source)
    check_singular_sets(module, source)
    check_derivative_jumps(module, source)
    check_friction(module, source)


def check_friction(module, source: str) -> None:
    """``friction``, if declared: a friction law of ``problem.friction``; Tresca has no gap (its
    bilateral normal contact in elasticity is u . n = 0); two bodies scalar only; Coulomb's is
    elastic, and 2D between two bodies. ``history``, if declared: a ``friction.LoadHistory``, whose steps
    change data only of a reference case (an exact case's data are its u's)."""
    from .friction import FRICTIONLESS, Coulomb, Frictionless, LoadHistory, Tresca
    law = getattr(module, "friction", FRICTIONLESS)
    if not isinstance(law, (Frictionless, Tresca, Coulomb)):
        raise CaseError(f"case {source}: friction must be harness.problem.Tresca(threshold=...), "
                        f"harness.problem.Coulomb(coefficient=...) or harness.problem.FRICTIONLESS, got {law!r}")
    elastic = getattr(module, "physics", "scalar") != "scalar"
    if isinstance(law, Tresca) and getattr(module, "second_body", None) is not None and elastic:
        raise CaseError(f"case {source}: Tresca friction between two elastic bodies is not implemented (scalar only)")
    if isinstance(law, Tresca) and getattr(module, "gap", None) is not None:
        raise CaseError(f"case {source}: Tresca friction has no gap (scalar: no unilateral condition; elasticity: "
                        f"bilateral u . n = 0 on Gamma_C)")
    if isinstance(law, Coulomb) and not elastic:
        raise CaseError(f"case {source}: Coulomb friction needs a normal stress: physics = \"elasticity\"")
    if isinstance(law, Coulomb) and getattr(module, "second_body", None) is not None and \
            (geometry_dimension(module.geometry) if hasattr(module, "geometry") else 2) != 2:
        raise CaseError(f"case {source}: Coulomb friction between two bodies is 2D only (the mortar coupling, harness.fem.mortar)")
    history = getattr(module, "history", None)
    if history is not None and not isinstance(history, LoadHistory):
        raise CaseError(f"case {source}: history must be harness.problem.LoadHistory(steps), got {history!r}")
    if history is not None and hasattr(module, "u") and any(step.overrides() for step in history.steps):
        raise CaseError(f"case {source}: the steps of an exact case's history cannot change its data (they are u's); "
                        f"declare the data instead (a reference case)")


def _check_strings(module, source: str) -> None:
    """The texts are strings, and the name, which names the case everywhere, is not blank."""
    for key in ("name", "description", "theorem", "regime"):
        if hasattr(module, key) and not isinstance(getattr(module, key), str):
            raise CaseError(f"case {source}: {key} must be a string, got {getattr(module, key)!r}")
    if hasattr(module, "name") and not module.name.strip():
        raise CaseError(f"case {source}: name must not be empty")


def _check_number(module, source: str, key: str, low: float, finite: bool = True, optional_nan: bool = False) -> None:
    """``key``, if declared, is a number (not a bool) > ``low``, finite unless ``finite`` is
    False, and NaN only where ``optional_nan`` allows it (a reference case's unknown rate)."""
    if not hasattr(module, key):
        return
    value = getattr(module, key)
    ok = isinstance(value, (int, float)) and not isinstance(value, bool)
    if ok and math.isnan(value):
        ok = optional_nan
    elif ok:
        ok = value > low and (math.isfinite(value) or not finite)
    if not ok:
        bound = f"> {low:g}" + ("" if finite else " (inf allowed)")
        raise CaseError(f"case {source}: {key} must be a number {bound}, got {value!r}")


def _check_level_counts(module, source: str) -> None:
    """The levels a case asks for: enough for a rate fit (three levels), P1's asymptotic levels
    P2's or one more, and report_levels per report profile."""
    for key in ("asymptotic_levels", "asymptotic_levels_p1"):
        levels = getattr(module, key, None)
        if levels is not None and (isinstance(levels, bool) or not isinstance(levels, int) or levels < 3):
            raise CaseError(f"case {source}: {key} must be an integer >= 3 (a fit needs three levels), got {levels!r}")
    p1, p2 = getattr(module, "asymptotic_levels_p1", None), getattr(module, "asymptotic_levels", None)
    if p1 is not None and p2 is not None and p1 not in (p2, p2 + 1):
        raise CaseError(f"case {source}: asymptotic_levels_p1 must be asymptotic_levels ({p2}) or one more, got {p1}")
    capped = getattr(module, "report_levels", None)
    # a fit needs three levels; a case read against a theory's quantities (``predicted_quantities``:
    # the 3D Hertz sphere, whose third level costs 8 times the dofs) may stop at two
    fewest = 2 if getattr(module, "predicted_quantities", None) is not None else 3
    if capped is not None and not (isinstance(capped, dict) and capped and all(
            profile in REPORT_PROFILES and isinstance(n, int) and not isinstance(n, bool) and n >= fewest
            for profile, n in capped.items())):
        raise CaseError(f"case {source}: report_levels must map report profiles ({', '.join(REPORT_PROFILES)}) to "
                        f"integers >= {fewest}, got {capped!r}")


def _check_predictions(module, source: str) -> None:
    """A theory's predictions are functions of the contact force, and the theory has a name,
    which the report prints beside them."""
    for key in ("predicted_quantities", "predicted_pressure", "predicted_friction", "predicted_traction"):
        if getattr(module, key, None) is not None and not callable(getattr(module, key)):
            raise CaseError(f"case {source}: {key} must be a function of the contact force, got {getattr(module, key)!r}")
    for key in ("predicted_quantities", "predicted_friction", "predicted_traction"):
        if hasattr(module, key) and not isinstance(getattr(module, "prediction", None), str):
            raise CaseError(f"case {source}: {key} needs prediction, the theory's name (a string)")
    friction = getattr(module, "friction", None)
    for key in ("predicted_friction", "predicted_traction"):
        if hasattr(module, key) and getattr(friction, "name", "") != "coulomb":
            raise CaseError(f"case {source}: {key} needs a Coulomb friction law (friction = Coulomb(mu_F))")


def _check_coefficients(module, source: str) -> None:
    """u and the data are NGSolve CoefficientFunctions or finite numbers; the data may be None
    (not given), a declared u may not (a reference case leaves u out instead)."""
    for key in ("u", "f", "dirichlet", "neumann", "gap", "contact_load"):
        value = getattr(module, key, None)
        if (value is None and not (key == "u" and hasattr(module, "u"))) or isinstance(value, ngs.CoefficientFunction):
            continue
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
            raise CaseError(f"case {source}: {key} must be an NGSolve CoefficientFunction or a finite number, got {value!r}")


def _points_of(values, count: int | None) -> bool:
    """``values`` is a sequence of points of finite numbers, each of ``count`` coordinates."""
    try:
        return all(len(point) == count and all(math.isfinite(float(c)) for c in point) for point in values)
    except (TypeError, ValueError):
        return False


def check_singular_sets(module, source: str) -> None:
    """singular_points: points of the geometry's dimension; singular_lines (3D only): segments,
    each two distinct 3D points."""
    dimension = geometry_dimension(module.geometry) if hasattr(module, "geometry") else 2
    points = getattr(module, "singular_points", None)
    if points is not None and not _points_of(points, dimension):
        pair = "(x, y) pairs" if dimension == 2 else "(x, y, z) triples (a 3D geometry)"
        raise CaseError(f"case {source}: singular_points must be a list of {pair} of finite numbers, got {points!r}")
    lines = getattr(module, "singular_lines", None)
    if lines is None:
        return
    if dimension != 3:
        raise CaseError(f"case {source}: singular_lines are 3D only (a 2D case declares singular_points), got {lines!r}")
    try:
        ok = all(len(line) == 2 and _points_of(line, 3) and tuple(map(float, line[0])) != tuple(map(float, line[1]))
                 for line in lines)
    except TypeError:
        ok = False
    if not ok:
        raise CaseError(f"case {source}: singular_lines must be a list of segments ((x, y, z), (x, y, z)) of finite "
                        f"numbers with distinct ends, got {lines!r}")


def check_derivative_jumps(module, source: str) -> None:
    """derivative_jumps (2D only): segments, each two distinct (x, y) points of finite numbers."""
    jumps = getattr(module, "derivative_jumps", None)
    if jumps is None:
        return
    dimension = geometry_dimension(module.geometry) if hasattr(module, "geometry") else 2
    if dimension != 2:
        raise CaseError(f"case {source}: derivative_jumps are 2D only (the error and load quadratures of a 3D case "
                        f"have no rule for them), got {jumps!r}")
    try:
        ok = not isinstance(jumps, str) and all(
            not isinstance(segment, str) and len(segment) == 2 and _points_of(segment, 2)
            and tuple(map(float, segment[0])) != tuple(map(float, segment[1])) for segment in jumps)
    except TypeError:
        ok = False
    if not ok:
        raise CaseError(f"case {source}: derivative_jumps must be a list of segments ((x0, y0), (x1, y1)) of finite "
                        f"numbers with distinct ends, got {jumps!r}")


def check_second_body(case, source: str) -> None:
    """A two-body case: a ``bodies.MirrorBody`` on a 2D geometry, with its own Dirichlet data
    only beside no u (the mirror solution would not be the lower body's)."""
    from .bodies import MirrorBody
    if not isinstance(case.second_body, MirrorBody):
        raise CaseError(f"case {source}: second_body must be harness.problem.bodies.MirrorBody(geometry, maxh), "
                        f"got {type(case.second_body).__name__}")
    if case.dimension != 2 or geometry_dimension(case.second_body.geometry) != 2:
        raise CaseError(f"case {source}: two bodies are 2D only (both geometries must be polygons)")
    if case.u is not None and case.second_body.dirichlet is not None:
        raise CaseError(f"case {source}: second_body declares its own dirichlet, so the mirror solution is not the "
                        f"lower body's: declare the data instead of u (a reference case)")


def physics_of(module, source: str):
    """The case's ``physics``: scalar unless it declares physics = "elasticity" (with poisson)."""
    name = getattr(module, "physics", "scalar")
    if name not in PHYSICS:
        raise CaseError(f"case {source}: physics must be one of {', '.join(PHYSICS)}, got {name!r}")
    if name == "scalar":
        return SCALAR
    if not hasattr(module, "poisson"):
        raise CaseError(f"case {source}: an elastic case must declare poisson (Poisson's ratio)")
    try:
        return Elasticity(young=float(getattr(module, "young", 1.0)), poisson=float(module.poisson))
    except ValueError as exc:
        raise CaseError(f"case {source}: {exc}") from None


def reference_levels(module, source: str) -> int:
    levels = getattr(module, "reference_levels", DEFAULT_REFERENCE_LEVELS)
    if not isinstance(levels, int) or levels < 1:
        raise CaseError(f"case {source}: reference_levels must be a positive integer, got {levels!r}")
    return levels


def optional_fields(module) -> dict:
    fields = {}
    for key in ("expected_log_exponent", "regime", "gap", "contact_load", "singular_points", "conjectured",
                "transition_curve", "asymptotic_levels", "asymptotic_levels_p1", "report_profile", "second_body",
                "singular_lines", "report_levels", "prediction", "predicted_quantities", "predicted_pressure",
                "predicted_friction", "predicted_traction", "derivative_jumps", "friction", "history"):
        if hasattr(module, key):
            fields[key] = getattr(module, key)
    if hasattr(module, "f"):
        fields["declared_f"] = module.f
    if "transition_curve" in fields:
        fields["transition_curve"] = tuple(tuple(tuple(map(float, p)) for p in line) for line in fields["transition_curve"])
    if fields.get("singular_points") is not None:
        fields["singular_points"] = tuple(tuple(map(float, point)) for point in fields["singular_points"])
    if fields.get("report_levels") is not None:
        fields["report_levels"] = tuple(sorted(fields["report_levels"].items()))     # hashable, like the rest
    if fields.get("singular_lines") is not None:
        fields["singular_lines"] = tuple(tuple(tuple(map(float, point)) for point in line) for line in fields["singular_lines"])
    if "derivative_jumps" in fields:
        fields["derivative_jumps"] = tuple(tuple(tuple(map(float, point)) for point in segment)
                                           for segment in fields["derivative_jumps"] or ())
    for key in ("gap", "contact_load"):
        if fields.get(key) is not None:
            fields[key] = ngs.CF(fields[key])
    if getattr(module, "grad_u", None) is not None:
        fields["declared_grad_u"] = ngs.CF(module.grad_u)
    return fields
