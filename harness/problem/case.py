"""The case contract: what a case module declares, and how the harness finds and loads it.

A case module (one file in ``cases/``, or any file given by path) defines at module level

    name                   short identifier used on the command line and in results
    description            one line
    geometry               a netgen 2D geometry whose boundary carries the labels
                           'contact' (Gamma_C), 'dirichlet' (Gamma_u), 'neumann' (Gamma_g);
                           ``harness.problem.geometry.polygon`` builds one. Or a netgen 3D geometry
                           (OCC or CSG) with the same labels on its faces (and 'interior' on
                           faces inside the body): a 3D case (Section 6; scalar only), whose
                           u is a function of x, y and z; ``harness.problem.geometry.contact_box``
    maxh                   mesh size of the coarse (level 0) mesh
    u                      the exact solution, an NGSolve CoefficientFunction of x and y
                           (or, for a reference case, no u and the data below)
    nu                     its Sobolev regularity: u in H^{nu - eps} for every eps > 0
    expected_rate          exponent p of the theorem's bound C h^p |log h|^q
    expected_log_exponent  exponent q of that bound (default 0; 1/4 for Thm 4.2 ii / 5.2 ii)
    theorem                which result of the paper predicts the rate, e.g. "4.1 ii, 5.1 ii"
                           (nu, expected_rate and theorem are optional for a reference case:
                           without them the report gives the measured rate only)
    regime                 optional, the regularity regime in words
    conjectured            optional, True when expected_rate is a belief, not a theorem (Remark
                           4.3): the report states whether the data support it or show a loss
    gap                    optional CoefficientFunction alpha: the constraint is u - alpha >= 0
    contact_load           optional CoefficientFunction g_C: du/dn - g_C >= 0 on Gamma_C
    f                      optional volume load, -Laplace(u) in closed form (0 for a harmonic
                           u): cheaper to evaluate than the derived one, and checked against it
    grad_u                 optional grad u in closed form (a dim-vector; in elasticity the
                           Jacobian, row i = grad u_i): the error norms evaluate it at every
                           quadrature point, where the derived one of a deep u (logs, powers,
                           oscillations) costs more; checked against the derived one
    singular_points        optional list of points (x, y) where u is singular, each a polygon
                           corner; the error and load quadratures are graded there, graded
                           meshes toward them. Default: every point of the geometry. [] for a
                           solution singular nowhere. In 3D points (x, y, z), for graded meshes
                           only (no vertex needed there)
    singular_lines         optional (3D), the straight lines along which u is singular (an edge
                           singularity r^(nu - 1) in the distance r to the line), each a segment
                           ((x, y, z), (x, y, z)): graded meshes refine toward them. A 3D case
                           on graded meshes declares these or singular_points ([]: singular
                           nowhere)
    derivative_jumps       optional (2D), the straight segments ((x0, y0), (x1, y1)) across which a
                           derivative of u (or of f) jumps inside the domain, along no mesh line
                           (smooth's D^3 u across x = 0): the error and load quadratures
                           subdivide the elements they cross (``fem.element_quadrature``).
                           Default: none
    physics                optional, "scalar" (default) or "elasticity" (Remark 2.3; see below)
    transition_curve       optional (3D), the exact contact/separation curves on Gamma_C: a
                           list of polylines, each a list of points (x, y) of the plane of
                           Gamma_C, which the report draws on its pictures of Gamma_C
    asymptotic_levels      optional int >= 3: the number of P2 levels by which the case's fits are
                           asymptotic (one level more moves no fitted rate by more than
                           0.01: ``--levels`` one higher shows it); the default report stops there instead of at its
                           profile's levels (``study.planning.cache.case_settings``), ``--levels`` and
                           the fine profile do not
    asymptotic_levels_p1   optional int >= 3: the same for the P1 methods (order 1), which a
                           study otherwise runs one level past P2, to P2's finest number of
                           dofs (``methods.method.EXTRA_LEVELS``): P2's levels or one more
    report_levels          optional {profile: int >= 3}: the most levels a report of that profile
                           runs for the case, where its levels cost more than the profile's
                           levels assume (``{"default": 4, "fine": 5}``); unlike
                           asymptotic_levels it claims nothing about the fits (the report's
                           verdicts say what the levels show); ``--levels`` overrides it
    prediction             optional, with predicted_quantities and predicted_pressure: a closed-form
                           theory the case is read against, by name (Hertz's); the report sets
                           each row's quantities of interest against it at the row's force
    predicted_quantities   optional, force -> {results column (qoi_*): predicted value}
    predicted_pressure     optional, (s, force) -> the predicted pressure at the coordinates s
                           along Gamma_C (x for a horizontal Gamma_C), drawn on the contact figure
    predicted_friction     optional (a friction case with a prediction), (force, tangential_force)
                           -> {results column: predicted value} at the row's computed P
                           (``qoi_force``) and Q (``qoi_tangential_force``): Cattaneo's stick zone
                           ``qoi_stick_measure`` (2c), Mindlin's (pi c^2)
    predicted_traction     optional, (s, force, tangential_force) -> the predicted shear traction
                           q at the points s of Gamma_C (2D: the coordinate along tau, (n,);
                           3D: the points, (n, 3)), in the sense of the applied shear: the rows'
                           ``err_traction_prediction`` is the discrete friction force's relative
                           L2(Gamma_C) error against it (``measure.quantities.traction_prediction``)
    report_profile         optional, the first report profile that includes the case: "default"
                           (the default) or "fine" -- a case whose study costs more than the
                           five minutes of ``make report`` allow, run by ``make report-fine``
                           or ``report --case NAME``; the default report names it
    second_body            optional ``harness.problem.bodies.MirrorBody(geometry, maxh)``: a
                           two-body case (Section 6), the declared data being the upper body's
                           and the lower body its mirror image across Gamma_C, meshed on its
                           own (``problem.bodies``); 2D, solved by the mortar methods. A
                           two-body reference case (no u) declares the upper body's data; the
                           lower body takes its own Dirichlet data (``MirrorBody(...,
                           dirichlet=...)``) or the upper's, and every body's errors are
                           measured against the reference method's solution k levels finer
    friction               optional friction law on Gamma_C (``harness.problem.friction``):
                           ``Tresca(threshold=s)`` replaces the Signorini conditions by Tresca's
                           (scalar: |d_n u - g_C| <= s; elasticity: u . n = 0 and
                           |sigma_t| <= s), which validation checks; ``Coulomb(coefficient=mu_F)``
                           (elasticity) adds |sigma_t| <= mu_F p to the Signorini conditions.
                           Default: frictionless
    history                optional ``LoadHistory((LoadStep(...), ...))``: quasi-static load steps
                           solved in order, the state carried over (Coulomb's slip is the
                           increment of a step); the last step is the case's own data, and the
                           earlier ones may change a reference case's dirichlet, neumann and f
    groups                 optional list of group names the case belongs to beyond those derived
                           from what it is (``DERIVED_GROUPS``), e.g. ["paper"]: ``--case
                           GROUP`` runs every case of a group (``expand_groups``)

An *elastic case* (``physics = "elasticity"``, ``harness.problem.physics.Elasticity``) declares besides

    poisson                Poisson's ratio, 0 <= poisson < 1/2 (plane strain on a 2D geometry,
                           the 3D body on a 3D one)
    young                  optional Young's modulus (default 1)
    u                      the exact displacement, a CoefficientFunction with one component
                           per dimension
    gap                    optional initial gap alpha: the constraint is u . n - alpha <= 0
    contact_load           optional traction g_C on Gamma_C, a vector: sigma(u) n - g_C = -p n
                           with p >= 0 the contact pressure (frictionless: its tangential part is
                           sigma_t(u), which validation checks)
    f                      optional, -div sigma(u) in closed form (checked against the derived one)

and the harness derives f = -div sigma(u), the traction sigma(u) n on Gamma_g and u on Gamma_u.
An elastic reference case (2D: no 3D reference cases yet) declares instead f, dirichlet and neumann
(the traction sigma(u) n on Gamma_g) as vectors with one component per dimension, or numbers, each
the same in every component.

From u the harness derives f = -Laplace(u) (unless declared), the Neumann data du/dn on
Gamma_g and the Dirichlet data u on Gamma_u (docs/mathematics.md §1: nonzero Dirichlet data, a gap and a load on
Gamma_C are the paper's "straightforward" generalisations that make any u exact).

A *reference case* has no closed-form solution. It leaves out u and declares the data instead:

    f                      the volume load (required)
    dirichlet              u_D on Gamma_u, a CoefficientFunction (required)
    neumann                g = du/dn on Gamma_g, a CoefficientFunction (required)
    reference_levels       k: every method's errors are measured against the nodal P2 solution
                           on the mesh k levels finer than P2's finest studied one (default 2)

gap and contact_load as above. ``python -m harness run --reference-levels K`` chooses k, and
for an exact case measures against a reference instead of u (which checks the reference).
"""
from __future__ import annotations

