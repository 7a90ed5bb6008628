"""The orthogonal projection onto the kernel of a few general constraint rows, for CG on an
affine space (``multigrid.pcg``) and for their least-squares multipliers.

With B the active rows restricted to the free dofs (m x n, m << n: the rows of Gamma_C's
triangles), P = I - B^T (B B^T)^{-1} B. B touches only the dofs of Gamma_C, so P is applied
on those (``columns``) with one sparse factorisation of the small matrix B B^T (a 2D surface
operator: one row per triangle of Gamma_C, far fewer than the volume's dofs).

B B^T may be singular: on a patch of triangles whose vertices are all pinned and whose outer
edges are Dirichlet, a triangle's row sees only its three edge bubbles, each shared with one
neighbour, so multipliers +1, -1 alternating between neighbours cancel on every bubble when the
patch's triangles can be coloured that way (every inner vertex of even degree, as on structured
meshes); nearly so otherwise (eigenvalues 1e-4 against 1.6 on transition-line-3d's level 1,
``projected_multigrid``). Then B x is orthogonal to the kernel of
B B^T for every x, and the factorisation of B B^T + d I (d at 1e-10 of its diagonal) followed
by two steps of iterative refinement gives the minimum-norm solution to round-off: d perturbs
the other eigen-directions by d / lambda, which each refinement step squares away.
"""
from __future__ import annotations

import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import splu

from .options import SolverOptions

_DEFAULT = SolverOptions()


class RowProjection:
    """P = I - B^T (B B^T)^{-1} B for ``rows`` (m x n CSR, zero on the pinned columns); ``shift``
    (d, relative to B B^T's diagonal) and ``refinements``: the module's note."""

    def __init__(self, rows: sp.csr_matrix, shift: float = _DEFAULT.projection_shift,
                 refinements: int = _DEFAULT.projection_refinements):
        rows = sp.csr_matrix(rows)
        self.columns = np.unique(rows.indices)
        self.B = rows[:, self.columns].tocsr()
        self.BT = self.B.T.tocsr()
        gram = (self.B @ self.BT).tocsc()
        self.gram = gram
        self.refinements = refinements
        d = shift * float(np.abs(gram.diagonal()).max(initial=1.0))
        # B B^T + d I is symmetric positive definite: a symmetric fill-reducing order and no
        # pivoting (stable for SPD matrices, as Cholesky is): a faster factorisation and faster
        # solves than SuperLU's default (COLAMD, partial pivoting)
        self._factor = splu((gram + d * sp.identity(gram.shape[0], format="csc")).tocsc(),
                            permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0,
                            options={"SymmetricMode": True}) if gram.shape[0] else None

    def _gram_solve(self, rhs: np.ndarray) -> np.ndarray:
        """(B B^T)^+ rhs for rhs in the range of B B^T."""
        if self._factor is None:
            return np.zeros(0)
        y = self._factor.solve(rhs)
        for _ in range(self.refinements):
            y += self._factor.solve(rhs - self.gram @ y)
        return y

    def multipliers(self, x: np.ndarray) -> np.ndarray:
        """y = (B B^T)^{-1} B x: the least-squares multipliers of a force x (x = B^T y + P x)."""
        return self._gram_solve(self.B @ x[self.columns])

    def apply(self, x: np.ndarray) -> np.ndarray:
        """P x (a new array)."""
        out = x.copy()
        self.apply_in_place(out)
        return out

    def apply_in_place(self, x: np.ndarray) -> None:
        """x <- P x, touching only ``columns`` (no pass over all of x)."""
        if len(self.columns):
            x[self.columns] -= self.BT @ self.multipliers(x)

    def onto(self, z: np.ndarray, target: np.ndarray) -> np.ndarray:
        """The point of {B z = target} nearest to z (a new array)."""
        out = z.copy()
        if len(self.columns):
            out[self.columns] += self.BT @ self._gram_solve(target - self.B @ z[self.columns])
        return out
