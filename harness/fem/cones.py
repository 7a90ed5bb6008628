"""Discrete contact cones given by nodal functionals, as bound constraints in their own variables.

A cone (``ContactModel``) asks v_h >= alpha at the vertices of Gamma_C and, for P2, one
functional per contact edge:
* ``mean`` -- K_h (Section 3): int_{t_i} v_h >= int_{t_i} alpha; the degrees of freedom of J_h;
* ``midpoint`` -- K~_h (Section 5, before (5.1)): v_h >= alpha at the edge midpoints
  x_{i+1/2}; the degrees of freedom of the Lagrange interpolant I_h;
* none -- P1, whose trace is linear: the vertex values alone make the cone exact.

On a straight edge [a, b] the P2 trace is v(t) = (1-t) v_a + t v_b - c_e t(1-t)/2 with c_e the
hierarchical bubble coefficient, so

    midpoint value = (v_a + v_b)/2 - c_e/8,     edge mean = (v_a + v_b)/2 - c_e/12.

Replacing c_e by the midpoint value (nodal) or by the edge mean (mean) is a local, invertible
change of variables u = S z after which each cone is a set of simple lower bounds on z. With a
gap alpha the bounds are alpha(x_i), alpha(x_{i+1/2}) and the edge means of alpha.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from ..mesh.points import evaluate
from .assembly import ContactTraceFunction, DiscreteProblem
from .nested import cone_prediction
from .sparse import congruence_terms, csr_positions, csr_view

# Gauss-Legendre points on [0, 1] for edge means of the gap (exact for polynomial gaps of
# degree <= 15, far below the discretisation error otherwise).
_GL_T, _GL_W = np.polynomial.legendre.leggauss(8)
_GL_T, _GL_W = 0.5 * (_GL_T + 1.0), 0.5 * _GL_W


# Each edge functional as a rule sum_k w_k v(t_k) on [0, 1], exact for quadratics: the midpoint
# value, or Simpson's rule for the edge mean.
EDGE_RULES = {"midpoint": ((0.5, 1.0),), "edge-mean": ((0.0, 1 / 6), (0.5, 4 / 6), (1.0, 1 / 6))}


@dataclass(frozen=True)
class ContactModel:
    """v_h >= alpha at the vertices of Gamma_C and, if ``edge_functional`` is given ("edge-mean"
    or "midpoint"), that functional of v_h >= the same of alpha on every contact edge."""

    edge_functional: str | None = None

    def __post_init__(self):
        if self.edge_functional not in (None, *EDGE_RULES):
            raise ValueError(f"edge functional must be one of {', '.join(EDGE_RULES)} or None, got {self.edge_functional!r}")

    @property
    def edge_rule(self) -> tuple[tuple[float, float], ...]:
        return EDGE_RULES.get(self.edge_functional, ())

    def _check(self, problem: DiscreteProblem) -> None:
        if problem.order > 2 or (self.edge_functional is not None) != bool(len(problem.edge_dofs)):
            raise ValueError(f"a cone with edge functional {self.edge_functional!r} does not fit an order-{problem.order} space")

    @property
    def bubble_value(self) -> float:
        """The edge functional of the bubble -t(1-t)/2: -1/8 (midpoint) or -1/12 (mean)."""
        return sum(-0.5 * w * t * (1 - t) for t, w in self.edge_rule)

    @property
    def weight(self) -> float:
        """w in c_e = w (v_a + v_b) - 2 w z_e: 4 (nodal) or 6 (mean)."""
        return -0.5 / self.bubble_value

    def constraint_matrix(self, problem: DiscreteProblem) -> sp.csr_matrix:
        """G with G u = (vertex values on Gamma_C, edge functionals): one row per constraint.

        Edge row: (v_a + v_b)/2 + bubble_value * c_e, i.e. c_e/8 (midpoint) or c_e/12 (mean).
        """
        nv, ne = len(problem.vertex_dofs), len(problem.edge_dofs)
        ends = problem.end_dofs[:ne]           # no edge rows for P1
        edge_rows = nv + np.arange(ne)
        rows = np.concatenate([np.arange(nv), edge_rows, edge_rows, edge_rows])
        cols = np.concatenate([problem.vertex_dofs, ends[:, 0], ends[:, 1], problem.edge_dofs])
        vals = np.concatenate([np.ones(nv), np.full(2 * ne, 0.5), np.full(ne, self.bubble_value)])
        return sp.csr_matrix((vals, (rows, cols)), shape=(nv + ne, problem.ndof))

    def constraint_values(self, problem: DiscreteProblem, u: np.ndarray) -> np.ndarray:
        return self.constraint_matrix(problem) @ u

    def edge_values(self, problem: DiscreteProblem, u: np.ndarray) -> np.ndarray:
        return self.constraint_values(problem, u)[len(problem.vertex_dofs):]

    def constrained_dofs(self, problem: DiscreteProblem) -> np.ndarray:
        """Dofs carrying the constrained variables in z: Gamma_C vertices, then Gamma_C edges."""
        return np.concatenate([problem.vertex_dofs, problem.edge_dofs])

    def transform(self, problem: DiscreteProblem, edge: np.ndarray | None = None,
                  ends: np.ndarray | None = None) -> sp.csr_matrix:
        """S with u = S z: identity except the rows of the contact-edge bubbles (``edge``, each
        between the vertex dofs ``ends``; default the contact variable's: ``problem.edge_dofs``,
        ``problem.end_dofs``)."""
        n = problem.ndof
        edge = problem.edge_dofs if edge is None else edge
        ends = problem.end_dofs if ends is None else ends
        if not len(edge):
            return sp.identity(n, format="csr")
        w = self.weight
        diagonal = np.ones(n)
        diagonal[edge] = -2.0 * w
        rows = np.concatenate([np.arange(n), edge, edge])
        cols = np.concatenate([np.arange(n), ends[:, 0], ends[:, 1]])
        vals = np.concatenate([diagonal, np.full(len(edge), w), np.full(len(edge), w)])
        return sp.csr_matrix((vals, (rows, cols)), shape=(n, n))

    def lower_bounds(self, case, problem: DiscreteProblem) -> np.ndarray:
        """Gap values for the constrained variables, in the order of ``constrained_dofs``."""
        mesh, trace = problem.mesh, problem.trace
        n_edges = len(problem.edge_dofs)
        if case.obstacle is None:
            return np.zeros(len(trace.vertices) + n_edges)
        gap = case.obstacle
        at_vertices = evaluate(gap, mesh, trace.vertex_points)
        if self.edge_functional == "midpoint":
            on_edges = evaluate(gap, mesh, trace.midpoints)
        elif self.edge_functional == "edge-mean":
            on_edges = evaluate(gap, mesh, trace.points(_GL_T)) @ _GL_W
        else:
            on_edges = np.zeros(0)
        return np.concatenate([at_vertices, on_edges])


class ProblemQP:
    """What a QP posed on a ``DiscreteProblem`` (its attribute ``problem``) takes from it."""

    @property
    def free(self) -> np.ndarray:
        return self.problem.free

    @property
    def lift(self) -> np.ndarray:
        return self.problem.lift


@dataclass
class GeneralRowsQP(ProblemQP):
    """min 1/2 u'Ku - b'u over u = u_D on Gamma_u and B u >= g, B's first rows the vertex values
    on Gamma_C (``vertex_rows``, in the order of ``problem.vertex_dofs``), then rows on the cells
    of Gamma_C (the 3D triangle means, ``face_means``; edge functionals, ``edge_functionals``)."""

    problem: DiscreteProblem
    K: sp.csr_matrix
    K_ngs: object
    b: np.ndarray
    B: sp.csr_matrix
    g: np.ndarray

    @property
    def n_vertices(self) -> int:
        return len(self.problem.vertex_dofs)


def vertex_rows(case, problem: DiscreteProblem) -> tuple[sp.csr_matrix, np.ndarray]:
    """(rows, values): v_h at each vertex of Gamma_C >= alpha there."""
    vertices = problem.vertex_dofs
    rows = sp.csr_matrix((np.ones(len(vertices)), (np.arange(len(vertices)), vertices)), shape=(len(vertices), problem.ndof))
    values = (np.zeros(len(vertices)) if case.obstacle is None
              else np.ravel(evaluate(case.obstacle, problem.mesh, problem.trace.vertex_points)))
    return rows, values


def end_status(problem: DiscreteProblem, vertex_active: np.ndarray) -> np.ndarray:
    """(m, 2) the status of the vertex constraints at both ends of each contact edge, from one
    per vertex of Gamma_C (in the order of ``problem.vertex_dofs``)."""
    status = dict(zip(problem.trace.vertices.tolist(), vertex_active))
    return np.vectorize(status.get, otypes=[bool])(problem.trace.edge_vertices)


@dataclass
class ContactQP(ProblemQP):
    """The discrete inequality (3.6) or (5.1) as min 1/2 z'Kz - b'z over z = u_D on Gamma_u and
    z[C] >= alpha, in the model's variables z (u = S z). All dofs are kept (Dirichlet ones are
    pinned by the solver), so that z, u and NGSolve vectors share one numbering."""

    model: ContactModel
    problem: DiscreteProblem
    S: sp.csr_matrix
    K: sp.csr_matrix            # S^T A S
    K_ngs: object               # the same as an NGSolve matrix, for the sparse Cholesky
    b: np.ndarray               # S^T (load vector)
    C: np.ndarray               # constrained variables: Gamma_C vertex dofs, then edge dofs
    alpha: np.ndarray           # their lower bounds

    def to_u(self, z: np.ndarray) -> np.ndarray:
        return self.S @ z

    def predicted_active(self, previous: ContactTraceFunction | None) -> np.ndarray | None:
        """Nested iteration: the active set predicted by the previous level's trace
        (``fem.nested.cone_prediction``)."""
        return cone_prediction(previous, self.problem)

    def trace_function(self, u: np.ndarray, active: np.ndarray) -> ContactTraceFunction:
        return contact_trace(self.problem, u, active)


def contact_trace(problem: DiscreteProblem, u: np.ndarray, active: np.ndarray) -> ContactTraceFunction:
    """u_h's trace with the status of a cone's contact rows ``active`` (vertices, then edges)."""
    nv = len(problem.vertex_dofs)
    end_active = end_status(problem, active[:nv])
    # Without edge constraints (P1) an edge is in contact when both its ends are: the linear
    # trace then vanishes on all of it, and the fine vertex at its midpoint inherits that.
    edge_active = active[nv:] if len(problem.edge_dofs) else end_active.all(axis=1)
    return ContactTraceFunction.of(problem, u, end_active, edge_active)


def transformed_matrix(problem: DiscreteProblem, S: sp.csr_matrix, take: bool = False, rows: np.ndarray | None = None):
    """K = S^T A S, as a scipy view and its NGSolve matrix.

    With S = I + D, D nonzero only in the rows E of the contact-edge bubbles,
    K = A + P + P^T + D_E^T A_EE D_E with P = D_E^T A[E, :]: every term is built from the
    O(|E|) rows of A at E, and (each contact edge lying in one triangle) fits A's sparsity
    pattern, so K is A with those few values changed: no product of n x n matrices, no format
    conversion. K goes into a copy of A, or, with ``take``, into A's own memory
    (``DiscreteProblem.take_stiffness``).
    """
    A, E = problem.A, problem.edge_dofs if rows is None else rows
    P, Q = congruence_terms(A, S[E], E)
    rows = np.concatenate([P.row, P.col, Q.row]).astype(np.int64)
    cols = np.concatenate([P.col, P.row, Q.col]).astype(np.int64)
    positions = csr_positions(A, rows, cols)
    if take:
        K, K_ngs = problem.take_stiffness()
    else:
        K_ngs = problem.A_ngs.CreateMatrix()
        K = csr_view(K_ngs)
    np.add.at(K.data, positions, np.concatenate([P.data, P.data, Q.data]))
    return K, K_ngs


def contact_qp(case, problem: DiscreteProblem, model: ContactModel, take_stiffness: bool = False) -> ContactQP:
    """The model's QP on ``problem``; ``take_stiffness`` for the last model of a level: its K
    is made in the memory of the stiffness matrix, which the problem no longer has after."""
    model._check(problem)
    S = model.transform(problem)
    K, K_ngs = transformed_matrix(problem, S, take=take_stiffness)
    return ContactQP(model, problem, S, K, K_ngs, S.T @ problem.b, model.constrained_dofs(problem),
                     model.lower_bounds(case, problem))


def contact_pressure(problem, multipliers: np.ndarray) -> np.ndarray:
    """Discrete contact pressure per cell of Gamma_C (contact edge; 3D: triangle): each vertex
    and edge multiplier shared among the cells holding it in proportion to their size, divided
    by the cell's size. Its integral over Gamma_C is the total discrete contact force sum(lambda)."""
    trace = problem.trace
    size = trace.cell_sizes
    nv, ne = len(problem.vertex_dofs), len(trace.edges)
    lam_vertex = multipliers[:nv]
    lam_edge = multipliers[nv:] if len(problem.edge_dofs) else np.zeros(ne)    # P1: vertices only
    total = np.zeros(len(size))
    for index, lam, count in ((np.searchsorted(trace.vertices, trace.cell_vertices), lam_vertex, nv),
                              (trace.cell_edges, lam_edge, ne)):
        adjacent = np.bincount(index.ravel(), weights=np.repeat(size, index.shape[1]), minlength=count)
        total += (lam[index] * (size[:, None] / adjacent[index])).sum(axis=1)
    return total / size
