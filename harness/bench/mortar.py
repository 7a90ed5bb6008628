"""The two-body rows of `bench`: a mortar method's contact solve on two non-matching meshes, as
the study makes it (the coupling on the intersection of the trace meshes, the dual change of
variables, the active set on the two bodies' coupled multigrid, ``solvers.two_body_multigrid``,
nested iteration from the coarser level), against one linear solve of the same matrix by the
same multigrid CG from the same start; beside it the same contact solve on sparse Cholesky and
one linear solve of both bodies without contact by Cholesky (each body's matrix factorised and
solved once)."""
from __future__ import annotations

import dataclasses
import resource

import numpy as np
import pandas as pd

from .common import fresh_rows, timed

MORTAR_CASE = "two-body-transition-r32"
# levels of the two-body hierarchy: 1.3e5, 5.1e5, 2.0e6 and 8.1e6 dofs (both bodies)
MORTAR_LEVELS = (4, 5, 6, 7)


def mortar_methods() -> tuple:
    """The registered two-body methods with dual multipliers (bounds after the dual change of
    variables: ``methods.mortar.Mortar``), in registry order."""
    from ..methods import METHODS
    return tuple(m.name for m in METHODS.values() if 2 in m.bodies and getattr(m, "multipliers", None) == "dual")


MORTAR_COLUMNS = ["case", "method", "ndof", "t_contact", "t_contact_first", "t_setup", "t_linear", "ratio_linear", "iterations", "cg_iterations",
                  "linear_cg_iterations", "kkt_residual", "t_contact_cholesky", "t_linear_cholesky", "ratio_cholesky",
                  "kkt_residual_cholesky", "peak_rss_mb"]
MORTAR_GOAL = 1.5       # the contact solve / one linear solve of the same matrix by the same multigrid CG
# the Cholesky columns up to this size: past it the factorisation's fill nears the memory of the
# machines this runs on
CHOLESKY_UP_TO = 3_000_000


def _pair(case, bodies, steps, order):
    from ..fem.assembly import discretise
    from ..fem.two_body import TwoBodyProblem
    return TwoBodyProblem(*(discretise(body, step.mesh, order) for body, step in zip(bodies, steps)))


