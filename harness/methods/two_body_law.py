"""A contact law between two bodies on non-matching meshes: the one-body law's master-slave
form on the jumps (``fem.contact_laws.two_body``), solved by the same semismooth Newton method
on the joint system of both bodies, load step by load step, to a relative residual <= 1e-10.
The Nitsche family's `mortar-nitsche` (P2) and `mortar-nitsche-p1` are such methods
(``methods.nitsche``); the frictionless law, Tresca's and Coulomb's, in 2D, scalar and elastic.

The linear solves, as on one body (``solvers.newton``): on uniform pairs, which have a joint
hierarchy, CG (GMRES for Coulomb's nonsymmetric Jacobian) preconditioned by a V-cycle whose
finest level is the joint Jacobian, the law's terms across Gamma_C included, and whose coarse
levels are each body's own (``solvers.two_body_multigrid.law_levels``); on graded and adaptive
pairs a sparse factorisation of the joint Jacobian, updated step by step. Each load step starts
from the coarser level's same step: its u_h prolongated body by body (a hierarchy's), the
branches of its nearest points.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..fem.contact_laws.friction_laws import law_for
from ..fem.contact_laws.two_body import joint_load_step, two_body_system
from ..fem.nested import nearest_status
from ..solvers.load_steps import previous_state, solve_history
from ..solvers.two_body_multigrid import p1_injected
from .method import LawCarry, LevelSolve, SolveFields, timer
from .mortar import joint_p1_values, max_penetration
from .protocol import ContactLawMethod


@dataclass(frozen=True)
class TwoBodyLaw(ContactLawMethod):
    """A ``ContactLawMethod`` between two bodies (its law, parameters and friction as on one
    body; the module's note)."""

    bodies: tuple = (2,)
    dimensions: tuple = (2,)

    def system(self, case, problem, take_stiffness: bool = False):
        """The law's system on the pair (``fem.contact_laws.two_body``); on a frictional case
        its friction law's (``fem.contact_laws.friction_laws.law_for``)."""
        law = law_for(self.calibrated_law, case.friction) if case.frictional else self.calibrated_law
        return two_body_system(case, problem, law)

    def refusal(self, case) -> str | None:
        """Also: Coulomb in elasticity only (its law needs the normal and the slip channels)."""
        if case.friction.name == "coulomb" and not case.physics.rotated_frame and case.friction.name in self.friction:
            return "Coulomb's law needs elasticity's normal and slip channels"
        return super().refusal(case)

    def solve(self, case, problem, carry, multilevel, take_stiffness: bool = False, phases=None) -> LevelSolve:
        timed = timer(phases)
        with timed("setup"):
            system = self.system(case, problem)
        with timed("solve"):
            history = solve_history(case, system, lambda k, steps: _step_guess(system, carry, multilevel, k, steps),
                                    multilevel, self.solver, at_step=joint_load_step)
            solution = history.combined()
        u = solution.u
        pressure = system.quadrature.edge_means(system.pressure(u))
        fields = SolveFields(max_penetration(case, problem, u), float(pressure.min()), solution.residual,
                             solution.status, solution.iterations, solution.linear_iterations,
                             active_constraints=int(np.count_nonzero(solution.active)), backward_error=solution.backward,
                             solve_seconds=solution.seconds, load_steps=len(history.steps))
        points = system.quadrature.points
        earlier = tuple(LawCarry(joint_p1_values(problem, s.u), points=points, active=s.active) for s in history.steps[:-1])
        return LevelSolve(fields, u, None, pressure,
                          LawCarry(joint_p1_values(problem, u), points=points, active=solution.active, steps=earlier),
                          previous=history.steps[-2].u if len(history.steps) > 1 else None)


def _step_guess(system, carry, multilevel, step: int, steps: list):
    """(start, predicted branch) of load step ``step``: from the coarser level's same step (its
    u_h prolongated body by body where the pair has a hierarchy, the branch of its nearest
    points), else the previous step's state (``methods.protocol.step_guess``, for two bodies)."""
    same = None
    if carry is not None:
        same = carry if step == len(carry.steps) else carry.steps[step] if step < len(carry.steps) else None
    if same is None:
        return previous_state(steps)
    pair = system.problem.pair
    start = None if multilevel is None else p1_injected(pair, multilevel.prolongated(same.p1))
    return start, nearest_status(same.points, same.active, system.quadrature.points)
