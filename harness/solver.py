"""Exact solution of the discrete contact problems (3.6) and (5.1).

After the change of variables of ``models`` both are the bound-constrained convex QP

    minimise 1/2 z^T K z - r^T z   subject to   z_i >= alpha_i  for i in C,

with K symmetric positive definite (Gamma_u has positive measure). Its KKT conditions,

    K z - r = lambda (supported on C),  z_C >= alpha,  lambda >= 0,  lambda (z_C - alpha) = 0,

are solved exactly by a primal-dual active set method (the semismooth Newton method of
Hintermueller, Ito and Kunisch, SIAM J. Optim. 13 (2002)): guess the active set, solve the
linear system with z = alpha there, update the guess from the signs of lambda and z - alpha.

Two things make it exact and robust:
* it stops on the KKT residual, never only on a repeated active set: with quadratic elements
  the `mean` model has degenerate complementarity (lambda_i = 0 = z_i - alpha_i) and plain PDAS
  can cycle among equivalent sets whose KKT residual is already at round-off (MATH.md Section 6);
* if an active set repeats while the residual is still large, it switches to Murty's
  least-index principal pivoting, which is finite for the positive definite Schur complement
  of K on C.

And two things make it fast:
* one sparse Cholesky factorisation serves many active sets: an active set that differs from
  the factorised one in a few indices D is solved exactly by a bordered system with |D|
  extra solves (block elimination / Schur complement on D), columns cached across iterations;
* nested iteration: the study passes the active set predicted by the previous level.
"""
from __future__ import annotations

import time
from dataclasses import dataclass, field

import ngsolve as ngs
import numpy as np
import scipy.sparse as sp

DEFAULT_TOLERANCE = 1e-10


@dataclass(frozen=True)
class KKT:
    """Relative KKT residuals of a candidate solution (each dimensionless)."""

    primal: float          # max (alpha - z)^+ / max(|z|, |alpha|)
    dual: float            # max (-lambda)^+ on the active set / |r|
    complementarity: float # max |lambda_i (z_i - alpha_i)| / (|r| max(|z|, |alpha|))
    stationarity: float    # max |(K z - r)_i| off the active set / |r|

    @property
    def residual(self) -> float:
        return max(self.primal, self.dual, self.complementarity, self.stationarity)


def kkt_residuals(K, r, z, C, alpha, active) -> KKT:
    g = K @ z - r
    scale_r = max(np.abs(r).max(), np.finfo(float).tiny)
    scale_z = max(np.abs(z).max(), np.abs(alpha).max(), np.finfo(float).tiny)
    lam, slack = g[C], z[C] - alpha
    off_active = np.ones(len(z), dtype=bool)
    off_active[C[active]] = False
    return KKT(
        primal=float(max(0.0, -slack.min(initial=0.0)) / scale_z),
        dual=float(max(0.0, -lam[active].min(initial=0.0)) / scale_r),
        complementarity=float(np.abs(lam * slack).max(initial=0.0) / (scale_r * scale_z)),
        stationarity=float(np.abs(g[off_active]).max(initial=0.0) / scale_r),
    )


@dataclass
class QPSolution:
    z: np.ndarray
    multipliers: np.ndarray     # lambda on C (K z - r restricted to C)
    active: np.ndarray          # bool on C
    kkt: KKT
    iterations: int
    factorizations: int
    extra_solves: int
    seconds: float
    status: str                 # "converged" or a reason it is not


class Cholesky:
    """K[F, F]^{-1} by NGSolve's sparse Cholesky, applied to numpy vectors (zero off F)."""

    def __init__(self, K_ngs, free: np.ndarray):
        bits = ngs.BitArray(np.asarray(free, dtype=bool).tolist())
        self._inverse = K_ngs.Inverse(bits, inverse="sparsecholesky")
        self._rhs = K_ngs.CreateColVector()
        self._sol = K_ngs.CreateColVector()

    def solve(self, rhs: np.ndarray) -> np.ndarray:
        self._rhs.FV().NumPy()[:] = rhs
        self._sol.data = self._inverse * self._rhs
        return self._sol.FV().NumPy().copy()