import dataclasses
import hashlib
import math
from dataclasses import dataclass
from functools import cached_property
from pathlib import Path

import ngsolve as ngs

from ..core.names import look_up
from ..core.plugins import PluginError, entry_point_files
from .contract import (  # noqa: F401
    DEFAULT_REFERENCE_LEVELS,
    REFERENCE_OPTIONAL,
    REFERENCE_REQUIRED,
    REPORT_PROFILES,
    REQUIRED,
    CaseError,
    check_declared,
    check_second_body,
    import_file,
    optional_fields,
    physics_of,
    reference_levels,
)
from .friction import FRICTIONLESS, STATIC
from .geometry import geometry_dimension
from .physics import SCALAR, gradient


def _cases_dir() -> Path:
    """The registered cases' folder: the installed package ``signorini_cases`` (the repository's
    cases/, shipped with the wheel; an editable install maps it there), or cases/ beside this
    package in a checkout that is not installed."""
    try:
        import signorini_cases
        return Path(signorini_cases.__file__).resolve().parent
    except ImportError:
        return Path(__file__).resolve().parents[2] / "cases"


CASES_DIR = _cases_dir()
# installed packages declare their cases (case modules) in this entry-point group
CASE_ENTRY_POINTS = "signorini_harness.cases"


@dataclass(frozen=True, eq=False)
class Case:
    name: str
    description: str
    geometry: object
    maxh: float
    u: ngs.CoefficientFunction | None     # None: a reference case
    nu: float
    expected_rate: float
    theorem: str
    expected_log_exponent: float = 0.0
    regime: str = ""
    gap: ngs.CoefficientFunction | None = None
    contact_load: ngs.CoefficientFunction | None = None
    declared_f: object = None                  # the module's f: a number or a CoefficientFunction
    declared_grad_u: ngs.CoefficientFunction | None = None     # the module's grad_u
    singular_points: tuple | None = None
    singular_lines: tuple | None = None                # 3D: segments ((x, y, z), (x, y, z))
    derivative_jumps: tuple = ()                       # 2D: segments ((x, y), (x, y)) a derivative jumps across
    source: str = ""
    dirichlet: ngs.CoefficientFunction | None = None   # reference cases: u_D on Gamma_u
    neumann: ngs.CoefficientFunction | None = None     # reference cases: g on Gamma_g
    reference_levels: int | None = None                # None: errors against the exact u
    conjectured: bool = False                          # expected_rate is a belief, not a theorem
    physics: object = SCALAR                           # ``physics.Scalar`` or ``physics.Elasticity``
    transition_curve: tuple = ()                       # 3D: polylines on Gamma_C for the pictures
    asymptotic_levels: int | None = None               # the default report's levels for this case
    asymptotic_levels_p1: int | None = None            # and for its P1 methods
    report_profile: str = "default"                    # the first report profile that includes it
    report_levels: tuple | None = None                 # ((profile, most levels), ...): its budget
    prediction: str = ""                               # a closed-form theory the case is read against
    predicted_quantities: object = None                # force -> {results column: predicted value}
    predicted_pressure: object = None                  # (s along Gamma_C, force) -> pressure
    predicted_friction: object = None                  # (force, tangential force) -> {column: value}
    predicted_traction: object = None                  # (s, force, tangential force) -> shear traction
    second_body: object = None                         # ``bodies.MirrorBody``: a two-body case
    declared_groups: tuple = ()                        # the module's groups (``Case.groups``)
    friction: object = FRICTIONLESS                    # ``friction.Tresca``: the friction law on Gamma_C
    history: object = STATIC                           # ``friction.LoadHistory``: the load steps, in order

    @property
    def bodies(self) -> int:
        """1, or 2 for a two-body case (``second_body``)."""
        return 1 if self.second_body is None else 2

    @property
    def groups(self) -> tuple[str, ...]:
        """The groups ``--case`` finds the case in besides "all": those of what it is (its
        dimension, physics, bodies, and "reference" without a closed-form u), then those it
        declares."""
        derived = (f"{self.dimension}d", self.physics.name, "two-body" if self.bodies == 2 else "",
                   "" if self.exact else "reference", "friction" if self.frictional else "")
        return tuple(group for group in derived if group) + self.declared_groups

    @property
    def frictional(self) -> bool:
        """A friction law other than frictionless holds on Gamma_C (``friction``)."""
        return self.friction.name != FRICTIONLESS.name

    @property
    def exact(self) -> bool:
        """Errors are measured against the closed-form u (else against a reference solution)."""
        return self.reference_levels is None

    @property
    def dirichlet_data(self) -> ngs.CoefficientFunction:
        """u_D on Gamma_u: the reference case's data, or the exact u. (A case file declares
        one of them, ``_exact_case``; both are set only on a case made in code, a load step's
        Dirichlet values or a second body's own, ``bodies.MirrorBody.dirichlet``: its errors are
        still measured against u.)"""
        return self.dirichlet if self.dirichlet is not None else self.u

    def neumann_data(self, normal: ngs.CoefficientFunction) -> ngs.CoefficientFunction:
        """g on Gamma_g (du/dn, or the traction sigma(u) n): from the exact u, or the reference
        case's data."""
        return self.physics.flux(self.grad_u, normal) if self.u is not None else self.neumann

    def at_step(self, step: int) -> "Case":
        """The case with the data of its history's step ``step`` (0-based; the last is the case
        itself, ``friction.LoadHistory``): numbers are constant fields of the physics."""
        def data(value):
            return self.physics.constant(value) if isinstance(value, (int, float)) else ngs.CF(value)
        overrides = self.history.steps[step].overrides()
        return dataclasses.replace(self, **{k: (v if k == "declared_f" else data(v)) for k, v in overrides.items()})

    def with_reference(self, levels: int) -> "Case":
        """This case with errors measured against a reference ``levels`` levels finer."""
        if levels < 1:
            raise CaseError(f"reference levels must be a positive integer, got {levels}")
        return dataclasses.replace(self, reference_levels=int(levels))

    @cached_property
    def dimension(self) -> int:
        """2 for a polygon (netgen's SplineGeometry), 3 for an OCC or CSG solid."""
        return geometry_dimension(self.geometry)

    @cached_property
    def grad_u(self) -> ngs.CoefficientFunction:
        """grad u, as declared by the case or derived from u."""
        if self.u is None:
            raise AttributeError(f"case {self.name!r} has no exact solution (a reference case)")
        return self.derived_grad_u if self.declared_grad_u is None else self.declared_grad_u

    @cached_property
    def derived_grad_u(self) -> ngs.CoefficientFunction:
        """grad u by NGSolve's symbolic differentiation of u."""
        return gradient(self.u, self.dimension)

    @cached_property
    def derived_f(self) -> ngs.CoefficientFunction:
        """The volume load the exact u asks for: -Laplace(u) (2.1), or -div sigma(u)."""
        if self.u is None:
            raise AttributeError(f"case {self.name!r} has no exact solution (a reference case)")
        return self.physics.load(self.u, self.dimension)

    @cached_property
    def f(self) -> ngs.CoefficientFunction:
        """Volume load, as declared by the case or derived from u."""
        if self.declared_f is None:
            return self.derived_f
        if isinstance(self.declared_f, (int, float)):
            return self.physics.constant(self.declared_f)
        return ngs.CF(self.declared_f)

    @property
    def f_vanishes(self) -> bool:
        """The case declares f = 0 (a harmonic u): the volume load needs no quadrature at all."""
        return isinstance(self.declared_f, (int, float)) and self.declared_f == 0

    @property
    def obstacle(self) -> ngs.CoefficientFunction | None:
        """The lower bound of the contact variable (``physics``): alpha, or -alpha in elasticity."""
        return self.physics.obstacle(self.gap)

    @property
    def expected_bound(self) -> str:
        return bound_text(self.expected_rate, self.expected_log_exponent)


