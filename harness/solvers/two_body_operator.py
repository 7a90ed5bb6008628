"""K = diag(A_1, A_2) + C as an NGSolve operator: each body's own NGSolve matrix, never copied,
and a coupling C that is nonzero only in the rows and columns of a small set T of dofs near the
interface (a mortar QP's K = S^T A S, ``fem.two_body.dual_bound_qp``; its P1 levels,
``two_body_multigrid``).

Why not one NGSolve matrix of K: K's pattern is A's plus cross entries between the bodies, so it
does not fit in A's memory as one body's transformed matrix does (``fem.cones``), and copying
it into NGSolve (``fem.sparse.ngsolve_matrix``) cost 5.1 s for two P2 bodies at 2.0e6 dofs, four
times one linear multigrid solve of both bodies.

Gauss-Seidel on K without K: C vanishes off T x T, so every row of K outside T is A's row, with
A's columns (K_BB = A_BB and K_BT = A_BT for the bulk B, the complement of T). A sweep of
NGSolve's Gauss-Seidel on each body's A over the bulk rows is therefore the sweep of K over
those rows; the rows of T, a few dofs per interface node, are then relaxed together by an
exact solve of K_TT (block Gauss-Seidel, the bulk rows single, T one block). The backward sweep
runs the same steps in reverse order (T first), so forward and backward are adjoint and the
V-cycle built on them stays symmetric positive definite (``multigrid.TruncatedVCycle``)."""
from __future__ import annotations

import ngsolve as ngs
import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import splu

from ..fem.sparse import csr_block_diag, csr_view, ngsolve_matrix
from .bound_constraints import row_sums


class CoupledBlocks(ngs.BaseMatrix):
    """diag(``blocks``) + ``coupling`` on the joint vector (the blocks' dofs one after another),
    with the interface of an NGSolve matrix that ``multigrid`` reads: ``K * x``, ``height``,
    column vectors, ``smoother(mask)``. ``coupling``: symmetric, scipy; its nonzero rows are T."""

    def __init__(self, blocks: list, coupling: sp.spmatrix):
        super().__init__()
        self.blocks = list(blocks)
        self.offsets = np.cumsum([0] + [block.height for block in self.blocks])
        self.n = int(self.offsets[-1])
        self.ranges = [(int(a), int(b)) for a, b in zip(self.offsets[:-1], self.offsets[1:])]
        coupling = sp.csr_matrix(coupling)
        # the rows and the columns C reaches (a nonsymmetric C's may differ)
        self.interface = np.union1d(np.flatnonzero(np.diff(coupling.indptr) > 0), np.unique(coupling.indices))
        self.C_T = coupling[self.interface][:, self.interface].tocsr()
        # the rows T of diag(A_1, A_2), all columns: the T block's residual reads the bulk through them
        self.A_T = _rows_of_blocks([csr_view(block) for block in self.blocks], self.offsets, self.interface)
        # the bulk rows' NGSolve smoothers of the last pin set, by their mask: a new active set
        # pins rows of T only (the bounds are the slave's trace variables), so they carry over
        self._bulk_smoothers: tuple[bytes, list] = (b"", [])
        self._matmul_vectors = None

    def Height(self) -> int:        # noqa: N802 -- NGSolve's BaseMatrix interface
        return self.n

    def Width(self) -> int:         # noqa: N802
        return self.n

    def CreateColVector(self):      # noqa: N802
        return ngs.BaseVector(self.n)

    def CreateRowVector(self):      # noqa: N802
        return ngs.BaseVector(self.n)

    def Mult(self, x, y) -> None:   # noqa: N802
        for block, (start, stop) in zip(self.blocks, self.ranges):
            y.Range(start, stop).data = block * x.Range(start, stop)
        x_np, y_np = x.FV().NumPy(), y.FV().NumPy()
        y_np[self.interface] += self.C_T @ x_np[self.interface]

    def MultAdd(self, scale, x, y) -> None:     # noqa: N802 -- ``r.data = b - K * x`` comes here
        for block, (start, stop) in zip(self.blocks, self.ranges):
            y.Range(start, stop).data += scale * (block * x.Range(start, stop))
        x_np, y_np = x.FV().NumPy(), y.FV().NumPy()
        y_np[self.interface] += scale * (self.C_T @ x_np[self.interface])

    def __matmul__(self, z: np.ndarray) -> np.ndarray:
        """K z for a NumPy vector (the active set method's KKT residuals), through two work
        vectors made once (memory first touched is dear: ``multigrid.TruncatedVCycle``)."""
        if self._matmul_vectors is None:
            self._matmul_vectors = self.CreateColVector(), self.CreateColVector()
        x, y = self._matmul_vectors
        x.FV().NumPy()[:] = z
        self.Mult(x, y)
        return y.FV().NumPy().copy()

    def row_norm(self, rows: np.ndarray) -> float:
        """max over ``rows`` (a mask) of sum_j |K_ij|: A's row sums off T, those of A + C on T."""
        sums = np.concatenate([row_sums(csr_view(block)) for block in self.blocks])
        sums[self.interface] = row_sums(self.A_T + _embed_columns(self.C_T, self.interface, self.n))
        return float(sums[rows].max(initial=0.0))

    def scipy(self) -> sp.csr_matrix:
        """K as one scipy matrix (for the tests and small levels)."""
        blocks = csr_block_diag([csr_view(block) for block in self.blocks])
        coupling = _embed_columns(self.C_T, self.interface, self.n)
        return (blocks + sp.csr_matrix((coupling.data, coupling.indices, _expand_indptr(coupling.indptr, self.interface, self.n)),
                                       shape=(self.n, self.n))).tocsr()

    def smoother(self, mask: np.ndarray) -> "BlockGaussSeidel":
        return BlockGaussSeidel(self, mask)

    def Inverse(self, freedofs, inverse: str = "sparsecholesky"):  # noqa: N802 -- NGSolve's interface
        """NGSolve's factorisation of a copy of K (the coarsest level of a V-cycle: small)."""
        self._copy = ngsolve_matrix(self.scipy())
        return self._copy.Inverse(freedofs, inverse=inverse)


