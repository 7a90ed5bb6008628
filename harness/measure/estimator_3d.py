"""The residual estimator's volume, jump and Neumann terms on tetrahedra (3D), scalar and
elastic: the 3D counterpart of ``estimator.MeshTerms``, with the same interface
(``volume_and_jumps(gfu, order, physics)``, ``neumann``, ``along_neumann``), so that
``estimator.ResidualEstimator`` serves both dimensions.

The terms are those of the 2D estimator (``estimator``'s docstring) with faces F for edges:

    h_T^2 ||f + div F(u_h)||_T^2 + 1/2 sum_{F in dT interior} h_{T,F} ||[F(u_h) n]||_F^2
      + sum_{F in dT on Gamma_g} h_{T,F} ||g - F(u_h) n||_F^2,

and the Gamma_C terms of ``estimator.ResidualEstimator`` on the triangles of Gamma_C: the terms
of the residual estimators cited there (Hild & Nicaise, Numer. Math. 101 (2005), scalar; M2AN 41
(2007), elasticity; and others), carried from edges to faces. Whether those papers' analyses
cover 3D is not claimed (docs/theory/references.md says what was read), and no constant is claimed. The
weights are NGSolve's ``ngsolve.specialcf.mesh_size``, as in 2D (checked numerically):

    h_T = (6 |T|)^(1/3) = |det J|^(1/3)           in the volume,
    h_{T,F} = 3 |T| / |F|, the height of T over F  on the element boundary,

so that the jump term of T on F is 1/2 (3|T|/|F|) int_F j^2 = |T|/8 (sum_i j_i^2 + (sum_i j_i)^2)
for the jump j, linear on F with values j_1, j_2, j_3 at its corners (the P1 mass matrix on a
triangle is |F|/12 (1 + I)). On Gamma_C the estimator's contact terms use h_F = diam(F) (the
contact quadrature's h, the 3D counterpart of the contact edge's length).

grad u_h is linear on a P2 tetrahedron (constant on P1), and so is the flux F(u_h): its values
at the four vertices give the jumps at the corners of every face and the (constant) divergence
sum_k F(x_k) grad lambda_k. tests/test_adaptive_3d.py holds the result to NGSolve's own
element-boundary integration of the same terms.
"""
from __future__ import annotations

from collections import OrderedDict
from dataclasses import dataclass

import ngsolve as ngs
import numpy as np

from ..fem.element_quadrature import ElementQuadrature
from ..mesh.points import cells, coordinates, mesh_key, mesh_points
from .facets import element_bits, neumann_facets

# face k of a tetrahedron is the one opposite its local vertex k
FACE_CORNERS = np.array([[1, 2, 3], [0, 2, 3], [0, 1, 3], [0, 1, 2]])
# vertex numbers of a face packed into one int64 key: nv^3 < 2^63
MAX_VERTICES = 2_000_000
# elements per batch of point evaluation (``vertex_fluxes``)
POINT_BATCH = 1 << 17


