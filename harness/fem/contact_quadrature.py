"""The basis of X_h on Gamma_C, sampled at Gauss points of its cells (edges in 2D, triangles in
3D): what the weak methods integrate (their contact terms are integrals over Gamma_C of the
contact variable and of its flux, which the bound-constrained cones never need).

Two kinds of rows, in every physics and dimension (``problem.physics``: the contact variable
c(v) and its flux, u and d_n u for the scalar problem, -v . n and -sigma_n(v) in elasticity):

Both are NGSolve's basis of the volume element holding each point, of any order, evaluated
there (``scalar_basis_at``) and combined by the physics (``trace_rows`` and ``flux_rows`` of
``problem.physics.Scalar`` and ``problem.physics.Elasticity``), written in the problem's
variables (the rotated frame, ``rotated_frame``):

* ``T``, the trace of c(v). For P2 it is the closed form of docs/mathematics.md §3 (hats
  1 - t, t and the bubble -t (1 - t) / 2 along an edge), to round-off; for P_k, k >= 3, each
  edge carries k - 1 edge functions too.
* ``N``, the flux of c(v) at the points, made on first use.

tests/test_weak_contact.py checks both against NGSolve's own evaluation of a random u_h.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property

import ngsolve as ngs
import numpy as np
import scipy.sparse as sp
from scipy.spatial import cKDTree

from ..mesh.points import evaluate, in_elements
from .polynomials import barycentric_lattice

# Gauss points per contact edge: exact for polynomials of degree 7 (the P2 contact terms are of
# degree <= 4 where the bracket [.]_+ does not switch); the few edges where it switches, at a
# contact/separation transition, are integrated approximately, as by any code that assembles
# the nonlinear form with a fixed rule.
GAUSS_POINTS = 4
# |entry| of a trace row at or below which it is round-off of a basis function vanishing there
ROUNDOFF = 1e-13


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
    # quadratures, and a cycle would keep its matrices alive until a full garbage collection);
    # or N itself (``fem.contact_laws.two_body``: the rows on both bodies' dofs)
    _flux: tuple | None = field(default=None, repr=False, compare=False)
    degree: np.ndarray | None = None     # (q,) the degree of each point's cell (``fem.assembly.DiscreteProblem.edge_degrees``)

    @cached_property
    def N(self) -> sp.csr_matrix:
        """(q, ndof) the flux of the contact variable of every basis function at the points:
        d_n v (scalar), -sigma_n(v) = -n . sigma(v) n (elasticity); made on first use: only
        the weak methods read it, and the error measurement, the loads and the best
        approximation make quadratures too."""
        if sp.issparse(self._flux):
            return self._flux
        fes, physics, basis, volumes = self._flux
        return flux_rows(fes, physics, basis, volumes, self.points, self.normals)

    def edge_means(self, values: np.ndarray) -> np.ndarray:
        """Mean over each contact edge of a function given at the points."""
        n_edges = self.edge.max() + 1 if len(self.edge) else 0
        integral = np.bincount(self.edge, weights=self.weights * values, minlength=n_edges)
        return integral / np.bincount(self.edge, weights=self.weights, minlength=n_edges)


@dataclass(frozen=True)
class ContactNodes:
    """The Lagrange nodes of the trace of X_h on Gamma_C and the map to the contact variable's
    values there: ``L @ u`` is c(u_h) at ``x`` (u_h in 2D scalar problems, -u_h . n in
    elasticity), whatever NGSolve's hierarchical basis (its edge dofs are bubble coefficients,
    not values). The vertices of Gamma_C come first, in ``mesh.trace.ContactTrace.vertices``' order, then the
    nodes inside its cells, cell by cell."""

    x: np.ndarray               # (n, dim) the nodes
    L: sp.csr_matrix            # (n, ndof) the contact variable's value of every basis function there
    vertices: int               # the first ``vertices`` nodes are Gamma_C's vertices


def lagrange_nodes(problem) -> ContactNodes:
    """The nodes (i / k) of every cell of Gamma_C (edges in 2D, triangles in 3D; k the cell's
    degree) once each, and the basis evaluated there (``trace_rows``) in the element holding the
    cell."""
    trace = problem.trace
    if trace.faces is None:
        corners = np.stack([trace.a, trace.b], axis=1)
        cells, volumes, normals, degrees = len(trace.a), trace.volumes, trace.normals, problem.edge_degrees
        lattice = {k: np.column_stack([1.0 - t, t]) for k in set(degrees.tolist()) for t in [np.arange(k + 1) / k]}
    else:
        faces = trace.faces
        corners, cells, volumes, normals = faces.corners(trace), len(faces.vertices), faces.volumes, faces.normals
        degrees = np.full(cells, problem.order)
        lattice = {problem.order: barycentric_lattice(problem.order)}
    cell = np.concatenate([np.full(len(lattice[k]), c) for c, k in enumerate(degrees.tolist())]).astype(np.int64)
    weights = np.concatenate([lattice[k] for k in degrees.tolist()]) if cells else np.zeros((0, 2))
    points = np.einsum("nc,ncd->nd", weights, corners[cell])
    # one node per point: the vertices of Gamma_C first (a lattice point at a corner), each
    # evaluated in the first cell that holds it
    key = np.round(points / max(np.abs(points).max(initial=0.0), 1.0), 12)
    _, first = np.unique(key, axis=0, return_index=True)
    corner = (weights == 1.0).any(axis=1)[first]
    chosen = np.concatenate([first[corner][np.argsort(_vertex_rank(trace, points[first[corner]]))],
                             np.sort(first[~corner])])
    T = trace_rows(problem.fes, problem.physics, problem.basis, volumes[cell[chosen]], points[chosen],
                   normals[cell[chosen]])
    return ContactNodes(points[chosen], T, int(corner.sum()))


def _vertex_rank(trace, points: np.ndarray) -> np.ndarray:
    """Each of ``points`` (vertices of Gamma_C) by its position in ``mesh.trace.ContactTrace.vertices``' order."""
    return cKDTree(trace.vertex_points).query(points)[1]


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


