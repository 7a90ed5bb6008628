"""The rotated frame of an elastic problem at the nodes of Gamma_C (Remark 2.3): the contact
variable c = -u . n and the tangential displacements in place of the Cartesian components, and
the change of basis written into an assembled matrix in place."""
from __future__ import annotations

from dataclasses import dataclass

import ngsolve as ngs
import numpy as np
import scipy.sparse as sp

from ..mesh.trace import ContactTrace
from .sparse import csr_positions


@dataclass(frozen=True)
class RotatedFrame:
    """At each node of Gamma_C of a vector space: the variables (t, c) = (u . tau, -u . n) in 2D,
    (t1, t2, c) = (u . tau1, u . tau2, -u . n) in 3D, in place of the Cartesian components, so
    that u = sum t_i tau_i - c n (an orthogonal change of basis Q: NGSolve's coefficients =
    Q @ ours; Q = I where n = -e_y, resp. -e_z). The contact variable c then sits in the last
    component's dofs, where ``fem.assembly._contact_dofs`` finds it. Tangents (``tangents``): tau = (-n_y, n_x)
    in 2D; in 3D tau1 the unit projection of e_x (or e_y when n is near e_x) on the tangent
    plane and tau2 = -n x tau1, so that (tau1, tau2, -n) is a right-handed orthonormal basis.

    A vertex of Gamma_C needs one normal: Gamma_C must be flat through each of its vertices
    (the discrete contact conditions on the normal displacement of a kink would need the
    normals of its cells, and the cones would no longer be bounds)."""

    pairs: np.ndarray       # (k, dim) the dofs (one per component) of each node of Gamma_C
    normals: np.ndarray     # (k, dim) the outward unit normal there

    @classmethod
    def of(cls, fes, trace: ContactTrace) -> "RotatedFrame":
        dim = fes.mesh.dim
        nodes = [(ngs.EDGE, int(e)) for e in trace.edges] + [(ngs.VERTEX, int(v)) for v in trace.edge_vertices.ravel()]
        normals = np.concatenate([trace.normals, np.repeat(trace.normals, 2, axis=0)])
        # a node's dofs come in component blocks: (dim, functions) -> one tuple per basis function
        # (an edge of P1 has none, of P_k k - 1: the rotation applies to each, the normal being
        # constant along a flat edge)
        dofs = [np.reshape(fes.GetDofNrs(ngs.NodeId(kind, number)), (dim, -1)).T for kind, number in nodes]
        owner = np.repeat(np.arange(len(nodes)), [len(d) for d in dofs])
        pairs = np.concatenate(dofs).astype(np.int64)
        normals = normals[owner]
        unique, first, which = np.unique(pairs[:, 0], return_index=True, return_inverse=True)
        # every cell at a node must give it the same normal
        kinked = np.abs(normals - normals[first][which]).max(axis=1) > 1e-12
        if kinked.any():
            kind, number = nodes[owner[int(np.argmax(kinked))]]
            point = ", ".join(f"{c:.4g}" for c in fes.mesh[ngs.NodeId(kind, number)].point)
            raise ValueError(f"Gamma_C has a kink at ({point}): elastic contact needs it "
                             f"flat through each of its vertices")
        return cls(pairs[first], normals[first])

    @property
    def identity(self) -> bool:
        outward = np.zeros(self.normals.shape[1])
        outward[-1] = -1.0
        return bool(np.allclose(self.normals, outward, atol=1e-14))

    def tangents(self) -> np.ndarray:
        """(k, dim - 1, dim): the tangent vectors of each node."""
        n = self.normals
        if n.shape[1] == 2:
            return np.stack([-n[:, 1], n[:, 0]], axis=1)[:, None, :]
        seed = np.where((np.abs(n[:, 0]) < 0.9)[:, None], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0])
        first = seed - (seed * n).sum(axis=1, keepdims=True) * n
        first /= np.linalg.norm(first, axis=1, keepdims=True)
        return np.stack([first, np.cross(-n, first)], axis=1)

    def blocks(self) -> np.ndarray:
        """(k, dim, dim): Q at each node, column j the Cartesian components of ours j."""
        return np.concatenate([self.tangents(), -self.normals[:, None, :]], axis=1).transpose(0, 2, 1)

    def matrix(self, ndof: int) -> sp.csr_matrix:
        """Q: identity off Gamma_C, ``blocks`` at its nodes."""
        dim = self.pairs.shape[1]
        off = np.ones(ndof, bool)
        off[self.pairs.ravel()] = False
        rest = np.flatnonzero(off)
        rows = np.repeat(self.pairs, dim, axis=1).ravel()           # (k, i, j) -> pairs[k, i]
        cols = np.tile(self.pairs, (1, dim)).ravel()                # (k, i, j) -> pairs[k, j]
        return sp.csr_matrix((np.concatenate([np.ones(len(rest)), self.blocks().ravel()]),
                              (np.concatenate([rest, rows]), np.concatenate([rest, cols]))), shape=(ndof, ndof))


def rotate_in_place(A: sp.csr_matrix, Q: sp.csr_matrix) -> None:
    """A <- Q^T A Q in A's own memory. Q mixes the two dofs of one node, which A already couples
    with every dof it couples either of them with, so Q^T A Q fits A's sparsity pattern."""
    K = (Q.T @ A @ Q).tocoo()
    positions = csr_positions(A, K.row.astype(np.int64), K.col.astype(np.int64))
    A.data[:] = 0.0
    np.add.at(A.data, positions, K.data)
