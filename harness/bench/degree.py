"""The degree rows of `bench`: on transition-r32's uniform meshes, the contact solve of P3 and P4
on the finest level, from the nested start (the coarser level solved by the same method), against
one linear solve of the same stiffness by the same multigrid CG (the P1 hierarchy, its smoother on
the edge and cell dofs) from zero, and by sparse Cholesky: Nitsche (semismooth Newton) and the
Gauss-Lobatto cone (the general-constraint active set method on the projected multigrid). Each
measurement in a fresh process (``common.in_fresh_process``), the machine otherwise idle."""
from __future__ import annotations

import numpy as np
import pandas as pd

from .common import fastest, in_fresh_process, timed

DEGREE_CASE = "transition-r32"
# the level of each degree: P3 past 1e6 dofs, where the goal is judged; P4 at about half of that
DEGREE_LEVELS = {3: 6, 4: 5}
DEGREE_GOAL = 2.0               # a k = 3 contact solve / one linear solve, at >= 1e6 dofs
DEGREE_COLUMNS = ["method", "order", "ndof", "t_contact", "t_linear_multigrid", "t_linear_cholesky", "ratio_linear",
                  "iterations", "cg_iterations", "linear_cg_iterations", "kkt_residual"]


def _cone_row(method_name: str, level: int, connection) -> None:
    """A `FunctionalCone` of degree k: its solve of ``level`` from the nested start, and the
    linear multigrid solve of its matrix (A itself: the cone changes no variable)."""
    import ngsolve as ngs

    from ..fem.assembly import discretise
    from ..fem.p1_embedding import ContactEdges
    from ..mesh.levels import UniformRefinement
    from ..methods import get_method
    from ..problem.case import load_case
    from ..solvers.bound_constraints import DEFAULT_TOLERANCE, Cholesky, MultigridSystem
    from ..solvers.multigrid import Multilevel

    case, method = load_case(DEGREE_CASE), get_method(method_name)
    multilevel, carry = None, None
    with ngs.TaskManager():
        for step in UniformRefinement(case).levels(level + 1):
            multilevel = Multilevel(step.mesh, case.physics) if multilevel is None else multilevel.refined(step.mesh)
            if step.index < level - 1:
                continue
            problem = discretise(case, step.mesh, method.order)
            if step.index == level - 1:
                carry = method.solve(case, problem, None, multilevel).carry
        system = MultigridSystem(problem.A_ngs, problem.b, multilevel, ContactEdges.of(problem, model=False))
        scale = np.abs((problem.b - problem.A @ problem.lift)[problem.free]).max()

        def linear():
            system.cg_iterations = 0
            return timed(system.solve, ~problem.free, problem.lift, tol=0.1 * DEFAULT_TOLERANCE * scale)
        t_linear = fastest(linear)[0]
        linear_iterations = system.cg_iterations
        rhs = np.where(problem.free, problem.b - problem.A @ problem.lift, 0.0)
        t_cholesky = fastest(lambda: timed(lambda: Cholesky(problem.A_ngs, problem.free).solve(rhs)))[0]
        t_contact, solve = fastest(lambda: _timed_solve(method, case, problem, carry, multilevel))
    fields = solve.fields
    connection.send({"ndof": problem.ndof, "t": t_contact, "t_multigrid": t_linear, "linear_iterations": linear_iterations,
                     "t_cholesky": t_cholesky,
                     "iterations": fields["solver_iterations"], "cg_iterations": fields["linear_iterations"],
                     "kkt_residual": fields["kkt_residual"]})
    connection.close()


def _timed_solve(method, case, problem, carry, multilevel) -> tuple[float, object]:
    solve = method.solve(case, problem, carry, multilevel)
    return solve.fields["solve_seconds"], solve


def _row(method_name: str, level: int) -> dict:
    from ..methods import ContactLawMethod, get_method
    from .solvers import measure
    method = get_method(method_name)
    if isinstance(method, ContactLawMethod):
        contact, multigrid, cholesky = (measure(kind, method_name, level) for kind in ("contact", "multigrid", "cholesky"))
        linear_iterations, t_multigrid, t_cholesky = multigrid["iterations"], multigrid["t"], cholesky["t"]
    else:
        contact = in_fresh_process(_cone_row, (method_name, level), f"{method_name}/level {level}")
        linear_iterations, t_multigrid, t_cholesky = contact["linear_iterations"], contact["t_multigrid"], contact["t_cholesky"]
    return {"method": method_name, "order": method.order, "ndof": contact["ndof"], "t_contact": contact["t"],
            "t_linear_multigrid": t_multigrid, "t_linear_cholesky": t_cholesky,
            "ratio_linear": contact["t"] / min(t_multigrid, t_cholesky), "iterations": contact["iterations"],
            "cg_iterations": contact["cg_iterations"], "linear_cg_iterations": linear_iterations,
            "kkt_residual": contact["kkt_residual"]}


def degree_sizes() -> list[tuple[str, int]]:
    """(method, level) of the methods of the report's degree study (the role DEGREES) of degree
    3 and 4."""
    from ..methods import DEGREES, with_role
    return [(m.name, DEGREE_LEVELS[m.order]) for m in with_role(DEGREES) if m.order in DEGREE_LEVELS]


def run_degree_bench(sizes=None, progress=print) -> pd.DataFrame:
    rows = []
    for method_name, level in sizes or degree_sizes():
        rows.append(_row(method_name, level))
        r = rows[-1]
        progress(f"{method_name:11s} ndof {r['ndof']:>9d}  contact {r['t_contact']:6.2f} s  linear: multigrid "
                 f"{r['t_linear_multigrid']:6.2f} s, cholesky {r['t_linear_cholesky']:6.2f} s  ratio {r['ratio_linear']:.2f}")
    return pd.DataFrame(rows, columns=DEGREE_COLUMNS)


def degree_goals(frame: pd.DataFrame) -> list[tuple[str, bool, str]]:
    """The degree axis's solver goal, with the measured figures: every k = 3 row at >= 1e6 dofs within
    ``DEGREE_GOAL`` linear solves, every row exact."""
    big = frame[(frame.order == 3) & (frame.ndof >= 1_000_000)]
    figures = ", ".join(f"{m} {r:.2f} at {n:.2g} dofs" for m, r, n in zip(big.method, big.ratio_linear, big.ndof))
    return [(f"k = 3 contact solve <= {DEGREE_GOAL:g} x one linear solve at >= 1e6 dofs", bool(len(big))
             and bool((big.ratio_linear <= DEGREE_GOAL).all()), figures or "no k = 3 row at 1e6 dofs"),
            ("every degree row exact (KKT or Newton residual <= 1e-10)", bool((frame.kkt_residual <= 1e-10).all()),
             f"max {frame.kkt_residual.max():.1e}")]