# the smallest distance (absolute) from an edge end at which the graded rule puts a point: below
# it the point's coordinates round to the end (the edges at the singular points of an hp mesh
# are 1e-6 long and shorter), where a singular u's derivatives are 0/0
GRADED_FLOOR = 1e-14


def graded_depth(lengths: np.ndarray, points: int, depth: int = 30) -> int:
    """``depth`` of the ``graded`` rule of ``points`` points, or less where its point nearest an
    end, on the shortest of ``lengths``, would be nearer than ``GRADED_FLOOR``."""
    if not len(lengths):
        return depth
    nearest = lengths.min() * gauss(points)[0][0]
    return int(min(depth, max(1, np.floor(np.log2(nearest / GRADED_FLOOR)))))


def contact_quadrature(problem, points_per_edge: int | None = None, graded_at: np.ndarray | None = None) -> ContactQuadrature:
    """Gauss points of ``problem``'s contact edges and its basis (order 1 or 2) there; on the
    edges with an end at one of the vertices ``graded_at`` (singular points), the ``graded``
    rule instead. In 3D: a Gauss rule on every triangle of Gamma_C, of the degree
    ``points_per_edge`` Gauss points integrate exactly (``graded_at`` is empty in 3D). By
    default, ``GAUSS_POINTS`` or k + 1 for P_k, whichever is more: exact for the degree-2k
    products of the contact terms."""
    points_per_edge = points_per_edge or max(GAUSS_POINTS, problem.order + 1)
    if problem.trace.faces is not None:
        return _face_quadrature(problem, 2 * points_per_edge - 1)
    trace = problem.trace
    m = len(trace.edges)
    singular = np.zeros(m, bool) if graded_at is None else np.isin(trace.edge_vertices, graded_at).any(axis=1)
    rules = [gauss(points_per_edge), graded(points_per_edge, graded_depth(trace.lengths[singular], points_per_edge))]
    rule_of = singular.astype(int)
    edge = np.concatenate([np.full(len(rules[r][0]), k) for k, r in enumerate(rule_of)]).astype(np.int64)
    T_t = np.concatenate([rules[r][0] for r in rule_of])
    unit_w = np.concatenate([rules[r][1] for r in rule_of])
    return edge_quadrature(problem, edge, T_t, trace.lengths[edge] * unit_w)


