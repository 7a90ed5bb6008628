"""The elastic rows of `bench` (Remark 2.3): each P2 cone's contact solve, by the truncated
vector multigrid (``solvers.multigrid``: vector P1 coarse spaces in the rotated frame) with
nested iteration, against one linear elastic solve of the same matrix by the same multigrid CG,
and against sparse Cholesky; and Nitsche's (a contact law, ``fem.contact_laws.builtin``): its semismooth Newton
solve, nested, against one linear solve of its Jacobian (the final set's) by the same multigrid
CG, from zero and from the same start."""
from __future__ import annotations

import resource

import numpy as np
import pandas as pd

from .common import FAIR_COLUMNS, contact_goals, fastest, fresh_rows, timed
from .three_d import solve_row

# Poisson ratio 0.3 (the multigrid path; ``problem.physics.Elasticity.multigrid``), plane strain and 3D
ELASTIC_CASE = "elastic-transition-r32"
ELASTIC_CASE_3D = "elastic-transition-3d"


# (case, coarse maxh, level): 5.8e4 and 2.3e5 dofs on the plane-strain case's own hierarchy
# (maxh 0.5), 1.2e6 on a finer coarse mesh (maxh 0.25), then 3D: 8.1e4 and 6.0e5 dofs; the
# goals are set at the 2D 1.2e6 and the 3D 6.0e5
ELASTIC_SIZES = ((ELASTIC_CASE, None, 5), (ELASTIC_CASE, None, 6), (ELASTIC_CASE, 0.25, 6),
                 (ELASTIC_CASE_3D, None, 2), (ELASTIC_CASE_3D, None, 3))


# a 3D factorisation's fill grows like n^(4/3): past this it is minutes and gigabytes, not a comparison
CHOLESKY_MAX_NDOF_3D = 100_000


ELASTIC_COLUMNS = ["case", "method", "ndof", "t_contact", "t_linear", "ratio_linear", *FAIR_COLUMNS, "t_linear_cholesky", "iterations",
                   "cg_iterations", "linear_cg_iterations", "kkt_residual", "peak_rss_mb"]


def weak_methods() -> list[str]:
    """The weak methods of the elastic rows beside the paper's cones: the P2 contact laws the
    report sweeps (role SWEPT: Nitsche, penalty)."""
    from ..methods import SWEPT, ContactLawMethod, with_role
    return [m.name for m in with_role(SWEPT) if isinstance(m, ContactLawMethod) and m.order == 2]


def _measure_elastic(model_name: str, size: tuple, connection):
    import ngsolve as ngs

    from ..methods import ContactLawMethod, get_method
    from ..solvers.bound_constraints import Cholesky

    ngs.ngsglobals.msg_level = 0
    case, coarse_maxh, level = size
    if isinstance(get_method(model_name), ContactLawMethod):
        with ngs.TaskManager():
            connection.send(_weak_row(model_name, size))
        connection.close()
        return
    with ngs.TaskManager():
        row = solve_row(model_name, level, case, coarse_maxh)
        qp = row.qp
        rhs = np.where(qp.free, qp.b - qp.K @ qp.lift, 0.0)
        t_cholesky = np.nan
        if qp.problem.mesh.dim == 2 or qp.problem.ndof <= CHOLESKY_MAX_NDOF_3D:
            t_cholesky, _ = fastest(lambda: timed(lambda: Cholesky(qp.K_ngs, qp.free).solve(rhs)))
    connection.send({
        "case": case, "method": model_name, "ndof": qp.problem.ndof, "t_contact": row.t_contact, "t_linear": row.t_linear,
        "ratio_linear": row.t_contact / row.t_linear, **row.fair(), "t_linear_cholesky": t_cholesky,
        "iterations": row.solution.iterations, "cg_iterations": row.solution.work["cg_iterations"],
        "linear_cg_iterations": row.linear.cg_iterations, "kkt_residual": row.solution.kkt.residual,
        "peak_rss_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024,
    })
    connection.close()


def _weak_row(method_name: str, size: tuple) -> dict:
    """A weak method's row: its Newton solve from the nested start against one linear solve of
    its Jacobian by the same multigrid CG (``MultigridSystem``, the Newton step's linear solver)
    from zero and from the same start, to the Newton step's depth."""
    from ..fem.p1_embedding import ContactEdges
    from ..solvers.bound_constraints import MultigridSystem
    from ..solvers.newton import load_scale, solve_semismooth_newton
    from .common import fair_columns, linear_seconds, own_seconds
    from .solvers import weak_problem

    case, coarse_maxh, level = size
    system, start, predicted, multilevel = weak_problem(method_name, level, coarse_maxh, case)
    t_contact, solution = fastest(lambda: own_seconds(solve_semismooth_newton(system, start, multilevel, predicted=predicted)))
    problem = system.problem
    # the affine system of the solution's own set, J u_h = r, with the V-cycle of Newton's last step
    # (its coarse spaces truncated where the contact term is active, ``solvers.multigrid.TruncatedVCycle``;
    # without that hint CG needs many times the iterations)
    system.set_jacobian(solution.active)
    rhs, embedding = system.affine_rhs(solution.active), ContactEdges.of(problem, model=False)
    stiff = system.stiff_vertices(solution.active, multilevel.ndof)
    (t_linear, zero), (t_nested, nested) = (
        linear_seconds(MultigridSystem(system.J_ngs, rhs, multilevel, embedding, stiff_vertices=stiff), problem,
                       load_scale(system), s) for s in (None, start))
    zero_iterations = zero.cg_iterations
    return {"case": case, "method": method_name, "ndof": problem.ndof, "t_contact": t_contact, "t_linear": t_linear,
            "ratio_linear": t_contact / t_linear,
            **fair_columns(t_contact, solution.linear_iterations, t_linear, zero_iterations, t_nested, nested.cg_iterations),
            "t_linear_cholesky": np.nan, "iterations": solution.iterations, "cg_iterations": solution.linear_iterations,
            "linear_cg_iterations": zero_iterations, "kkt_residual": solution.residual,
            "peak_rss_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024}


def run_elastic_bench(sizes=ELASTIC_SIZES, models=None, progress=print) -> pd.DataFrame:
    """Each (model, size) in its own fresh process, like ``run_bench`` (default: the paper's
    models, the methods that declare the role PAPER, and ``weak_methods``)."""
    from ..methods import PAPER, role_names
    models = models or [*role_names(PAPER), *weak_methods()]
    return fresh_rows(_measure_elastic, "elastic", "multigrid CG", sizes, models, progress, ELASTIC_COLUMNS)


def elastic_goals(frame: pd.DataFrame) -> list[tuple[str, bool, str]]:
    """The elastic contact solve is exact and costs at most 1.5 linear multigrid solves (the
    cones) or 2 (Nitsche's Newton solve: a linear solve of its Jacobian per new set) at the
    largest size of each dimension."""
    goals = []
    weak = frame.method.isin(weak_methods())
    for case, label in ((ELASTIC_CASE, "elastic 2D"), (ELASTIC_CASE_3D, "elastic 3D")):
        for rows, kind, bound in ((frame[(frame.case == case) & ~weak], "", 1.5), (frame[(frame.case == case) & weak], " weak", 2.0)):
            if len(rows):
                goals += contact_goals(rows, label + kind, bound)
    return goals
