"""The friction rows of `bench` (issue 74): on tresca-r32's uniform meshes, the exact Tresca solve
of the finest level (the active set method on the bound-constrained dual, ``solvers.friction``,
nested from the coarser level solved by the same method, as the study does) against ONE linear
solve of the same matrix by the same multigrid CG with no friction rows (every friction row a
free Neumann dof: the Dirichlet/Neumann problem), from the same nested start to the same
tolerance (``ratio_nested``, the goal), and from zero (``ratio_linear``, shown). Each
measurement in a fresh process (``common.in_fresh_process``), the machine otherwise idle."""
from __future__ import annotations

import resource

import numpy as np
import pandas as pd

from .common import FAIR_COLUMNS, fair_columns, fastest, fresh_rows, linear_seconds, own_seconds

FRICTION_CASE = "tresca-r32"
FRICTION_LEVEL = 7                  # P2: 2.3e6 dofs (P1: 5.8e5)
# the nodal-type solve (the cones whose edge variable is the midpoint value: the nodal
# analogue) is judged against NODAL_GOAL, a contact law's against LAW_GOAL
NODAL_GOAL = 1.5
LAW_GOAL = 2.0


def cone_methods() -> tuple[str, ...]:
    """The registered P1/P2 cones whose Tresca rows are bounds (``methods.cones.BoundConstrained``)
    in 2D, timed by ``_cone_row``. Nothing outside ``methods/`` names a method: the bench asks
    what each is."""
    from ..methods import METHODS
    from ..methods.cones import BoundConstrained
    return tuple(m.name for m in METHODS.values() if isinstance(m, BoundConstrained) and "tresca" in m.friction
                 and 2 in m.dimensions and m.order <= 2)


def nodal_type(names) -> list[str]:
    """Those of ``names`` whose cone is the nodal analogue (the midpoint value per edge)."""
    from ..methods import METHODS
    return [name for name in names if getattr(getattr(METHODS[name], "cone", None), "edge_functional", None) == "midpoint"]
FRICTION_COLUMNS = ["case", "method", "ndof", "t_contact", "t_linear", "ratio_linear", *FAIR_COLUMNS, "iterations",
                    "cg_iterations", "linear_cg_iterations", "kkt_residual", "peak_rss_mb"]


def friction_problem(method_name: str, level: int, case_name: str = FRICTION_CASE):
    """The Tresca QP of ``level`` (``fem.friction.friction_qp``) on the study's hierarchy, with
    what nested iteration brings from ``level - 1`` solved by ``method_name`` itself:
    (qp, predicted set, multilevel, start)."""
    from ..fem.assembly import discretise
    from ..fem.friction import friction_qp
    from ..fem.nested import friction_prediction, nested_start
    from ..mesh.levels import UniformRefinement
    from ..methods import get_method
    from ..problem.case import load_case
    from ..solvers.multigrid import Multilevel

    case, method = load_case(case_name), get_method(method_name)
    multilevel, carry = None, None
    for step in UniformRefinement(case).levels(level + 1):
        multilevel = Multilevel(step.mesh, case.physics) if multilevel is None else multilevel.refined(step.mesh)
        if step.index == level - 1:
            carry = method.solve(case, discretise(case, step.mesh, method.order), None, multilevel).carry
    qp = friction_qp(case, discretise(case, step.mesh, method.order), method.cone)
    start = None if carry is None else nested_start(multilevel, carry.p1, qp.problem, qp.edges)
    return qp, friction_prediction(carry, qp.points), multilevel, start


def linear_friction_seconds(qp, multilevel, start=None) -> tuple[float, object]:
    """(seconds, the MultigridSystem) of one solve of ``qp``'s matrix without friction rows (the
    friction dofs free, load b: the Dirichlet/Neumann problem) by the friction solver's
    multigrid CG, from ``start``, as deep as its linear solves go (fastest of repeats)."""
    from ..solvers.bound_constraints import MultigridSystem
    from ..solvers.friction import FrictionBounds
    system = MultigridSystem(qp.K_ngs, qp.b, multilevel, qp.edges)
    rows = qp.c > 0
    load_scale = FrictionBounds(qp.K, qp.b, qp.free, qp.F[rows], qp.c[rows], qp.lift, system).load_scale
    return linear_seconds(system, qp, load_scale, start)


def _cone_row(method_name: str, level: int, connection) -> None:
    """A cone's Tresca solve of ``level`` (nested) against the linear solves of its matrix."""
    import ngsolve as ngs

    from ..solvers.friction import solve_friction_qp
    ngs.ngsglobals.msg_level = 0
    with ngs.TaskManager():
        qp, predicted, multilevel, start = friction_problem(method_name, level)
        t_linear, linear = linear_friction_seconds(qp, multilevel)
        linear_iterations = linear.cg_iterations
        t_nested, nested = linear_friction_seconds(qp, multilevel, start)
        t, solution = fastest(lambda: own_seconds(solve_friction_qp(qp, predicted, multilevel=multilevel, start=start)))
    connection.send(_row(method_name, qp.problem.ndof, t, solution.iterations, solution.work["cg_iterations"],
                         solution.kkt.residual, t_linear, linear_iterations, t_nested, nested.cg_iterations))
    connection.close()