def edge_quadrature(problem, edge: np.ndarray, t: np.ndarray, weights: np.ndarray) -> ContactQuadrature:
    """The quadrature of points at the parameters ``t`` of their contact edges ``edge`` (2D), of
    the given ``weights``, and the basis there."""
    trace = problem.trace
    points = trace.a[edge] + t[:, None] * (trace.b - trace.a)[edge]
    volumes, normals = trace.volumes[edge], trace.normals[edge]
    return ContactQuadrature(
        points=points,
        weights=weights,
        h=trace.lengths[edge],
        edge=edge,
        T=trace_rows(problem.fes, problem.physics, problem.basis, volumes, points, normals),
        normals=normals,
        _flux=(problem.fes, problem.physics, problem.basis, volumes),
        degree=problem.edge_degrees[edge],
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
    points = np.einsum("kc,fcd->fkd", lam, corners).reshape(-1, 3)
    volumes, normals = faces.volumes[face], faces.normals[face]
    return ContactQuadrature(
        points=points,
        weights=np.repeat(area, k) * np.tile(unit_w, f),
        h=np.repeat(diameter, k),
        edge=face,
        T=trace_rows(problem.fes, problem.physics, problem.basis, volumes, points, normals),
        normals=normals,
        _flux=(problem.fes, problem.physics, problem.basis, volumes),
        degree=np.full(len(face), problem.order),
    )


def flux_rows(fes, physics, basis, volumes: np.ndarray, points: np.ndarray, normals: np.ndarray) -> sp.csr_matrix:
    """(q, ndof) the flux of the contact variable of every basis function of ``fes`` at
    ``points`` (each in the volume element ``volumes``, outward unit ``normals``), in the
    problem's variables (``basis``: NGSolve's coefficients = basis @ ours, or None)."""
    scalar = _scalar_space(fes)
    dofs, _, grads = scalar_basis_at(scalar, volumes, points, values=False)
    return _component_rows(fes, scalar.ndof, basis, dofs, physics.flux_rows(grads, normals))


def trace_rows(fes, physics, basis, volumes: np.ndarray, points: np.ndarray, normals: np.ndarray) -> sp.csr_matrix:
    """(q, ndof) the contact variable c(v) of every basis function of ``fes`` at ``points`` on
    Gamma_C (each in the volume element ``volumes``, outward unit ``normals``), in the problem's
    variables: NGSolve's own basis of any order, evaluated (for k >= 3 each edge carries k - 1
    edge functions, NGSolve's scaled integrated Legendre polynomials, oriented by the edge's
    vertex numbers). Entries at round-off are dropped: the functions of the element's other
    edges and of its interior vanish on Gamma_C, and in the rotated frame so does the
    tangential variables' part of c."""
    scalar = _scalar_space(fes)
    dofs, values, _ = scalar_basis_at(scalar, volumes, points, gradients=False)
    rows = _component_rows(fes, scalar.ndof, basis, dofs, physics.trace_rows(values, normals))
    rows.data[np.abs(rows.data) <= ROUNDOFF] = 0.0
    rows.eliminate_zeros()
    return rows


def _scalar_space(fes):
    """``fes`` itself if scalar, else the scalar H1 space of its order and mesh: it numbers its
    dofs as each component block of a VectorH1 space does."""
    if isinstance(fes, ngs.H1):
        return fes
    return ngs.H1(fes.mesh, order=fes.globalorder)


def _component_rows(fes, block: int, basis, dofs: np.ndarray, pieces: list) -> sp.csr_matrix:
    """The rows of ``pieces`` [(component k, (q, l) values on the scalar ``dofs`` (q, l))] on the
    dofs of ``fes`` (component k's copy of scalar dof d is k * block + d), in the problem's
    variables (``basis``)."""
    q, local = dofs.shape
    rows = np.repeat(np.arange(q), local)
    parts = [sp.csr_matrix((values.ravel(), (rows, (k * block + dofs).ravel())), shape=(q, fes.ndof))
             for k, values in pieces]
    M = sum(parts[1:], parts[0]).tocsr()
    return M if basis is None else (M @ basis).tocsr()


def scalar_basis_at(fes, volumes: np.ndarray, points: np.ndarray, values: bool = True,
                    gradients: bool = True) -> tuple[np.ndarray, np.ndarray | None, np.ndarray | None]:
    """(dofs (q, l), values (q, l), gradients (q, l, dim)): the dofs of the volume element of each
    point (a scalar H1 space of any order) and the values and gradients of their basis functions
    there (None where not asked for). NGSolve evaluates them: the element's j-th local basis
    function is the j-th dof of the element in the discontinuous copy of the space (the same
    element, its dofs numbered element by element), so one GridFunction per local index,
    evaluated at every point at once, gives them all. An element of an hp space with fewer dofs
    than the largest pads its rows with its first dof, at value zero."""
    mesh = fes.mesh
    unique, which = np.unique(volumes, return_inverse=True)
    own = [fes.GetDofNrs(ngs.ElementId(ngs.VOL, int(e))) for e in unique]
    count = np.array([len(dofs) for dofs in own])
    local = int(count.max())
    element_dofs = np.array([list(dofs) + [dofs[0]] * (local - len(dofs)) for dofs in own], dtype=np.int64)
    broken = ngs.Discontinuous(fes)
    first = np.array([broken.GetDofNrs(ngs.ElementId(ngs.VOL, int(e)))[0] for e in unique], dtype=np.int64)
    in_elements(mesh, points, volumes)
    indicator = ngs.GridFunction(broken)
    coefficients = indicator.vec.FV().NumPy()
    value_of = np.empty((len(points), local)) if values else None
    gradient_of = np.empty((len(points), local, mesh.dim)) if gradients else None
    for j in range(local):
        coefficients[:] = 0.0
        coefficients[(first + j)[j < count]] = 1.0
        if values:
            value_of[:, j] = evaluate(indicator, mesh, points)
        if gradients:
            gradient_of[:, j] = evaluate(ngs.grad(indicator), mesh, points)
    return element_dofs[which], value_of, gradient_of


def at_points(cf, mesh, quadrature: ContactQuadrature) -> np.ndarray:
    """A CoefficientFunction (or None: zero) at the quadrature points."""
    if cf is None:
        return np.zeros(len(quadrature.weights))
    return evaluate(cf, mesh, quadrature.points)


def exact_pressure(case, problem, quadrature: ContactQuadrature) -> np.ndarray:
    """The exact contact pressure at the quadrature points: lambda = d_n u - g_C, or
    p = -(sigma_n(u) - g_n) in elasticity (``physics``)."""
    return case.physics.pressure(case, problem.mesh, quadrature.points, quadrature.normals)
