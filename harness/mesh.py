"""Mesh hierarchy (uniform refinement, h halves per level) and the trace of T_h on Gamma_C.

The contact trace T_h^C of Section 3 is the list of edges t_i = ]x_i, x_{i+1}[ lying on
Gamma_C; both discrete cones are defined through it. In 3D (the paper's Section 6) Gamma_C is a
union of triangles: the cones constrain the vertices and the *edges* of those triangles (on each
edge the P2 trace is a 1D quadratic, as in 2D), while integrals over Gamma_C run over the
triangles themselves (``ContactFaces``).
"""
from __future__ import annotations

import hashlib
from collections import OrderedDict
from dataclasses import dataclass

import ngsolve as ngs
import numpy as np

CONTACT = "contact"


def coarse_mesh(case) -> ngs.Mesh:
    return ngs.Mesh(case.geometry.GenerateMesh(maxh=case.maxh))


def boundary_labels(mesh: ngs.Mesh) -> set[str]:
    return set(mesh.GetBoundaries())


def mesh_hierarchy(case, levels: int):
    """Yield (level, mesh) for level = 0..levels-1 by uniform red refinement.

    netgen's own Refine() splits every triangle into four similar ones, so h halves exactly
    and shape regularity is kept (in 3D every tetrahedron into eight, Bey's red refinement:
    every edge is halved, and the shapes stay in finitely many classes) (NGSolve's Mesh.Refine() bisects and does not halve h).
    The mesh is one object refined in place, so that NGSolve keeps the parents of new vertices
    (the multigrid's prolongations): a level's mesh is valid until the next level is yielded.
    """
    mesh = coarse_mesh(case)
    for level in range(levels):
        if level:
            mesh.ngmesh.Refine()
        yield level, mesh


def coordinates(mesh: ngs.Mesh) -> np.ndarray:
    """(nv, dim) vertex coordinates (a copy: netgen's is a view of a mesh refined in place)."""
    return np.array(mesh.ngmesh.Coordinates()[:, :mesh.dim], copy=True)


def cells(mesh: ngs.Mesh) -> np.ndarray:
    """(ne, dim + 1) vertex numbers of the elements: triangles in 2D, tetrahedra in 3D."""
    table = mesh.ngmesh.Elements2D() if mesh.dim == 2 else mesh.ngmesh.Elements3D()
    return np.array(table.NumPy()["nodes"][:, :mesh.dim + 1], dtype=np.int64) - 1


def geometry_vertices(mesh: ngs.Mesh) -> np.ndarray:
    """Mesh vertices at the points of the geometry: where two boundary segments of different
    geometry lines meet (a corner, a label change, or a break such as a transition point on a
    straight Gamma_C), read from netgen's segment table, whose ``index`` is the geometry line.
    (2D only: in 3D a solution is singular along curves, ``quadrature.singular_vertices``.)"""
    segments = mesh.ngmesh.Elements1D().NumPy()
    ends = (segments["nodes"][:, :2].astype(np.int64) - 1).ravel()
    lines = np.repeat(segments["index"], 2)
    lowest, highest = np.full(mesh.nv, np.iinfo(np.int32).max), np.full(mesh.nv, -1)
    np.minimum.at(lowest, ends, lines)
    np.maximum.at(highest, ends, lines)
    return np.flatnonzero((highest >= 0) & (lowest != highest))


def vertices_at(mesh: ngs.Mesh, points, tol: float = 1e-10) -> np.ndarray:
    """Numbers of the mesh vertices at ``points``; ValueError naming a point that is no vertex."""
    coords = coordinates(mesh)
    out = []
    for point in np.asarray(points, float).reshape(-1, mesh.dim):
        distance = np.linalg.norm(coords - point, axis=1)
        nearest = int(np.argmin(distance))
        if distance[nearest] > tol * max(1.0, np.abs(coords).max()):
            raise ValueError(f"point {format_point(point)} is not a vertex of the mesh: make it a polygon corner")
        out.append(nearest)
    return np.array(out, dtype=np.int64)


