"""Exact solution of a cone's Signorini rows and Tresca rows together (unilateral contact with
given friction weights), the convex problem of each iterate of Coulomb friction on the cones
(``coulomb_cones``):

    minimise 1/2 z'Kz - b'z + sum_i c_i |z[F_i] - zprev_i|
    subject to z[C_j] >= alpha_j,   z = lift off ``free``,

K symmetric positive definite on the free dofs, c >= 0, C (the contact variable's rows) and F
(the tangential ones) disjoint. ``zprev`` is the slip reference: the tangential variables at the
end of the previous load step (the backward-Euler slip increment, ``solvers.load_steps``), 0 on a
static problem. Optimality, row by row: on C the Signorini conditions of ``bound_constraints``
(z_C >= alpha, lambda_n = (K z - b)_C >= 0, lambda_n (z_C - alpha) = 0); on F those of
``friction`` shifted by zprev (lambda_t = (b - K z)_F; stick: z_F = zprev, |lambda_t| <= c;
slip+: z_F >= zprev, lambda_t = c; slip-: z_F <= zprev, lambda_t = -c).

Both are sets of a primal-dual active set iteration (``pdas.primal_dual_active_set``), and each
set's problem is linear -- an active contact row pinned at alpha, a stick row pinned at zprev, a
slip row a Neumann row with +-c moved into the load -- solved by the cones' systems
(``bound_constraints.FactorisedSystem``, ``bound_constraints.MultigridSystem``). The rows in
``pdas``'s terms: (contact rows, slip+ rows, slip- rows); multipliers (lambda_n, the slips
z_F - zprev and zprev - z_F in force units); slacks (z_C - alpha over its scale, (c -+ lambda_t)
over the force scale), so that one scale (1) serves all rows.

A row of weight 0 (a separated node under Coulomb: no pressure; the vertices of the mean
analogue) carries no friction: its variable is free, not a row (``friction.solve_friction``).
"""
from __future__ import annotations

import time

import numpy as np

from .bound_constraints import QPSolution, row_norm
from .multigrid import max_abs
from .options import SolverOptions
from .pdas import KKT, primal_dual_active_set, resolved

_DEFAULT = SolverOptions()
_TINY = np.finfo(float).tiny