def bound_text(rate: float, log_exponent: float = 0.0) -> str:
    """The bound C h^p |log h|^q in words, e.g. 'h^1 |log h|^1/4' (NaN: no proven bound)."""
    if rate != rate:
        return "none proven"
    return f"h^{fraction(rate)}" + (f" |log h|^{fraction(log_exponent)}" if log_exponent else "")


def fraction(value: float) -> str:
    """2/3 rather than 0.666667 for the exponents of the paper."""
    from fractions import Fraction
    if not math.isfinite(value):         # a case that declares no rate (Coulomb's reference cases)
        return f"{value:g}"
    f = Fraction(value).limit_denominator(12)
    return str(f) if abs(float(f) - value) < 1e-9 else f"{value:g}"


def case_from_module(module, source: str) -> Case:
    check_declared(module, source)
    physics = physics_of(module, source)
    if hasattr(module, "u"):
        case = _exact_case(module, source)
    else:
        case = _reference_case(module, source, physics)
    if physics is not SCALAR:
        case = _elastic_case(case, physics, source)
    if case.second_body is not None:
        check_second_body(case, source)
    return dataclasses.replace(case, declared_groups=_declared_groups(module, source))


def _declared_groups(module, source: str) -> tuple[str, ...]:
    """The module's ``groups``: names of one word each, none of them a derived group's."""
    groups = getattr(module, "groups", ())
    if isinstance(groups, str) or not all(isinstance(g, str) and g and g.split() == [g] for g in groups):
        raise CaseError(f"case {source}: groups must be a list of names without spaces, got {groups!r}")
    derived = sorted(set(groups) & set(DERIVED_GROUPS))
    if derived:
        raise CaseError(f"case {source}: groups {', '.join(derived)} are derived from what the case declares, "
                        f"not declared (derived: {', '.join(DERIVED_GROUPS)})")
    return tuple(groups)


