"""The elastic rows of `bench` (Remark 2.3): each P2 cone's contact solve against one linear
elastic solve of the same matrix."""
from __future__ import annotations

import resource

import numpy as np
import pandas as pd

from .common import contact_goals, fastest, fresh_rows, own_seconds, timed

# Elasticity (Remark 2.3): the contact solve of each P2 model against one linear elastic solve
# (sparse Cholesky, factorisation and solve, of the same matrix with the Dirichlet pins only) on
# the elastic transition case: levels 5, 6, 7 = 5.8e4, 2.3e5 and 9.2e5 dofs.
ELASTIC_CASE = "elastic-transition-r32"


ELASTIC_LEVELS = (5, 6, 7)


ELASTIC_COLUMNS = ["case", "method", "ndof", "t_contact", "t_linear", "ratio_linear", "iterations", "factorizations",
                   "extra_solves", "kkt_residual", "peak_rss_mb"]


def _elastic_problem(model_name: str, level: int):
    """The elastic QP of ``level`` and the active set its level - 1 predicts (nested iteration)."""
    from ..fem.assembly import discretise
    from ..fem.cones import contact_qp
    from ..mesh.levels import UniformRefinement
    from ..methods import get_method
    from ..problem.case import load_case
    from ..solvers.active_set import solve_contact_qp

    case, method = load_case(ELASTIC_CASE), get_method(model_name)
    previous = None
    for lev, mesh in ((step.index, step.mesh) for step in UniformRefinement(case).levels(level + 1)):
        if lev < level - 1:
            continue
        qp = contact_qp(case, discretise(case, mesh, method.order), method.cone, take_stiffness=True)
        if lev == level - 1:
            coarse = solve_contact_qp(qp)
            previous = qp.trace_function(qp.to_u(coarse.z), coarse.active)
    return qp, qp.predicted_active(previous)


def _measure_elastic(model_name: str, level: int, connection):
    import ngsolve as ngs

    from ..solvers.active_set import Cholesky, solve_contact_qp

    ngs.ngsglobals.msg_level = 0
    with ngs.TaskManager():
        qp, predicted = _elastic_problem(model_name, level)
        rhs = np.where(qp.free, qp.b - qp.K @ qp.lift, 0.0)
        t_linear, _ = fastest(lambda: timed(lambda: Cholesky(qp.K_ngs, qp.free).solve(rhs)))
        t_contact, solution = fastest(lambda: own_seconds(solve_contact_qp(qp, predicted)))
    connection.send({
        "case": ELASTIC_CASE, "method": model_name, "ndof": qp.problem.ndof, "t_contact": t_contact, "t_linear": t_linear,
        "ratio_linear": t_contact / t_linear, "iterations": solution.iterations,
        "factorizations": solution.work["factorizations"], "extra_solves": solution.work["extra_solves"],
        "kkt_residual": solution.kkt.residual, "peak_rss_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024,
    })
    connection.close()


def run_elastic_bench(levels=ELASTIC_LEVELS, models=("mean", "nodal"), progress=print) -> pd.DataFrame:
    """Each (model, level) in its own fresh process, like ``run_bench``."""
    return fresh_rows(_measure_elastic, "elastic", "cholesky", levels, models, progress, ELASTIC_COLUMNS)


def elastic_goals(frame: pd.DataFrame) -> list[tuple[str, bool, str]]:
    """Issue 18: the elastic contact solve is exact and costs at most a few linear solves."""
    return contact_goals(frame, "elastic", 3)
