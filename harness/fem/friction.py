"""The paper's two P2 ideas carried over to Tresca friction (``problem.friction``): the friction
functional j(v) = int_{Gamma_C} s |v_t| by a quadrature in the variables of a contact model
(``fem.cones.ContactModel``), so that the discrete problem is

    minimise 1/2 z^T K z - b^T z + sum_i c_i |z_i|  over z = u_D on Gamma_u   (u = S z),

with c_i >= 0, one term per *friction variable* z_i: the slip v_t (v itself in the scalar
model, the tangential displacement in 2D elasticity) at Gamma_C's nodes, in the model's
variables. Its dual is a bound-constrained problem for the nodal friction forces
lambda_i = (b - K z)_i in [-c_i, c_i] (Stadler 2004, SIAM J. Optim. 15; the multiplier form
|lambda_h| <= s of the mixed methods), which ``solvers.friction`` solves exactly.

The quadratures, by model (2D: a cell is an edge; 3D: a triangle of Gamma_C):

* ``midpoint`` (the nodal analogue, K~_h of Section 5): s |v| at the P2 nodes with the weights of
  the P2 Lagrange interpolant's quadrature -- Simpson (|e|/6, 4|e|/6, |e|/6) on an edge; on a
  triangle 0 at the vertices and |T|/3 at the edge midpoints. Positive weights: j_h is convex,
  and its multiplier is a two-sided bound per node;
* ``edge-mean`` (the mean analogue, K_h of Section 3): |e| (mean of s on e) |mean of v on e| per
  edge, nothing at the vertices. It equals int_e s |v| whenever v keeps one sign on e and s is
  constant there (the exact rule for quadratics in the model's variables is |e| times the
  mean), and its multiplier is piecewise constant with |lambda_e| <= s_e: the classical P0
  multiplier of the mixed method, stable beside P2 (the edge bubbles). 2D only (in 3D the
  triangle means are general rows, ``fem.face_means``);
* none (P1): s |v| at the vertices with the lumped (trapezoidal) weights |e|/2, resp. |T|/3.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from ..mesh.points import evaluate
from .assembly import DiscreteProblem
from .cones import _GL_T, _GL_W, ContactModel, ProblemQP, transformed_matrix
from .p1_embedding import ContactEdges

# the quadrature weights of a cell's vertices and edges (fractions of its size), by model and
# dimension of Gamma_C's cells
WEIGHTS = {
    ("midpoint", 2): (1 / 6, 4 / 6), ("midpoint", 3): (0.0, 1 / 3),
    ("edge-mean", 2): (0.0, 1.0),
    (None, 2): (1 / 2, 0.0), (None, 3): (1 / 3, 0.0),
}


def friction_weights(problem: DiscreteProblem, model: ContactModel) -> tuple[np.ndarray, np.ndarray]:
    """The quadrature weights of j_h at Gamma_C's vertices (in the order of ``problem.vertex_dofs``)
    and at its edges (of ``problem.edge_dofs``; none for P1): each cell's size times its vertex
    and edge fractions (``WEIGHTS``), summed over the cells sharing the node."""
    trace = problem.trace
    cell_dim = 2 if trace.faces is None else 3
    key = (model.edge_functional, cell_dim)
    if key not in WEIGHTS:
        raise ValueError(f"no friction quadrature for the {model.edge_functional} model on {cell_dim}D bodies "
                         f"(the triangle means of 3D are general rows)")
    vertex_fraction, edge_fraction = WEIGHTS[key]
    size = trace.cell_sizes
    cell_vertices = np.searchsorted(trace.vertices, trace.cell_vertices)
    at_vertices = np.bincount(cell_vertices.ravel(), weights=np.repeat(size * vertex_fraction, cell_vertices.shape[1]),
                              minlength=len(trace.vertices))
    at_edges = np.bincount(trace.cell_edges.ravel(), weights=np.repeat(size * edge_fraction, trace.cell_edges.shape[1]),
                           minlength=len(trace.edges))
    return at_vertices, (at_edges if len(problem.edge_dofs) else np.zeros(0))


def thresholds(case, problem: DiscreteProblem, model: ContactModel) -> tuple[np.ndarray, np.ndarray]:
    """s where each quadrature point of j_h sits: at the vertices, and at the edge midpoints
    (nodal) or as the edge's mean of s (the mean analogue)."""
    s, mesh, trace = case.friction.threshold_function, problem.mesh, problem.trace
    at_vertices = evaluate(s, mesh, trace.vertex_points)
    if not len(problem.edge_dofs):
        return at_vertices, np.zeros(0)
    if model.edge_functional == "edge-mean":
        return at_vertices, evaluate(s, mesh, trace.points(_GL_T)) @ _GL_W
    return at_vertices, evaluate(s, mesh, trace.midpoints)


