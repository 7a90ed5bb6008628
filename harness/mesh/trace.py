"""The trace of T_h on Gamma_C.

The contact trace T_h^C of Section 3 is the list of edges t_i = ]x_i, x_{i+1}[ lying on
Gamma_C; both discrete cones are defined through it. In 3D (the paper's Section 6) Gamma_C is a
union of triangles: the cones constrain the vertices and the *edges* of those triangles (on each
edge the P2 trace is a 1D quadratic, as in 2D), while integrals over Gamma_C run over the
triangles themselves (``ContactFaces``).
"""
from __future__ import annotations

from dataclasses import dataclass

import ngsolve as ngs
import numpy as np

from .points import cells, coordinates

CONTACT = "contact"


@dataclass(frozen=True)
class ContactFaces:
    """3D: the triangles of T_h on Gamma_C, over which Gamma_C is integrated."""

    vertices: np.ndarray       # (f, 3) NGSolve vertex numbers of the corners
    edges: np.ndarray          # (f, 3) index in the trace's edges of side k, joining corners k, k+1 mod 3
    normals: np.ndarray        # (f, 3) outward unit normals
    volumes: np.ndarray        # (f,) NGSolve numbers of the tetrahedra on the triangles

    def corners(self, trace: "ContactTrace") -> np.ndarray:
        """(f, 3, 3) coordinates of the corners."""
        index = np.searchsorted(trace.vertices, self.vertices)
        return trace.vertex_points[index]


@dataclass(frozen=True)
class ContactTrace:
    """The edges of T_h on Gamma_C, with end points a, b and outward unit normals (in 3D the
    normal of a triangle of Gamma_C holding the edge, and ``faces``)."""

    edges: np.ndarray          # (m,) NGSolve edge numbers
    edge_vertices: np.ndarray  # (m, 2) NGSolve vertex numbers of the end points
    a: np.ndarray              # (m, dim) coordinates of the first end point
    b: np.ndarray              # (m, dim) coordinates of the second end point
    normals: np.ndarray        # (m, dim) outward unit normals
    opposite: np.ndarray       # (m,) 2D: vertex number of the third vertex of each edge's triangle
    faces: ContactFaces | None = None   # 3D: the triangles of Gamma_C
    volumes: np.ndarray | None = None   # 2D: (m,) NGSolve numbers of the triangles on the edges

    @property
    def dim(self) -> int:
        return self.a.shape[1]

    @property
    def vertices(self) -> np.ndarray:
        """Vertex numbers x_i on Gamma_C, sorted."""
        return np.unique(self.edge_vertices)

    @property
    def vertex_points(self) -> np.ndarray:
        """Coordinates of ``vertices``, in the same order."""
        _, first = np.unique(self.edge_vertices.ravel(), return_index=True)
        return np.concatenate([self.a, self.b], axis=1).reshape(-1, self.dim)[first]

    @property
    def lengths(self) -> np.ndarray:
        return np.linalg.norm(self.b - self.a, axis=1)

    @property
    def midpoints(self) -> np.ndarray:
        return 0.5 * (self.a + self.b)

    # The cells of Gamma_C: its edges in 2D, its triangles in 3D.
    @property
    def cell_vertices(self) -> np.ndarray:
        return self.edge_vertices if self.faces is None else self.faces.vertices

    @property
    def cell_edges(self) -> np.ndarray:
        """(cells, sides) index of each side of each cell in the edges (2D: a cell is its edge)."""
        return np.arange(len(self.edges))[:, None] if self.faces is None else self.faces.edges

    @property
    def cell_sizes(self) -> np.ndarray:
        """Length (2D) or area (3D) of each cell."""
        if self.faces is None:
            return self.lengths
        c = self.faces.corners(self)
        return 0.5 * np.linalg.norm(np.cross(c[:, 1] - c[:, 0], c[:, 2] - c[:, 0]), axis=1)

    def points(self, t: np.ndarray) -> np.ndarray:
        """Points a + t (b - a) for parameters t in [0, 1]: array (m, len(t), dim)."""
        return self.a[:, None, :] + t[None, :, None] * (self.b - self.a)[:, None, :]


def contact_trace(mesh: ngs.Mesh) -> ContactTrace:
    return contact_trace_2d(mesh) if mesh.dim == 2 else contact_trace_3d(mesh)


