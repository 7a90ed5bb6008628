"""Another finite element code's solutions, measured as the harness's own methods are
(``--method external:DIR``, ``harness.external(DIR)``).

The other code solved the levels of an export (``study.export``: the same meshes, the same
data, the right-hand side as moments against the Lagrange basis) and wrote, per level, its
solution's values at the P_k Lagrange nodes (docs/guide/export-format.md, "Solutions"). A P_k
function is determined by those values, so the harness rebuilds u_h exactly
(``fem.lagrange.LagrangeNodes``) and measures it like any row: every error, the quantities, the
rates and verdicts, the cost (the code's own seconds) and the report's cells. What the harness
cannot see is how the code solved: the row's ``kkt_residual``, iterations and seconds are the
code's own.
"""
from __future__ import annotations

import json
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..fem.assembly import ContactTraceFunction
from ..fem.cones import contact_pressure
from ..fem.lagrange import LAGRANGE_ORDERS, LagrangeNodes
from ..fem.nested import p1_values
from ..fem.penetration import max_penetration
from .method import Carry, Expectation, LevelSolve, Method, SolveFields, capped_expectation, timer

SOLUTION_FORMAT = "signorini-harness-solution"
# --method external:DIR
EXTERNAL_PREFIX = "external:"
SOLUTION_FORMAT_VERSION = 1
# a point matches a node within this fraction of the level's extent (the export's nodes are
# written in full double precision; another code's dof coordinates differ by round-off)
MATCH_TOLERANCE = 1e-9


class ExternalError(ValueError):
    """A one-line reason an external solution folder is refused."""


@dataclass(frozen=True)
class External(Method):
    """The solutions in ``folder`` of the case ``case_name``, computed by ``code``; ``like``: the
    harness method they discretise (its expected rate), if the folder names one."""

    folder: str = ""
    code: str = ""
    case_name: str = ""
    like: str | None = None
    options: dict = field(default_factory=dict, compare=False)
    physics: tuple = ("scalar", "elasticity")
    dimensions: tuple = (2, 3)
    friction: tuple = ("frictionless", "tresca")
    cost_model: str | float = 1e-5

    def refusal(self, case) -> str | None:
        if case.name != self.case_name:
            return f"its solutions ({self.folder}) are of case {self.case_name}"
        return super().refusal(case)

    def level_file(self, nodes: int) -> Path:
        """The level file whose solution has ``nodes`` values: the level of that size."""
        sizes = solution_sizes(Path(self.folder))
        if nodes not in sizes:
            raise ExternalError(f"external {self.name!r}: {self.folder} has no solution on the level with {nodes} nodes "
                                f"(it has {', '.join(map(str, sorted(sizes))) or 'none'}): a level is missing")
        return sizes[nodes]

    def solve(self, case, problem, carry, multilevel, take_stiffness: bool = False, phases=None) -> LevelSolve:
        timed = timer(phases)
        with timed("setup"):
            nodes = LagrangeNodes.of(problem.fes)
            level = read_level(self.level_file(nodes.count), self.name)
        with timed("solve"):
            u = rebuilt(problem, nodes, level, self.name)
        trace_u = ContactTraceFunction.of(problem, u)
        force = np.concatenate([problem.contact_residual(u)[:len(problem.vertex_dofs)], np.zeros(len(problem.edge_dofs))])
        pressure = contact_pressure(problem, force)
        fields = SolveFields(max_penetration(case, problem.mesh, trace_u), float(pressure.min()), level["residual"],
                             level["status"], level["iterations"], level["linear_iterations"],
                             solve_seconds=level["seconds"])
        return LevelSolve(fields, u, trace_u, pressure, Carry(p1_values(problem, u)))


def rebuilt(problem, nodes: LagrangeNodes, level: dict, name: str) -> np.ndarray:
    """u_h in the problem's variables from the values at the level's nodes (matched by position)."""
    components = problem.physics.components if problem.physics.rotated_frame else 1
    values = level["values"].reshape(len(level["values"]), -1)
    if values.shape[1] != components:
        raise ExternalError(f"external {name!r}: values have {values.shape[1]} components, the case's solution {components}")
    extent = float(np.ptp(nodes.points, axis=0).max())
    try:
        node = nodes.match(level["points"], MATCH_TOLERANCE * extent)
    except ValueError as exc:
        raise ExternalError(f"external {name!r}, {level['path'].name}: {exc}") from None
    at_nodes = np.empty_like(values)
    at_nodes[node] = values
    cartesian = nodes.coefficients(at_nodes)
    # the rotated frame's Q is orthogonal (``fem.rotated_frame``): ours = Q^T NGSolve's
    return cartesian if problem.basis is None else problem.basis.T @ cartesian


