"""A quasi-static load history (``problem.friction.LoadHistory``) solved step by step: each step
is the discrete problem of its data, solved by semismooth Newton to the same tolerance as a
static one (every step's residual <= 1e-10: a step is exact, not an increment of a linearised
path), and hands the next step its state -- the start of Newton and, for a friction law, the
slip reference: Coulomb's slip over a step is u_t - u_t(previous step) (the backward-Euler
discretisation of the rate problem, P. Wriggers, Computational Contact Mechanics, 2nd ed. 2006,
Sect. 5.2; L.-E. Andersson, Appl. Math. Optim. 42 (2000) for its existence, statement not read
here). A static case has one step: the problem itself.
"""
from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Callable

import numpy as np

from ..fem.assembly import at_load_step
from .newton import NewtonSolution, solve_semismooth_newton
from .options import SolverOptions


@dataclass
class HistorySolution:
    """The steps' Newton solutions, in order; the last is the case's final state."""

    steps: list

    @property
    def final(self) -> NewtonSolution:
        return self.steps[-1]

    def combined(self) -> NewtonSolution:
        """The final state with the history's worst residual and backward error, its total
        steps, linear iterations and seconds, and "converged" only if every step did (else the
        first failure, named by its step)."""
        failed = [(k, s) for k, s in enumerate(self.steps) if s.status != "converged"]
        status = "converged" if not failed else \
            (failed[0][1].status if len(self.steps) == 1 else f"load step {failed[0][0] + 1}: {failed[0][1].status}")
        return replace(self.final, residual=max(s.residual for s in self.steps), status=status,
                       iterations=sum(s.iterations for s in self.steps),
                       linear_iterations=sum(s.linear_iterations for s in self.steps),
                       seconds=sum(s.seconds for s in self.steps), backward=max(s.backward for s in self.steps))


def solve_history(case, system, guess: Callable, multilevel=None, options: SolverOptions = SolverOptions(),
                  at_step: Callable = at_load_step) -> HistorySolution:
    """Every step of ``case.history`` on ``system`` (a law's system set up on the final step's
    problem), in order. ``guess(k, previous)`` -> (start, predicted branch) of step k (nested
    iteration from the coarser level; ``previous`` the steps solved so far). ``at_step(case,
    problem, k)``: the problem of step k (two bodies: ``fem.contact_laws.two_body.joint_load_step``).
    The system is left at the last step, with the slip reference of the step before it."""
    final = system.problem
    steps = []
    for k in range(len(case.history)):
        system.at_step(at_step(case, final, k))
        if k and hasattr(system, "slip_state"):
            system.reference = system.slip_state(steps[-1].u)
        start, predicted = guess(k, steps)
        steps.append(solve_semismooth_newton(system, start, multilevel, predicted=predicted, options=options))
    return HistorySolution(steps)


def previous_state(steps: list) -> tuple[np.ndarray | None, np.ndarray | None]:
    """The last step's u and branch: the start of the next step where no finer guess exists."""
    return (steps[-1].u, steps[-1].active) if steps else (None, None)
