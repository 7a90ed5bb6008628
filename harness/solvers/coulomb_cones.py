"""Coulomb friction on the cones (``fem.coulomb_cones``): a fixed point over unilateral Tresca
problems (``unilateral_friction``), the threshold taken from the cone's own multiplier.

Iterate k solves the cone's Signorini rows with Tresca rows of the frozen weights c^k, then
c^{k+1} = mu_F lambda_n(z^k) (``fem.coulomb_cones.CoulombConeQP.thresholds``), until c stops
moving: max |c^{k+1} - c^k| <= ``tolerance`` max |c^{k+1}|. c^0 = 0 (the frictionless cone) on a
first load step, the previous step's weights after. A fixed point is the discrete Coulomb law
|lambda_t,i| <= mu_F lambda_n,i row by row. The same idea as ``coulomb_fixed_point`` for the
contact laws (Kunisch & Stadler, M2AN 39 (2005), read from its abstract); it contracts for
small mu_F only, and a history that does not converge within ``iterations`` says so in its
status (never "converged").

A load history (``problem.friction.LoadHistory``) is solved step by step, each step's slip
measured from the previous step's tangential variables (``load_steps``: the backward-Euler
increment).
"""
from __future__ import annotations

import time
from dataclasses import dataclass, field
from typing import Callable

import numpy as np

from .bound_constraints import QPSolution, row_norm
from .options import SolverOptions
from .unilateral_friction import solve_unilateral_friction

# Tresca problems allowed to one load step's fixed point
FIXED_POINT_ITERATIONS = 200


@dataclass
class CoulombStepSolution:
    """One load step: the last unilateral Tresca problem's ``solution`` (its multipliers
    (lambda_n, lambda_t)), the weights ``c`` it was solved with, the fixed point's iterations,
    active sets in all, last relative change of c and status."""

    solution: QPSolution
    c: np.ndarray
    iterations: int
    active_sets: int
    change: float
    seconds: float
    status: str
    work: dict = field(default_factory=dict)


def solve_coulomb_step(qp, b, lift, zprev, coefficient: float, system: Callable, c0=None, predicted=None, start=None,
                       options: SolverOptions = SolverOptions(), tolerance: float = 1e-10,
                       iterations: int = FIXED_POINT_ITERATIONS, K_norm: float | None = None) -> CoulombStepSolution:
    """The fixed point on ``qp`` (a ``fem.coulomb_cones.CoulombConeQP``) with the load ``b`` and
    lift of one step, slip reference ``zprev``; ``system(b)`` makes the step's linear system
    (its pins hold one value per dof through the step)."""
    clock = time.perf_counter()
    K_norm = row_norm(qp.K, qp.free) if K_norm is None else K_norm
    linear = system(b)
    c = np.zeros(len(qp.F)) if c0 is None else np.asarray(c0, float)
    sets, change, status = 0, np.inf, f"Coulomb fixed point: not converged in {iterations} Tresca problems"
    for k in range(1, iterations + 1):
        solution = solve_unilateral_friction(qp.K, b, qp.free, qp.C, qp.alpha, qp.F, c, zprev, lift, linear, options,
                                             predicted, start, K_norm)
        sets += solution.iterations
        if solution.status != "converged":
            status = f"Coulomb fixed point, Tresca problem {k}: {solution.status}"
            break
        following = qp.thresholds(coefficient, solution.multipliers[:len(qp.C)])
        change = float(np.abs(following - c).max(initial=0.0) / max(np.abs(following).max(initial=0.0), np.finfo(float).tiny))
        if change <= tolerance:
            status = "converged"
            break
        c, predicted, start = following, solution.active, solution.z
    if status != "converged" and not status.startswith("Coulomb fixed point, Tresca"):
        status += f" (last change of the weights {change:.1e})"
    return CoulombStepSolution(solution, c, k, sets, change, time.perf_counter() - clock, status, linear.work())


def solve_coulomb_history(qp, steps: list, coefficient: float, system: Callable, guess: Callable,
                          options: SolverOptions = SolverOptions(), K_norm: float | None = None) -> list:
    """Every load step in order: ``steps`` the (b, lift) of each, ``guess(k, previous)`` ->
    (predicted set, start) of step k from the steps solved so far. Step k > 0 measures its slip
    from step k - 1's tangential variables and starts its weights from step k - 1's. ``K_norm``:
    ||K||_inf over the free rows, if known (an operator K that is no scipy matrix)."""
    K_norm = row_norm(qp.K, qp.free) if K_norm is None else K_norm
    solved = []
    for k, (b, lift) in enumerate(steps):
        previous = solved[-1] if solved else None
        zprev = np.zeros(len(qp.F)) if previous is None else previous.solution.z[qp.F]
        c0 = None if previous is None else previous.c
        predicted, start = guess(k, solved)
        step = solve_coulomb_step(qp, b, lift, zprev, coefficient, system, c0, predicted, start, options, K_norm=K_norm)
        solved.append(step)
        if step.status != "converged":
            step.status = step.status if len(steps) == 1 else f"load step {k + 1}: {step.status}"
            break
    return solved
