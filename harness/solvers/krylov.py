"""GMRES for the nonsymmetric Newton systems (Coulomb friction's for every theta, the skew and
incomplete Nitsche variants), preconditioned by the harness's truncated V-cycle
(``multigrid.TruncatedVCycle``), as ``multigrid.pcg`` is for the symmetric ones.

Flexible GMRES (Y. Saad, A flexible inner-outer preconditioned GMRES algorithm, SIAM J. Sci.
Comput. 14 (1993) 461-469): right preconditioning with the preconditioned directions z_j = M v_j
kept, so that x = x0 + Z y and the residual GMRES minimises is the true one's (Saad, Iterative
Methods for Sparse Linear Systems, 2nd ed., 2003, Sect. 9.4.1); the V-cycle is the same linear
map at every step (Gauss-Seidel forward, then back), but flexibility costs only the stored Z and
keeps the iterate exact in floating point. Modified Gram-Schmidt with Givens rotations.

Stopping: max |r| <= tol over the free dofs, on the true residual (the harness's residuals are
max-norms). GMRES knows only ||r||_2, which bounds max |r| from above, and is at least
max |r|: the true residual is formed once ||r||_2 <= sqrt(n) tol (before, max |r| > tol is
certain) and every ``CHECK_EVERY`` steps after, and a restart (``RESTART`` directions) starts
from it.

The restart length: the V-cycle leaves a few slow modes where the material is nearly
incompressible (its Gauss-Seidel smoother does not see the divergence constraint's stiffness),
and a restart throws away the Krylov directions that had captured them. On Mindlin's sphere at
nu = 0.47 (3D P2, 182,955 dofs, the first Newton step from the nested start) the first 40 steps
gain 4.5 orders and every later restart of 40 only 0.7: 240 steps with RESTART = 40, 89 with 100.
A level finer (1.4e6 dofs) the V-cycle itself is not robust at nu = 0.47: 100 still leaves
1.2e-9 after 500 steps against the tolerance 1.2e-11, and Newton's fallback to a factorisation,
which ran out of 23 GiB there, is refused in one line (``newton.DIRECT_FALLBACK_DOFS_3D``).
Systems that converge within 40 steps are unchanged. Memory: at most
2 (RESTART + 1) vectors (V and Z), ``KRYLOV_BYTES_PER_DOF``, which a study's budget counts for
one-body Coulomb cases, the ones whose Newton systems come here (``study.execution.budget``).
"""
from __future__ import annotations

import numpy as np

RESTART = 100
KRYLOV_BYTES_PER_DOF = 2 * (RESTART + 1) * 8.0
CHECK_EVERY = 4


def gmres(K_ngs, preconditioner, rhs: np.ndarray, z: np.ndarray, free: np.ndarray, tol: float,
          max_iterations: int = 500) -> tuple[np.ndarray, int]:
    """Solve K[F, F] z_F = rhs_F - K[F, P] z_P by right-preconditioned FGMRES from the start z
    (whose pinned entries stay) until max |residual| <= tol on the free dofs; (z, iterations)."""
    mask = free.astype(float)
    x = z.copy()
    work = _Work(K_ngs)
    iterations = 0
    while iterations < max_iterations:
        r = _residual(work, x, rhs, mask)
        if np.abs(r).max(initial=0.0) <= tol:
            break
        x, steps = _cycle(work, preconditioner, x, r, rhs, mask, tol, max_iterations - iterations)
        iterations += steps
    return x, iterations


class _Work:
    """Two NGSolve vectors of K with their NumPy views, for products with K and the V-cycle."""

    def __init__(self, K_ngs):
        self.K = K_ngs
        self.a, self.b = K_ngs.CreateColVector(), K_ngs.CreateColVector()
        self.a_np, self.b_np = self.a.FV().NumPy(), self.b.FV().NumPy()

    def product(self, v: np.ndarray) -> np.ndarray:
        self.a_np[:] = v
        self.b.data = self.K * self.a
        return self.b_np.copy()

    def precondition(self, preconditioner, v: np.ndarray) -> np.ndarray:
        self.a_np[:] = v
        preconditioner.apply(self.a, self.b)
        return self.b_np.copy()


def _residual(work: _Work, x: np.ndarray, rhs: np.ndarray, mask: np.ndarray) -> np.ndarray:
    return (rhs - work.product(x)) * mask


def _cycle(work: _Work, preconditioner, x: np.ndarray, r: np.ndarray, rhs: np.ndarray, mask: np.ndarray,
           tol: float, budget: int) -> tuple[np.ndarray, int]:
    """One restart cycle from x with residual r = rhs - K x: (the new x, its Arnoldi steps)."""
    beta = float(np.linalg.norm(r))
    steps = min(RESTART, budget)
    V, Z = [r / beta], []
    H = np.zeros((steps + 1, steps))
    cs, sn = np.zeros(steps), np.zeros(steps)
    g = np.zeros(steps + 1)
    g[0] = beta
    bound = np.sqrt(np.count_nonzero(mask)) * tol
    for j in range(steps):
        Z.append(work.precondition(preconditioner, V[j]) * mask)
        w = work.product(Z[j]) * mask
        for i in range(j + 1):          # modified Gram-Schmidt
            H[i, j] = float(w @ V[i])
            w -= H[i, j] * V[i]
        length = float(np.linalg.norm(w))
        H[j + 1, j] = length
        _rotate(H, cs, sn, g, j)
        breakdown, last = length == 0.0, j == steps - 1
        if not breakdown:
            V.append(w / length)
        if breakdown or last or (abs(g[j + 1]) <= bound and j % CHECK_EVERY == 0):
            candidate = x + _combination(Z, H, g, j + 1)
            if breakdown or last or np.abs(_residual(work, candidate, rhs, mask)).max(initial=0.0) <= tol:
                return candidate, j + 1
    return x, steps


def _rotate(H: np.ndarray, cs: np.ndarray, sn: np.ndarray, g: np.ndarray, j: int) -> None:
    """Apply the earlier Givens rotations to column j of H, then the new one that zeroes H[j+1, j]."""
    for i in range(j):
        H[i, j], H[i + 1, j] = cs[i] * H[i, j] + sn[i] * H[i + 1, j], -sn[i] * H[i, j] + cs[i] * H[i + 1, j]
    norm = np.hypot(H[j, j], H[j + 1, j])
    cs[j], sn[j] = (1.0, 0.0) if norm == 0 else (H[j, j] / norm, H[j + 1, j] / norm)
    H[j, j], H[j + 1, j] = norm, 0.0
    g[j + 1], g[j] = -sn[j] * g[j], cs[j] * g[j]


def _combination(Z: list, H: np.ndarray, g: np.ndarray, k: int) -> np.ndarray:
    """Z y with y the solution of the k x k triangular least-squares system R y = g."""
    y = np.linalg.solve(np.triu(H[:k, :k]), g[:k]) if k else np.zeros(0)
    out = np.zeros_like(Z[0])
    for coefficient, direction in zip(y, Z):
        out += coefficient * direction
    return out