class UnilateralFriction:
    """The problem as a ``pdas.ConstraintKind`` (``active``: contact rows, slip+ rows, slip-
    rows). ``K_norm``: ||K||_inf over the free rows, if known (it depends on K alone)."""

    def __init__(self, K, b, free, C, alpha, F, c, zprev, lift, system, options: SolverOptions = _DEFAULT,
                 K_norm: float | None = None):
        self.K, self.b = K, np.asarray(b, float)
        self.free = np.asarray(free, bool)
        self.C, self.alpha = np.asarray(C, np.int64), np.asarray(alpha, float)
        self.F, self.c, self.zprev = np.asarray(F, np.int64), np.asarray(c, float), np.asarray(zprev, float)
        if (self.c < 0).any():
            raise ValueError("the friction weights must be >= 0")
        if not (self.free[self.C].all() and self.free[self.F].all()):
            raise ValueError("a contact or friction variable lies on the Dirichlet boundary")
        if np.intersect1d(self.C, self.F).size:
            raise ValueError("a variable is both a contact and a friction row")
        self.lift = np.where(self.free, 0.0, lift)
        self.system, self.options = system, options
        self._pinned_rows = np.flatnonzero(~self.free)
        # the force scale: the loads, the forces holding the rows at the obstacle and at zprev, c
        pins = np.zeros(len(self.b))
        pins[self.C], pins[self.F] = self.alpha, self.zprev
        held = max_abs(self._gradient(pins, with_load=False)) if pins.any() else 0.0
        self.load_scale = max(max_abs(self._gradient(self.lift)), held, float(self.c.max(initial=0.0)), _TINY)
        self.K_norm = row_norm(self.K, self.free) if K_norm is None else K_norm
        self.b_norm = float(np.abs(self.b[self.free]).max(initial=0.0))

    def _gradient(self, z: np.ndarray, with_load: bool = True) -> np.ndarray:
        g = self.K @ z
        if with_load:
            g -= self.b
        g[self._pinned_rows] = 0.0
        return g

    def _rows(self, active: np.ndarray):
        """(contact active, slip+, slip-, stick)."""
        m, k = len(self.C), len(self.F)
        contact, plus, minus = active[:m], active[m:m + k], active[m + k:]
        return contact, plus, minus, ~(plus | minus)

    def _contact_slack(self, z: np.ndarray, z_max: float) -> tuple[np.ndarray, float]:
        """z_C - alpha, round-off set to 0 (``pdas.resolved``), and its scale max(|z_C|, |alpha|)."""
        eps, zC = np.finfo(float).eps, z[self.C]
        bound = 2 * eps * (np.abs(zC) + np.abs(self.alpha)) + eps * z_max
        scale = max(np.abs(zC).max(initial=0.0), np.abs(self.alpha).max(initial=0.0), _TINY)
        return resolved(zC - self.alpha, bound), scale

    def kkt(self, z: np.ndarray, active: np.ndarray) -> tuple[KKT, np.ndarray]:
        """The relative KKT residuals of ``z`` under ``active`` and the rows' multipliers
        (lambda_n; the slips in force units)."""
        contact, plus, minus, stick = self._rows(active)
        g = self._gradient(z)
        lam_n, lam_t = g[self.C].copy(), -g[self.F]
        z_max = max_abs(z)
        slack, scale_c = self._contact_slack(z, z_max)
        slip, slip_scale = z[self.F] - self.zprev, max(z_max, _TINY)
        g[self.C[contact]] = 0.0
        g[self.F[plus]] += self.c[plus]
        g[self.F[minus]] -= self.c[minus]
        g[self.F[stick]] = 0.0
        stationary = max_abs(g)
        negative = max(0.0, -lam_n[contact].min(initial=0.0))
        beyond = float(np.maximum(np.abs(lam_t[stick]) - self.c[stick], 0.0).max(initial=0.0))
        complementarity = float(np.abs(lam_n * slack).max(initial=0.0))
        wrong_sign = float(max(np.maximum(-slip[plus], 0.0).max(initial=0.0), np.maximum(slip[minus], 0.0).max(initial=0.0)))
        kkt = KKT(primal=max(float(max(0.0, -slack.min(initial=0.0))) / scale_c, wrong_sign / slip_scale),
                  dual=max(negative, beyond) / self.load_scale,
                  complementarity=complementarity / (self.load_scale * scale_c),
                  stationarity=stationary / self.load_scale,
                  backward=max(stationary, negative, beyond, complementarity / scale_c)
                  / max(self.K_norm * z_max + self.b_norm, _TINY))
        ratio = self.load_scale / slip_scale
        return kkt, np.concatenate([lam_n, slip * ratio, -slip * ratio])

    def start_residual(self, z: np.ndarray, active: np.ndarray) -> float:
        return self.kkt(z, active)[0].residual

    def solve_set(self, active: np.ndarray, start, tol: float):
        """Active contact rows pinned at alpha, stick rows at zprev, slip rows' forces in the load."""
        contact, plus, minus, stick = self._rows(active)
        pinned = ~self.free
        pinned[self.C[contact]] = True
        pinned[self.F[stick]] = True
        values = self.lift.copy()
        values[self.C[contact]] = self.alpha[contact]
        values[self.F[stick]] = self.zprev[stick]
        load = self.b.copy()
        load[self.F[plus]] -= self.c[plus]
        load[self.F[minus]] += self.c[minus]
        self.system.set_load(load)
        z = self.system.solve(pinned, values, start, tol=tol)
        kkt, multipliers = self.kkt(z, active)
        return z, multipliers, kkt

    def slack(self, z: np.ndarray) -> tuple[np.ndarray, float]:
        """(z_C - alpha over its scale, (c - lambda_t, c + lambda_t) over the force scale), 1."""
        slack, scale_c = self._contact_slack(z, max_abs(z))
        lam_t = -self._gradient(z)[self.F]
        return np.concatenate([slack / scale_c, (self.c - lam_t) / self.load_scale,
                               (self.c + lam_t) / self.load_scale]), 1.0

    def solve(self, predicted: np.ndarray | None = None, start: np.ndarray | None = None) -> QPSolution:
        """From a predicted set (contact, slip+, slip-) and a start (nested iteration); the
        solution's ``multipliers`` are (lambda_n, lambda_t) = ((K z - b)_C, (b - K z)_F)."""
        clock = time.perf_counter()
        n = len(self.C) + 2 * len(self.F)
        active = np.zeros(n, bool) if predicted is None else np.asarray(predicted, bool).copy()
        options = self.options
        end = primal_dual_active_set(self, active, start, options, options.loose_gain, options.active_set_iterations)
        g = self._gradient(end.z)
        return QPSolution(z=end.z, multipliers=np.concatenate([g[self.C], -g[self.F]]), active=end.active, kkt=end.kkt,
                          iterations=end.iterations, work=self.system.work(), seconds=time.perf_counter() - clock,
                          status=end.status)


def solve_unilateral_friction(K, b, free, C, alpha, F, c, zprev, lift, system, options: SolverOptions = _DEFAULT,
                              predicted=None, start=None, K_norm: float | None = None) -> QPSolution:
    """min 1/2 z'Kz - b'z + sum c_i |z[F_i] - zprev_i| over z[C] >= alpha, z = lift off
    ``free``, from ``predicted`` (contact, slip+, slip- flags over every row of C and F) and
    ``start``. The returned ``active`` and ``multipliers`` ((K z - b)[C], (b - K z)[F]) cover
    every row; a row of weight 0 is a free variable, its branch the sign of its slip."""
    F, c, zprev = np.asarray(F, np.int64), np.asarray(c, float), np.asarray(zprev, float)
    m, rows = len(C), c > 0
    kind = UnilateralFriction(K, b, free, C, alpha, F[rows], c[rows], zprev[rows], lift, system, options, K_norm)
    if predicted is not None:
        predicted = np.asarray(predicted, bool)
        predicted = np.concatenate([predicted[:m], predicted[m:m + len(F)][rows], predicted[m + len(F):][rows]])
    solution = kind.solve(predicted, start)
    slip = solution.z[F] - zprev
    plus, minus = slip > 0, slip < 0
    k = int(rows.sum())
    plus[rows], minus[rows] = solution.active[m:m + k], solution.active[m + k:]
    solution.active = np.concatenate([solution.active[:m], plus, minus])
    g = K @ solution.z - np.asarray(b, float)
    solution.multipliers = np.concatenate([g[C], -g[F]])
    return solution
