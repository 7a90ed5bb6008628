"""The 3D rows of `bench` (the paper's Section 6): each method's contact solve against one linear
solve, on a 3D transition case."""
from __future__ import annotations

import resource

import pandas as pd

from .common import contact_goals, fastest, fresh_rows, own_seconds, timed
from .solvers import cone_problem

THREE_D_CASE = "transition-line-3d"


THREE_D_LEVELS = (1, 2, 3)         # 1.8e4, 1.3e5, 1.0e6 P2 dofs


THREE_D_COLUMNS = ["case", "method", "ndof", "t_contact", "t_linear", "ratio_linear", "iterations", "cg_iterations",
                   "linear_cg_iterations", "kkt_residual", "peak_rss_mb"]


def linear_multigrid_seconds(qp, multilevel) -> tuple[float, object]:
    """(seconds, the MultigridSystem) of one unconstrained solve of ``qp``'s matrix by the
    contact solver's multigrid CG, from zero, as deep as its linear solves go (fastest of
    repeats)."""
    from ..solvers.active_set import DEFAULT_TOLERANCE, ActiveSetSolver, MultigridSystem
    from ..solvers.multigrid import ContactEdges
    system = MultigridSystem(qp.K_ngs, qp.b, multilevel, ContactEdges.of(qp.problem))
    load_scale = ActiveSetSolver(qp.K, qp.b, qp.free, qp.C, qp.alpha, lift=qp.lift, system=system).load_scale

    def linear():
        system.cg_iterations = 0
        return timed(system.solve, ~qp.free, qp.lift, tol=0.1 * DEFAULT_TOLERANCE * load_scale)
    return fastest(linear)[0], system


def _measure_3d(model_name: str, level: int, connection):
    """Issue 19: a 3D contact solve (truncated multigrid, nested iteration) against one
    unconstrained solve of the same matrix by the same multigrid CG, from zero, as deep."""
    import ngsolve as ngs

    from ..solvers.active_set import solve_contact_qp

    ngs.ngsglobals.msg_level = 0
    with ngs.TaskManager():
        qp, predicted, multilevel, start = cone_problem(model_name, level, None, THREE_D_CASE)
        t_linear, system = linear_multigrid_seconds(qp, multilevel)
        t_contact, solution = fastest(lambda: own_seconds(solve_contact_qp(qp, predicted, multilevel=multilevel, start=start)))
    connection.send({
        "case": THREE_D_CASE, "method": model_name, "ndof": qp.problem.ndof, "t_contact": t_contact, "t_linear": t_linear,
        "ratio_linear": t_contact / t_linear, "iterations": solution.iterations,
        "cg_iterations": solution.work["cg_iterations"], "linear_cg_iterations": system.cg_iterations,
        "kkt_residual": solution.kkt.residual, "peak_rss_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024,
    })
    connection.close()


def run_3d_bench(levels=THREE_D_LEVELS, models=("mean", "nodal", "p1"), progress=print) -> pd.DataFrame:
    """Each (model, level) in its own fresh process, like ``run_bench``."""
    return fresh_rows(_measure_3d, "3D", "multigrid CG", levels, models, progress, THREE_D_COLUMNS)


def three_d_goals(frame: pd.DataFrame) -> list[tuple[str, bool, str]]:
    """Issue 19: the 3D contact solve is exact and within 2x one linear solve at the largest size."""
    return contact_goals(frame, "3D", 2)
