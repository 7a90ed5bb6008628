"""The basis of X_h on Gamma_C, sampled at Gauss points of its cells (edges in 2D, triangles in
3D): what the weak methods integrate (their contact terms are integrals over Gamma_C of the
contact variable and of its flux, which the bound-constrained cones never need).

Two kinds of rows, in every physics and dimension (``problem.physics``: the contact variable
c(v) and its flux, u and d_n u for the scalar problem, -v . n and -sigma_n(v) in elasticity):

* ``T``, the trace of c(v): built here from the hierarchical basis of the contact dofs. Each
  contact edge [a, b] lies in one triangle; on it, with the edge parameter t, the hats are
  1 - t, t and the P2 bubble -t (1 - t) / 2 (NGSolve's hierarchical P2 basis, docs/mathematics.md
  §3). In 3D, at a point of a triangle of Gamma_C with barycentric coordinates lambda, the hats
  are lambda_i and the bubble of side ij is -lambda_i lambda_j / 2. In elasticity the contact
  dofs are those of c in the rotated frame at Gamma_C's nodes (``rotated_frame``), and Gamma_C
  is flat through each of its vertices, so these rows are -v_h . n exactly.
* ``N``, the flux of c(v) at the points: the gradients of the volume element holding each point,
  of any order, evaluated by NGSolve (``scalar_basis_gradients``), combined by the physics
  (``flux_rows`` of ``problem.physics.Scalar`` and ``problem.physics.Elasticity``) and written in the problem's variables (the rotated frame).

tests/test_weak_contact.py checks both against NGSolve's own evaluation of a random u_h.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property

import ngsolve as ngs
import numpy as np
import scipy.sparse as sp

from ..mesh.points import evaluate, in_elements

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
    # what ``N`` is made from, when it is first asked for: the space, the physics, the change
    # of basis and each point's volume element (not the problem: the problem's caches hold
    # quadratures, and a cycle would keep its matrices alive until a full garbage collection)
    _flux: tuple | None = field(default=None, repr=False, compare=False)

    @cached_property
    def N(self) -> sp.csr_matrix:
        """(q, ndof) the flux of the contact variable of every basis function at the points:
        d_n v (scalar), -sigma_n(v) = -n . sigma(v) n (elasticity); made on first use: only
        the weak methods read it, and the error measurement, the loads and the best
        approximation make quadratures too."""
        fes, physics, basis, volumes = self._flux
        return flux_rows(fes, physics, basis, volumes, self.points, self.normals)

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
        _flux=(problem.fes, problem.physics, problem.basis, trace.volumes[edge]),
    )


def _face_quadrature(problem, degree: int) -> ContactQuadrature:
    """NGSolve's Gauss rule of ``degree`` on every triangle of a 3D Gamma_C."""
    trace, faces = problem.trace, problem.trace.faces
    rule = ngs.IntegrationRule(ngs.TRIG, degree)
    xi = np.array([ip.point[:2] for ip in rule])
    # barycentric as NGSolve maps its reference triangle (vertices (1, 0), (0, 1), (0, 0)) onto a
    # boundary element, whose corner order ``faces.vertices`` keeps: the points are NGSolve's own
    lam = np.column_stack([xi, 1.0 - xi.sum(axis=1)])                 # (k, 3)
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
        _flux=(problem.fes, problem.physics, problem.basis, faces.volumes[face]),
    )


def flux_rows(fes, physics, basis, volumes: np.ndarray, points: np.ndarray, normals: np.ndarray) -> sp.csr_matrix:
    """(q, ndof) the flux of the contact variable of every basis function of ``fes`` at
    ``points`` (each in the volume element ``volumes``, outward unit ``normals``), in the
    problem's variables (``basis``: NGSolve's coefficients = basis @ ours, or None)."""
    # the scalar space of the same order numbers its dofs as each component block of VectorH1
    scalar = ngs.H1(fes.mesh, order=fes.globalorder)
    dofs, grads = scalar_basis_gradients(scalar, volumes, points)
    block = scalar.ndof              # component k's copy of scalar dof d is k * block + d
    q, local = dofs.shape
    rows = np.repeat(np.arange(q), local)
    pieces = [sp.csr_matrix((values.ravel(), (rows, (k * block + dofs).ravel())), shape=(q, fes.ndof))
              for k, values in physics.flux_rows(grads, normals)]
    N = sum(pieces[1:], pieces[0]).tocsr()
    return N if basis is None else (N @ basis).tocsr()


def scalar_basis_gradients(fes, volumes: np.ndarray, points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(dofs (q, l), gradients (q, l, dim)): the dofs of the volume element of each point (a
    scalar H1 space of any order) and the gradients of their basis functions there. NGSolve
    evaluates them: the element's j-th local basis function is the j-th dof of the element in
    the discontinuous copy of the space (the same element, its dofs numbered element by element),
    so one GridFunction per local index, evaluated at every point at once, gives them all."""
    mesh = fes.mesh
    unique, which = np.unique(volumes, return_inverse=True)
    element_dofs = np.array([fes.GetDofNrs(ngs.ElementId(ngs.VOL, int(e))) for e in unique], dtype=np.int64)
    broken = ngs.Discontinuous(fes)
    first = np.array([broken.GetDofNrs(ngs.ElementId(ngs.VOL, int(e)))[0] for e in unique], dtype=np.int64)
    in_elements(mesh, points, volumes)
    indicator = ngs.GridFunction(broken)
    values = indicator.vec.FV().NumPy()
    gradient = ngs.grad(indicator)
    grads = np.empty((len(points), element_dofs.shape[1], mesh.dim))
    for j in range(element_dofs.shape[1]):
        values[:] = 0.0
        values[first + j] = 1.0
        grads[:, j] = evaluate(gradient, mesh, points)
    return element_dofs[which], grads


def _rows(columns: list, values: list, shape) -> sp.csr_matrix:
    rows = np.tile(np.arange(shape[0]), len(columns))
    return sp.csr_matrix((np.concatenate(values), (rows, np.concatenate(columns))), shape=shape)


def at_points(cf, mesh, quadrature: ContactQuadrature) -> np.ndarray:
    """A CoefficientFunction (or None: zero) at the quadrature points."""
    if cf is None:
        return np.zeros(len(quadrature.weights))
    return evaluate(cf, mesh, quadrature.points)


def exact_pressure(case, problem, quadrature: ContactQuadrature) -> np.ndarray:
    """The exact contact pressure at the quadrature points: lambda = d_n u - g_C, or
    p = -(sigma_n(u) - g_n) in elasticity (``physics``)."""
    return case.physics.pressure(case, problem.mesh, quadrature.points, quadrature.normals)
