"""NGSolve's sparse objects as NumPy/scipy ones, without copies or element-by-element loops:
the free dofs as a boolean array, a sparse matrix as a scipy CSR view of its memory, and the
positions of entries in a CSR pattern (for writing into NGSolve's matrices in place)."""
from __future__ import annotations

import ngsolve as ngs
import numpy as np
import scipy.sparse as sp


def free_dofs(fes) -> np.ndarray:
    """``fes.FreeDofs()`` as a boolean array, by NGSolve's projector onto them applied to ones:
    one vector operation, where converting the BitArray element by element is a Python loop over
    every dof."""
    ones = ngs.BaseVector(fes.ndof)
    ones.FV().NumPy()[:] = 1.0
    kept = ones.CreateVector()
    kept.data = ngs.Projector(fes.FreeDofs(), True) * ones
    return kept.FV().NumPy() != 0.0


def csr_view(matrix) -> sp.csr_matrix:
    """A scipy CSR matrix on the memory of an NGSolve sparse matrix (values and column indices
    shared, not copied); it keeps ``matrix`` alive."""
    values, columns, pointers = matrix.CSR()
    view = sp.csr_matrix((values.NumPy(), np.asarray(columns), np.asarray(pointers, dtype=np.int64)),
                         shape=(matrix.height, matrix.width), copy=False)
    view.owner = matrix
    return view


def ngsolve_matrix(K: sp.spmatrix):
    """An NGSolve copy of a scipy matrix (slow: prefer ``fem.cones.transformed_matrix``)."""
    coo = sp.coo_matrix(K)
    return ngs.la.SparseMatrixd.CreateFromCOO(
        coo.row.astype(np.int64), coo.col.astype(np.int64), coo.data.astype(float), K.shape[0], K.shape[1])


def csr_positions(M: sp.csr_matrix, rows: np.ndarray, cols: np.ndarray) -> np.ndarray:
    """Positions in ``M.data`` of the entries (rows[k], cols[k]), which must be in M's pattern
    (column indices sorted within each row, as NGSolve stores them)."""
    touched = np.unique(rows)
    starts, lengths = M.indptr[touched], np.diff(M.indptr)[touched]
    offsets = np.concatenate([[0], np.cumsum(lengths)[:-1]])
    positions = np.repeat(starts - offsets, lengths) + np.arange(lengths.sum())
    keys = np.repeat(touched, lengths) * M.shape[1] + M.indices[positions]
    wanted = rows * M.shape[1] + cols
    where = np.minimum(np.searchsorted(keys, wanted), len(keys) - 1)
    if not (np.all(np.diff(keys) > 0) and np.array_equal(keys[where], wanted)):
        raise RuntimeError("S^T A S does not fit the sparsity pattern of A: a contact edge outside one triangle?")
    return positions[where]


def congruence_terms(A: sp.csr_matrix, S_rows: sp.csr_matrix, rows: np.ndarray) -> tuple[sp.coo_matrix, sp.coo_matrix]:
    """(P, Q) with S^T A S = A + P + P^T + Q, for a symmetric A and a change of variables S that
    is the identity off ``rows`` (``S_rows``: its rows there): with S = I + R, R nonzero in those
    rows only (D = R[rows]), P = D^T A[rows, :] and Q = D^T A[rows, rows] D. Every term comes from
    the O(|rows|) rows of A there: no product of n x n matrices (``A`` may be any matrix with
    those rows and all columns)."""
    identity = sp.csr_matrix((np.ones(len(rows)), (np.arange(len(rows)), rows)), shape=(len(rows), A.shape[1]))
    D = (S_rows - identity).tocsr()
    A_rows = A[rows]
    return (D.T @ A_rows).tocoo(), (D.T @ (A_rows[:, rows] @ D)).tocoo()


def csr_block_diag(blocks: list) -> sp.csr_matrix:
    """diag(B_1, B_2, ...) of CSR matrices by concatenating their arrays (``scipy.sparse.block_diag``
    goes through COO: 1.6 s for two bodies' P2 matrices at 2e6 dofs)."""
    blocks = [sp.csr_matrix(block) for block in blocks]
    rows = np.cumsum([0] + [block.shape[0] for block in blocks])
    columns = np.cumsum([0] + [block.shape[1] for block in blocks])
    nnz = np.cumsum([0] + [block.nnz for block in blocks])
    indptr = np.concatenate([[0]] + [block.indptr[1:].astype(np.int64) + offset for block, offset in zip(blocks, nnz)])
    indices = np.concatenate([block.indices.astype(np.int64) + offset for block, offset in zip(blocks, columns)])
    data = np.concatenate([block.data for block in blocks])
    return sp.csr_matrix((data, indices, indptr), shape=(rows[-1], columns[-1]))