def _exact_case(module, source: str) -> Case:
    missing = [key for key in REQUIRED if not hasattr(module, key)]
    if missing:
        raise CaseError(f"case {source} lacks required attribute(s): {', '.join(missing)}")
    given = [key for key in ("dirichlet", "neumann") if hasattr(module, key)]
    if given:
        raise CaseError(f"case {source} declares u and {', '.join(given)}: the harness derives the boundary "
                        f"data from u; declare either u or the data (a reference case)")
    fields = {key: getattr(module, key) for key in REQUIRED}
    fields["u"] = ngs.CF(fields["u"])
    return Case(source=source, **fields, **optional_fields(module))


def _reference_case(module, source: str, physics=SCALAR) -> Case:
    """A case without u: f and the boundary data are required (ValueError names what lacks).
    A number as boundary data is that value in every component of the ``physics`` (a
    displacement's, in the geometry's dimension)."""
    missing = [key for key in REFERENCE_REQUIRED if not hasattr(module, key)]
    if missing:
        raise CaseError(f"case {source} has no exact solution u, so it must declare f, dirichlet and neumann; "
                        f"it lacks: {', '.join(missing)}")
    if physics is not SCALAR:
        physics = dataclasses.replace(physics, dim=geometry_dimension(module.geometry))

    def data(value) -> ngs.CoefficientFunction:
        return physics.constant(value) if isinstance(value, (int, float)) else ngs.CF(value)

    fields = {key: getattr(module, key) for key in REFERENCE_REQUIRED if key not in ("f", "dirichlet", "neumann")}
    fields |= {key: getattr(module, key, default) for key, default in REFERENCE_OPTIONAL.items()}
    fields["nu"], fields["expected_rate"] = float(fields["nu"]), float(fields["expected_rate"])
    fields |= {"u": None, "dirichlet": data(module.dirichlet), "neumann": data(module.neumann),
               "reference_levels": reference_levels(module, source), "physics": physics}
    return Case(source=source, **fields, **optional_fields(module))


