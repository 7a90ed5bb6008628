"""Mesh arrays (vertices, cells, geometry vertices) and point evaluation of coefficient
functions at many points, with the points located once per mesh."""
from __future__ import annotations

import hashlib
import weakref
from collections import OrderedDict

import ngsolve as ngs
import numpy as np

# local edges of an NGSolve triangle (vertex pairs), in the order of its edge dofs
TRIANGLE_EDGES = ((0, 2), (1, 2), (0, 1))


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
    (2D only: in 3D a solution is singular along curves, ``fem.element_quadrature.singular_vertices``.)"""
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


def evaluate(cf: ngs.CoefficientFunction, mesh: ngs.Mesh, points: np.ndarray) -> np.ndarray:
    """Values of cf at points (..., dim); vector-valued cf gives a trailing component axis."""
    values = np.asarray(cf(located(mesh, points)))
    if cf.dim == 1:
        return values.reshape(points.shape[:-1])
    return values.reshape(points.shape[:-1] + (cf.dim,))


# Locating points in a mesh is netgen's search-tree walk, point by point, which costs far more
# than evaluating a coefficient function there. A level evaluates u, grad u, the gap and the
# load at the same Gamma_C points for every order and method: they are located once (the last
# few point sets).
_LOCATED: "OrderedDict[tuple, tuple]" = OrderedDict()


_LOCATED_KEPT = 8


def mesh_key(mesh: ngs.Mesh) -> tuple:
    """What identifies a mesh in a cache. A mesh refined in place keeps its id, and under local
    refinement (``mesh.bisection``) a point set can stay the same while the elements holding the
    points change: the key holds the refinement count and the element count too. (A cache
    keeps the mesh itself beside what it made, so that an id is not reused.)"""
    return (id(mesh), mesh.levels, mesh.ne)


def _key(mesh: ngs.Mesh, flat: np.ndarray) -> tuple:
    """The cache key of a point set in a mesh (``mesh_key``)."""
    return mesh_key(mesh) + (flat.shape, hashlib.blake2b(flat.tobytes(), digest_size=16).digest())


def located(mesh: ngs.Mesh, points: np.ndarray) -> np.ndarray:
    """NGSolve's mesh points (element and local coordinates) of ``points`` (..., dim), flattened."""
    flat = np.ascontiguousarray(points.reshape(-1, mesh.dim), dtype=float)
    key = _key(mesh, flat)
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
    _LOCATED[_key(mesh, flat)] = (mesh, found)
    while len(_LOCATED) > _LOCATED_KEPT:
        _LOCATED.popitem(last=False)


# (a weak reference to the mesh, a located record) per mesh object: the record layout and
# NGSolve's mesh pointer (weak: a mesh kept here would outlive its study, as a whole refined
# mesh; its id is checked against the live object, so a reused id is never trusted)
_TEMPLATES: "OrderedDict[int, tuple]" = OrderedDict()
_TEMPLATES_KEPT = 4


def mesh_points(mesh: ngs.Mesh, count: int) -> np.ndarray:
    """``count`` zeroed volume points of ``mesh`` as NGSolve's mesh-point records, for the caller
    to fill with element numbers (``nr``) and local coordinates: points made directly, which a
    coefficient function evaluates without a search. The record layout and the mesh pointer
    come from one point search per mesh object, made the first time: a volume search builds
    netgen's element search tree (a cost that grows with the mesh), again after every refinement,
    while a mesh refined in place keeps its pointer."""
    hit = _TEMPLATES.get(id(mesh))
    if hit is None or hit[0]() is not mesh:
        hit = (weakref.ref(mesh), mesh(*coordinates(mesh)[:1].T))
        _TEMPLATES[id(mesh)] = hit
        while len(_TEMPLATES) > _TEMPLATES_KEPT:
            _TEMPLATES.popitem(last=False)
    template = hit[1]
    points = np.zeros(count, dtype=template.dtype)
    points["meshptr"], points["VorB"], points["facetnr"] = template["meshptr"][0], 0, -1
    return points


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
    # inside the closed element, in floating point: a point on a side (a Gamma_C Gauss point)
    # must map back onto it, not 1e-17 outside -- NGSolve maps with the last coordinate
    # 1 - sum(local), and a case's u may have a branch cut on Gamma_C (atan2(y, x) at y = -0.0
    # is -pi, at y = 0 pi: transition-r32's u changed sign there)
    np.maximum(local, 0.0, out=local)
    for k in range(1, mesh.dim):
        local[:, k] = np.minimum(local[:, k], 1.0 - local[:, :k].sum(axis=1))
    found = mesh_points(mesh, len(flat))
    for k, name in enumerate("xyz"[:mesh.dim]):
        found[name] = local[:, k]
    found["nr"] = owners
    remember(mesh, flat, found)