def format_point(point) -> str:
    """(0.5, 0) or (0.5, 0, 1): a point in an error message."""
    return "(" + ", ".join(f"{c:.4g}" for c in point) + ")"


def mesh_size(mesh: ngs.Mesh) -> float:
    """h of the paper: the largest element diameter (longest element edge)."""
    p = coordinates(mesh)[cells(mesh)]
    corners = p.shape[1]
    sides = np.stack([p[:, j] - p[:, i] for i in range(corners) for j in range(i + 1, corners)], axis=1)
    return float(np.sqrt((sides**2).sum(axis=2)).max())


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


def evaluate(cf: ngs.CoefficientFunction, mesh: ngs.Mesh, points: np.ndarray) -> np.ndarray:
    """Values of cf at points (..., dim); vector-valued cf gives a trailing component axis."""
    values = np.asarray(cf(located(mesh, points)))
    if cf.dim == 1:
        return values.reshape(points.shape[:-1])
    return values.reshape(points.shape[:-1] + (cf.dim,))


# Locating points in a mesh is netgen's search-tree walk, about 5 us per point in 3D (0.7 s for
# the 1.4e5 Gamma_C Gauss points of a 9e4-tetrahedron mesh), while evaluating a coefficient
# function there costs 1% of it. A level evaluates u, grad u, the gap and the load at the same
# Gamma_C points for every order and method: they are located once (the last few point sets).
_LOCATED: "OrderedDict[tuple, tuple]" = OrderedDict()
_LOCATED_KEPT = 8


def located(mesh: ngs.Mesh, points: np.ndarray) -> np.ndarray:
    """NGSolve's mesh points (element and local coordinates) of ``points`` (..., dim), flattened."""
    flat = np.ascontiguousarray(points.reshape(-1, mesh.dim), dtype=float)
    key = (id(mesh), flat.shape, hashlib.blake2b(flat.tobytes(), digest_size=16).digest())
    hit = _LOCATED.get(key)
    if hit is not None and hit[0] is mesh:          # the mesh itself is kept: its id is not reused
        _LOCATED.move_to_end(key)
        return hit[1]
    found = mesh(*flat.T)
    remember(mesh, flat, found)
    return found


def remember(mesh: ngs.Mesh, points: np.ndarray, found: np.ndarray) -> None:
    """Record that ``points`` (n, dim) are NGSolve's mesh points ``found``."""
    flat = np.ascontiguousarray(points.reshape(-1, mesh.dim), dtype=float)
    key = (id(mesh), flat.shape, hashlib.blake2b(flat.tobytes(), digest_size=16).digest())
    _LOCATED[key] = (mesh, found)
    while len(_LOCATED) > _LOCATED_KEPT:
        _LOCATED.popitem(last=False)


def in_elements(mesh: ngs.Mesh, points: np.ndarray, elements: np.ndarray) -> None:
    """Make ``points`` (..., dim), each inside (or on the boundary of) the volume element of the
    same index in ``elements`` (...), known without searching the mesh (``located``): their
    local coordinates are their barycentric coordinates in the element, with respect to its
    first ``dim`` vertices in NGSolve's order. Volume points, so that derivatives of volume
    functions evaluate there too."""
    flat = points.reshape(-1, mesh.dim)
    owners = np.broadcast_to(elements, points.shape[:-1]).ravel()
    corners = coordinates(mesh)[cells(mesh)[owners]]                  # (n, dim + 1, dim)
    edges = corners[:, :-1] - corners[:, -1:]                         # from the last vertex
    local = np.linalg.solve(np.swapaxes(edges, 1, 2), (flat - corners[:, -1])[..., None])[..., 0]
    template = mesh(*flat[:1].T)                  # one search: the record layout and the mesh pointer
    found = np.zeros(len(flat), dtype=template.dtype)
    for k, name in enumerate("xyz"[:mesh.dim]):
        found[name] = local[:, k]
    found["meshptr"], found["VorB"], found["facetnr"] = template["meshptr"][0], 0, -1
    found["nr"] = owners
    remember(mesh, flat, found)
