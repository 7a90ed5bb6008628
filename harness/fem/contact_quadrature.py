"""The basis of X_h on Gamma_C, sampled at Gauss points of the contact edges: what penalty and
Nitsche methods integrate (their contact terms are integrals over Gamma_C of functions of
u_h and of its normal derivative, which the bound-constrained cones never need).

Each contact edge [a, b] lies in one triangle (a, b, c). On it lambda_c = 0, and with the edge
parameter t, lambda_a = 1 - t, lambda_b = t. NGSolve's hierarchical P2 basis (docs/mathematics.md §3)
has the hats lambda_i and one bubble -lambda_i lambda_j / 2 per edge, so at a point of [a, b]

    trace:  hats a, b: 1 - t, t;   bubble ab: -t (1 - t) / 2   (bubbles ac, bc and the hat c vanish)
    d/dn:   hat i: d_n lambda_i;   bubble ab: -(t d_n lambda_a + (1 - t) d_n lambda_b) / 2;
            bubble ac: -(1 - t) d_n lambda_c / 2;   bubble bc: -t d_n lambda_c / 2,

the gradients of the barycentric coordinates being constant on the triangle. P1 keeps the
hats. tests/test_weak_contact.py checks both operators against NGSolve's own evaluation.

In 3D Gamma_C is a union of triangles (a, b, c) of the boundary: at a point with barycentric
coordinates lambda, the hats are lambda_i and the bubble of side ij is -lambda_i lambda_j / 2
(``ContactQuadrature`` integrates over the triangles; the normal derivatives, which only the
weak methods need, are 2D only).
"""
from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property

import ngsolve as ngs
import numpy as np
import scipy.sparse as sp

from ..mesh.points import TRIANGLE_EDGES, cells, coordinates, evaluate, in_elements

# Gauss points per contact edge: exact for polynomials of degree 7 (the P2 contact terms are of
# degree <= 4 where the bracket [.]_+ does not switch); the few edges where it switches, at a
# contact/separation transition, are integrated approximately, as by any code that assembles
# the nonlinear form with a fixed rule.
GAUSS_POINTS = 4


@dataclass(frozen=True)
class ContactQuadrature:
    """Gauss points on Gamma_C and the basis there: ``T @ u`` gives u_h, ``N @ u`` d_n u_h at
    the points; ``weights`` include the edge lengths, ``h`` is the length of each point's edge."""

    points: np.ndarray          # (q, dim)
    weights: np.ndarray         # (q,)
    h: np.ndarray               # (q,) diameter of the point's cell (contact edge; 3D: triangle)
    edge: np.ndarray            # (q,) index of the point's cell (in problem.trace's edges; 3D: its faces)
    T: sp.csr_matrix            # (q, ndof) trace values of the basis (of the contact variable)
    normals: np.ndarray         # (q, dim) outward unit normal at each point
    # what ``N`` is made from, when it is first asked for, for a 2D scalar problem: its space,
    # trace and the points' edge parameters (not the problem: the problem's caches hold
    # quadratures, and a cycle would keep its matrices alive until a full garbage collection)
    _flux: tuple | None = field(default=None, repr=False, compare=False)

    @cached_property
    def N(self) -> sp.csr_matrix | None:
        """(q, ndof) outward normal derivatives of the basis at the points (2D scalar problems,
        else None); made on first use: only the weak methods and the estimator read it, and
        the error measurement, the loads and the best approximation make quadratures too."""
        if self._flux is None:
            return None
        return _normal_derivatives(*self._flux, self.edge, self.T.shape)

    def edge_means(self, values: np.ndarray) -> np.ndarray:
        """Mean over each contact edge of a function given at the points."""
        n_edges = self.edge.max() + 1 if len(self.edge) else 0
        integral = np.bincount(self.edge, weights=self.weights * values, minlength=n_edges)
        return integral / np.bincount(self.edge, weights=self.weights, minlength=n_edges)


def gauss(points: int) -> tuple[np.ndarray, np.ndarray]:
    """Gauss-Legendre points and weights on [0, 1]."""
    t, w = np.polynomial.legendre.leggauss(points)
    return 0.5 * (t + 1.0), 0.5 * w