@dataclass
class FrictionQP(ProblemQP):
    """min 1/2 z'Kz - b'z + sum_i c_i |z[F_i]| over z = lift where not ``free``, in the model's
    variables (u = S z): ``F`` the friction variables (Gamma_C's vertices, then its edges, in
    the order of ``problem.vertex_dofs`` and ``problem.edge_dofs``), ``c`` their weights
    (quadrature weight times s). In elasticity the normal dofs of Gamma_C are pinned at 0
    (bilateral contact, u . n = 0) and ``normal`` holds them."""

    model: ContactModel
    problem: DiscreteProblem
    S: sp.csr_matrix
    K: sp.csr_matrix
    K_ngs: object
    b: np.ndarray
    F: np.ndarray
    c: np.ndarray
    edges: ContactEdges          # the P1 embedding in these variables (multigrid, nested start)
    normal: np.ndarray           # the pinned normal dofs (elasticity), else empty

    @property
    def free(self) -> np.ndarray:
        free = self.problem.free.copy()
        free[self.normal] = False
        return free

    @property
    def lift(self) -> np.ndarray:
        lift = self.problem.lift.copy()
        lift[self.normal] = 0.0
        return lift

    def to_u(self, z: np.ndarray) -> np.ndarray:
        return self.S @ z

    @property
    def points(self) -> np.ndarray:
        """The friction variables' nodes: Gamma_C's vertices, then its edges' midpoints."""
        trace = self.problem.trace
        return np.concatenate([trace.vertex_points, trace.midpoints[:len(self.problem.edge_dofs)]])


def friction_variables(problem: DiscreteProblem) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(the friction dofs at Gamma_C's vertices, at its edges, the ends of each edge): the
    contact variable's own in the scalar model, the tangential component's in elasticity (in the
    rotated frame the component before the contact one, ``fem.rotated_frame``)."""
    if not problem.physics.rotated_frame:
        return problem.vertex_dofs, problem.edge_dofs, problem.end_dofs[:len(problem.edge_dofs)]
    if problem.mesh.dim != 2:
        raise ValueError("Tresca friction on the nodal cones is 2D in elasticity: in 3D the slip is a 2-vector and "
                         "its set a disc (use a contact law: Nitsche or penalty)")
    block = problem.ndof // problem.physics.components
    return problem.vertex_dofs - block, problem.edge_dofs - block, problem.end_dofs[:len(problem.edge_dofs)] - block


def friction_qp(case, problem: DiscreteProblem, model: ContactModel) -> FrictionQP:
    """The model's friction problem on ``problem`` (the case's ``friction`` a ``Tresca``)."""
    model._check(problem)
    vertices, edges, ends = friction_variables(problem)
    normal = np.concatenate([problem.vertex_dofs, problem.edge_dofs]) if problem.physics.rotated_frame else np.zeros(0, np.int64)
    changed = np.concatenate([edges, problem.edge_dofs]) if problem.physics.rotated_frame else edges
    changed_ends = np.concatenate([ends, problem.end_dofs[:len(problem.edge_dofs)]]) if problem.physics.rotated_frame else ends
    S = model.transform(problem, changed, changed_ends)
    K, K_ngs = transformed_matrix(problem, S, rows=changed)
    weights = np.concatenate(friction_weights(problem, model))
    c = weights * np.concatenate(thresholds(case, problem, model))
    return FrictionQP(model, problem, S, K, K_ngs, S.T @ problem.b, np.concatenate([vertices, edges]).astype(np.int64), c,
                      ContactEdges.of_edges(problem, changed, changed_ends), normal.astype(np.int64))
