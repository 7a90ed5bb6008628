"""Mesh hierarchy (uniform refinement, h halves per level) and the trace of T_h on Gamma_C.

The contact trace T_h^C of Section 3 is the list of edges t_i = ]x_i, x_{i+1}[ lying on
Gamma_C; both discrete cones are defined through it.
"""
from __future__ import annotations

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
    and shape regularity is kept (NGSolve's Mesh.Refine() bisects and does not halve h).
    The mesh is one object refined in place, so that NGSolve keeps the parents of new vertices
    (the multigrid's prolongations): a level's mesh is valid until the next level is yielded.
    """
    mesh = coarse_mesh(case)
    for level in range(levels):
        if level:
            mesh.ngmesh.Refine()
        yield level, mesh


def geometry_vertices(mesh: ngs.Mesh) -> np.ndarray:
    """Mesh vertices at the points of the geometry: where two boundary segments of different
    geometry lines meet (a corner, a label change, or a break such as a transition point on a
    straight Gamma_C), read from netgen's segment table, whose ``index`` is the geometry line."""
    segments = mesh.ngmesh.Elements1D().NumPy()
    ends = (segments["nodes"][:, :2].astype(np.int64) - 1).ravel()
    lines = np.repeat(segments["index"], 2)
    lowest, highest = np.full(mesh.nv, np.iinfo(np.int32).max), np.full(mesh.nv, -1)
    np.minimum.at(lowest, ends, lines)
    np.maximum.at(highest, ends, lines)
    return np.flatnonzero((highest >= 0) & (lowest != highest))


def vertices_at(mesh: ngs.Mesh, points, tol: float = 1e-10) -> np.ndarray:
    """Numbers of the mesh vertices at ``points``; ValueError naming a point that is no vertex."""
    coords = np.array(mesh.ngmesh.Coordinates()[:, :2])
    out = []
    for point in np.asarray(points, float).reshape(-1, 2):
        distance = np.hypot(*(coords - point).T)
        nearest = int(np.argmin(distance))
        if distance[nearest] > tol * max(1.0, np.abs(coords).max()):
            raise ValueError(f"point ({point[0]:.4g}, {point[1]:.4g}) is not a vertex of the mesh: make it a polygon corner")
        out.append(nearest)
    return np.array(out, dtype=np.int64)


def mesh_size(mesh: ngs.Mesh) -> float:
    """h of the paper: the largest element diameter (longest triangle edge)."""
    coords = np.array(mesh.ngmesh.Coordinates()[:, :2])
    tri = np.array(mesh.ngmesh.Elements2D().NumPy()["nodes"][:, :3], dtype=np.int64) - 1
    p = coords[tri]
    sides = np.stack([p[:, 1] - p[:, 0], p[:, 2] - p[:, 1], p[:, 0] - p[:, 2]], axis=1)
    return float(np.sqrt((sides**2).sum(axis=2)).max())


@dataclass(frozen=True)
class ContactTrace:
    """The edges of T_h on Gamma_C, with end points a, b and outward unit normals."""

    edges: np.ndarray          # (m,) NGSolve edge numbers
    edge_vertices: np.ndarray  # (m, 2) NGSolve vertex numbers of the end points
    a: np.ndarray              # (m, 2) coordinates of the first end point
    b: np.ndarray              # (m, 2) coordinates of the second end point
    normals: np.ndarray        # (m, 2) outward unit normals
    opposite: np.ndarray       # (m,) vertex number of the third vertex of each edge's triangle

    @property
    def vertices(self) -> np.ndarray:
        """Vertex numbers x_i on Gamma_C, sorted."""
        return np.unique(self.edge_vertices)

    @property
    def vertex_points(self) -> np.ndarray:
        """Coordinates of ``vertices``, in the same order."""
        _, first = np.unique(self.edge_vertices.ravel(), return_index=True)
        return np.concatenate([self.a, self.b], axis=1).reshape(-1, 2)[first]

    @property
    def lengths(self) -> np.ndarray:
        return np.linalg.norm(self.b - self.a, axis=1)

    @property
    def midpoints(self) -> np.ndarray:
        return 0.5 * (self.a + self.b)

    def points(self, t: np.ndarray) -> np.ndarray:
        """Points a + t (b - a) for parameters t in [0, 1]: array (m, len(t), 2)."""
        return self.a[:, None, :] + t[None, :, None] * (self.b - self.a)[:, None, :]


def contact_trace(mesh: ngs.Mesh) -> ContactTrace:
    edges, verts, normals, opposite = [], [], [], []
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
    if not edges:
        raise ValueError("the mesh has no boundary edge labelled 'contact'")
    verts = np.array(verts, dtype=np.int64)
    coords = np.array([mesh[ngs.NodeId(ngs.VERTEX, int(v))].point for v in verts.ravel()]).reshape(-1, 2, 2)
    return ContactTrace(np.array(edges, dtype=np.int64), verts, coords[:, 0], coords[:, 1], np.array(normals),
                        np.array(opposite, dtype=np.int64))


def evaluate(cf: ngs.CoefficientFunction, mesh: ngs.Mesh, points: np.ndarray) -> np.ndarray:
    """Values of cf at points (..., 2); vector-valued cf gives a trailing component axis."""
    flat = points.reshape(-1, 2)
    values = np.asarray(cf(mesh(flat[:, 0], flat[:, 1])))
    if cf.dim == 1:
        return values.reshape(points.shape[:-1])
    return values.reshape(points.shape[:-1] + (cf.dim,))