def graded(points: int, depth: int = 30) -> tuple[np.ndarray, np.ndarray]:
    """A composite Gauss rule on [0, 1] graded geometrically towards both ends (intervals
    [2^-k-1, 2^-k] down to 2^-depth, and their mirror images): exact to round-off for integrands
    like r^{-1/2} p(r) at an end, which a Gauss rule integrates with an O(1) relative error."""
    t, w = gauss(points)
    edges = np.concatenate([[0.0], 0.5 ** np.arange(depth, 0, -1)])         # 0, 2^-depth, ..., 1/2
    left_t = np.concatenate([a + t * (b - a) for a, b in zip(edges[:-1], edges[1:])])
    left_w = np.concatenate([w * (b - a) for a, b in zip(edges[:-1], edges[1:])])
    return np.concatenate([left_t, 1.0 - left_t[::-1]]), np.concatenate([left_w, left_w[::-1]])


def contact_quadrature(problem, points_per_edge: int = GAUSS_POINTS, graded_at: np.ndarray | None = None) -> ContactQuadrature:
    """Gauss points of ``problem``'s contact edges and its basis (order 1 or 2) there; on the
    edges with an end at one of the vertices ``graded_at`` (singular points), the ``graded``
    rule instead. In 3D: a Gauss rule on every triangle of Gamma_C, of the degree
    ``points_per_edge`` Gauss points integrate exactly (``graded_at`` is empty in 3D)."""
    if problem.trace.faces is not None:
        return _face_quadrature(problem, 2 * points_per_edge - 1)
    trace = problem.trace
    m = len(trace.edges)
    rules = [gauss(points_per_edge), graded(points_per_edge)]
    singular = np.zeros(m, bool) if graded_at is None else np.isin(trace.edge_vertices, graded_at).any(axis=1)
    rule_of = singular.astype(int)
    edge = np.concatenate([np.full(len(rules[r][0]), k) for k, r in enumerate(rule_of)]).astype(np.int64)
    T_t = np.concatenate([rules[r][0] for r in rule_of])
    unit_w = np.concatenate([rules[r][1] for r in rule_of])
    la, lb = 1.0 - T_t, T_t
    # the contact variable's dofs (``discrete``): u_h itself, or c = -u_h . n in elasticity
    cols_T = [problem.end_dofs[edge, 0], problem.end_dofs[edge, 1]]
    vals_T = [la, lb]
    if problem.order == 2:
        cols_T.append(problem.edge_dofs[edge])
        vals_T.append(-0.5 * la * lb)
    shape = (len(edge), problem.ndof)
    points = trace.a[edge] + T_t[:, None] * (trace.b - trace.a)[edge]
    in_elements(problem.mesh, points, trace.volumes[edge])
    return ContactQuadrature(
        points=points,
        weights=trace.lengths[edge] * unit_w,
        h=trace.lengths[edge],
        edge=edge,
        T=_rows(cols_T, vals_T, shape),
        normals=trace.normals[edge],
        _flux=(problem.fes, trace, T_t) if problem.physics.flux_rows else None,
    )


def _face_quadrature(problem, degree: int) -> ContactQuadrature:
    """NGSolve's Gauss rule of ``degree`` on every triangle of a 3D Gamma_C."""
    trace, faces = problem.trace, problem.trace.faces
    rule = ngs.IntegrationRule(ngs.TRIG, degree)
    xi = np.array([ip.point[:2] for ip in rule])
    lam = np.column_stack([1.0 - xi.sum(axis=1), xi])                 # (k, 3) barycentric
    unit_w = 2.0 * np.array([ip.weight for ip in rule])               # the reference triangle's area is 1/2
    corners = faces.corners(trace)                                     # (f, 3, 3)
    area = 0.5 * np.linalg.norm(np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]), axis=1)
    diameter = np.linalg.norm(corners - np.roll(corners, -1, axis=1), axis=2).max(axis=1)
    f, k = len(area), len(unit_w)
    face = np.repeat(np.arange(f), k)
    vertex_dof = problem.vertex_dofs[np.searchsorted(trace.vertices, faces.vertices)]    # (f, 3)
    cols_T = [vertex_dof[face, c] for c in range(3)]
    vals_T = [np.tile(lam[:, c], f) for c in range(3)]
    if problem.order == 2:
        for side in range(3):           # side k joins corners k and k+1
            cols_T.append(problem.edge_dofs[faces.edges[face, side]])
            vals_T.append(np.tile(-0.5 * lam[:, side] * lam[:, (side + 1) % 3], f))
    points = np.einsum("kc,fcd->fkd", lam, corners).reshape(-1, 3)
    in_elements(problem.mesh, points, np.repeat(faces.volumes, len(lam)))
    return ContactQuadrature(
        points=points,
        weights=np.repeat(area, k) * np.tile(unit_w, f),
        h=np.repeat(diameter, k),
        edge=face,
        T=_rows(cols_T, vals_T, (f * k, problem.ndof)),
        normals=faces.normals[face],
    )


