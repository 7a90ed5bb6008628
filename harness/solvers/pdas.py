"""The primal-dual active set iteration (Hintermueller, Ito & Kunisch, SIAM J. Optim. 13 (2002)),
once for every kind of inequality constraint: the bounds z_C >= alpha of the cones
(``bound_constraints``) and the general rows B z >= g (``general_constraints``).

The iteration -- guess the active set, solve the equality-constrained problem of the guess,
update the guess from the signs of the multipliers and the slacks -- is the same for both; what
differs is how a set's linear problem is solved, how its multipliers and KKT residual are
measured and what the slack of a constraint is. A ``ConstraintKind`` supplies those three and
``primal_dual_active_set`` does the rest: the stopping test on the KKT residual (never on a
repeated set alone), Murty's least-index rule once a set would repeat, and the loose solves of
new sets on iterative systems (the forcing term, ``loose_depth``).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Protocol

import numpy as np

from .options import SolverOptions


@dataclass(frozen=True)
class KKT:
    """Relative KKT residuals of a candidate solution (each dimensionless), and the normwise
    backward error of its stationarity."""

    primal: float           # max (alpha - z_C)^+ / max(|z_C|, |alpha|)
    dual: float             # max (-lambda)^+ on the active set / |b - K u_D|
    complementarity: float  # max |lambda_i (z_i - alpha_i)| / (|b - K u_D| max(|z_C|, |alpha|))
    stationarity: float     # max |K z - b| on free dofs off the active set / |b - K u_D|
    backward: float = 0.0   # the three force parts (dual, complementarity, stationarity), unscaled,
                            # over ||K||_inf ||z||_inf + ||b||_inf: a normwise backward error

    @property
    def residual(self) -> float:
        return max(self.primal, self.dual, self.complementarity, self.stationarity)

    def converged(self, options: SolverOptions) -> bool:
        """``residual`` <= tol (``options.tolerance``); or, where tol times the load lies below
        what double precision resolves in K z - b, primal feasibility <= tol and the force parts
        at round-off.

        The relative stationarity has a floor: K z - b is computed with an error of about
        eps ||K|| ||z||, while the load |b| ~ h^d |f| shrinks under refinement, so the floor
        grows like eps cond(K) ~ eps h^-2, for a direct solve of the same active set as for a
        tighter CG; no polishing goes below it (tests/test_solver.py asks for less, and the solve
        ends converged at round-off). What double precision can certify is
        the normwise backward error (Rigal & Gaches 1967; Higham, Accuracy and Stability of
        Numerical Algorithms, 2002, Theorem 7.1): z solves the system of a K and b perturbed by
        that relative amount. The multipliers and the complementarity are forces of the same
        K z - b and share its floor. ``options.roundoff_backward_error`` = 1e-13, about 450 eps."""
        tol = options.tolerance
        return self.residual <= tol or (self.primal <= tol and self.backward <= options.roundoff_backward_error)


def resolved(slack: np.ndarray, bound: np.ndarray) -> np.ndarray:
    """``slack`` with each value within its ``bound`` of zero set to 0: a constraint value
    double precision cannot tell from 0. The bound is the rounding error of computing the value,
    gamma_{n+1} (|b|.|z| + |g|) for a row b of n nonzeros (Higham, Accuracy and Stability of
    Numerical Algorithms, 2002, Lemma 3.1 and (3.4)), plus what an error of eps ||z||_inf in
    each entry of z, the least any solve of K z = b leaves, moves it: eps ||z||_inf sum |b|.
    Without it, on a face where u = alpha = 0 (tests/data/quadratic_binding_3d.py) the constraint
    values are round-off read against a scale of the same size: a relative violation of 1, and
    ``mean`` would report "stalled" on a solution exact to round-off."""
    return np.where(np.abs(slack) <= bound, 0.0, slack)


def loose_depth(residual: float, full: float, forcing: float, gain: float) -> float:
    """The depth of the solve of a new set, from the current relative residual: ``forcing``
    times it, when that is at least ``gain`` times shallower than the full depth."""
    depth = forcing * residual
    return depth if depth >= gain * full else full


def next_active_set(active: np.ndarray, leave: np.ndarray, enter: np.ndarray, seen: set,
                    pivoting: bool) -> tuple[np.ndarray, bool]:
    """(the next active set, whether pivoting): the primal-dual update (the rows that ``leave``
    out, those that ``enter`` in), or, once a set would repeat (or already when ``pivoting``),
    Murty's least-index rule: flip only the first violated row."""
    candidate = (active & ~leave) | enter
    if pivoting or candidate.tobytes() in seen:
        first = int(np.flatnonzero(leave | enter)[0])
        candidate = active.copy()
        candidate[first] = not active[first]
        return candidate, True
    return candidate, False


