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
import scipy.sparse.linalg as spla

from ..mesh.points import evaluate
from .assembly import DiscreteProblem
from .cones import _GL_T, _GL_W, ContactModel, ProblemQP, transformed_matrix
from .edge_functionals import edge_functional_rows, rules_per_edge
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
    variables (u = S z): ``F`` the friction variables (Gamma_C's vertices, then its edges' in
    the order of ``problem.edge_dofs``), ``c`` their weights (quadrature weight times s),
    ``points`` their nodes, ``edge_of_row`` the contact edge of each edge variable. In
    elasticity the normal dofs of Gamma_C are pinned at 0 (bilateral contact, u . n = 0) and
    ``normal`` holds them."""

    problem: DiscreteProblem
    S: sp.csr_matrix
    K: sp.csr_matrix
    K_ngs: object
    b: np.ndarray
    F: np.ndarray
    c: np.ndarray
    edges: ContactEdges          # the P1 embedding in these variables (multigrid, nested start)
    normal: np.ndarray           # the pinned normal dofs (elasticity), else empty
    points: np.ndarray           # (len(F), dim) the node of each friction variable
    edge_of_row: np.ndarray      # the contact edge of each edge variable (F's rows past the vertices)
    # elasticity: the cone variables of the pinned contact variable (u = S_n z_n on its dofs), in
    # which its reaction is the cones' multiplier (``normal_reaction``); None: its vertex hats'
    normal_model: ContactModel | None = None

    def normal_reaction(self, u: np.ndarray) -> np.ndarray:
        """The bilateral contact's reaction on the contact variable's rows (Gamma_C's vertices,
        then its edges): the residual a(u_h, .) - L(.) in the variables of ``normal_model``'s
        cone (the vertex values and the midpoint values or edge means: the multipliers a
        frictionless cone of the model has, ``fem.cones.contact_pressure`` reads them), or, for
        the P_k functionals, on the vertex hats only (as for a solve of one's own)."""
        problem = self.problem
        residual = problem.A @ u - problem.b
        if self.normal_model is None:
            return np.concatenate([residual[problem.vertex_dofs], np.zeros(len(problem.trace.edges))])
        return (self.normal_model.transform(problem).T @ residual)[self.normal]

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
    S = model.transform(problem, edges, ends)
    weights = np.concatenate(friction_weights(problem, model))
    c = weights * np.concatenate(thresholds(case, problem, model))
    trace = problem.trace
    points = np.concatenate([trace.vertex_points, trace.midpoints[:len(edges)]])
    qp = _qp(problem, S, edges, vertices, c, ContactEdges.of_edges(problem, edges, ends), points, np.arange(len(edges)))
    qp.normal_model = model
    return qp


def _qp(problem, S, changed, vertices, c, embedding, points, edge_of_row) -> FrictionQP:
    """The QP of the change of variables ``S`` (the identity off the dofs ``changed``)."""
    K, K_ngs = transformed_matrix(problem, S, rows=changed)
    # bilateral contact: the contact variable's dofs on Gamma_C pinned at 0 (in NGSolve's own
    # variables: its trace then vanishes on all of Gamma_C)
    normal = np.concatenate([problem.vertex_dofs, problem.edge_dofs]) if problem.physics.rotated_frame else np.zeros(0)
    return FrictionQP(problem, S, K, K_ngs, S.T @ problem.b, np.concatenate([vertices, changed]).astype(np.int64), c,
                      embedding, normal.astype(np.int64), points, np.asarray(edge_of_row, np.int64))


def rules_friction_qp(case, problem: DiscreteProblem, rules) -> FrictionQP:
    """P_k (2D) with the friction variables of a cone of edge functionals (``fem.edge_functionals``,
    k - 1 per edge of degree k): the vertex values and, on each edge, its functionals of v_t (the
    values at the k - 1 interior Gauss-Lobatto points: the nodal analogue at degree k; the means
    over k - 1 sub-edges: the mean analogue), in place of the edge's k - 1 dofs (u = S z, S
    block by block per edge). j_h weighs each variable by the interpolatory rule of these k + 1
    functionals (exact on P_k: ``interpolatory_weights``) times s."""
    if problem.trace.faces is not None:
        raise ValueError("friction on a cone of edge functionals is 2D")
    vertices, edges, ends = friction_variables(problem)
    rows = edge_functional_rows(problem, rules)
    if problem.physics.rotated_frame:
        rows = _shifted_columns(rows, edges[0] - problem.edge_dofs[0] if len(edges) else 0)
    block = rows[:, edges].tocsc()
    if block.shape[0] != block.shape[1]:
        raise ValueError("friction on a cone of edge functionals needs k - 1 functionals per contact edge of degree k")
    inverse = spla.inv(block) if block.shape[0] else block
    selection = sp.csr_matrix((np.ones(len(edges)), (np.arange(len(edges)), edges)), shape=(len(edges), problem.ndof))
    keep = np.ones(problem.ndof)
    keep[edges] = 0.0
    S_rows = inverse @ (selection - rows @ sp.diags(keep))
    scatter = sp.csr_matrix((np.ones(len(edges)), (edges, np.arange(len(edges)))), shape=(problem.ndof, len(edges)))
    S = (sp.diags(keep) + scatter @ S_rows).tocsr()
    c, points, end_weights, edge_of_row = _functional_quadrature(case, problem, rules)
    embedding = ContactEdges.of_edges(problem, edges, ends[edge_of_row] if len(edges) else ends, end_weights)
    return _qp(problem, S, edges, vertices, c, embedding, points, edge_of_row)


def _shifted_columns(rows: sp.csr_matrix, shift: int) -> sp.csr_matrix:
    """``rows`` with every column moved by ``shift`` (the contact component's rows read on the
    tangential component: in the rotated frame the two share one scalar basis on Gamma_C)."""
    rows = rows.tocsr(copy=True)
    rows.indices = rows.indices + shift
    return rows


def interpolatory_weights(rule_set: tuple) -> np.ndarray:
    """The weights (w_a, w_b, w_1, ..., w_m) of the rule w_a v(0) + w_b v(1) + sum_j w_j l_j(v)
    exact for the polynomials of degree m + 1 on [0, 1] (the moments int t^p = 1/(p + 1)), for
    the functionals ``rule_set`` (each ((t, w), ...)). The Gauss-Lobatto points give the
    Gauss-Lobatto weights, the sub-edge means 0 at the ends and 1/m each. A negative weight
    would make j_h non-convex: refused."""
    columns = [lambda p: 0.0 ** p, lambda p: 1.0] + [
        (lambda p, rule=rule: sum(w * t ** p for t, w in rule)) for rule in rule_set]
    n = len(columns)
    moments = np.array([[column(p) for column in columns] for p in range(n)])
    weights = np.linalg.solve(moments, 1.0 / np.arange(1, n + 1))
    if (weights < -1e-12).any():
        raise ValueError(f"the functionals {rule_set} give a quadrature with negative weights {weights}: j_h would not be convex")
    return np.maximum(weights, 0.0)


def _functional_quadrature(case, problem: DiscreteProblem, rules):
    """(c: the weight times s of every friction variable, vertices first; their nodes; the
    weights of its edge's two ends in each edge variable for a linear function,
    (sum w (1 - t), sum w t); the edge of each edge variable)."""
    trace, mesh = problem.trace, problem.mesh
    per_edge = rules_per_edge(problem, rules)
    s = case.friction.threshold_function
    vertex_c = np.zeros(len(trace.vertices))
    edge_c, points, end_weights, edge_of_row = [], [], [], []
    ends = np.searchsorted(trace.vertices, trace.edge_vertices)
    length = trace.lengths
    for e, rule_set in enumerate(per_edge):
        weights = interpolatory_weights(rule_set)
        np.add.at(vertex_c, ends[e], length[e] * weights[:2])
        for j, rule in enumerate(rule_set):
            t, w = np.array([p for p, _ in rule]), np.array([q for _, q in rule])
            along = trace.a[e] + t[:, None] * (trace.b[e] - trace.a[e])
            # s where the functional sits: l_j(s) / l_j(1)
            edge_c.append(length[e] * weights[2 + j] * float(evaluate(s, mesh, along) @ w / w.sum()))
            end_weights.append((float(w @ (1.0 - t)), float(w @ t)))
            points.append(trace.a[e] + (w @ t / w.sum()) * (trace.b[e] - trace.a[e]))
            edge_of_row.append(e)
    vertex_c *= evaluate(s, mesh, trace.vertex_points)
    dim = trace.a.shape[1]
    return (np.concatenate([vertex_c, edge_c]), np.concatenate([trace.vertex_points, np.reshape(points, (-1, dim))]),
            np.reshape(end_weights, (-1, 2)), np.array(edge_of_row, np.int64))