@dataclass(frozen=True)
class MeshFaces:
    """The faces of the tetrahedra of one 3D mesh, as arrays: each element's volume and
    barycentric gradients, every interior face as the two (element, face) that share it, and
    for each (element, face) the local vertices of the face ordered by vertex number (so that
    the two sides of an interior face list its corners in the same order)."""

    cells: np.ndarray           # (ne, 4) vertex numbers, NGSolve's order
    volume: np.ndarray          # (ne,)
    grad_lambda: np.ndarray     # (ne, 4, 3) gradients of the barycentric coordinates
    corners_by_number: np.ndarray   # (ne, 4, 3) local vertices of face k, by increasing vertex number
    interior: np.ndarray        # (k, 2, 2) the two (element, face) of each interior face
    boundary: np.ndarray        # (b, 2) the (element, face) of each boundary face

    @classmethod
    def make(cls, mesh: ngs.Mesh) -> "MeshFaces":
        if mesh.dim != 3:
            raise ValueError("MeshFaces is for 3D meshes")
        if mesh.nv >= MAX_VERTICES:
            raise ValueError(f"MeshFaces packs a face's vertices into one integer: at most {MAX_VERTICES} vertices")
        table, p = cells(mesh), coordinates(mesh)
        volume, grad_lambda = barycentric_gradients(p[table])
        # small integer types: a P1 level of transition-line-3d in the fine profile has 5.9e6
        # tetrahedra, and these tables are 4 x 3 entries per tetrahedron
        table = table.astype(np.int32)
        vertices = table[:, FACE_CORNERS]                                      # (ne, 4, 3)
        corners_by_number = np.take_along_axis(np.broadcast_to(FACE_CORNERS.astype(np.int8), vertices.shape),
                                               np.argsort(vertices, axis=2), axis=2)
        vertices.sort(axis=2)
        nv = np.int64(mesh.nv)
        key = ((vertices[..., 0] * nv + vertices[..., 1]) * nv + vertices[..., 2]).ravel()
        del vertices
        order = np.argsort(key, kind="stable")
        sorted_key = key[order]
        del key
        paired = np.flatnonzero(sorted_key[1:] == sorted_key[:-1])
        single = np.ones(len(sorted_key), bool)
        single[paired] = single[paired + 1] = False
        pairs = np.stack([order[paired], order[paired + 1]], axis=1)          # flat (element * 4 + face)
        lone = order[single]
        return cls(table, volume, grad_lambda, corners_by_number,
                   np.stack([pairs // 4, pairs % 4], axis=2).astype(np.int32),
                   np.stack([lone // 4, lone % 4], axis=1).astype(np.int32))


def vertex_points(mesh: ngs.Mesh, elements: np.ndarray, per_element: int) -> np.ndarray:
    """NGSolve mesh points at the first ``per_element`` vertices (4, or 1) of each of the
    tetrahedra ``elements`` (element e's vertex k at index per_element e + k; local coordinates
    e_0, e_1, e_2 and 0: the local coordinates are the barycentric coordinates of the first
    three vertices, ``points.in_elements``), for evaluating volume functions -- gradients
    included -- there without a search."""
    points = mesh_points(mesh, per_element * len(elements))
    for axis, name in enumerate("xyz"):
        points[name] = np.tile(np.eye(4)[axis, :per_element], len(elements))
    points["nr"] = np.repeat(elements, per_element)
    return points


def barycentric_gradients(corners: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(|T|, grad lambda_k) of tetrahedra with ``corners`` (ne, 4, 3): with e_i = x_i - x_3 the
    columns of J, grad lambda_0..2 are the rows of J^-1, (e_1 x e_2, e_2 x e_0, e_0 x e_1) / det J
    (cross products: no batched LAPACK call), and lambda_3 = 1 - the others."""
    e0, e1, e2 = (corners[:, i] - corners[:, 3] for i in range(3))
    rows = np.stack([np.cross(e1, e2), np.cross(e2, e0), np.cross(e0, e1)], axis=1)
    det = np.einsum("ed,ed->e", e0, rows[:, 0])
    rows /= det[:, None, None]
    return np.abs(det) / 6.0, np.concatenate([rows, -rows.sum(axis=1, keepdims=True)], axis=1)


def neumann_faces(mesh: ngs.Mesh, faces: MeshFaces) -> tuple:
    """(neumann, along): a piecewise constant on the facets, 1 on those of Gamma_g; and the
    tetrahedra with a face on Gamma_g (a BitArray): the Neumann residual is integrated on those
    elements' boundaries only (``estimator.neumann_sides`` in 2D)."""
    neumann, wanted = neumann_facets(mesh)
    elements, face = faces.boundary.T
    own = np.sort(faces.cells[elements[:, None], FACE_CORNERS[face]], axis=1)
    nv = np.int64(mesh.nv)
    hit = np.isin((own[:, 0] * nv + own[:, 1]) * nv + own[:, 2], (wanted[:, 0] * nv + wanted[:, 1]) * nv + wanted[:, 2])
    return neumann, element_bits(mesh, elements[hit])


class TetrahedronTerms:
    """What the estimator needs of one tetrahedral mesh and the case's data (``estimator.MeshTerms``
    in 3D): made once per mesh for the problems of both orders (the last few are kept)."""

    _made: OrderedDict = OrderedDict()
    KEPT = 2

    @classmethod
    def of(cls, case, quadrature: ElementQuadrature, volume_order: int) -> "TetrahedronTerms":
        mesh = quadrature.mesh
        key = mesh_key(mesh) + (case.source, case.name, volume_order)
        hit = cls._made.get(key)
        if hit is not None and hit[0] is mesh:
            return hit[1]
        made = cls(case, quadrature, volume_order)
        cls._made[key] = (mesh, made)
        while len(cls._made) > cls.KEPT:
            cls._made.popitem(last=False)
        return made

    def __init__(self, case, quadrature: ElementQuadrature, volume_order: int):
        self.mesh = mesh = quadrature.mesh
        faces = MeshFaces.make(mesh)
        self.neumann, self.along_neumann = neumann_faces(mesh, faces)
        self.volume, self.grad_lambda = faces.volume, faces.grad_lambda
        self.h2 = (6.0 * self.volume) ** (2.0 / 3.0) * self.volume          # h_T^2 |T|, h_T = (6|T|)^(1/3)
        self._jump_rows(faces)
        self._load_moments(case, quadrature, volume_order)

    def _jump_rows(self, faces: MeshFaces) -> None:
        """Each interior face F = T1 | T2: T1 and T2 (``first``, ``second``), the local vertices
        of its three corners in each (the same corners in the same order), T1's outward unit
        normal -grad lambda_k / |grad lambda_k| (k the vertex opposite F); the jump term of F goes
        to T1 and to T2, each weighted |T|/8 (module docstring)."""
        (self.first, first_face), (self.second, second_face) = faces.interior[:, 0].T, faces.interior[:, 1].T
        self.first_corners = faces.corners_by_number[self.first, first_face]          # (k, 3)
        self.second_corners = faces.corners_by_number[self.second, second_face]
        inward = faces.grad_lambda[self.first, first_face]
        self.jump_normals = np.ascontiguousarray((-inward / np.linalg.norm(inward, axis=1, keepdims=True)).T)   # (3, k)

    def _load_moments(self, case, quadrature: ElementQuadrature, volume_order: int) -> None:
        """f_T (the mean of f on T) and h_T^2 ||f - f_T||_T^2 per element and component: with
        them h_T^2 ||f + div F||_T^2 = h_T^2 ||f - f_T||_T^2 + h_T^2 |T| |f_T + div F_T|^2 (P2:
        div F(u_h) constant on T), as in 2D."""
        ne, components = len(self.volume), case.physics.components
        self.mean_f, self.oscillation = np.zeros((ne, components)), np.zeros(ne)
        if case.f_vanishes:
            return
        for i in range(components):
            integral, deviation = quadrature.element_moments(case.f[i], volume_order)
            self.mean_f[:, i] = integral / self.volume
            self.oscillation += (6.0 * self.volume) ** (2.0 / 3.0) * deviation

    def vertex_fluxes(self, gfu: ngs.GridFunction, order: int, physics) -> np.ndarray:
        """F(u_h) at the four vertices of every tetrahedron, (ne, 4, components, 3); for P1, where
        it is constant on each tetrahedron, at one vertex, (ne, 1, components, 3). Evaluated in
        batches of elements (NGSolve's point records are 48 bytes each)."""
        ne, components = len(self.volume), physics.components
        per_element = 4 if order > 1 else 1
        gradients = np.empty((ne, per_element, components, 3))
        for elements in np.array_split(np.arange(ne), max(1, ne // POINT_BATCH)):
            points = vertex_points(self.mesh, elements, per_element)
            gradients[elements] = np.asarray(ngs.grad(gfu)(points)).reshape(len(elements), per_element, components, 3)
        return physics.flux_array(gradients)

    def volume_and_jumps(self, gfu: ngs.GridFunction, order: int, physics) -> np.ndarray:
        """h_T^2 ||f + div F(u_h)||_T^2 + the jumps of F(u_h) n on T's interior faces, per element."""
        ne = len(self.volume)
        flux = self.vertex_fluxes(gfu, order, physics)
        # F(u_h) is linear on a P2 tetrahedron: div F = sum_k F(x_k) grad lambda_k, constant
        divergence = np.einsum("ekcd,ekd->ec", flux, self.grad_lambda) if order > 1 else 0.0
        eta2 = self.oscillation + self.h2 * ((self.mean_f + divergence) ** 2).sum(axis=1)
        squares = self.jump_squares(flux)
        # the jump term of F goes to both tetrahedra, each weighted by its own |T| / 8
        return (eta2 + np.bincount(self.first, weights=self.volume[self.first] / 8.0 * squares, minlength=ne)
                + np.bincount(self.second, weights=self.volume[self.second] / 8.0 * squares, minlength=ne))

    def jump_squares(self, flux: np.ndarray) -> np.ndarray:
        """sum_i j_i^2 + (sum_i j_i)^2 per interior face, summed over the components, j_i the jump
        of F n at corner i: T1's outward flux plus T2's, T2's normal being -T1's (module docstring)."""
        per_element = flux.shape[1]
        rows = [(per_element * self.first + (self.first_corners[:, c] if per_element > 1 else 0),
                 per_element * self.second + (self.second_corners[:, c] if per_element > 1 else 0)) for c in range(3)]
        nx, ny, nz = self.jump_normals
        squares = 0.0
        for i in range(flux.shape[2]):
            fx, fy, fz = (flux[:, :, i, d].ravel() for d in range(3))
            jumps = [nx * (fx[a] - fx[b]) + ny * (fy[a] - fy[b]) + nz * (fz[a] - fz[b]) for a, b in rows]
            squares = squares + sum(j**2 for j in jumps) + sum(jumps) ** 2
        return squares
