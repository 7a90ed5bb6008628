"""The 3D rows of `bench` (the paper's Section 6): each method's contact solve against one linear
solve, on a 3D transition case."""
from __future__ import annotations

import resource
from dataclasses import dataclass

import pandas as pd

from .common import (
    FAIR_COLUMNS,
    contact_goals,
    fair_columns,
    fastest,
    fresh_rows,
    linear_multigrid_seconds,
    linear_seconds,
    own_seconds,
)
from .solvers import cone_problem

THREE_D_CASE = "transition-line-3d"


THREE_D_LEVELS = (1, 2, 3)         # 1.8e4, 1.3e5, 1.0e6 P2 dofs


THREE_D_COLUMNS = ["case", "method", "ndof", "t_contact", "t_linear", "ratio_linear", *FAIR_COLUMNS, "iterations",
                   "cg_iterations", "linear_cg_iterations", "kkt_residual", "peak_rss_mb"]


def face_mean_problem(level: int, case_name: str = THREE_D_CASE, model_name: str | None = None):
    """The 3D `mean`'s face-mean QP of ``level`` on the study's hierarchy, with what nested
    iteration brings from ``level - 1`` (solved by the method ``model_name``, by default the
    registered ``CellMean``): predicted set, start."""
    from ..fem.assembly import discretise
    from ..fem.face_means import face_mean_qp
    from ..fem.nested import nested_start
    from ..fem.p1_embedding import ContactEdges
    from ..mesh.levels import UniformRefinement
    from ..methods import get_method
    from ..problem.case import load_case
    from ..solvers.multigrid import Multilevel

    case, method = load_case(case_name), get_method(model_name or _cell_means()[0])
    multilevel, carry = None, None
    for lev, mesh in ((step.index, step.mesh) for step in UniformRefinement(case).levels(level + 1)):
        multilevel = Multilevel(mesh, case.physics) if multilevel is None else multilevel.refined(mesh)
        if lev == level - 1:
            carry = method.solve(case, discretise(case, mesh, 2), None, multilevel).carry
    qp = face_mean_qp(case, discretise(case, mesh, 2), take_stiffness=True)
    start = None if carry is None else nested_start(multilevel, carry.p1, qp.problem, ContactEdges.of(qp.problem, model=False))
    return qp, qp.predicted_active(None if carry is None else carry.trace), multilevel, start


@dataclass
class SolveRow:
    """One row's measurements: the contact solve (nested iteration from the level below) and
    the linear solves of its matrix by the same multigrid CG, from zero and from the same start."""

    qp: object
    t_contact: float
    solution: object
    t_linear: float
    linear: object                  # the MultigridSystem of the solve from zero (its cg_iterations)
    t_nested: float
    nested: object                  # ... of the solve from the contact solve's start

    def fair(self) -> dict:
        return fair_columns(self.t_contact, self.solution.work["cg_iterations"], self.t_linear, self.linear.cg_iterations,
                            self.t_nested, self.nested.cg_iterations)


def solve_row(model_name: str, level: int, case_name: str = THREE_D_CASE, coarse_maxh=None) -> SolveRow:
    """One row: the contact solve (nested iteration from ``level`` - 1) and the linear multigrid
    solves of its matrix (``SolveRow``). The 3D `mean` is the face-mean QP (general rows,
    ``solvers.projected_multigrid``), every other method a cone of bounds."""
    from ..problem.case import load_case
    from ..solvers.bound_constraints import solve_contact_qp
    if model_name not in _cell_means() or load_case(case_name).dimension != 3:
        qp, predicted, multilevel, start = cone_problem(model_name, level, coarse_maxh, case_name)
        linear = [linear_multigrid_seconds(qp, multilevel, s) for s in (None, start)]
        t_contact, solution = fastest(lambda: own_seconds(solve_contact_qp(qp, predicted, multilevel=multilevel, start=start)))
        return SolveRow(qp, t_contact, solution, *linear[0], *linear[1])
    from ..fem.p1_embedding import ContactEdges
    from ..solvers.bound_constraints import MultigridSystem
    from ..solvers.general_constraints import GeneralConstraintSolver
    from ..solvers.projected_multigrid import ProjectedMultigridSystem
    qp, predicted, multilevel, start = face_mean_problem(level, case_name, model_name)
    embedding = ContactEdges.of(qp.problem, model=False)

    def contact():
        return GeneralConstraintSolver(qp.K, qp.b, qp.free, qp.B, qp.g, lift=qp.lift,
                                       system=ProjectedMultigridSystem(qp.K_ngs, multilevel, embedding))
    load_scale = contact().load_scale
    linear = [linear_seconds(MultigridSystem(qp.K_ngs, qp.b, multilevel, embedding), qp, load_scale, s) for s in (None, start)]
    t_contact, solution = fastest(lambda: own_seconds(contact().solve(predicted, start)))
    return SolveRow(qp, t_contact, solution, *linear[0], *linear[1])


def _measure_3d(model_name: str, level: int, connection):
    """A 3D contact solve (truncated multigrid, nested iteration) against one unconstrained
    solve of the same matrix by the same multigrid CG, from zero, as deep; and from the same
    start."""
    import ngsolve as ngs

    ngs.ngsglobals.msg_level = 0
    with ngs.TaskManager():
        row = solve_row(model_name, level)
    connection.send({
        "case": THREE_D_CASE, "method": model_name, "ndof": row.qp.problem.ndof, "t_contact": row.t_contact,
        "t_linear": row.t_linear, "ratio_linear": row.t_contact / row.t_linear, "iterations": row.solution.iterations,
        "cg_iterations": row.solution.work["cg_iterations"], "linear_cg_iterations": row.linear.cg_iterations,
        "kkt_residual": row.solution.kkt.residual, "peak_rss_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024,
        **row.fair(),
    })
    connection.close()


def _cell_means() -> list[str]:
    """The registered methods whose 3D cone is the triangle means (``methods.cones.CellMean``:
    general rows, not bounds)."""
    from ..methods import METHODS
    from ..methods.cones import CellMean
    return [name for name, m in METHODS.items() if isinstance(m, CellMean)]


def three_d_methods() -> tuple:
    """The registered one-body methods that discretise 3D scalar contact, in registry order."""
    from ..methods import METHODS
    return tuple(m.name for m in METHODS.values() if 3 in m.dimensions and 1 in m.bodies and "scalar" in m.physics)


def run_3d_bench(levels=THREE_D_LEVELS, models=None, progress=print) -> pd.DataFrame:
    """Each (model, level) in its own fresh process, like ``run_bench`` (default:
    ``three_d_methods()``)."""
    return fresh_rows(_measure_3d, "3D", "multigrid CG", levels, models or three_d_methods(), progress, THREE_D_COLUMNS)


def three_d_goals(frame: pd.DataFrame) -> list[tuple[str, bool, str]]:
    """The goals: the 3D contact solve is exact and within 1.5x one linear solve at the largest
    size."""
    return contact_goals(frame, "3D", 1.5)