def read_level(path: Path, name: str) -> dict:
    """A level file's arrays, checked: points (n, d), values (n,) or (n, c), all finite; seconds,
    iterations; optional linear_iterations, residual, status."""
    try:
        with np.load(path, allow_pickle=False) as data:
            arrays = {key: data[key] for key in data.files}
    except (OSError, ValueError) as exc:
        raise ExternalError(f"external {name!r}: {path} is not a readable .npz ({exc})") from None
    missing = [key for key in ("points", "values", "seconds", "iterations") if key not in arrays]
    if missing:
        raise ExternalError(f"external {name!r}: {path.name} lacks {', '.join(missing)}")
    points, values = np.asarray(arrays["points"], float), np.asarray(arrays["values"], float)
    if points.ndim != 2 or len(values) != len(points):
        raise ExternalError(f"external {name!r}: {path.name} has {len(values)} values at {len(points)} points")
    for key, array in (("points", points), ("values", values)):
        if not np.all(np.isfinite(array)):
            raise ExternalError(f"external {name!r}: {path.name}'s {key} hold NaN or infinite entries")
    return {"path": path, "points": points, "values": values, "seconds": float(arrays["seconds"]),
            "iterations": int(arrays["iterations"]), "residual": float(arrays.get("residual", np.nan)),
            "linear_iterations": int(arrays["linear_iterations"]) if "linear_iterations" in arrays else None,
            "status": str(arrays.get("status", "converged"))}


def solution_sizes(folder: Path) -> dict[int, Path]:
    """{number of values: level file} of a solution folder (read once per file: the header only)."""
    sizes = {}
    for path in sorted(folder.glob("level-*.npz")):
        with np.load(path, allow_pickle=False) as data:
            if "values" in data.files:
                sizes[len(data["values"])] = path
    return sizes


def external(folder, name: str | None = None) -> External:
    """The method of the solutions in ``folder`` (its manifest.json and level-L.npz files,
    docs/guide/export-format.md); ``name`` overrides the manifest's method name. A folder that
    is not one is refused in one line."""
    folder = Path(folder)
    manifest = _manifest(folder)
    order = manifest.get("order", 2)
    if order not in LAGRANGE_ORDERS:
        raise ExternalError(f"{folder}: order {order!r}; external solutions are P1 or P2")
    sizes = solution_sizes(folder)
    if not sizes:
        raise ExternalError(f"{folder} has no level-L.npz solution files")
    for path in sizes.values():             # what needs no mesh is checked before any study starts
        read_level(path, str(manifest["method"]))
    like = manifest.get("like")
    code = str(manifest.get("code", "another code"))
    return External(name=name or str(manifest["method"]), order=int(order), contact=f"{code}: {manifest.get('model', like or 'its own')}",
                    reference=code, expected=_expected(like, int(order)), folder=str(folder.resolve()), code=code,
                    case_name=str(manifest["case"]), like=like, options=dict(manifest.get("options", {})))


def _manifest(folder: Path) -> dict:
    path = folder / "manifest.json"
    try:
        manifest = json.loads(path.read_text())
    except FileNotFoundError:
        raise ExternalError(f"{folder}: no manifest.json (an external solution folder has one)") from None
    except ValueError as exc:
        raise ExternalError(f"{path} is not JSON ({exc})") from None
    if not isinstance(manifest, dict) or manifest.get("format") != SOLUTION_FORMAT:
        raise ExternalError(f"{path}: format is not {SOLUTION_FORMAT!r}")
    if manifest.get("format_version") != SOLUTION_FORMAT_VERSION:
        raise ExternalError(f"{path}: format_version {manifest.get('format_version')!r}; this harness reads {SOLUTION_FORMAT_VERSION}")
    missing = [key for key in ("method", "case") if not manifest.get(key)]
    if missing:
        raise ExternalError(f"{path} lacks {', '.join(missing)}")
    return manifest


def _expected(like: str | None, order: int):
    """The expectation of the harness method ``like`` (what the code discretises), else the
    best a P_k method can do for the case's regularity, h^min(nu - 1, k)."""
    def expected(case) -> Expectation:
        if like:
            from .registry import get_method
            return get_method(like).expected(case)
        return capped_expectation(case.nu, order, "the case's regularity (no theory of the code's method given)")
    return expected

