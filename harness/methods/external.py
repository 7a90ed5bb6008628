"""Another finite element code's solutions, measured as the harness's own methods are
(``--method external:DIR``, ``harness.external(DIR)``).

The other code solved the levels of an export (``study.export``: the same meshes, the same
data, the right-hand side as moments against the Lagrange basis) and wrote, per level, its
solution's values at the P_k Lagrange nodes (docs/guide/measure-your-code.md, "Solutions"). A P_k
function is determined by those values, so the harness rebuilds u_h exactly
(``fem.lagrange.LagrangeNodes``) and measures it like any row: every error, the quantities, the
rates and verdicts, the cost (the code's own seconds) and the report's cells. What the harness
cannot see is how the code solved: the row's ``kkt_residual``, iterations and seconds are the
code's own.
"""
from __future__ import annotations

import json
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from ..fem.assembly import ContactTraceFunction
from ..fem.lagrange import LAGRANGE_ORDERS, LagrangeNodes
from ..fem.nested import p1_values
from ..fem.penetration import max_penetration
from .method import Carry, Expectation, LevelSolve, Method, SolveFields, capped_expectation, timer
from .protocol import vertex_force_pressure

SOLUTION_FORMAT = "signorini-harness-solution"
# --method external:DIR
EXTERNAL_PREFIX = "external:"
SOLUTION_FORMAT_VERSION = 1
# the harness methods the drivers of examples/codes discretise exactly (their --model): the
# paper's nodal cone and Nitsche's law (``bench.codes`` runs them side by side)
DRIVER_MODELS = ("nodal", "nitsche")
# a point matches a node within this fraction of the level's extent (the export's nodes are
# written in full double precision; another code's dof coordinates differ by round-off)
MATCH_TOLERANCE = 1e-9


class ExternalError(ValueError):
    """A one-line reason an external solution folder is refused."""


@dataclass(frozen=True)
class External(Method):
    """Another code's solutions, computed by ``code``: ``solutions`` ((case name, folder), ...),
    one folder per case; ``like``: the harness method they discretise (its expected rate), if
    the folders name one."""

    solutions: tuple = ()
    code: str = ""
    like: str | None = None
    options: dict = field(default_factory=dict, compare=False)
    physics: tuple = ("scalar", "elasticity")
    dimensions: tuple = (2, 3)
    friction: tuple = ("frictionless", "tresca")
    cost_model: str | float = 1e-5

    @property
    def cases(self) -> tuple[str, ...]:
        return tuple(case for case, _ in self.solutions)

    def refusal(self, case) -> str | None:
        if case.name not in self.cases:
            return f"its solutions are of {', '.join(self.cases)}"
        return super().refusal(case)

    def joined(self, other: "External") -> "External":
        """This method with ``other``'s solutions of other cases (the same code, order and ``like``)."""
        if (other.order, other.like, other.code) != (self.order, self.like, self.code):
            raise ExternalError(f"two external methods named {self.name!r} of different codes, orders or models: rename one")
        clash = set(self.cases) & set(other.cases)
        if clash and dict(self.solutions) != dict(other.solutions):
            raise ExternalError(f"two solution folders of {self.name!r} on {', '.join(sorted(clash))}")
        return replace(self, solutions=tuple((dict(self.solutions) | dict(other.solutions)).items()))

    def level_file(self, case_name: str, nodes: int) -> Path:
        """The level file of ``case_name`` whose solution has ``nodes`` values: the level of that size."""
        folder = Path(dict(self.solutions)[case_name])
        sizes = solution_sizes(folder)
        if nodes not in sizes:
            raise ExternalError(f"external {self.name!r}: {folder} has no solution on the level with {nodes} nodes "
                                f"(it has {', '.join(map(str, sorted(sizes))) or 'none'}): a level is missing")
        return sizes[nodes]

    def solve(self, case, problem, carry, multilevel, take_stiffness: bool = False, phases=None) -> LevelSolve:
        timed = timer(phases)
        with timed("setup"):
            nodes = LagrangeNodes.of(problem.fes)
            level = read_level(self.level_file(case.name, nodes.count), self.name)
        with timed("solve"):
            u = rebuilt(problem, nodes, level, self.name)
        trace_u = ContactTraceFunction.of(problem, u)
        pressure = vertex_force_pressure(problem, u)
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


def read_external(folder, name: str | None = None) -> External:
    """The method of the solutions in ``folder`` (its manifest.json and level-L.npz files,
    docs/guide/measure-your-code.md), or in its subfolders, one per case, of one code and method;
    ``name`` overrides the manifests' method name. A folder that is neither is refused in one line."""
    folder = Path(folder)
    folders = [folder] if (folder / "manifest.json").exists() else sorted(p.parent for p in folder.glob("*/manifest.json"))
    if not folders:
        _manifest(folder)                   # the one-line refusal of a folder without a manifest
    manifests = [_checked_folder(each) for each in folders]
    first = manifests[0]
    for each, manifest in zip(folders[1:], manifests[1:]):
        if (manifest["method"], manifest.get("order", 2), manifest.get("like")) != (first["method"], first.get("order", 2), first.get("like")):
            raise ExternalError(f"{each}: method {manifest['method']!r} of order {manifest.get('order', 2)}, like "
                                f"{manifest.get('like')!r}; {folders[0]} has another: one method per folder")
    cases = [str(manifest["case"]) for manifest in manifests]
    if len(set(cases)) != len(cases):
        raise ExternalError(f"{folder}: two solution folders of one case")
    order, like, code = int(first.get("order", 2)), first.get("like"), str(first.get("code", "another code"))
    return External(name=name or str(first["method"]), order=order, contact=f"{code}: {first.get('model', like or 'its own')}",
                    reference=code, expected=_expected(like, order), code=code, like=like,
                    solutions=tuple((case, str(each.resolve())) for case, each in zip(cases, folders)),
                    options=dict(first.get("options", {})))


def _checked_folder(folder: Path) -> dict:
    """The manifest of one case's solution folder, its level files checked (what needs no mesh)."""
    manifest = _manifest(folder)
    if manifest.get("order", 2) not in LAGRANGE_ORDERS:
        raise ExternalError(f"{folder}: order {manifest.get('order')!r}; external solutions are P1 or P2")
    sizes = solution_sizes(folder)
    if not sizes:
        raise ExternalError(f"{folder} has no level-L.npz solution files")
    for path in sizes.values():
        read_level(path, str(manifest["method"]))
    return manifest


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
    """Without ``like``: the best a P_k method can do for the case's regularity, h^min(nu - 1, k)
    (with it, ``registry.external`` gives the harness method's own expectation)."""
    def expected(case) -> Expectation:
        return capped_expectation(case.nu, order, "the case's regularity (no theory of the code's method given)")
    return expected