class BlockGaussSeidel:
    """Symmetric block Gauss-Seidel of a ``CoupledBlocks`` on the dofs of ``mask``: NGSolve's
    point Gauss-Seidel of each A_k over the bulk rows, then T's free rows exactly (module
    docstring); ``SmoothBack`` in the reverse order."""

    def __init__(self, K: CoupledBlocks, mask: np.ndarray):
        mask = np.asarray(mask, dtype=bool)
        bulk = mask.copy()
        bulk[K.interface] = False
        self.K = K
        self.ranges = K.ranges
        key = bulk.tobytes()
        if K._bulk_smoothers[0] != key:
            K._bulk_smoothers = key, [block.CreateSmoother(ngs.BitArray(bulk[a:b].tolist()))
                                      for block, (a, b) in zip(K.blocks, self.ranges)]
        self.smoothers = K._bulk_smoothers[1]
        free_T = mask[K.interface]
        self.rows = K.interface[free_T]
        self.A_rows = K.A_T[free_T]
        self.C_rows = K.C_T[free_T]
        K_TT = (K.A_T[:, K.interface] + K.C_T)[free_T][:, free_T]
        self.lu = splu(K_TT.tocsc()) if len(self.rows) else None

    def _block(self, x, b) -> None:
        """x_T += K_TT^{-1} (b - K x)_T on T's free rows."""
        if self.lu is None:
            return
        x_np = x.FV().NumPy()
        residual = b.FV().NumPy()[self.rows] - self.A_rows @ x_np - self.C_rows @ x_np[self.K.interface]
        x_np[self.rows] += self.lu.solve(residual)

    def Smooth(self, x, b) -> None:         # noqa: N802 -- NGSolve's smoother interface
        for smoother, (start, stop) in zip(self.smoothers, self.ranges):
            smoother.Smooth(x.Range(start, stop), b.Range(start, stop))
        self._block(x, b)

    def SmoothBack(self, x, b) -> None:     # noqa: N802
        self._block(x, b)
        for smoother, (start, stop) in zip(reversed(self.smoothers), reversed(self.ranges)):
            smoother.SmoothBack(x.Range(start, stop), b.Range(start, stop))


def _rows_of_blocks(blocks: list, offsets: np.ndarray, rows: np.ndarray) -> sp.csr_matrix:
    """Rows ``rows`` (joint numbering) of diag(``blocks``) as a CSR matrix with all joint columns."""
    parts = []
    for block, start, stop in zip(blocks, offsets[:-1], offsets[1:]):
        local = rows[(rows >= start) & (rows < stop)] - start
        part = block[local].tocoo()
        parts.append(sp.csr_matrix((part.data, (part.row, part.col + start)), shape=(len(local), int(offsets[-1]))))
    return sp.vstack(parts, format="csr")


def _expand_indptr(indptr: np.ndarray, rows: np.ndarray, n: int) -> np.ndarray:
    """The row pointers of a matrix whose rows ``rows`` are a compact CSR's (``indptr``), others empty."""
    counts = np.zeros(n, dtype=np.int64)
    counts[rows] = np.diff(indptr)
    return np.concatenate([[0], np.cumsum(counts)])


def _embed_columns(C_T: sp.csr_matrix, interface: np.ndarray, n: int) -> sp.csr_matrix:
    """The compact rows C_T (columns numbered within ``interface``) with the joint columns."""
    return sp.csr_matrix((C_T.data, interface[C_T.indices], C_T.indptr), shape=(C_T.shape[0], n))