def contact_trace_2d(mesh: ngs.Mesh) -> ContactTrace:
    edges, verts, normals, opposite, volumes = [], [], [], [], []
    for el in mesh.Elements(ngs.BND):
        if el.mat != CONTACT:
            continue
        (edge,) = el.edges
        va, vb = el.vertices
        pa, pb = np.array(mesh[va].point), np.array(mesh[vb].point)
        # The outward normal points away from the third vertex of the adjacent triangle.
        (volume,) = mesh[edge].elements
        (third,) = [v for v in mesh[volume].vertices if v not in (va, vb)]
        tangent = pb - pa
        normal = np.array([tangent[1], -tangent[0]]) / np.linalg.norm(tangent)
        if normal @ (np.array(mesh[third].point) - pa) > 0:
            normal = -normal
        edges.append(edge.nr)
        verts.append((va.nr, vb.nr))
        normals.append(normal)
        opposite.append(third.nr)
        volumes.append(volume.nr)
    if not edges:
        raise ValueError("the mesh has no boundary edge labelled 'contact'")
    verts = np.array(verts, dtype=np.int64)
    coords = coordinates(mesh)
    return ContactTrace(np.array(edges, dtype=np.int64), verts, coords[verts[:, 0]], coords[verts[:, 1]], np.array(normals),
                        np.array(opposite, dtype=np.int64), volumes=np.array(volumes, dtype=np.int64))


def contact_trace_3d(mesh: ngs.Mesh) -> ContactTrace:
    """The triangles of Gamma_C and their edges, each edge once (in the order the triangles
    first name them), normals outward (away from the fourth vertex of the tetrahedron on each
    triangle). One pass of Python over the triangles reads their corners and edges; normals,
    tetrahedra and edge numbering are array work, not a Python loop per triangle."""
    faces = [(el.vertices, el.edges) for el in mesh.Boundaries(CONTACT).Elements()]
    if not faces:
        raise ValueError("the mesh has no boundary face labelled 'contact'")
    corners = np.array([[v.nr for v in vertices] for vertices, _ in faces], dtype=np.int64)       # (f, 3)
    # netgen's triangle numbers its edges (2, 0), (1, 2), (0, 1): side k = (corner k, corner k + 1)
    # is edge 2, 1, 0 (``_check_triangle_edges`` holds it on the first triangle)
    edge_numbers = np.array([[e.nr for e in edges] for _, edges in faces], dtype=np.int64)[:, [2, 1, 0]]
    _check_triangle_edges(mesh, corners[0], edge_numbers[0])
    coords = coordinates(mesh)
    points = coords[corners]
    normals = np.cross(points[:, 1] - points[:, 0], points[:, 2] - points[:, 0])
    normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    volumes, fourth = _tetrahedra_on(mesh, corners)
    flip = np.einsum("fd,fd->f", normals, coords[fourth] - points[:, 0]) > 0
    normals[flip] *= -1.0
    # the trace's edges in the order the triangles first name them
    flat = edge_numbers.ravel()
    unique, first, inverse = np.unique(flat, return_index=True, return_inverse=True)
    order = np.argsort(first, kind="stable")
    rank = np.empty_like(order)
    rank[order] = np.arange(len(order))
    sides = rank[inverse].reshape(-1, 3)
    firsts = first[order]
    face_of, side_of = firsts // 3, firsts % 3
    verts = np.stack([corners[face_of, side_of], corners[face_of, (side_of + 1) % 3]], axis=1)
    faces_table = ContactFaces(corners, sides, normals, volumes)
    return ContactTrace(unique[order], verts, coords[verts[:, 0]], coords[verts[:, 1]], normals[face_of],
                        np.full(len(verts), -1, dtype=np.int64), faces_table)


def _check_triangle_edges(mesh: ngs.Mesh, corners: np.ndarray, edges: np.ndarray) -> None:
    """Side k of a triangle joins its corners k and k + 1 (netgen's local edge order, read)."""
    for k, edge in enumerate(edges):
        ends = {v.nr for v in mesh[ngs.NodeId(ngs.EDGE, int(edge))].vertices}
        if ends != {int(corners[k]), int(corners[(k + 1) % 3])}:
            raise RuntimeError("netgen's triangle edge order is not the one contact_trace_3d reads")


def _tetrahedra_on(mesh: ngs.Mesh, triangles: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(the tetrahedron on each boundary triangle, its vertex off the triangle), by matching the
    sorted vertex triples against the tetrahedra's faces."""
    tets = cells(mesh)
    nv = np.int64(mesh.nv)
    faces = np.sort(np.stack([np.delete(tets, k, axis=1) for k in range(4)], axis=1), axis=2).reshape(-1, 3)
    keys = (faces[:, 0] * nv + faces[:, 1]) * nv + faces[:, 2]          # nv < 2e6: below 2^63
    order = np.argsort(keys)
    wanted = np.sort(triangles, axis=1)
    position = order[np.searchsorted(keys, (wanted[:, 0] * nv + wanted[:, 1]) * nv + wanted[:, 2], sorter=order)]
    volumes, opposite = position // 4, position % 4
    return volumes, tets[volumes, opposite]
