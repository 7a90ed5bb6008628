"""The mortar coupling of two bodies on non-matching meshes along a straight Gamma_C (the
paper's Section 6).

Each body is a ``DiscreteProblem`` in its own frame (``problem.bodies``: the lower body is the
mirror image of the upper one, so both see Gamma_C on y = 0 with the body above it), whose
contact variable c_k is u_k (scalar) or -u_k . n_k (elasticity, the rotated frame). In both
physics the opening of the interface is c_1 + c_2 (docs/mathematics.md §8: the lower body's
scalar variable is -u_2, whose mirror image solves the upper body's problem), and the contact
condition is c_1 + c_2 >= 2 * obstacle.

The condition is imposed weakly against a multiplier space M_h on the *slave* body's trace
(body 1): for every multiplier basis function psi_i,

    int_{Gamma_C} psi_i (c_1 + c_2) ds  >=  int_{Gamma_C} psi_i 2 obstacle ds,

one row of B z >= g with z = (u_1, u_2). The integrals of psi_i (slave, piecewise P_k on the
slave's edges) against the master's basis functions (piecewise P_k on the master's edges) are
computed exactly: on the segments of the *intersection* of the two trace meshes both are
polynomials of degree k, and a Gauss rule of ``POINTS`` points integrates their product
exactly (the gap, a given function, is integrated by the same rule).

Multipliers (``MULTIPLIERS``), both on the slave's Lagrange nodes (vertices, and for P2 the
edge midpoints):

* ``standard``: psi_i = phi_i, the slave's Lagrange basis (continuous piecewise P_k): Ben
  Belgacem, Hild & Laborde, Math. Models Methods Appl. Sci. 9 (1999) for P1; the continuous
  piecewise quadratic multipliers of Hild & Laborde, Appl. Numer. Math. 41 (2002) for P2.
  The rows couple neighbouring slave nodes: a general-constraint QP.
* ``dual``: biorthogonal to the slave's Lagrange basis, edge by edge, psi^e = D_e M_e^{-1}
  phi^e (M_e the edge's mass matrix, D_e = diag(int phi^e)): int psi_i phi_j = delta_ij D_ii
  (Wohlmuth, SIAM J. Numer. Anal. 38 (2000); for contact Hueeber & Wohlmuth, Comput. Methods
  Appl. Mech. Engrg. 194 (2005)). A row then holds the slave's value at its own node only:
  after a local change of variables the constraint is a bound, and on matching meshes the
  condition is the one-body nodal one (for P1 `p1`'s, for P2 `nodal`'s K~_h).

``edge_functional="edge-mean"`` (P2 only) is `mean`'s counterpart: with Pi the dual mortar projection
onto the slave's P2 trace (Pi w = sum_j (int psi_j w / D_jj) phi_j), Pi(c_1 + c_2) >= 2 obstacle
at the slave's vertices (the dual rows of the vertices) and its mean over each slave edge
(Simpson's rule on Pi, exact: 1/6, 2/3, 1/6 of the vertex, midpoint, vertex rows over D) >= that
of 2 obstacle. On matching meshes: `mean`'s K_h.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from ..mesh.points import evaluate
from .assembly import DiscreteProblem

MULTIPLIERS = ("dual", "standard")
# Gauss points per intersection segment: exact for the products of two P2 traces (degree 4)
# with room for a smooth gap
POINTS = 6
# Gamma_C of both bodies must lie on y = 0 (the mirror image of the lower body): to this tolerance
FLAT = 1e-12


@dataclass(frozen=True)
class TraceElements:
    """One body's trace on Gamma_C as 1D elements [left, right] on the x axis, sorted, with the
    dofs of the contact variable's trace basis on each: [left end, right end] (P1) and the
    edge bubble -t(1-t)/2 (P2, NGSolve's hierarchical basis, docs/mathematics.md §3)."""

    left: np.ndarray        # (m,)
    right: np.ndarray       # (m,)
    dofs: np.ndarray        # (m, 2 or 3)
    vertex_index: np.ndarray  # (m, 2): position of the left and right end in ``mesh.trace.ContactTrace.vertices``
    edge_index: np.ndarray    # (m,): position of the edge in ``mesh.trace.ContactTrace`` (its order)

    @classmethod
    def of(cls, problem: DiscreteProblem) -> "TraceElements":
        trace = problem.trace
        if trace.dim != 2:
            raise ValueError("two bodies are coupled on a 2D Gamma_C (a line) only")
        if max(np.abs(trace.a[:, 1]).max(), np.abs(trace.b[:, 1]).max()) > FLAT:
            raise ValueError("two bodies need Gamma_C on the line y = 0 in each body's frame")
        xa, xb = trace.a[:, 0], trace.b[:, 0]
        swap = xa > xb
        ends = np.where(swap[:, None], problem.end_dofs[:, ::-1], problem.end_dofs)
        vertex_index = np.searchsorted(trace.vertices, trace.edge_vertices)
        vertex_index = np.where(swap[:, None], vertex_index[:, ::-1], vertex_index)
        dofs = np.column_stack([ends, problem.edge_dofs]) if len(problem.edge_dofs) else ends
        order = np.argsort(np.minimum(xa, xb))
        return cls(np.minimum(xa, xb)[order], np.maximum(xa, xb)[order], dofs[order], vertex_index[order], order)

    def locate(self, x: np.ndarray) -> np.ndarray:
        """The element holding each of ``x`` (interior points of the elements)."""
        return np.clip(np.searchsorted(self.left, x, side="right") - 1, 0, len(self.left) - 1)

    def parameters(self, x: np.ndarray, e: np.ndarray) -> np.ndarray:
        """The local parameter t in [0, 1] of the points x (segments, points) on their elements e
        (one per segment)."""
        return (x - self.left[e][:, None]) / (self.right[e] - self.left[e])[:, None]


def trace_at(problem: DiscreteProblem, x: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(dofs (q, k + 1), basis (q, k + 1), h (q,)): the trace element of ``problem`` holding each
    point (x, 0) of Gamma_C, its contact variable's dofs and their trace basis there, and the
    element's length; ValueError where a point lies beyond the body's Gamma_C."""
    side = TraceElements.of(problem)
    reach = FLAT * max(1.0, np.abs(x).max(initial=0.0))
    if len(x) and (x.min() < side.left[0] - reach or x.max() > side.right[-1] + reach):
        raise ValueError("the upper body's Gamma_C reaches beyond the lower body's: no jump there")
    e = side.locate(x)
    h = side.right[e] - side.left[e]
    return side.dofs[e], hierarchical_basis(np.clip((x - side.left[e]) / h, 0.0, 1.0), problem.order), h


def trace_rows_at(problem: DiscreteProblem, x: np.ndarray, tangential: bool = False) -> sp.csr_matrix:
    """(q, ndof) the rows of ``problem``'s contact variable at the points (x, 0) of Gamma_C
    (``trace_at``); ``tangential`` (elasticity): of u . e_x, whose block comes one before the
    normal one (``fem.assembly.DiscreteProblem.tangential_dofs``)."""
    dofs, basis, _ = trace_at(problem, x)
    if tangential:
        dofs = dofs - problem.ndof // 2
    rows = np.repeat(np.arange(len(x)), dofs.shape[1])
    return sp.csr_matrix((basis.ravel(), (rows, dofs.ravel())), shape=(len(x), problem.ndof))


def hierarchical_basis(t: np.ndarray, order: int) -> np.ndarray:
    """The trace basis of ``TraceElements.dofs`` at parameters t in [0, 1]: (len(t), order + 1)."""
    columns = [1.0 - t, t] + ([-0.5 * t * (1.0 - t)] if order == 2 else [])
    return np.column_stack(columns)


def lagrange_basis(t: np.ndarray, order: int) -> np.ndarray:
    """The slave's Lagrange trace basis at t: nodes left, right (and midpoint for P2)."""
    if order == 1:
        return np.column_stack([1.0 - t, t])
    return np.column_stack([(1.0 - t) * (1.0 - 2.0 * t), t * (2.0 * t - 1.0), 4.0 * t * (1.0 - t)])


def dual_coefficients(order: int) -> np.ndarray:
    """C with psi = C phi on one edge (reference [0, 1]; the same on every edge: mass matrix
    and integrals scale alike): C = D M^{-1}, so that int psi_i phi_j = delta_ij int phi_j."""
    t, w = np.polynomial.legendre.leggauss(POINTS)
    t, w = 0.5 * (t + 1.0), 0.5 * w
    phi = lagrange_basis(t, order)
    mass = phi.T @ (w[:, None] * phi)
    return np.diag(phi.T @ w) @ np.linalg.inv(mass)


@dataclass(frozen=True)
class MortarCoupling:
    """The rows B z >= g of the mortar condition for z = (slave dofs, master dofs), one per
    slave Lagrange node: its vertices in the order of the slave trace's vertices, then (P2) its
    edge midpoints in the order of its edges (``mesh.trace.ContactTrace``) -- the order of the one-body cones'
    constrained variables (``cones.ContactModel.constrained_dofs``).

    ``D``: int psi_i over Gamma_C per row (the weight of the row: for dual multipliers the
    diagonal of the slave block, int psi_i phi_i = int phi_i)."""

    B: sp.csr_matrix
    g: np.ndarray
    D: np.ndarray
    multipliers: str

    @property
    def rows(self) -> int:
        return self.B.shape[0]


def _node_rows(slave: TraceElements, n_vertices: int, order: int) -> np.ndarray:
    """Per slave element, the row of each of its Lagrange nodes: left, right (, midpoint)."""
    rows = slave.vertex_index
    if order == 2:
        rows = np.column_stack([rows, n_vertices + slave.edge_index])
    return rows


def intersection(slave: TraceElements, master: TraceElements) -> np.ndarray:
    """The segments of the common refinement of the two trace meshes on their overlap."""
    low = max(slave.left[0], master.left[0])
    high = min(slave.right[-1], master.right[-1])
    if not high > low:
        raise ValueError("the two bodies' Gamma_C do not overlap")
    breaks = np.unique(np.concatenate([slave.left, slave.right, master.left, master.right]))
    # points closer than round-off are one point: coinciding vertices of the two meshes
    breaks = breaks[np.concatenate([[True], np.diff(breaks) > 1e-13 * max(1.0, high - low)])]
    breaks = breaks[(breaks >= low - 1e-14) & (breaks <= high + 1e-14)]
    return np.column_stack([breaks[:-1], breaks[1:]])


def mortar_coupling(slave: DiscreteProblem, master: DiscreteProblem, obstacle=None, multipliers: str = "dual",
                    edge_functional: str = "midpoint") -> MortarCoupling:
    """The mortar rows of the opening c_slave + c_master >= 2 obstacle (module docstring).

    ``obstacle`` (a CoefficientFunction of the slave's frame, or None for 0) is evaluated on the
    slave mesh. ``edge_functional``: "midpoint" (the rows of the multipliers themselves) or
    "edge-mean" (P2 dual only: vertex rows, then the slave edges' means of the dual projection)."""
    if multipliers not in MULTIPLIERS:
        raise ValueError(f"multipliers must be one of {', '.join(MULTIPLIERS)}, got {multipliers!r}")
    order = slave.order
    if master.order != order:
        raise ValueError("the two bodies must have the same finite element order")
    if edge_functional == "edge-mean" and (order != 2 or multipliers != "dual"):
        raise ValueError("the edge-mean mortar condition is for P2 with dual multipliers")
    mine, theirs = TraceElements.of(slave), TraceElements.of(master)
    segments = intersection(mine, theirs)
    t, w = np.polynomial.legendre.leggauss(POINTS)
    t, w = 0.5 * (t + 1.0), 0.5 * w
    x = segments[:, :1] + t[None, :] * (segments[:, 1:] - segments[:, :1])          # (s, q)
    weights = (segments[:, 1] - segments[:, 0])[:, None] * w[None, :]                # (s, q)
    e_slave, e_master = mine.locate(x.mean(axis=1)), theirs.locate(x.mean(axis=1))
    t_slave, t_master = mine.parameters(x, e_slave), theirs.parameters(x, e_master)
    psi = lagrange_basis(t_slave.ravel(), order)                                     # (s q, k+1)
    if multipliers == "dual":
        psi = psi @ dual_coefficients(order).T
    psi = psi.reshape(*x.shape, -1) * weights[..., None]                              # weighted, (s, q, k+1)
    n_vertices = len(slave.trace.vertices)
    n_rows = n_vertices + (len(slave.trace.edges) if order == 2 else 0)
    node_rows = _node_rows(mine, n_vertices, order)[e_slave]                           # (s, k+1)

    def block(elements, e, t_local, n_columns, offset):
        basis = hierarchical_basis(t_local.ravel(), order).reshape(*x.shape, -1)       # (s, q, k+1)
        local_matrix = np.einsum("sqi,sqj->sij", psi, basis)
        columns = elements.dofs[e]                                                    # (s, k+1)
        rows = np.broadcast_to(node_rows[:, :, None], local_matrix.shape)
        cols = np.broadcast_to(columns[:, None, :], local_matrix.shape) + offset
        return sp.csr_matrix((local_matrix.ravel(), (rows.ravel(), cols.ravel())), shape=(n_rows, n_columns))

    n = slave.ndof + master.ndof
    B = block(mine, e_slave, t_slave, n, 0) + block(theirs, e_master, t_master, n, slave.ndof)
    if obstacle is None:
        gap_values = np.zeros(x.shape)
    else:
        points = np.stack([x, np.zeros_like(x)], axis=-1)
        gap_values = evaluate(obstacle, slave.mesh, points)
    g = np.bincount(node_rows.ravel(), weights=np.einsum("sqi,sq->si", psi, 2.0 * gap_values).ravel(), minlength=n_rows)
    D = np.bincount(node_rows.ravel(), weights=psi.sum(axis=1).ravel(), minlength=n_rows)
    coupling = MortarCoupling(B.tocsr(), g, D, multipliers)
    return coupling if edge_functional == "midpoint" else _edge_means(coupling, slave, mine)


def _edge_means(coupling: MortarCoupling, slave: DiscreteProblem, mine: TraceElements) -> MortarCoupling:
    """`mean`'s rows from the dual ones: the vertex rows, and per slave edge the integral of the
    dual projection Pi over it, |t| (pi_left/6 + 2 pi_mid/3 + pi_right/6), pi_j = row_j / D_j
    (Simpson's rule, exact on P2), so that on matching meshes it is the edge mean of `mean`."""
    n_vertices = len(slave.trace.vertices)
    m = len(slave.trace.edges)
    length = mine.right - mine.left
    # per slave edge (in trace order): its left and right vertex rows
    ends = np.empty((m, 2), np.int64)
    ends[mine.edge_index] = mine.vertex_index
    lengths = np.empty(m)
    lengths[mine.edge_index] = length
    scale = 1.0 / coupling.D
    rows = np.concatenate([np.arange(n_vertices), np.repeat(n_vertices + np.arange(m), 3)])
    cols = np.concatenate([np.arange(n_vertices), np.column_stack([ends, n_vertices + np.arange(m)]).ravel()])
    weights = np.column_stack([lengths / 6, lengths / 6, 2 * lengths / 3])
    values = np.concatenate([np.ones(n_vertices), (weights * scale[np.column_stack([ends, n_vertices + np.arange(m)])]).ravel()])
    T = sp.csr_matrix((values, (rows, cols)), shape=(coupling.rows, coupling.rows))
    B, g = (T @ coupling.B).tocsr(), T @ coupling.g
    D = np.concatenate([coupling.D[:n_vertices], lengths])
    return MortarCoupling(B, g, D, "dual mean")