def _elastic_case(case: Case, physics, source: str) -> Case:
    """``case`` with its elastic ``physics`` (plane strain on a 2D geometry, the body itself on a
    3D one), whose displacement data -- u, or a reference case's f, dirichlet, neumann and
    contact_load -- must be vectors of one component per dimension (refused in one line)."""
    physics = dataclasses.replace(physics, dim=case.dimension)
    if case.u is not None:
        fields = {"u": case.u}
    else:
        fields = {"f": case.f, "dirichlet": case.dirichlet, "neumann": case.neumann, "contact_load": case.contact_load}
    for key, value in fields.items():
        if value is not None and not physics.is_field(value):
            raise CaseError(f"case {source}: {key} must be a {physics.components}-vector for {physics.name}, "
                            f"got dimension {value.dim}")
    return dataclasses.replace(case, physics=physics)


def _registered_files() -> list[Path]:
    """The case files of cases/, then those installed packages declare (``CASE_ENTRY_POINTS``:
    ``my-case = "mypkg.cases.my_case"``, a case module)."""
    return sorted(p for p in CASES_DIR.glob("*.py") if not p.name.startswith("_")) + installed_case_files()


def installed_case_files() -> list[Path]:
    """The files of the case modules of the entry-point group ``CASE_ENTRY_POINTS``
    (``harness.core.plugins.entry_point_files``)."""
    try:
        return entry_point_files(CASE_ENTRY_POINTS, "case")
    except PluginError as exc:
        raise CaseError(str(exc)) from exc.__cause__


