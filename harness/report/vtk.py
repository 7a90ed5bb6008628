"""ParaView and VisIt files of the discrete solutions: per case x method, one VTK XML
unstructured grid (.vtu) per level of Omega and one of Gamma_C, and a ParaView collection (.pvd)
over the levels of each, whose "time" is the level.

* Omega: P2 solutions on quadratic cells (VTK_QUADRATIC_TRIANGLE / _TETRA: the vertices and
  the edge midpoints, where a P2 function's values determine it), P1 on linear cells; point
  data ``u_h`` (scalar) or ``displacement`` (elasticity, three components so that ParaView's
  Warp By Vector applies), and for a case with an exact solution ``u`` and ``error`` = u - u_h.
* Gamma_C: its edges (2D, quadratic lines) or triangles (3D), point data ``gap_h`` = the
  contact variable of u_h minus its obstacle (u_h - alpha; in elasticity -u_h . n + alpha,
  ``physics``) and ``active`` (the constraints the contact solver held active there: the
  vertex conditions, and for P2 the edge condition of ``mean`` or the midpoint condition of
  ``nodal``, shown at the edge's midpoint; none for Nitsche and penalty, which have no
  constraints), cell data ``pressure`` (the discrete contact pressure, ``methods.method.LevelSolve.pressure``)
  and ``in_contact`` = pressure > 0, for the 3D ``mean`` also ``active`` (its triangle-mean
  condition; its midpoints have none), and for an exact case ``gap`` and ``exact_pressure``.

Written with meshio (binary, zlib-compressed XML that ParaView, VisIt and VTK's own readers
open); ``VtkWriter`` is an ``on_level`` hook of the study (``run --vtk``, ``report --vtk``).
"""
from __future__ import annotations

import os
import re
from pathlib import Path

import meshio
import numpy as np

from ..mesh.points import cells, coordinates, evaluate, in_elements
from ..study.chain.rows import study_levels
from ..study.chain.snapshots import problem_vertex_values
from ..study.storage.files import TEMPORARY_MARK, write_atomic

# VTK's node order of quadratic cells: the corners, then the midpoints of these corner pairs
QUADRATIC_SIDES = {2: ((0, 1), (1, 2), (2, 0)), 3: ((0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3))}
VOLUME_CELLS = {(2, 1): "triangle", (2, 2): "triangle6", (3, 1): "tetra", (3, 2): "tetra10"}
CONTACT_CELLS = {(2, 1): "line", (2, 2): "line3", (3, 1): "triangle", (3, 2): "triangle6"}


def _padded(values: np.ndarray) -> np.ndarray:
    """Vectors with three components (ParaView warps by 3-vectors)."""
    if values.ndim == 1 or values.shape[1] == 3:
        return values
    return np.concatenate([values, np.zeros((len(values), 3 - values.shape[1]))], axis=1)


def _points3(points: np.ndarray) -> np.ndarray:
    return _padded(np.asarray(points, float))