def _measure_mortar(method_name: str, level: int, connection):
    import ngsolve as ngs

    from ..mesh.levels import UniformRefinement
    from ..methods import get_method
    from ..problem.bodies import lower_body
    from ..problem.case import registered_cases
    from ..solvers.multigrid import Multilevel
    from ..solvers.two_body_multigrid import JointMultilevel

    ngs.ngsglobals.msg_level = 0
    method = get_method(method_name)
    case = registered_cases()[MORTAR_CASE]
    bodies = (case, lower_body(case))
    level += method.extra_levels          # P1 to about P2's dofs
    walks = [UniformRefinement(body).levels(level + 1) for body in bodies]
    carry, multilevel = None, None
    for current in range(level + 1):
        steps = [next(walk) for walk in walks]
        meshes = [step.mesh for step in steps]
        multilevel = JointMultilevel(*(Multilevel(mesh, case.physics) for mesh in meshes)) if multilevel is None \
            else multilevel.refined(meshes)
        if current < level - 1:
            continue
        with ngs.TaskManager():
            problem = _pair(case, bodies, steps, method.order)
            if current == level - 1:            # the coarser level: what nested iteration carries
                carry = method.solve(case, problem, None, multilevel).carry
                continue
            row = _mortar_row(case, method, problem, carry, multilevel)
    connection.send({"case": MORTAR_CASE, "method": method_name, "ndof": problem.ndof, **row,
                     "peak_rss_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024})
    connection.close()


def _linear_multigrid(problem, carry, multilevel) -> tuple[float, int]:
    """(seconds, CG iterations) of one linear solve of both bodies without contact, each by its
    own truncated multigrid CG (``Multilevel``, pins: Gamma_u) from the contact solve's start
    (the coarser level's u_h prolongated): what the two bodies cost apart."""
    from ..fem.nested import nested_start
    from ..fem.p1_embedding import ContactEdges
    from ..solvers.bound_constraints import ActiveSetSolver, MultigridSystem
    from .common import linear_seconds
    seconds, iterations, offset = 0.0, 0, 0
    for body, hierarchy in zip(problem.bodies, multilevel.bodies):
        edges = ContactEdges.of(body, model=False)
        n = hierarchy.matrices[-2].height
        start = nested_start(hierarchy, carry.p1[offset: offset + n], body, edges)
        offset += n
        system = MultigridSystem(body.A_ngs, body.b, hierarchy, edges)
        qp = _BodyQP(body)
        load_scale = ActiveSetSolver(body.A, body.b, body.free, qp.C, qp.alpha, lift=body.lift, system=system).load_scale
        t, system = linear_seconds(system, qp, load_scale, start)
        seconds, iterations = seconds + t, iterations + system.cg_iterations
    return seconds, iterations


class _BodyQP:
    """One body's problem as ``common.linear_seconds`` reads a QP (no contact constraints)."""

    def __init__(self, body):
        self.free, self.lift = body.free, body.lift
        self.C, self.alpha = np.zeros(0, np.int64), np.zeros(0)


def _mortar_row(case, method, problem, carry, multilevel) -> dict:
    """The level's contact solve on the multigrid and on Cholesky, and the linear solves of both
    bodies without contact by multigrid and by Cholesky."""
    from ..solvers.bound_constraints import Cholesky

    # the multigrid at every size (the study takes it from ``mortar_multigrid_from`` dofs)
    on_multigrid = dataclasses.replace(method, solver=dataclasses.replace(method.solver, mortar_multigrid_from=0))
    # Twice, the faster kept, as the linear solves (``common.fastest``): the first run of a fresh
    # process grows its memory by the set-up's and the solver's, and on these machines memory
    # first touched costs about 1.7 ms per MB; the linear solves after it find that memory
    # touched. Measured at 8.1e6 dofs: first runs 1.2-2.2 s slower than second runs of the same
    # solve (``t_contact_first``, shown).
    runs = [timed(on_multigrid.solve, case, problem, carry, multilevel) for _ in range(2)]
    t_contact, solve = min(runs, key=lambda run: run[0])
    t_linear, linear_iterations = _linear_multigrid(problem, carry, multilevel)
    fields = solve.fields
    row = {"t_contact": t_contact, "t_contact_first": runs[0][0], "t_setup": t_contact - fields["solve_seconds"], "t_linear": t_linear,
           "ratio_linear": t_contact / t_linear, "iterations": fields["solver_iterations"],
           "cg_iterations": fields["linear_iterations"], "linear_cg_iterations": linear_iterations,
           "kkt_residual": fields["kkt_residual"]}
    # the Cholesky columns: what the study ran below ``solvers.options.SolverOptions.mortar_multigrid_from``, up to
    # the size that fits in memory
    if problem.ndof >= CHOLESKY_UP_TO:
        return row | dict.fromkeys(["t_contact_cholesky", "t_linear_cholesky", "ratio_cholesky", "kkt_residual_cholesky"],
                                   float("nan"))
    t_cholesky, factorised = timed(method.solve, case, problem, carry, None)     # no hierarchy: Cholesky

    def linear_cholesky():
        for body in problem.bodies:
            rhs = np.where(body.free, body.b - body.A @ body.lift, 0.0)
            Cholesky(body.A_ngs, body.free).solve(rhs)
    t_linear_cholesky, _ = timed(linear_cholesky)
    return row | {"t_contact_cholesky": t_cholesky, "t_linear_cholesky": t_linear_cholesky,
                  "ratio_cholesky": t_cholesky / t_linear_cholesky, "kkt_residual_cholesky": factorised.fields["kkt_residual"]}


def run_mortar_bench(levels=MORTAR_LEVELS, methods=None, progress=print) -> pd.DataFrame:
    """Each (method, level) in its own fresh process, like ``run_bench`` (default:
    ``mortar_methods()``)."""
    return fresh_rows(_measure_mortar, "two bodies", "multigrid", levels, methods or mortar_methods(), progress, MORTAR_COLUMNS)


def mortar_goals(frame: pd.DataFrame) -> list[tuple[str, bool, str]]:
    """At the largest size: the contact solve on the multigrid against one linear solve of the
    same matrix by the same multigrid CG (goal 1.5), and the Cholesky path's ratio (shown); the
    KKT residual of both judged at every size."""
    largest = frame[frame.ndof == frame.ndof.max()]
    return [
        (f"two bodies: mortar contact solve <= {MORTAR_GOAL}x one linear multigrid solve at the largest size",
         bool((largest.ratio_linear <= MORTAR_GOAL).all()),
         ", ".join(f"{m} {r:.2f} at {n:.2g} dofs" for m, r, n in zip(largest.method, largest.ratio_linear, largest.ndof))),
        ("two bodies: on Cholesky, contact solve / one linear solve of both bodies, largest size it runs (shown)", True,
         ", ".join(f"{m} {r:.2f} at {n:.2g} dofs" for m, r, n in
                   frame.dropna(subset=["ratio_cholesky"]).groupby("method", sort=False).last()
                   .reset_index()[["method", "ratio_cholesky", "ndof"]].itertuples(index=False))),
        ("two bodies: KKT residual <= 1e-10 at every size, multigrid and Cholesky",
         bool((frame.kkt_residual <= 1e-10).all() and (frame.kkt_residual_cholesky.dropna() <= 1e-10).all()),
         f"max {max(frame.kkt_residual.max(), frame.kkt_residual_cholesky.max()):.1e}"),
    ]
