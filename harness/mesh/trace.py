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

from .points import coordinates

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
    """The triangles of Gamma_C and their edges, each edge once, normals outward (away from
    the fourth vertex of the tetrahedron on each triangle)."""
    region = mesh.Boundaries(CONTACT)
    edge_index: dict[int, int] = {}
    edge_vertices, edge_normals, face_vertices, face_edges, face_normals, face_volumes = [], [], [], [], [], []
    for el in region.Elements():
        corners = [v.nr for v in el.vertices]
        points = np.array([mesh[v].point for v in el.vertices])
        normal = np.cross(points[1] - points[0], points[2] - points[0])
        normal /= np.linalg.norm(normal)
        (face,) = el.faces
        (volume,) = mesh[face].elements
        (fourth,) = [v for v in mesh[volume].vertices if v.nr not in corners]
        if normal @ (np.array(mesh[fourth].point) - points[0]) > 0:
            normal = -normal
        ends = {frozenset(v.nr for v in mesh[e].vertices): e.nr for e in el.edges}
        sides = []
        for k in range(3):
            pair = (corners[k], corners[(k + 1) % 3])
            number = ends[frozenset(pair)]
            if number not in edge_index:
                edge_index[number] = len(edge_vertices)
                edge_vertices.append(pair)
                edge_normals.append(normal)
            sides.append(edge_index[number])
        face_vertices.append(corners)
        face_edges.append(sides)
        face_normals.append(normal)
        face_volumes.append(volume.nr)
    if not edge_index:
        raise ValueError("the mesh has no boundary face labelled 'contact'")
    verts = np.array(edge_vertices, dtype=np.int64)
    coords = coordinates(mesh)
    faces = ContactFaces(np.array(face_vertices, dtype=np.int64), np.array(face_edges, dtype=np.int64),
                         np.array(face_normals), np.array(face_volumes, dtype=np.int64))
    return ContactTrace(np.array(list(edge_index), dtype=np.int64), verts, coords[verts[:, 0]], coords[verts[:, 1]],
                        np.array(edge_normals), np.full(len(verts), -1, dtype=np.int64), faces)