class ConstraintKind(Protocol):
    """What the iteration needs of a kind of constraint (the bound and the general-constraint
    solvers are each one)."""

    system: object              # the linear solver of a set; ``iterative`` if its solves are as deep as asked
    lift: np.ndarray            # the pinned values, zero on the free dofs: the start of a cold start
    load_scale: float           # the scale of the forces: solve depths are relative to it

    def start_residual(self, z: np.ndarray, active: np.ndarray) -> float:
        """The relative residual of a start, which sets the depth of the first solve."""

    def solve_set(self, active: np.ndarray, start, tol: float) -> tuple[np.ndarray, np.ndarray, KKT]:
        """(z, multipliers, KKT residuals) of the equality-constrained problem of ``active``,
        solved from ``start`` to max |K z - b| <= tol (absolute) off the constraints."""

    def slack(self, z: np.ndarray) -> tuple[np.ndarray, float]:
        """The constraint values minus their bounds, and the scale of the constraint values."""


@dataclass
class Iterate:
    """Where the iteration stopped: the last set's solution and why it stopped."""

    z: np.ndarray
    multipliers: np.ndarray
    active: np.ndarray
    kkt: KKT
    iterations: int
    status: str                 # "converged" or why not


def primal_dual_active_set(kind: ConstraintKind, active: np.ndarray, start: np.ndarray | None,
                           options: SolverOptions, gain: float, max_iterations: int) -> Iterate:
    """The active set iteration on ``kind`` from the set ``active`` (a prediction, or none) and,
    for iterative systems, the ``start`` vector (nested iteration).

    It stops on the KKT residual (``KKT.converged``: <= tol, or feasible with the force parts at
    round-off), never on a repeated set alone: a degenerate complementarity (lambda_i = 0 =
    z_i - alpha_i) lets plain PDAS cycle among equivalent sets whose KKT residual is already at
    round-off (docs/mathematics.md §5). Linear solves go ``options.linear_depth`` of the KKT
    tolerance deep, so that the stationarity they leave never decides the KKT check. With an
    iterative system, a set that is new is solved only to ``options.forcing`` times the current
    KKT residual (the first to that of the start), when that is ``gain`` times shallower
    (``loose_depth``): an inexact semismooth Newton step (the forcing term of Dembo, Eisenstat &
    Steihaug, SIAM J. Numer. Anal. 19 (1982)). That solve only decides the next set; the set it
    leaves unchanged is solved again, from there, to the full depth, which decides convergence,
    and only sets judged on full-depth solves count as seen (for Murty's rule).

    A set is updated by the rows that violate it beyond the KKT tolerance, when there are any: a
    row within the tolerance is not why the KKT check failed, and flipping it churns degenerate
    rows (`mean`'s vertex constraints inside a contact zone: their basis functions have zero
    mean on every contact edge, so their multipliers and slacks are second differences of the
    pressure, O(h^2) and of either sign; ``bench --only adaptive`` counts the sets)."""
    seen: set[bytes] = set()
    pivoting = False
    iterative = getattr(kind.system, "iterative", False)
    full = options.linear_depth * options.tolerance
    initial = kind.lift if start is None else start
    depth = loose_depth(kind.start_residual(initial, active), full, options.forcing, gain) if iterative else full
    status = f"not converged in {max_iterations} iterations"
    z = start                   # each solve starts from the previous iterate
    for iteration in range(1, max_iterations + 1):
        z, lam, kkt = kind.solve_set(active, z, depth * kind.load_scale)
        if kkt.converged(options):
            status = "converged"
            break
        leave, enter = _violated(kind, z, lam, active, max(depth, options.tolerance))
        if not (leave.any() or enter.any()):
            leave, enter = _violated(kind, z, lam, active, depth)
        if not (leave.any() or enter.any()):
            if depth > full:
                depth = full        # the set of a loose solve: solve it to the full depth
                continue
            status = f"stalled: KKT residual {kkt.residual:.2e} with a consistent active set"
            break
        if depth <= full:
            seen.add(active.tobytes())      # sets judged on a full-depth solve only
        active, pivoting = next_active_set(active, leave, enter, seen, pivoting)
        depth = loose_depth(kkt.residual, full, options.forcing, gain) if iterative and not pivoting else full
    return Iterate(z, lam, active, kkt, iteration, status)


def _violated(kind: ConstraintKind, z: np.ndarray, lam: np.ndarray, active: np.ndarray,
              depth: float) -> tuple[np.ndarray, np.ndarray]:
    """(active rows whose multiplier is negative, inactive rows that are violated), each at a
    fraction of the solve's depth, so that neither round-off nor a loose solve's residual
    flips a row."""
    slack, scale_z = kind.slack(z)
    leave = active & (lam < -depth * kind.load_scale)
    enter = ~active & (slack < -depth * scale_z)
    return leave, enter