# the cases of the files read so far, by (path, name in messages, sha1 of the text): a file is run
# again only when its text changed (every command and many tests ask for the registry, and
# each would otherwise run every registered file again)
_READ: dict[tuple[str, str, str], Case] = {}


def case_of_file(path: Path, source: str) -> Case:
    """The case of the file ``path`` (``source``: its name in messages), run afresh whenever its
    text changed since it was last read."""
    key = (str(path), source, hashlib.sha1(Path(path).read_bytes()).hexdigest())
    if key not in _READ:
        _READ[key] = case_from_module(import_file(path), source)
    return _READ[key]


def registered_cases(dimension: int | None = None) -> dict[str, Case]:
    """Every case module in cases/ (of that ``dimension`` if given), by name: the scalar 2D
    ones, the elastic ones, then the 3D ones, each in order of regularity nu."""
    cases = [case_of_file(path, str(path)) for path in _registered_files()]
    cases = [case for case in cases if dimension is None or case.dimension == dimension]
    return {case.name: case for case in sorted(cases, key=lambda c: (c.dimension, c.physics.name != "scalar",
                                                                      c.nu if c.nu == c.nu else float("inf"), c.name))}


# the groups every case is sorted into by what it is (``Case.groups``); "all" holds every case
DERIVED_GROUPS = ("all", "2d", "3d", "scalar", "elasticity", "two-body", "reference", "friction")


def case_groups(cases: dict[str, Case] | None = None) -> dict[str, list[str]]:
    """Every group of the registered ``cases`` (default: the registry) with its cases' names,
    in registry order: "all", the derived groups, then the declared ones. A group that names
    a case is refused (``--case NAME`` would be ambiguous)."""
    cases = registered_cases() if cases is None else cases
    groups: dict[str, list[str]] = {"all": list(cases)}
    for case in cases.values():
        for group in case.groups:
            groups.setdefault(group, []).append(case.name)
    clash = sorted(set(groups) & set(cases))
    if clash:
        raise CaseError(f"case group(s) {', '.join(clash)} share a case's name: rename the group")
    return {group: groups[group] for group in sorted(groups, key=_group_order)}


def _group_order(group: str) -> tuple:
    return (0, DERIVED_GROUPS.index(group)) if group in DERIVED_GROUPS else (1, group)


def expand_groups(specs) -> list:
    """``specs`` (names, paths, ``Case`` objects, ...) with each group name replaced by its
    cases' names (``case_groups``), each spec once, in the order given. A case file or case
    of that name comes before a group."""
    groups = None
    expanded: list = []
    for spec in specs:
        members = [spec]
        if isinstance(spec, str) and not spec.endswith(".py") and not Path(spec).is_file():
            groups = case_groups() if groups is None else groups
            members = groups.get(spec, members)
        expanded += [item for item in members if not any(item is seen or item == seen for seen in expanded)]
    return expanded


def load_case(spec: str) -> Case:
    """A registered case by name, or a case file by path (a group of cases: ``expand_groups``)."""
    path = Path(spec)
    if spec.endswith(".py") or path.is_file():
        if not path.is_file():
            raise CaseError(f"case file not found: {spec}")
        return case_of_file(path.resolve(), str(path))
    cases = registered_cases()
    groups = case_groups(cases)
    if spec in groups and spec not in cases:
        raise CaseError(f"{spec!r} is a group of cases ({', '.join(groups[spec])}): name one case here")
    return look_up(cases, spec, "case", CaseError, also=f"; groups: {', '.join(groups)}")
