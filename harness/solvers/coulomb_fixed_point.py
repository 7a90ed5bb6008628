"""Coulomb friction by a fixed point over Tresca problems: the independent cross-check of the
coupled semismooth Newton method (``newton`` on a Coulomb law's system,
``fem.contact_laws.coulomb``).

Each iterate solves unilateral contact with Tresca friction whose threshold is frozen at the
points of Gamma_C, s_k = mu_F p_n(u_{k-1}) (p_n the law's pressure [x_n]_+, the same formula
the coupled law puts into its threshold), and the iteration stops when the threshold no longer
moves: s_{k+1} = s_k to ``tolerance`` relative. Its limit solves the coupled law exactly (a
fixed point of s -> mu_F p_n(u(s)) is the Coulomb law (*) of ``fem.contact_laws.coulomb``), so
it reaches the discrete solution the Newton method finds by another road: the Coulomb
coupling is never linearised, and every Tresca problem with theta = 1 has a symmetric Jacobian
(multigrid CG, not GMRES). Where the two disagree, the discrete problem has two solutions (or
one method failed): the mu_F axis of the report says which. The idea is the classical one
(K. Kunisch & G. Stadler, M2AN 39 (2005) 827-854, "fixed point ideas", read from its abstract;
H. B. Khenous, J. Pommier & Y. Renard, Appl. Numer. Math. 56 (2006) 163-192 compare such fixed
points with Newton, abstract read); it contracts for small mu_F only, and may not converge for
large mu_F: its status says so.
"""
from __future__ import annotations

import time
from dataclasses import dataclass, replace

import numpy as np

from ..fem.contact_laws.channels import check_friction_law
from .newton import load_scale, solve_semismooth_newton
from .options import SolverOptions

# Newton steps allowed to each Tresca problem (the coupled method's default is 60)
INNER_STEPS = 400


@dataclass
class FixedPointSolution:
    u: np.ndarray
    iterations: int             # Tresca problems solved
    newton_steps: int           # their Newton steps, in all
    linear_iterations: int      # their CG (or GMRES) iterations, in all
    change: float               # the last relative change of the threshold
    residual: float             # max |F(u)| / scale of the coupled Coulomb system
    seconds: float
    status: str


def solve_fixed_point(system, start: np.ndarray | None = None, multilevel=None, options: SolverOptions = SolverOptions(),
                      tolerance: float = 1e-10, iterations: int = 200) -> FixedPointSolution:
    """The Coulomb law's system ``system`` (``fem.contact_laws.channels.FrictionSystem`` with a
    ``coefficient``) solved by the fixed point over Tresca problems (the module's note), from
    ``start``; the system is left as it was."""
    clock = time.perf_counter()
    mu, flags = system.coefficient, (system.symmetric, system.affine, system.nonsymmetric_krylov)
    if mu is None:
        raise ValueError("the fixed point over Tresca problems solves a Coulomb law's system (one with a coefficient)")
    u, steps, linear, change, status = start, 0, 0, np.inf, f"not converged in {iterations} Tresca problems"
    # the first Tresca problems start far from their solutions (the first is frictionless, its
    # slips may point the other way): their damped Newton runs are long, not stalled
    options = replace(options, newton_iterations=max(options.newton_iterations, INNER_STEPS),
                      stall_steps=max(options.stall_steps, INNER_STEPS // 4))
    try:
        # the law checked with a positive threshold (with s = 0 the disc's slip branch is the
        # constant 0, affine; the thresholds to come are not zero), then the first problem's s = 0
        system.coefficient, system.threshold = None, np.ones_like(system.threshold)
        system.symmetric, system.affine = check_friction_law(system)
        system.threshold = np.zeros_like(system.threshold)
        for k in range(1, iterations + 1):
            solution = solve_semismooth_newton(system, u, multilevel, options=options)
            u, steps, linear = solution.u, steps + solution.iterations, linear + solution.linear_iterations
            if solution.status != "converged":
                status = f"Tresca problem {k}: {solution.status}"
                break
            threshold = mu * system.pressure(u)
            change = float(np.abs(threshold - system.threshold).max() / max(np.abs(threshold).max(), np.finfo(float).tiny))
            system.threshold = threshold
            if change <= tolerance:
                status = "converged"
                break
    finally:
        system.coefficient, system.threshold = mu, np.zeros_like(system.threshold)
        system.symmetric, system.affine, system.nonsymmetric_krylov = flags
    residual = float(np.abs(system.residual(u)).max(initial=0.0) / load_scale(system))
    return FixedPointSolution(u, k, steps, linear, change, residual, time.perf_counter() - clock, status)
