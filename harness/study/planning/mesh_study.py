"""The report's mesh study: cases of the paper limited by one singular point (scalar and elastic, one body
and two, and in the fine profile a transition line in 3D) and a case without u (each level against its own reference), on graded and
adaptive meshes (``mesh.strategies``), beside the uniform rows of the main study; stored per
(case, mesh) under ``results/meshes`` and reused while code, case file and settings are unchanged.

The methods are those that declare the role MESH_STUDY (the fine profile adds the PAPER, BASELINE
and SWEPT ones: ``methods.method.Method.roles``). The finest adaptive mesh of ``PICTURE_METHOD`` (the reference
method, ``measure.reference``) is kept (``FinestMesh``) for the report's picture. Its section of the report,
text, tables and figures: ``report.sections.meshes``.
"""
from __future__ import annotations

import io
from pathlib import Path

import numpy as np
import pandas as pd

from ...measure.reference import REFERENCE_METHOD
from ...mesh.points import cells, coordinates
from ...mesh.strategies import parse_meshes, refusal
from ...mesh.trace import contact_trace
from ...methods import BASELINE, MESH_STUDY, PAPER, SWEPT, methods_named
from ..storage.files import write_atomic
from .stored import read_stored

PLAN = {
    # a junction (r^1/2), a transition point (r^3/2), the elastic junction at 3 pi / 4 (r^0.5445:
    # Remark 2.3's body, the elastic estimator), and two bodies at a junction (r^1/2 on each side:
    # the two-body estimator, one marking over both bodies, the mortar coupling per level;
    # wedge-r23, a scalar junction at 3 pi / 4, stays out to keep the report's budget); a case
    # without u, its free boundary's ends found by the estimator (each level measured against
    # its own reference: ``measure.level_reference``)
    "cases": ("corner-r12", "transition-r32", "elastic-wedge", "two-body-junction", "smooth-obstacle"),
    # the fine profile's too: in 3D the r^3/2 transition line (graded toward the line, the 3D
    # estimator on tetrahedra). At the default budget (1.3e5 dofs) its adaptive P2 is still
    # pre-asymptotic, for work the default report has not to spare
    "fine_cases": ("transition-line-3d",),
    # the methods that declare these roles (``methods.Method.roles``): a cone of each order and Nitsche
    "roles": (MESH_STUDY,),
    "meshes": ("graded", "adaptive"),
}
# the fine profile's: also the paper's, the baseline and the swept methods (mean and penalty)
FINE_ROLES = (MESH_STUDY, PAPER, BASELINE, SWEPT)
PICTURE_METHOD = REFERENCE_METHOD


def mesh_config(settings: dict) -> dict:
    """What the report runs on graded and adaptive meshes: the profile's ``mesh_levels``
    (the budget of dofs: an adaptive chain stops at the uniform level's number of elements),
    the methods of the report that declare a role of ``MESH_STUDY`` (``FINE_ROLES`` in the fine
    profile), in the report's order; the fine profile adds ``PLAN["fine_cases"]`` (3D)."""
    roles = set(FINE_ROLES if settings.get("profile") == "fine" else PLAN["roles"])
    chosen = methods_named(settings["methods"])
    cases = list(PLAN["cases"]) + (list(PLAN["fine_cases"]) if settings.get("profile") == "fine" else [])
    return {"cases": cases, "meshes": list(PLAN["meshes"]),
            "methods": [m.name for m in chosen if roles & set(m.roles)], "levels": settings["mesh_levels"],
            "levels_3d": settings.get("mesh_levels_3d", settings["mesh_levels"])}


def mesh_levels(case, config: dict) -> int:
    """The uniform level count whose finest level is the budget of ``case``'s graded and
    adaptive chains: a 3D level has 8 times the dofs of the last, a 2D one 4 times."""
    return config["levels_3d"] if case.dimension == 3 else config["levels"]


def mesh_jobs_plan(cases, config: dict):
    """(case, mesh strategy, methods) of every chain group the mesh study runs. In 3D P1 stops
    at P2's budget of elements, not one uniform level past it as in 2D: that level (8 times
    the elements) would make transition-line-3d's P1 chains many times their work at P2's budget
    (graded meshes of P1 are made by bisection there, μ = 1), beyond the report's budget."""
    methods = methods_named(config["methods"]) if config["methods"] else []
    for case in cases:
        if case.name not in config["cases"] or not methods:
            continue
        own = [m.with_extra_levels(0) for m in methods] if case.dimension == 3 else methods
        for mesh in parse_meshes(config["meshes"]):
            if refusal(mesh, case) is None:
                yield case, mesh, own


class FinestMesh:
    """An ``on_level`` hook keeping every adaptive level's mesh of ``PICTURE_METHOD`` (vertices and
    triangles; in 3D the triangles of Gamma_C, where the contact's singular lines lie); the store
    keeps the finest."""

    def __call__(self, case, method, level, problem, solve):
        if method.name != PICTURE_METHOD:
            return None
        if problem.mesh.dim == 3:
            trace = contact_trace(problem.mesh)
            return trace.vertex_points, np.searchsorted(trace.vertices, trace.faces.vertices)
        return coordinates(problem.mesh), cells(problem.mesh)


def save_finest_mesh(kept: dict, path: Path) -> None:
    levels = [level for (name, level) in kept if name == PICTURE_METHOD]
    if not levels:
        return
    points, triangles = kept[(PICTURE_METHOD, max(levels))]
    buffer = io.BytesIO()
    np.savez_compressed(buffer, points=points, triangles=triangles)
    write_atomic(path, buffer.getvalue())


def load_finest_mesh(path: Path):
    """(points, triangles) or None."""
    if not Path(path).is_file():
        return None
    with np.load(path) as data:
        return data["points"], data["triangles"]


def read_mesh_results(store: Path, cases, config: dict) -> pd.DataFrame:
    """Every stored (case, mesh) frame the mesh study of ``config`` has for ``cases`` (empty if none)."""
    return read_stored(store, mesh_jobs_plan(cases, config))
