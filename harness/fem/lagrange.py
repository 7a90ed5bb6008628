"""The Lagrange nodes of a whole mesh for P1 and P2, and the change of basis between values at
them and NGSolve's hierarchical coefficients: what another finite element code shares with the
harness (``harness.export``, the ``external`` method).

A P_k function is determined by its values at the Lagrange nodes (unisolvence), so the values
at the nodes are a basis-free description of u_h: another code's nodal solution is the
harness's function exactly when the values agree. NGSolve's order-2 basis is hierarchical
(docs/mathematics.md §5: u(midpoint) = (u_a + u_b)/2 - c_e/8), so the map E from coefficients to
nodal values is sparse and invertible: E[i, j] = phi_j(x_i), evaluated by NGSolve itself
(``contact_quadrature.scalar_basis_at``). A linear functional L of the problem (its load) is
b = L(phi_j) in NGSolve's basis; against the Lagrange basis psi_i (psi_i(x_l) = delta_il,
psi_i = sum_j (E^-1)_ji phi_j) it is E^-T b: the "moments" another code adds to its right-hand
side to solve the harness's discrete problem.
"""
from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import ngsolve as ngs
import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from ..mesh.points import cells, coordinates
from .contact_quadrature import scalar_basis_at

# the orders whose nodes are the vertices and the edge midpoints (the paper's P2, and P1)
LAGRANGE_ORDERS = (1, 2)
# the vertex pairs of a cell's edge nodes in VTK's (and Gmsh's) order: triangle6 v0 v1 v2 m01 m12
# m20, tetra10 v0 v1 v2 v3 m01 m12 m02 m03 m13 m23
VTK_EDGES = {2: ((0, 1), (1, 2), (2, 0)), 3: ((0, 1), (1, 2), (0, 2), (0, 3), (1, 3), (2, 3))}


@dataclass(frozen=True)
class LagrangeNodes:
    """The nodes of P_k (k = 1, 2) on a mesh: its nv vertices first (NGSolve's numbering), then
    one midpoint per edge; each cell's nodes in VTK order (``cell_nodes``); ``E`` the values at
    the nodes of NGSolve's scalar basis of order k (n, n)."""

    points: np.ndarray          # (n, dim)
    cell_nodes: np.ndarray      # (nc, nloc)
    edge_keys: np.ndarray       # (n - nv,) min * nv + max of each midpoint's edge, sorted
    nv: int
    E: sp.csc_matrix

    @classmethod
    def of(cls, fes) -> "LagrangeNodes":
        """The nodes of ``fes`` (a scalar or vector H1 space of order 1 or 2)."""
        order = fes.globalorder
        if order not in LAGRANGE_ORDERS:
            raise ValueError(f"the Lagrange nodes are written for P1 and P2, not P{order}")
        mesh = fes.mesh
        vertices, corner = coordinates(mesh), cells(mesh)
        nv = len(vertices)
        if order == 1:
            points, cell_nodes, keys = vertices, corner, np.zeros(0, np.int64)
        else:
            pairs = np.stack([corner[:, list(pair)] for pair in VTK_EDGES[mesh.dim]], axis=1)   # (nc, e, 2)
            flat = np.sort(pairs, axis=2).reshape(-1, 2)
            keys, inverse = np.unique(flat[:, 0] * nv + flat[:, 1], return_inverse=True)
            ends = np.column_stack([keys // nv, keys % nv])
            points = np.concatenate([vertices, vertices[ends].mean(axis=1)])
            cell_nodes = np.concatenate([corner, nv + inverse.reshape(len(corner), -1)], axis=1)
        owner = np.zeros(len(points), np.int64)       # a cell holding each node, to evaluate the basis in
        owner[cell_nodes.ravel()] = np.repeat(np.arange(len(cell_nodes)), cell_nodes.shape[1])
        scalar = ngs.H1(mesh, order=order)
        dofs, values, _ = scalar_basis_at(scalar, owner, points, gradients=False)
        E = sp.csc_matrix((values.ravel(), (np.repeat(np.arange(len(points)), dofs.shape[1]), dofs.ravel())),
                          shape=(len(points), scalar.ndof))
        E.eliminate_zeros()
        if E.shape[0] != E.shape[1]:
            raise ValueError(f"{E.shape[0]} Lagrange nodes against {E.shape[1]} dofs of P{order}")
        return cls(points, cell_nodes, keys, nv, E)

    @property
    def count(self) -> int:
        return len(self.points)

    @cached_property
    def _lu(self):
        return spla.splu(self.E)

    def node_of_pairs(self, pairs: np.ndarray) -> np.ndarray:
        """The midpoint node of each vertex pair (..., 2) (an edge of the mesh)."""
        low, high = np.minimum(pairs[..., 0], pairs[..., 1]), np.maximum(pairs[..., 0], pairs[..., 1])
        return self.nv + np.searchsorted(self.edge_keys, low * self.nv + high)

    def facet_nodes(self, facets: np.ndarray) -> np.ndarray:
        """The nodes of boundary facets (their vertices (f, dim)) in VTK order: line3 v0 v1 m01,
        triangle6 v0 v1 v2 m01 m12 m20."""
        if not len(self.edge_keys):
            return facets
        local = ((0, 1),) if facets.shape[1] == 2 else VTK_EDGES[2]
        return np.concatenate([facets] + [self.node_of_pairs(facets[:, list(p)])[:, None] for p in local], axis=1)

    def values(self, coefficients: np.ndarray, components: int) -> np.ndarray:
        """(n, components) the values at the nodes of a function with NGSolve's (Cartesian)
        ``coefficients``: a vector space numbers its dofs in component blocks."""
        blocks = np.asarray(coefficients, float).reshape(components, -1)
        return np.column_stack([self.E @ block for block in blocks])

    def coefficients(self, values: np.ndarray) -> np.ndarray:
        """NGSolve's coefficients of the P_k function with ``values`` (n, components) at the nodes."""
        return np.concatenate([self._lu.solve(np.ascontiguousarray(column)) for column in np.asarray(values, float).T])

    def moments(self, dual: np.ndarray, components: int) -> np.ndarray:
        """(n, components) a functional given by its values on NGSolve's basis (``dual``, a load
        vector), against the Lagrange basis: E^-T dual per component."""
        blocks = np.asarray(dual, float).reshape(components, -1)
        return np.column_stack([self._lu.solve(block, trans="T") for block in blocks])

    def match(self, points: np.ndarray, tolerance: float) -> np.ndarray:
        """The node at each of ``points`` (within ``tolerance``): a permutation of the nodes, or a
        one-line ValueError (a count that differs, a point at no node, two points at one node)."""
        from scipy.spatial import cKDTree
        points = np.asarray(points, float)
        if points.shape != self.points.shape:
            raise ValueError(f"{len(points)} points in {points.shape[1:] or 'scalar'} shape, the level has "
                             f"{self.count} P{'2' if len(self.edge_keys) else '1'} nodes in {self.points.shape[1]}D")
        distance, node = cKDTree(self.points).query(points)
        far = np.flatnonzero(~(distance <= tolerance))
        if len(far):
            raise ValueError(f"{len(far)} points match no node of the level (the first, {points[far[0]].round(6).tolist()}, "
                             f"is {distance[far[0]]:.2g} from the nearest; tolerance {tolerance:.2g})")
        if len(np.unique(node)) != len(node):
            raise ValueError("two points match the same node of the level")
        return node
