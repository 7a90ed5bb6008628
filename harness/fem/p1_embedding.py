"""The finest P1 level inside a problem's variables: the embedding E of P1 functions (vertex
values) into X_h in the contact model's variables z (``ContactEdges``). The multigrid's finest
transfer (``solvers.multigrid.TruncatedVCycle``) and the nested start (``fem.nested``) both go
through it.
"""
from __future__ import annotations

from dataclasses import dataclass

import ngsolve as ngs
import numpy as np


@dataclass(frozen=True)
class ContactEdges:
    """The finest P1 level inside the problem's variables z: z = E c for a P1 function c, and
    the restriction E^T. E differs from the plain injection (vertex dofs, bubbles zero) where
    the contact model's variables differ from NGSolve's hierarchical ones: the bubble of contact
    edge k is replaced by a combination of its ends (u = S z, ``fem.cones``), so a P1 function
    with vertex values c has z_e = (c_a + c_b)/2 there (``edge_dofs``, ``end_dofs``; none for
    ``of(problem, model=False)``). A vector problem's P1 dofs are (vertex, component) at
    k nv + v, its z NGSolve's component blocks (``p1_dofs``); both are in the same rotated frame
    at the vertices of Gamma_C (``Multilevel``), so E does not rotate.

    Scalar problems: vertex v's dof is v, so ``p1_dofs`` is None (the first n entries)."""

    edge_dofs: np.ndarray                   # (m,) z's dof of each contact edge's variable
    end_dofs: np.ndarray                    # (m, 2) the P1 dofs of its ends (their contact component)
    p1_dofs: np.ndarray | None = None       # z's dof of each P1 dof (None: the same number)
    # (m, 2) the weights of the two ends in each edge variable's value for a P1 function: 1/2 and
    # 1/2 for the midpoint value and the edge mean (None), 1 - t and t for the value at the point
    # t of the edge (the Gauss-Lobatto points of P_k's nodal variables, ``fem.friction``)
    end_weights: np.ndarray | None = None

    @classmethod
    def of(cls, problem, model: bool = True) -> "ContactEdges":
        """From a ``fem.assembly.DiscreteProblem``, whose space must number vertex v's dof of
        component k as k ndof/components + v (NGSolve's H1 and VectorH1 do); ``model``: with the
        contact model's edge variables."""
        mesh, ndof = problem.mesh, problem.ndof
        nv, components = mesh.nv, problem.physics.components
        block = ndof // components
        numbering = tuple(nv - 1 + k * block for k in range(components))
        contact_component = (components - 1) * block
        if problem.fes.GetDofNrs(ngs.NodeId(ngs.VERTEX, nv - 1)) != numbering or \
                not np.array_equal(problem.vertex_dofs, contact_component + problem.trace.vertices):
            raise RuntimeError("the space does not number vertex dofs by vertex; the multigrid needs it")
        has_edges = model and len(problem.edge_dofs)
        ends = problem.end_dofs if has_edges else np.zeros((0, 2), dtype=np.int64)
        edges = problem.edge_dofs if has_edges else np.zeros(0, np.int64)
        return cls.of_edges(problem, edges, ends)

    @classmethod
    def of_edges(cls, problem, edges: np.ndarray, ends: np.ndarray, end_weights: np.ndarray | None = None) -> "ContactEdges":
        """The embedding whose changed variables are the dofs ``edges`` (each the value of a
        contact edge's function between its two ``ends``, dofs of z): the contact component's
        (``of``), or others too (a tangential component under friction, ``fem.friction``)."""
        nv, components = problem.mesh.nv, problem.physics.components
        block = problem.ndof // components
        # z's vertex dof k block + v is P1 dof k nv + v; one component: the same number (slices)
        p1_dofs = np.concatenate([k * block + np.arange(nv) for k in range(components)])
        same = p1_dofs[-1] == len(p1_dofs) - 1
        return cls(np.asarray(edges, np.int64), (ends // block) * nv + ends % block, None if same else p1_dofs, end_weights)

    @property
    def weights(self) -> np.ndarray:
        return np.full((len(self.edge_dofs), 2), 0.5) if self.end_weights is None else self.end_weights

    @property
    def identity(self) -> bool:
        """Whether E is the identity (a P1 problem without changed variables)."""
        return self.p1_dofs is None and not len(self.edge_dofs)

    def _vertex_part(self, r: np.ndarray, n: int) -> np.ndarray:
        return r[:n].copy() if self.p1_dofs is None else r[self.p1_dofs]

    def prolongate(self, c: np.ndarray, z: np.ndarray) -> None:
        """z += E c."""
        if self.p1_dofs is None:
            z[: len(c)] += c
        else:
            z[self.p1_dofs] += c
        w = self.weights
        z[self.edge_dofs] += w[:, 0] * c[self.end_dofs[:, 0]] + w[:, 1] * c[self.end_dofs[:, 1]]

    def restrict(self, r: np.ndarray, n: int) -> np.ndarray:
        """E^T r, of the finest P1 level's size ``n``."""
        c = self._vertex_part(r, n)
        w, at_edges = self.weights, r[self.edge_dofs]
        np.add.at(c, self.end_dofs[:, 0], w[:, 0] * at_edges)
        np.add.at(c, self.end_dofs[:, 1], w[:, 1] * at_edges)
        return c

    def touched(self, mask: np.ndarray, n: int) -> np.ndarray:
        """The P1 dofs whose image E e_j reaches a dof of ``mask`` (bool over z): the hats a
        truncated coarse space must drop when ``mask`` holds the pins."""
        hit = self._vertex_part(mask, n).astype(bool)
        hit[self.end_dofs[mask[self.edge_dofs]].ravel()] = True
        return hit

    def values(self, u: np.ndarray, n: int) -> np.ndarray:
        """u's vertex values as a P1 function of ``n`` dofs (E's left inverse on P1 functions:
        the model's edge variables do not enter)."""
        return self._vertex_part(u, n)


# No change of variables, scalar problems: penalty and Nitsche work in NGSolve's own hierarchical
# variables, where a P1 function is its vertex values and zero bubbles (a vector problem's own:
# ``ContactEdges.of(problem, model=False)``).
HIERARCHICAL = ContactEdges(np.zeros(0, np.int64), np.zeros((0, 2), np.int64))