def _law_row(method_name: str, level: int, connection, case_name: str = FRICTION_CASE) -> None:
    """A contact law's friction solve of ``level`` on ``case_name`` (its own ``solve``, nested
    from its coarser level) against the linear multigrid solve of the Dirichlet/Neumann problem of
    its space (NGSolve's matrix A, no Gamma_C term), from zero and from the law's nested start."""
    import ngsolve as ngs

    from ..fem.assembly import discretise
    from ..fem.nested import start_from
    from ..fem.p1_embedding import ContactEdges
    from ..mesh.levels import UniformRefinement
    from ..methods import get_method
    from ..problem.case import load_case
    from ..solvers.bound_constraints import DEFAULT_TOLERANCE, MultigridSystem
    from ..solvers.multigrid import Multilevel
    from .common import timed

    ngs.ngsglobals.msg_level = 0
    case, method = load_case(case_name), get_method(method_name)
    multilevel, carry = None, None
    with ngs.TaskManager():
        for step in UniformRefinement(case).levels(level + 1):
            multilevel = Multilevel(step.mesh, case.physics) if multilevel is None else multilevel.refined(step.mesh)
            # the study's chain: every coarser level nested from the one before (a Coulomb law's
            # Newton method from zero on a fine level may end on a poor branch set, whose
            # prediction then costs the timed level dozens of damped steps)
            if step.index < level:
                carry = method.solve(case, discretise(case, step.mesh, method.order), carry, multilevel).carry
        problem = discretise(case, step.mesh, method.order)
        system = MultigridSystem(problem.A_ngs, problem.b, multilevel, ContactEdges.of(problem, model=False))
        scale = np.abs((problem.b - problem.A @ problem.lift)[problem.free]).max()
        start = start_from(carry, multilevel, problem, model=False)
        linear = []
        for s in (None, start):
            def solve(s=s):
                system.cg_iterations = 0
                return timed(system.solve, ~problem.free, problem.lift, s, tol=0.1 * DEFAULT_TOLERANCE * scale)
            linear += [fastest(solve)[0], system.cg_iterations]
        t, level_solve = fastest(lambda: timed(method.solve, case, problem, carry, multilevel))
    fields = level_solve.fields
    connection.send(_row(method_name, problem.ndof, t, fields["solver_iterations"], fields["linear_iterations"],
                         fields["kkt_residual"], *linear, case_name=case_name))
    connection.close()


def _row(method_name, ndof, t, iterations, cg_iterations, kkt, t_linear, linear_iterations, t_nested, nested_iterations,
         case_name: str = FRICTION_CASE):
    return {"case": case_name, "method": method_name, "ndof": ndof, "t_contact": t, "t_linear": t_linear,
            "ratio_linear": t / t_linear, "iterations": iterations, "cg_iterations": cg_iterations,
            "linear_cg_iterations": linear_iterations, "kkt_residual": kkt,
            "peak_rss_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024,
            **fair_columns(t, cg_iterations, t_linear, linear_iterations, t_nested, nested_iterations)}


def friction_law_methods() -> tuple:
    """The swept P2 contact laws (``methods.method.SWEPT``: Nitsche) that declare "tresca" at run
    time, each timed by ``_law_row``, its own ``solve`` from its coarser level."""
    from ..methods import SWEPT, ContactLawMethod, with_role
    return tuple(m.name for m in with_role(SWEPT) if isinstance(m, ContactLawMethod) and m.order == 2
                 and "tresca" in m.friction)


def nitsche_laws(names) -> list[str]:
    """Those of ``names`` whose contact law is Nitsche's (``fem.contact_laws.builtin.Nitsche``): the
    goal LAW_GOAL is theirs; the penalty is shown beside them."""
    from ..fem.contact_laws.builtin import Nitsche
    from ..methods import METHODS
    return [name for name in names if isinstance(getattr(METHODS[name], "law", None), Nitsche)]


def run_friction_bench(level: int = FRICTION_LEVEL, cones=None, progress=print) -> pd.DataFrame:
    """Each cone's row, then each law's of ``friction_law_methods``, each in a fresh process."""
    cones = cone_methods() if cones is None else cones
    frames = [fresh_rows(_cone_row, "friction", "multigrid CG", (level,), cones, progress, FRICTION_COLUMNS)]
    laws = friction_law_methods()
    if laws:
        frames.append(fresh_rows(_law_row, "friction", "multigrid CG", (level,), laws, progress, FRICTION_COLUMNS))
    return pd.concat(frames, ignore_index=True)


def friction_goals(frame: pd.DataFrame) -> list[tuple[str, bool, str]]:
    """The goals (issue 74): the P2 nodal-type Tresca solve within NODAL_GOAL linear multigrid
    solves from the same nested start, a law's within LAW_GOAL; every row exact (KKT <= 1e-10)."""
    def ratios(rows):
        return ", ".join(f"{r.method} {r.ratio_nested:.2f} ({int(r.iterations)} sets, {int(r.contact_vcycles)} V-cycles "
                         f"against {int(r.nested_iterations)}) at {r.ndof:.2g} dofs" for r in rows.itertuples())
    nodal = frame[frame.method.isin(nodal_type(frame.method))]
    laws = frame[frame.method.isin(nitsche_laws(frame.method))]
    goals = [(f"friction P2 nodal Tresca solve <= {NODAL_GOAL:g}x one linear multigrid solve from the same start",
              bool(len(nodal)) and bool((nodal.ratio_nested <= NODAL_GOAL).all()), ratios(nodal)),
             ("friction other cones (shown)", True, ratios(frame[~frame.method.isin([*nodal.method, *laws.method])]))]
    if len(laws):
        goals.append((f"friction Nitsche-Tresca <= {LAW_GOAL:g}x one linear multigrid solve",
                      bool((laws.ratio_nested <= LAW_GOAL).all()), ratios(laws)))
    return goals + [("friction KKT residual <= 1e-10 in every row", bool((frame.kkt_residual <= 1e-10).all()),
                     f"max {frame.kkt_residual.max():.1e}")]
