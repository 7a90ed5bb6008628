"""The discrete two-body problem of one level: each body's ``DiscreteProblem`` on its own mesh
(``problem.bodies``: the lower body in its mirrored frame solves the upper body's problem) and
the joint QP of the mortar condition (``mortar``):

    minimise  1/2 a_1(u_1, u_1) - L_1(u_1) + 1/2 a_2(u_2, u_2) - L_2(u_2)
    over      u_k = u_D on Gamma_u of each body,   B (u_1, u_2) >= g,

whose multipliers lambda >= 0 are the mortar pressure's coefficients (the same on both bodies:
the fluxes balance). z = (u_1, u_2) concatenates the two bodies' NGSolve numberings.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property

import numpy as np
import scipy.sparse as sp

from .assembly import DiscreteProblem
from .mortar import MortarCoupling, TraceElements, hierarchical_basis, intersection
from .sparse import congruence_terms, csr_block_diag


@dataclass
class TwoBodyProblem:
    """The two bodies' discrete problems of one level (the same order)."""

    upper: DiscreteProblem      # the slave body of the mortar condition
    lower: DiscreteProblem      # the master body, in its mirrored frame

    @property
    def bodies(self) -> tuple[DiscreteProblem, DiscreteProblem]:
        return self.upper, self.lower

    @property
    def ndof(self) -> int:
        return self.upper.ndof + self.lower.ndof

    @property
    def order(self) -> int:
        return self.upper.order

    def split(self, z: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(u_1, u_2) of a joint vector."""
        return z[: self.upper.ndof], z[self.upper.ndof:]


@dataclass
class JointQP:
    """The two-body QP: block-diagonal K, the loads, free dofs and lifts side by side."""

    K: sp.csr_matrix
    b: np.ndarray
    free: np.ndarray
    lift: np.ndarray


def joint_qp(problem: TwoBodyProblem) -> JointQP:
    upper, lower = problem.bodies
    return JointQP(csr_block_diag([upper.A, lower.A]), np.concatenate([upper.b, lower.b]),
                   np.concatenate([upper.free, lower.free]), np.concatenate([upper.lift, lower.lift]))


def opening(problem: TwoBodyProblem, z: np.ndarray, samples: int = 9) -> tuple[np.ndarray, np.ndarray]:
    """The opening c_1 + c_2 of the interface at ``samples`` points of every segment of the
    intersection of the two trace meshes (ends included): (x, values), both (segments, samples).
    Between the slave's nodes the discrete opening may be negative although every mortar row
    holds (the condition is weak)."""
    elements = [TraceElements.of(body) for body in problem.bodies]
    segments = intersection(*elements)
    t = np.linspace(0.0, 1.0, samples)
    x = segments[:, :1] + t[None, :] * (segments[:, 1:] - segments[:, :1])
    total = np.zeros_like(x)
    for body, trace, u in zip(problem.bodies, elements, problem.split(z)):
        e = trace.locate(0.5 * (segments[:, 0] + segments[:, 1]))
        basis = hierarchical_basis(trace.parameters(x, e).ravel(), body.order).reshape(*x.shape, -1)
        total += np.einsum("sqj,sj->sq", basis, u[trace.dofs[e]])
    return x, total


@dataclass
class BoundQP:
    """The dual mortar QP as bounds (``dual_bound_qp``): min 1/2 z'Kz - b'z over z = lift on the
    pinned dofs and z[C] >= alpha, u = S z with S = I + R, K = diag(A_1, A_2) + ``K_interface``.
    With ``T`` (``dual_bound_qp(..., tangential=True)``): z[T] is the dual projection of the
    tangential jump at the slave's nodes, in C's node order, unbounded; friction acts on it."""

    R: sp.csr_matrix            # S - I: nonzero in the slave's trace rows C only
    blocks: list                # A_1, A_2 (scipy views of the bodies' NGSolve matrices)
    K_interface: sp.csr_matrix  # K - diag(A_1, A_2): nonzero in the rows and columns near Gamma_C only
    b: np.ndarray
    free: np.ndarray
    lift: np.ndarray
    C: np.ndarray
    alpha: np.ndarray
    D: np.ndarray       # the dual rows' weights int psi_i: row multiplier = (force on z[C]) / D
    T: np.ndarray = field(default_factory=lambda: np.zeros(0, np.int64))   # the tangential jump's variables

    @property
    def changed(self) -> np.ndarray:
        """The rows where S differs from the identity: C, then T."""
        return np.concatenate([self.C, self.T])

    @property
    def F(self) -> np.ndarray:
        """T under the name the cones' Coulomb solver reads (``solvers.coulomb_cones.solve_coulomb_step``)."""
        return self.T

    def thresholds(self, coefficient: float, normal_force: np.ndarray) -> np.ndarray:
        """c_i = mu_F p_i, p_i = (K z - b)_{C_i} = D_i lambda_n,i: row i of T and of C share the
        slave node i and its weight D_i, so |tau_i| <= c_i is |lambda_t,i| <= mu_F lambda_n,i
        (round-off negatives of p read as 0)."""
        return coefficient * np.maximum(normal_force, 0.0)

    def with_load(self, b: np.ndarray) -> np.ndarray:
        """The load in z of the bodies' joint load ``b`` (b + R^T b; K does not change)."""
        return b + self.R.T @ b

    @cached_property
    def K(self) -> sp.csr_matrix:
        """K as one scipy matrix, made on first use (sparse Cholesky, the general-constraint
        cross-check); the multigrid never makes it (``solvers.two_body_operator``)."""
        K = (csr_block_diag(self.blocks) + self.K_interface).tocsr()
        K.sort_indices()
        return K

    @cached_property
    def S(self) -> sp.csr_matrix:
        """S = I + R as one matrix, made on first use (the tests; the solvers read R's rows)."""
        return (sp.identity(self.R.shape[0], format="csr") + self.R).tocsr()

    def S_rows(self, rows: np.ndarray) -> sp.csr_matrix:
        """The rows ``rows`` of S (``identity_plus_rows``)."""
        return identity_plus_rows(self.R, rows)

    def to_u(self, z: np.ndarray) -> np.ndarray:
        return z + self.R @ z

    def to_z(self, u: np.ndarray) -> np.ndarray:
        """z with S z = u: S is the identity off the changed rows C (and T), so z = u there and
        z_C = S_CC^{-1} (u_C - S_CR u_R) (S_CC: the identity on the vertex rows, the edge rows
        -2w on the diagonal and w at their ends: triangular; T's rows alike)."""
        from scipy.sparse.linalg import spsolve
        changed = self.changed
        S_C = self.S_rows(changed)
        rest = u.copy()
        rest[changed] = 0.0
        z = rest
        z[changed] = spsolve(S_C[:, changed].tocsc(), u[changed] - S_C @ rest)
        return z


def dual_bound_qp(problem: TwoBodyProblem, dual: MortarCoupling, weight: float | None = None,
                  tangential: bool = False) -> BoundQP:
    """The dual mortar condition (``mortar_coupling(..., "dual")``, one row per slave node) as
    bounds, by a change of variables local to the slave's trace (Wohlmuth 2000, Section 4; for
    contact Hueeber & Wohlmuth 2005): with m_i = (master part of row i) / D_i, the row is
    D_i (N_i(u_1) + m_i u_2), N_i the slave's nodal value at node i, so the new variable of a
    slave vertex dof is pi_v = u_1,v + m_v u_2 and that of a slave edge pi_e = N_e(u_1) + m_e u_2
    (the dual projection of the opening at the node), each bounded below by g_i / D_i.

    ``weight`` (P2): the one-body cones' w (``cones.ContactModel.weight``): 4 keeps the midpoint
    variable pi_e (`mortar-nodal`), 6 replaces it by the edge mean of the projection,
    mu_e = (pi_a + pi_b)/6 + 2 pi_e / 3 (`mortar-mean`): in both, with NGSolve's bubble
    c_e = 8 ((u_a + u_b)/2 - N_e(u)) (docs/mathematics.md §3),

        c_e = w (pi_a + pi_b) - 2 w z_e + (8 m_e - 4 m_a - 4 m_b) u_2.

    ``tangential`` (elasticity, 2D, w = 4): also the dual projection of the tangential jump
    [u_t] = t_1 - t_2 (t_k = u_k,x in each body's frame, the component block before the normal
    one) at the slave's nodes, pi_t,i = N_i(t_1) - m_i t_2: the same rows with the master term
    negated, unbounded (``BoundQP.T``).
    """
    upper = problem.upper
    n1, n = upper.ndof, problem.ndof
    if dual.multipliers != "dual":
        raise ValueError("only dual multipliers make the mortar condition a bound")
    w = 4.0 if weight is None else float(weight)
    if tangential and (not upper.physics.rotated_frame or upper.mesh.dim != 2 or (upper.order == 2 and w != 4.0)):
        raise ValueError("the tangential jump's rows are 2D elasticity with nodal edge variables (w = 4) only")
    V, E, ends = upper.vertex_dofs, upper.edge_dofs, upper.end_dofs
    nv = len(V)
    m = (sp.diags(1.0 / dual.D) @ dual.B[:, n1:]).tocsr()            # (rows, n2)
    alpha = dual.g / dual.D
    if len(E) and w == 6.0:
        a, b = _edge_rows(V, ends, n1)
        alpha = np.concatenate([alpha[:nv], (alpha[a] + alpha[b]) / 6.0 + 2.0 * alpha[nv:] / 3.0])
    channels = [_channel(V, E, ends, m, n1, w, 1.0)]
    C, T = np.concatenate([V, E]), np.zeros(0, np.int64)
    if tangential:
        # the tangential component's block comes before the normal one in each body (``fem.friction.friction_variables``)
        shift_1, shift_2 = n1 // 2, problem.lower.ndof // 2
        m_t = m.tocsr(copy=True)
        m_t.indices = m_t.indices - shift_2
        channels.append(_channel(V - shift_1, E - shift_1, ends - shift_1, m_t, n1, w, -1.0))
        T = C - shift_1
    rows, cols, vals = (np.concatenate([part for channel in channels for part in channel[k]]) for k in range(3))
    R = sp.csr_matrix((vals, (rows, cols)), shape=(n, n))
    # K = S^T A S from the slave trace's rows of A (S is the identity elsewhere): A_1's rows with
    # the joint columns (the same arrays, no copy)
    A_1 = upper.A
    slave_rows = sp.csr_matrix((A_1.data, A_1.indices, A_1.indptr), shape=(n1, n), copy=False)
    changed = np.concatenate([C, T])
    P, Q = congruence_terms(slave_rows, identity_plus_rows(R, changed), changed)
    b, free, lift = (np.concatenate([getattr(body, name) for body in problem.bodies]) for name in ("b", "free", "lift"))
    return BoundQP(R, [upper.A, problem.lower.A], (P + P.T + Q).tocsr(), b + R.T @ b, free, lift, C, alpha, dual.D, T)


def _edge_rows(V: np.ndarray, ends: np.ndarray, n1: int) -> tuple[np.ndarray, np.ndarray]:
    """The vertex rows (positions in V) of each slave edge's two ends."""
    row_of_vertex = np.full(n1, -1, np.int64)
    row_of_vertex[V] = np.arange(len(V))
    return row_of_vertex[ends[:, 0]], row_of_vertex[ends[:, 1]]


def _channel(V: np.ndarray, E: np.ndarray, ends: np.ndarray, m: sp.csr_matrix, n1: int, w: float, sign: float):
    """R's entries (rows, cols, vals lists) of one projected quantity on the slave's dofs V, E
    (edge ends ``ends``) with master rows m (joint columns n1 + m's): sign +1 the opening
    (u_1,v = pi_v - m_v u_2), -1 the tangential jump (t_1,v = pi_t,v + m_v t_2). S = I + R,
    R made apart: a COO matrix of all n rows costs seconds at 8e6."""
    nv, ne = len(V), len(E)
    mv = m[:nv].tocoo()
    rows, cols, vals = [V[mv.row]], [n1 + mv.col], [-sign * mv.data]
    if ne:
        a, b = _edge_rows(V, ends, n1)
        rows += [E, E, E]
        cols += [E, ends[:, 0], ends[:, 1]]
        vals += [np.full(ne, -2.0 * w - 1.0), np.full(ne, w), np.full(ne, w)]
        me = (8.0 * m[nv:] - 4.0 * m[a] - 4.0 * m[b]).tocoo()
        rows.append(E[me.row]), cols.append(n1 + me.col), vals.append(sign * me.data)
    return rows, cols, vals


def identity_plus_rows(R: sp.csr_matrix, rows: np.ndarray) -> sp.csr_matrix:
    """The rows ``rows`` of I + R, from R's (I + R itself, an identity of all n rows, is never
    made: 160 MB at 8e6 dofs)."""
    identity = sp.csr_matrix((np.ones(len(rows)), (np.arange(len(rows)), rows)), shape=(len(rows), R.shape[1]))
    return (identity + R[rows]).tocsr()