def ngsolve_matrix(K: sp.spmatrix):
    coo = sp.coo_matrix(K)
    return ngs.la.SparseMatrixd.CreateFromCOO(
        coo.row.astype(np.int64), coo.col.astype(np.int64), coo.data.astype(float), K.shape[0], K.shape[1]
    )


@dataclass
class _Factored:
    """A factorisation of K with the indices P fixed at alpha, and its cached border columns."""

    P: np.ndarray               # fixed indices (positions in z)
    cholesky: Cholesky
    y0: np.ndarray              # solution with exactly P fixed
    columns: dict = field(default_factory=dict)


class ActiveSetSolver:
    """Primal-dual active set solver for min 1/2 z'Kz - r'z, z[C] >= alpha.

    ``refactor_above``: an active set differing from the factorised one in more than this
    many uncached indices is refactorised; 0 gives the textbook method (refactorise at every
    iteration).
    """

    def __init__(self, K: sp.csr_matrix, r: np.ndarray, C: np.ndarray, alpha: np.ndarray,
                 tol: float = DEFAULT_TOLERANCE, max_iterations: int = 500, refactor_above: int = 24):
        self.K, self.r, self.C, self.alpha = sp.csr_matrix(K), np.asarray(r, float), np.asarray(C), np.asarray(alpha, float)
        self.tol, self.max_iterations, self.refactor_above = tol, max_iterations, refactor_above
        self._K_ngs = ngsolve_matrix(self.K)
        self._Kc = sp.csc_matrix(self.K)
        self._factored: _Factored | None = None
        self.factorizations = 0
        self.extra_solves = 0

    # -- linear solves with z fixed at alpha on C[active] -------------------------------
    def _factorize(self, fixed: np.ndarray) -> _Factored:
        free = np.ones(len(self.r), dtype=bool)
        free[fixed] = False
        cholesky = Cholesky(self._K_ngs, free)
        self.factorizations += 1
        z = np.zeros(len(self.r))
        z[fixed] = self._alpha_of(fixed)
        z[free] = cholesky.solve(np.where(free, self.r - self.K @ z, 0.0))[free]
        return _Factored(P=fixed, cholesky=cholesky, y0=z)

    def _alpha_of(self, indices: np.ndarray) -> np.ndarray:
        lookup = np.empty(len(self.r))
        lookup[self.C] = self.alpha
        return lookup[indices]

    def _column(self, fac: _Factored, index: int, released: bool) -> np.ndarray:
        """K00^{-1} K[F0, d] for a released index d, K00^{-1} e_q for a newly fixed q."""
        key = (index, released)
        if key not in fac.columns:
            free = np.ones(len(self.r), dtype=bool)
            free[fac.P] = False
            if released:
                rhs = self._Kc[:, index].toarray().ravel()
            else:
                rhs = np.zeros(len(self.r))
                rhs[index] = 1.0
            fac.columns[key] = np.where(free, fac.cholesky.solve(np.where(free, rhs, 0.0)), 0.0)
            self.extra_solves += 1
        return fac.columns[key]

    def _solve_fixed(self, fixed: np.ndarray) -> np.ndarray:
        fac = self._factored
        if fac is None or self.refactor_above == 0:
            self._factored = self._factorize(fixed)
            return self._factored.y0.copy()
        released = np.setdiff1d(fac.P, fixed)   # R: fixed in the factorisation, free now
        added = np.setdiff1d(fixed, fac.P)      # Q: free in the factorisation, fixed now
        uncached = sum((int(d), True) not in fac.columns for d in released) + \
            sum((int(q), False) not in fac.columns for q in added)
        if uncached > self.refactor_above:
            self._factored = self._factorize(fixed)
            return self._factored.y0.copy()
        if len(released) == 0 and len(added) == 0:
            return fac.y0.copy()
        # Bordered system (block elimination): rows F0 carry K00 z0 = h0 - K0R dR + E_Q mu,
        # rows R close the released unknowns z_R = alpha_R + dR, rows Q enforce z_Q = alpha_Q.
        W_R = np.column_stack([self._column(fac, int(d), True) for d in released]) if len(released) else np.zeros((len(self.r), 0))
        W_Q = np.column_stack([self._column(fac, int(q), False) for q in added]) if len(added) else np.zeros((len(self.r), 0))
        K_R = self.K[released]
        top = np.hstack([self.K[released][:, released].toarray() - K_R @ W_R, K_R @ W_Q])
        bottom = np.hstack([-W_R[added], W_Q[added]])
        rhs = np.concatenate([self.r[released] - K_R @ fac.y0, self._alpha_of(added) - fac.y0[added]])
        sol = np.linalg.solve(np.vstack([top, bottom]), rhs)
        dR, mu = sol[: len(released)], sol[len(released):]
        z = fac.y0 - W_R @ dR + W_Q @ mu
        z[released] += dR
        z[added] = self._alpha_of(added)
        return z

    # -- the active set iteration ---------------------------------------------------------
    def solve(self, initial_active: np.ndarray | None = None) -> QPSolution:
        start = time.perf_counter()
        active = np.zeros(len(self.C), dtype=bool) if initial_active is None else initial_active.copy()
        seen: set[bytes] = set()
        pivoting = False
        status = f"not converged in {self.max_iterations} iterations"
        for iteration in range(1, self.max_iterations + 1):
            z = self._solve_fixed(self.C[active])
            kkt = kkt_residuals(self.K, self.r, z, self.C, self.alpha, active)
            lam = (self.K @ z - self.r)[self.C]
            if kkt.residual <= self.tol:
                status = "converged"
                break
            seen.add(active.tobytes())
            # Decisions use a fraction of the tolerance so that round-off never flips an index.
            scale_r = max(np.abs(self.r).max(), np.finfo(float).tiny)
            scale_z = max(np.abs(z).max(), np.abs(self.alpha).max(), np.finfo(float).tiny)
            leave = active & (lam < -0.1 * self.tol * scale_r)
            enter = ~active & (z[self.C] - self.alpha < -0.1 * self.tol * scale_z)
            if not (leave.any() or enter.any()):
                status = f"stalled: KKT residual {kkt.residual:.2e} with a consistent active set"
                break
            if pivoting:
                # Murty's least-index rule: flip only the first violated index.
                first = int(np.flatnonzero(leave | enter)[0])
                leave, enter = np.zeros_like(leave), np.zeros_like(enter)
                (leave if active[first] else enter)[first] = True
            candidate = (active & ~leave) | enter
            if candidate.tobytes() in seen and not pivoting:
                pivoting = True
                first = int(np.flatnonzero(leave | enter)[0])
                candidate = active.copy()
                candidate[first] = not active[first]
            active = candidate
        return QPSolution(
            z=z, multipliers=lam, active=active, kkt=kkt, iterations=iteration,
            factorizations=self.factorizations, extra_solves=self.extra_solves,
            seconds=time.perf_counter() - start, status=status,
        )


def solve_contact_qp(K, r, C, alpha, initial_active=None, textbook=False, tol=DEFAULT_TOLERANCE) -> QPSolution:
    """The harness's solver; ``textbook=True`` gives the reference PDAS (cold start,
    refactorisation at every iteration) used by the benchmark and the tests."""
    if textbook:
        return ActiveSetSolver(K, r, C, alpha, tol=tol, refactor_above=0).solve(None)
    return ActiveSetSolver(K, r, C, alpha, tol=tol).solve(initial_active)
