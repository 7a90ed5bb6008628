"""The two-body rows of `bench` (issue 34): a mortar method's contact solve on two non-matching
meshes, as the study makes it (the coupling on the intersection of the trace meshes, the dual
change of variables, the active set on sparse Cholesky, nested iteration from the coarser level),
against one linear solve of the same two bodies without contact (each body's stiffness matrix
factorised by sparse Cholesky and solved once)."""
from __future__ import annotations

import resource

import numpy as np
import pandas as pd

from .common import fresh_rows, timed

MORTAR_CASE = "two-body-transition-r32"
# levels of the two-body hierarchy: 1.3e5, 5.1e5 and 2.0e6 dofs (both bodies)
MORTAR_LEVELS = (4, 5, 6)


def mortar_methods() -> tuple:
    """The registered two-body methods with dual multipliers (bounds after the dual change of
    variables: ``_mortar.Mortar``), in registry order."""
    from ..methods import METHODS
    return tuple(m.name for m in METHODS.values() if 2 in m.bodies and getattr(m, "multipliers", None) == "dual")


MORTAR_COLUMNS = ["case", "method", "ndof", "t_contact", "t_setup", "t_linear", "ratio_linear", "iterations", "factorizations",
                  "kkt_residual", "peak_rss_mb"]


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
    from ..solvers.active_set import Cholesky

    ngs.ngsglobals.msg_level = 0
    method = get_method(method_name)
    case = registered_cases()[MORTAR_CASE]
    bodies = (case, lower_body(case))
    level += method.extra_levels          # P1 to about P2's dofs
    walks = [UniformRefinement(body).levels(level + 1) for body in bodies]
    carry = None
    for current in range(level + 1):
        steps = [next(walk) for walk in walks]
        if current < level - 1:
            continue
        with ngs.TaskManager():
            problem = _pair(case, bodies, steps, method.order)
            if current == level - 1:            # the coarser level: what nested iteration carries
                carry = method.solve(case, problem, None, None).carry
                continue
            t_contact, solve = timed(method.solve, case, problem, carry, None)

            def linear():
                for body in problem.bodies:
                    rhs = np.where(body.free, body.b - body.A @ body.lift, 0.0)
                    Cholesky(body.A_ngs, body.free).solve(rhs)
            t_linear, _ = timed(linear)
    fields = solve.fields
    connection.send({
        "case": MORTAR_CASE, "method": method_name, "ndof": problem.ndof, "t_contact": t_contact,
        "t_setup": t_contact - fields["solve_seconds"], "t_linear": t_linear, "ratio_linear": t_contact / t_linear,
        "iterations": fields["solver_iterations"], "factorizations": fields["linear_iterations"],
        "kkt_residual": fields["kkt_residual"], "peak_rss_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024,
    })
    connection.close()


def run_mortar_bench(levels=MORTAR_LEVELS, methods=None, progress=print) -> pd.DataFrame:
    """Each (method, level) in its own fresh process, like ``run_bench`` (default:
    ``mortar_methods()``)."""
    return fresh_rows(_measure_mortar, "two bodies", "Cholesky", levels, methods or mortar_methods(), progress, MORTAR_COLUMNS)


def mortar_goals(frame: pd.DataFrame) -> list[tuple[str, bool, str]]:
    """Issue 34 states the ratio at >= 1e6 dofs (no bound set): shown; the KKT residual judged."""
    largest = frame[frame.ndof == frame.ndof.max()]
    return [
        ("two bodies: mortar contact solve / one linear solve of both bodies at the largest size (shown)", True,
         ", ".join(f"{m} {r:.2f} at {n:.2g} dofs" for m, r, n in zip(largest.method, largest.ratio_linear, largest.ndof))),
        ("two bodies: KKT residual <= 1e-10 at every size", bool((frame.kkt_residual <= 1e-10).all()),
         f"max {frame.kkt_residual.max():.1e}"),
    ]