def volume_nodes(mesh, order: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(points (n, dim), cells (ne, nodes) in VTK's order, the element holding each point):
    the vertices, and for order 2 the midpoints of the edges, numbered after the vertices."""
    table = cells(mesh)
    coords = coordinates(mesh)
    nv, ne = len(coords), len(table)
    owner = np.empty(nv, dtype=np.int64)
    owner[table.ravel()] = np.repeat(np.arange(ne), table.shape[1])
    if order == 1:
        return coords, table, owner
    pairs = np.stack([table[:, list(side)] for side in QUADRATIC_SIDES[mesh.dim]], axis=1)     # (ne, sides, 2)
    keys = np.sort(pairs, axis=2) @ np.array([nv, 1])
    unique, first, index = np.unique(keys.ravel(), return_index=True, return_inverse=True)
    a, b = unique // nv, unique % nv
    points = np.concatenate([coords, 0.5 * (coords[a] + coords[b])])
    owners = np.concatenate([owner, first // pairs.shape[1]])
    return points, np.concatenate([table, nv + index.reshape(ne, -1)], axis=1), owners


def volume_fields(case, problem, u: np.ndarray) -> tuple[np.ndarray, list, dict]:
    """(points, cells, point data) of u_h on Omega (and u, u - u_h for an exact case)."""
    mesh = problem.mesh
    points, table, owners = volume_nodes(mesh, problem.order)
    in_elements(mesh, points, owners)           # made directly: no search of the mesh
    u_h = evaluate(problem.gridfunction(u), mesh, points)
    name = "displacement" if case.physics.elastic else "u_h"
    data = {name: _padded(u_h)}
    if case.u is not None:
        exact = evaluate(case.u, mesh, points)
        data |= {"u": _padded(exact), "error": _padded(exact - u_h)}
    return points, [(VOLUME_CELLS[mesh.dim, problem.order], table)], data


def contact_fields(case, problem, solve) -> tuple[np.ndarray, list, dict, dict]:
    """(points, cells, point data, cell data) on Gamma_C (see the module's docstring)."""
    trace, trace_u, mesh = problem.trace, solve.trace_u, problem.mesh
    nv = len(trace.vertices)
    ends = np.searchsorted(trace.vertices, trace.edge_vertices)                      # (m, 2)
    vertex_active = np.zeros(nv, bool)
    np.logical_or.at(vertex_active, ends.ravel(), np.asarray(trace_u.end_active, bool).ravel())
    values, active = problem_vertex_values(problem, trace_u), vertex_active
    points = trace.vertex_points
    if problem.order == 2:
        points = np.concatenate([points, trace.midpoints])
        values = np.concatenate([values, trace_u.at(np.array([0.5]))[:, 0]])
        # the 3D `mean` has no condition at a midpoint: its triangles' are cell data below
        midpoint_active = np.zeros(len(trace.edges), bool) if trace_u.face_active is not None else trace_u.edge_active
        active = np.concatenate([active, np.asarray(midpoint_active, bool)])
    if trace.faces is None:
        table = ends if problem.order == 1 else np.concatenate([ends, nv + np.arange(len(ends))[:, None]], axis=1)
        centres, normals = trace.midpoints, trace.normals
    else:
        corners = np.searchsorted(trace.vertices, trace.faces.vertices)
        table = corners if problem.order == 1 else np.concatenate([corners, nv + trace.faces.edges], axis=1)
        centres, normals = trace.faces.corners(trace).mean(axis=1), trace.faces.normals
    obstacle = evaluate(case.obstacle, mesh, points) if case.obstacle is not None else np.zeros(len(points))
    point_data = {"gap_h": values - obstacle, "active": active.astype(np.uint8)}
    pressure = np.asarray(solve.pressure, float)
    cell_data = {"pressure": pressure, "in_contact": (pressure > 0).astype(np.uint8)}
    if trace_u.face_active is not None:
        cell_data["active"] = np.asarray(trace_u.face_active, np.uint8)
    if case.u is not None:
        point_normals = _point_normals(trace, table, normals, len(points))
        point_data["gap"] = case.physics.contact_value(case, mesh, points, point_normals) - obstacle
        cell_data["exact_pressure"] = case.physics.pressure(case, mesh, centres, normals)
    return points, [(CONTACT_CELLS[mesh.dim, problem.order], table)], point_data, cell_data


def _point_normals(trace, table: np.ndarray, normals: np.ndarray, n: int) -> np.ndarray:
    """A unit normal at each point of Gamma_C: the normal of (one of) its cells. (On a kink of
    Gamma_C the contact variable of elasticity takes one side's normal, as the dofs do.)"""
    out = np.zeros((n, trace.dim))
    out[table.ravel()] = np.repeat(normals, table.shape[1], axis=0)
    return out


def level_files(directory: Path, case: str, method: str, level: int) -> tuple[Path, Path]:
    """(Omega's, Gamma_C's) .vtu of one level."""
    folder = Path(directory) / case / method
    return folder / f"omega_level{level}.vtu", folder / f"gamma_c_level{level}.vtu"


def two_body_volume_fields(case, problem, z: np.ndarray) -> tuple[np.ndarray, list, dict, dict]:
    """Both bodies (``fem.two_body``) as one .vtu: the lower one mirrored back to y < 0 with the
    real u_2 (``problem.bodies``: the scalar variable negated, a displacement's y component
    flipped), and the cell data ``body`` (0 upper, 1 lower)."""
    parts = [volume_fields(case, body, u) for body, u in zip(problem.bodies, problem.split(z))]
    (upper_points, upper_cells, upper_data), (lower_points, lower_cells, lower_data) = parts
    flip = np.array([1.0, -1.0, 1.0])
    mirror = (lambda v: v * flip) if case.physics.elastic else (lambda v: -v)
    points = np.concatenate([upper_points, lower_points * flip[:upper_points.shape[1]]])
    cells = upper_cells + [(kind, table + len(upper_points)) for kind, table in lower_cells]
    data = {key: np.concatenate([upper_data[key], mirror(lower_data[key])]) for key in upper_data}
    body = [np.full(len(table), k, np.uint8) for k, (_, table) in enumerate(cells)]
    return points, cells, data, {"body": body}


def two_body_interface_fields(case, problem, solve) -> tuple[np.ndarray, list, dict, dict]:
    """Gamma_C of two bodies as the segments of the intersection of their trace meshes: the
    discrete and exact opening less twice the gap at the segment ends, the mortar pressure of
    the slave edge holding each segment."""
    from ..fem.mortar import TraceElements
    from ..fem.two_body import opening
    x, values = opening(problem, solve.u, 2)
    points = np.stack([x.ravel(), np.zeros(x.size)], axis=1)
    upper = problem.upper
    twice_gap = 2.0 * evaluate(case.obstacle, upper.mesh, points) if case.obstacle is not None else np.zeros(len(points))
    point_data = {"gap_h": values.ravel() - twice_gap}
    if case.u is not None:
        normals = np.broadcast_to(np.array([0.0, -1.0]), points.shape)
        point_data["gap"] = 2.0 * case.physics.contact_value(case, upper.mesh, points, normals) - twice_gap
    slave = TraceElements.of(upper)
    edge = slave.edge_index[slave.locate(x.mean(axis=1))]
    cell_data = {"pressure": np.asarray(solve.pressure, float)[edge]}
    return points, [("line", np.arange(x.size).reshape(-1, 2))], point_data, cell_data


def write_level(directory: Path, case, method, level: int, problem, solve) -> tuple[Path, Path]:
    """One level's two .vtu files and the two collections over the levels written so far."""
    omega, gamma = level_files(directory, case.name, method.name, level)
    omega.parent.mkdir(parents=True, exist_ok=True)
    if case.bodies == 2:
        points, table, data, cell_data = two_body_volume_fields(case, problem, solve.u)
        _write(omega, meshio.Mesh(_points3(points), table, point_data=data, cell_data=cell_data))
        points, table, point_data, cell_data = two_body_interface_fields(case, problem, solve)
    else:
        points, table, data = volume_fields(case, problem, solve.u)
        _write(omega, meshio.Mesh(_points3(points), table, point_data=data))
        points, table, point_data, cell_data = contact_fields(case, problem, solve)
    _write(gamma, meshio.Mesh(_points3(points), table, point_data=point_data,
                              cell_data={k: [v] for k, v in cell_data.items()}))
    for stem in ("omega", "gamma_c"):
        write_collection(omega.parent, stem)
    return omega, gamma


def _write(path: Path, mesh: meshio.Mesh) -> None:
    """A .vtu written whole or not at all (a reader never sees half a file)."""
    partial = path.with_name(f".{path.name}{TEMPORARY_MARK}-{os.getpid()}.vtu")
    meshio.write(partial, mesh, file_format="vtu")
    os.replace(partial, path)


LEVEL_FILE = re.compile(r"(?P<stem>\w+)_level(?P<level>\d+)\.vtu$")


def write_collection(folder: Path, stem: str) -> Path:
    """``stem``.pvd: the ParaView collection of the folder's ``stem``_level*.vtu, the level as
    its time step (ParaView's time slider then steps through the refinement)."""
    levels = sorted(int(m["level"]) for p in Path(folder).iterdir()
                    if (m := LEVEL_FILE.match(p.name)) and m["stem"] == stem)
    entries = "\n".join(f'    <DataSet timestep="{level}" group="" part="0" file="{stem}_level{level}.vtu"/>'
                        for level in levels)
    text = ('<?xml version="1.0"?>\n<VTKFile type="Collection" version="0.1" byte_order="LittleEndian">\n'
            f"  <Collection>\n{entries}\n  </Collection>\n</VTKFile>\n")
    path = Path(folder) / f"{stem}.pvd"
    return write_atomic(path, text)


class VtkWriter:
    """``on_level`` hook: writes every level it sees (``finest``: {method name: level} -> only
    those levels) under ``directory``/case/method/. Keeps nothing: the study's rows are
    unchanged, and a hook is pickled to worker processes as it is."""

    def __init__(self, directory: Path, finest: dict | None = None):
        self.directory = Path(directory)
        self.finest = finest

    def written(self, case, methods, levels: int) -> bool:
        """Are the finest studied level's files of every method of ``case`` there (a study of
        ``levels`` levels)?"""
        return all(path.is_file() for m in methods if m.supports(case)
                   for path in level_files(self.directory, case.name, m.name, study_levels(m, levels) - 1))

    def __call__(self, case, method, level, problem, solve) -> None:
        if self.finest is None or self.finest.get(method.name) == level:
            write_level(self.directory, case, method, level, problem, solve)
        return None
