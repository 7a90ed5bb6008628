"""A cone's level on a Coulomb case (2D elasticity, one body): its Signorini rows and the Tresca
rows of its friction analogue with the threshold from its own multiplier
(``fem.coulomb_cones``), solved by the fixed point over unilateral Tresca problems
(``solvers.coulomb_cones``) at every step of the case's load history, nested from the coarser
level's same step. The row's fields are the frictionless cone's (pressure from the contact
multipliers, penetration of u_h's trace) with ``solver_iterations`` the fixed point's
iterations (unilateral Tresca problems solved, over all steps) and ``kkt_residual`` the worst
step's: its last Tresca problem's KKT residual or the last relative change of the weights,
whichever is larger.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..fem.assembly import at_load_step
from ..fem.cones import contact_pressure
from ..fem.coulomb_cones import coulomb_cone_qp
from ..fem.nested import cone_prediction, friction_prediction, nested_start, p1_values
from ..fem.penetration import max_penetration
from ..solvers.bound_constraints import FactorisedSystem, MultigridSystem
from ..solvers.coulomb_cones import solve_coulomb_history
from .method import ConeCarry, LevelSolve, SolveFields, timer


@dataclass(frozen=True)
class CoulombConeCarry(ConeCarry):
    """A cone's carry on a Coulomb case: the trace with the contact rows' status (``trace``), the
    friction rows' nodes and (slip+, slip-) flags (``points``, ``active``:
    ``fem.nested.friction_prediction`` reads them) and the carries of the steps before the last."""

    points: np.ndarray | None = None
    active: np.ndarray | None = None
    steps: tuple = ()


def solve_coulomb_cone(case, problem, model, carry, multilevel, phases, options) -> LevelSolve:
    """A level of ``case`` (``problem.friction.Coulomb``) on the cone ``model``."""
    timed = timer(phases)
    with timed("setup"):
        qp = coulomb_cone_qp(case, problem, model)
        steps = [qp.at_step(at_load_step(case, problem, k)) for k in range(len(case.history))]
    if multilevel is not None and multilevel.ndof != problem.mesh.nv * problem.physics.components:
        raise ValueError("the multilevel hierarchy does not end at this problem's mesh (refined() missed?)")

    def system(b):
        if multilevel is None:
            return FactorisedSystem(qp.K, qp.K_ngs, b, options.refactor_above)
        return MultigridSystem(qp.K_ngs, b, multilevel, qp.edges, options=options)

    with timed("solve"):
        history = solve_coulomb_history(qp, steps, case.friction.coefficient, system,
                                        lambda k, solved: _guess(qp, problem, carry, multilevel, k, solved), options)
    carries = [_carry(qp, problem, step) for step in history]
    final, m = history[-1].solution, len(qp.C)
    u, trace_u = qp.to_u(final.z), carries[-1].trace
    pressure = contact_pressure(problem, final.multipliers[:m])
    failed = [step.status for step in history if step.status != "converged"]
    work = [step.work.get("cg_iterations", step.work.get("factorizations", 0)) for step in history]
    fields = SolveFields(max_penetration(case, problem.mesh, trace_u), float(pressure.min()),
                         max(max(step.solution.kkt.residual, step.change) for step in history),
                         failed[0] if failed else "converged", sum(step.iterations for step in history), int(sum(work)),
                         active_constraints=int(final.active[:m].sum()), n_contact_constraints=m + 2 * len(qp.F),
                         backward_error=max(step.solution.kkt.backward for step in history),
                         solve_seconds=sum(step.seconds for step in history), load_steps=len(history))
    previous = qp.to_u(history[-2].solution.z) if len(history) > 1 else None
    last = carries[-1]
    return LevelSolve(fields, u, trace_u, pressure,
                      CoulombConeCarry(last.p1, trace=last.trace, points=last.points, active=last.active,
                                       steps=tuple(carries[:-1])), previous=previous)


def _carry(qp, problem, step) -> CoulombConeCarry:
    solution, m = step.solution, len(qp.C)
    u = qp.to_u(solution.z)
    return CoulombConeCarry(p1_values(problem, u), trace=qp.trace_function(u, solution.active[:m]), points=qp.points,
                            active=solution.active[m:])


def _guess(qp, problem, carry, multilevel, k: int, solved: list):
    """(predicted rows, start) of load step ``k``: from the coarser level's same step (its
    contact status by ``cone_prediction``, its slip branches by ``friction_prediction``, its
    u_h interpolated), else from the step before on this level, else none."""
    coarse = None
    if carry is not None:
        coarse = carry if k == len(carry.steps) else carry.steps[k] if k < len(carry.steps) else None
    if coarse is not None:
        predicted = np.concatenate([cone_prediction(coarse.trace, problem), friction_prediction(coarse, qp.points)])
        start = None if multilevel is None else nested_start(multilevel, coarse.p1, problem, qp.edges)
        return predicted, start
    if solved:
        return solved[-1].solution.active, solved[-1].solution.z
    return None, None