def _normal_derivatives(fes, trace, T_t: np.ndarray, edge: np.ndarray, shape) -> sp.csr_matrix:
    """The outward normal derivative of every scalar basis function at the points (Nitsche's
    flux term; see the module docstring)."""
    mesh, order = fes.mesh, fes.globalorder
    m = len(trace.edges)
    a, b = trace.edge_vertices.T
    c = trace.opposite                                  # vertex c of the triangle on each edge
    # each contact triangle's dofs: one per local vertex (in the cell table's order), then, for
    # P2, one per side in the order of TRIANGLE_EDGES (one call per triangle, no node objects)
    dofs = np.array([fes.GetDofNrs(ngs.ElementId(ngs.VOL, int(t))) for t in trace.volumes], dtype=np.int64)
    local = cells(mesh)[trace.volumes]
    if not all(((local == v[:, None]).sum(axis=1) == 1).all() for v in (a, b, c)):
        raise RuntimeError("a contact edge's triangle does not hold its vertices and the opposite one")
    vertex_dofs = np.column_stack([(dofs[:, :3] * (local == v[:, None])).sum(axis=1) for v in (a, b, c)])
    edge_dofs = np.zeros((m, 3), dtype=np.int64)        # bubble dofs of ab, ac, bc (order 2)
    if order == 2:
        for k, (p, q) in enumerate(((a, b), (a, c), (b, c))):
            for side, (i, j) in enumerate(TRIANGLE_EDGES):
                joins = ((local[:, i] == p) & (local[:, j] == q)) | ((local[:, i] == q) & (local[:, j] == p))
                edge_dofs[joins, k] = dofs[joins, 3 + side]
    grad = _barycentric_gradients(trace.a, trace.b, coordinates(mesh)[c])    # (m, 3, 2): a, b, c
    dn = np.einsum("mij,mj->mi", grad, trace.normals)                   # (m, 3)
    la, lb = 1.0 - T_t, T_t
    dna, dnb, dnc = (dn[edge, i] for i in range(3))
    cols_N = [vertex_dofs[edge, 0], vertex_dofs[edge, 1], vertex_dofs[edge, 2]]
    vals_N = [dna, dnb, dnc]
    if order == 2:
        cols_N += [edge_dofs[edge, 0], edge_dofs[edge, 1], edge_dofs[edge, 2]]
        vals_N += [-0.5 * (lb * dna + la * dnb), -0.5 * la * dnc, -0.5 * lb * dnc]
    return _rows(cols_N, vals_N, shape)


def _rows(columns: list, values: list, shape) -> sp.csr_matrix:
    rows = np.tile(np.arange(shape[0]), len(columns))
    return sp.csr_matrix((np.concatenate(values), (rows, np.concatenate(columns))), shape=shape)


def _barycentric_gradients(a: np.ndarray, b: np.ndarray, c: np.ndarray) -> np.ndarray:
    """Gradients of lambda_a, lambda_b, lambda_c on each triangle (a, b, c): (m, 3, 2)."""
    J = np.stack([b - a, c - a], axis=2)               # columns: the edges from a
    # (lambda_b, lambda_c) = J^{-1} (x - a): their gradients are the rows of J^{-1}
    inverse = np.linalg.inv(J)
    grad_b, grad_c = inverse[:, 0, :], inverse[:, 1, :]
    return np.stack([-grad_b - grad_c, grad_b, grad_c], axis=1)


def at_points(cf, mesh, quadrature: ContactQuadrature) -> np.ndarray:
    """A CoefficientFunction (or None: zero) at the quadrature points."""
    if cf is None:
        return np.zeros(len(quadrature.weights))
    return evaluate(cf, mesh, quadrature.points)


def exact_pressure(case, problem, quadrature: ContactQuadrature) -> np.ndarray:
    """The exact contact pressure at the quadrature points: lambda = d_n u - g_C, or
    p = -(sigma_n(u) - g_n) in elasticity (``physics``)."""
    return case.physics.pressure(case, problem.mesh, quadrature.points, quadrature.normals)
