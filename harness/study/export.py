"""Export a case's discrete problems, level by level, for another finite element code to solve
(``python -m harness export``, ``harness.export``): the format docs/guide/export-format.md
describes, version ``FORMAT_VERSION``.

Per level: the mesh (vertices, cells, labelled boundary facets), the P_k Lagrange nodes, the
data sampled there, the right-hand side as moments against the Lagrange basis (with the
harness's own quadratures, so that another code solves the harness's discrete problem
exactly), the discrete Dirichlet values, the exact solution where known, and Gamma_C's Gauss
points with the contact data (what a Nitsche code integrates). Written as NumPy arrays (.npz),
VTK (.vtu) and Gmsh (.msh, format 2.2) through meshio, and a manifest (JSON) saying what everything is.
The solutions come back as ``methods.external``'s folders.
"""
from __future__ import annotations

import json
import os
from pathlib import Path

import numpy as np

from ..fem.assembly import discretise
from ..fem.contact_laws.system import contact_data
from ..fem.contact_quadrature import contact_quadrature
from ..fem.lagrange import LAGRANGE_ORDERS, LagrangeNodes
from ..mesh.levels import UniformRefinement
from ..mesh.points import cells, coordinates, evaluate
from ..methods.external import SOLUTION_FORMAT, SOLUTION_FORMAT_VERSION
from ..methods.nitsche import GAMMA0

FORMAT = "signorini-harness-export"
FORMAT_VERSION = 1
# the boundary labels of a case (``problem.case``) as facet tags; a 3D case's other face labels
# (``interior``) follow from 4 on, named in the manifest
LABELS = {"contact": 1, "dirichlet": 2, "neumann": 3}
MESHIO_CELLS = {(2, 1): ("triangle", "line"), (2, 2): ("triangle6", "line3"),
                (3, 1): ("tetra", "triangle"), (3, 2): ("tetra10", "triangle6")}


class ExportError(ValueError):
    """A one-line reason an export is refused."""


def export(case, levels: int, out, order: int = 2, progress=None) -> Path:
    """Write ``levels`` uniform levels of ``case`` (a ``problem.case.Case``) at P_``order`` into
    the folder ``out``; returns the manifest's path. ``progress(level, path)`` is called per level.
    A folder holding anything but an export is refused (nothing is overwritten but an export)."""
    _check(case, levels, order)
    out = Path(out)
    _claim(out)
    records, labels = [], dict(LABELS)
    for level in UniformRefinement(case).levels(levels):
        arrays = level_arrays(case, level.mesh, order, labels)
        records.append(write_level(out, level.index, arrays, level.h, order))
        if progress is not None:
            progress(level.index, out / records[-1]["file"])
    path = out / "manifest.json"
    _atomic_text(path, json.dumps(manifest(case, order, records, labels), indent=1))
    return path


def _check(case, levels: int, order: int) -> None:
    if order not in LAGRANGE_ORDERS:
        raise ExportError(f"export writes P1 and P2 (the paper's), not P{order}")
    if not isinstance(levels, int) or levels < 1:
        raise ExportError(f"levels must be a positive integer, got {levels!r}")
    if case.bodies != 1:
        raise ExportError(f"case {case.name!r} has two bodies; export writes one-body cases")


def _claim(out: Path) -> None:
    """Make ``out``, or take it over if it holds an export; refuse any other folder with files in it."""
    if out.exists() and not out.is_dir():
        raise ExportError(f"{out} is a file, not a folder")
    manifest_path = out / "manifest.json"
    if out.is_dir() and any(out.iterdir()):
        try:
            ours = json.loads(manifest_path.read_text()).get("format") == FORMAT
        except (OSError, ValueError, AttributeError):
            ours = False
        if not ours:
            raise ExportError(f"{out} holds files that are not an export of the harness; give an empty or new folder")
    out.mkdir(parents=True, exist_ok=True)


def level_arrays(case, mesh, order: int, labels: dict) -> dict:
    """What one level's .npz holds (docs/guide/export-format.md), by name."""
    problem = discretise(case, mesh, order)
    nodes = LagrangeNodes.of(problem.fes)
    components = problem.physics.components if problem.physics.rotated_frame else 1
    facets, facet_labels = boundary_facets(mesh, labels)
    arrays = {"vertices": coordinates(mesh), "cells": cells(mesh), "facets": facets, "facet_labels": facet_labels,
              "nodes": nodes.points, "cell_nodes": nodes.cell_nodes}
    facet_nodes = arrays["facet_nodes"] = nodes.facet_nodes(facets)
    for name, label in (("contact", 1), ("dirichlet", 2), ("neumann", 3)):
        on = np.zeros(nodes.count, bool)
        on[facet_nodes[facet_labels == label].ravel()] = True
        arrays[f"on_{name}"] = on
    arrays["normal"] = contact_normals(problem, nodes)
    arrays["u_dirichlet"] = nodes.values(problem.cartesian(problem.lift), components)
    arrays["load"] = nodes.moments(problem.cartesian(problem.b), components)
    arrays.update(node_data(case, mesh, nodes.points, arrays["on_contact"], components))
    arrays.update(contact_points(case, problem))
    return arrays


def boundary_facets(mesh, labels: dict) -> tuple[np.ndarray, np.ndarray]:
    """(vertices (f, dim), label (f,)) of the boundary elements; a label not yet in ``labels``
    gets the next number."""
    import ngsolve as ngs
    vertices, names = [], []
    for element in mesh.Elements(ngs.BND):
        vertices.append([v.nr for v in element.vertices])
        names.append(element.mat)
    for name in sorted(set(names) - set(labels)):
        labels[name] = max(labels.values()) + 1
    return np.array(vertices, np.int64).reshape(-1, mesh.dim), np.array([labels[n] for n in names], np.int64)


def contact_normals(problem, nodes: LagrangeNodes) -> np.ndarray:
    """(n, dim) the outward unit normal of Gamma_C at its nodes (of a cell holding the node), NaN
    elsewhere."""
    trace = problem.trace
    normal = np.full(nodes.points.shape, np.nan)
    ends = trace.edge_vertices
    for which in (ends[:, 0], ends[:, 1]) + ((nodes.node_of_pairs(ends),) if len(nodes.edge_keys) else ()):
        normal[which] = trace.normals
    return normal


def node_data(case, mesh, points: np.ndarray, on_contact: np.ndarray, components: int) -> dict:
    """The case's data at the nodes, (n, components) each, and (n,) for the obstacle and the
    friction threshold on Gamma_C (NaN off it)."""
    def sampled(function, default=0.0) -> np.ndarray:
        if function is None:
            return np.full((len(points), components), default)
        return evaluate(function, mesh, points).reshape(len(points), components)

    data = {"f": sampled(case.f), "contact_load": sampled(case.contact_load)}
    on = np.flatnonzero(on_contact)
    gap = np.full(len(points), np.nan)
    gap[on] = 0.0 if case.gap is None else evaluate(case.gap, mesh, points[on]).ravel()
    data["gap"] = gap
    if case.frictional:
        threshold = np.full(len(points), np.nan)
        threshold[on] = evaluate(case.friction.threshold_function, mesh, points[on]).ravel()
        data["threshold"] = threshold
    if case.exact:
        data["u_exact"] = sampled(case.u)
    return data


def contact_points(case, problem) -> dict:
    """Gamma_C's Gauss points of the contact laws (``fem.contact_quadrature.contact_quadrature``:
    Nitsche's), with h, the normals, and the obstacle and load of the contact variable there."""
    quadrature = contact_quadrature(problem)
    obstacle, load = contact_data(case, problem, quadrature)
    return {"q_points": quadrature.points, "q_weights": quadrature.weights, "q_h": quadrature.h,
            "q_normals": quadrature.normals, "q_obstacle": obstacle, "q_load": load}


def write_level(out: Path, index: int, arrays: dict, h: float, order: int) -> dict:
    """The level's .npz, .vtu and .msh (each written to a temporary name, then renamed: a killed
    export leaves no half-written file); its manifest record."""
    stem = f"level-{index}"
    tmp = out / f".{stem}.npz"
    np.savez_compressed(tmp, **arrays)
    os.replace(tmp, out / f"{stem}.npz")
    for suffix, options in ((".vtu", {}), (".msh", {"file_format": "gmsh22", "binary": False})):
        tmp = out / f".{stem}{suffix}"
        meshio_mesh(arrays, order, gmsh=suffix == ".msh").write(tmp, **options)
        os.replace(tmp, out / f"{stem}{suffix}")
    return {"level": index, "file": f"{stem}.npz", "vtu": f"{stem}.vtu", "msh": f"{stem}.msh", "h": h,
            "nodes": int(len(arrays["nodes"])), "cells": int(len(arrays["cells"])),
            "ndof": int(arrays["load"].size)}


def meshio_mesh(arrays: dict, order: int, gmsh: bool):
    """The level as a meshio mesh on the Lagrange nodes: the cells (quadratic for P2) with the
    nodal data; for Gmsh also the boundary facets, tagged by label (``gmsh:physical``)."""
    import meshio
    dim = arrays["nodes"].shape[1]
    cell_type, facet_type = MESHIO_CELLS[dim, order]
    points = np.pad(arrays["nodes"], ((0, 0), (0, 3 - dim)))        # both formats store 3D points
    facet_nodes = arrays["facet_nodes"]
    point_data = {name: arrays[name] for name in ("u_exact", "u_dirichlet", "load", "f", "gap", "contact_load") if name in arrays}
    point_data = {name: np.nan_to_num(value, nan=0.0) for name, value in point_data.items()}
    if not gmsh:
        return meshio.Mesh(points, [(cell_type, arrays["cell_nodes"])], point_data=point_data)
    tags = [np.zeros(len(arrays["cell_nodes"]), np.int64), arrays["facet_labels"]]
    return meshio.Mesh(points, [(cell_type, arrays["cell_nodes"]), (facet_type, facet_nodes)],
                       cell_data={"gmsh:physical": tags, "gmsh:geometrical": tags})


def manifest(case, order: int, records: list, labels: dict) -> dict:
    """The export's manifest: the format, the case and its theory, the levels, the labels, the
    conventions of the contact variable and of Nitsche's law (to reproduce `nitsche`)."""
    from .. import __version__
    from .planning.cache import git_commit
    physics = case.physics
    elastic = physics.rotated_frame
    described = {"name": case.name, "description": case.description, "physics": physics.name,
                 "dimension": case.dimension, "exact": case.exact, "nu": case.nu, "expected_rate": case.expected_rate,
                 "expected_log_exponent": case.expected_log_exponent, "theorem": case.theorem, "regime": case.regime,
                 "friction": {"law": case.friction.name} if case.frictional else None}
    if elastic:
        described.update(young=physics.young, poisson=physics.poisson, lame_lambda=physics.lam, lame_mu=physics.mu,
                         plane="strain" if case.dimension == 2 else None)
    return {"format": FORMAT, "format_version": FORMAT_VERSION, "harness_version": __version__, "commit": git_commit(),
            "case": described, "order": order, "components": physics.components if elastic else 1,
            "units": "nondimensional: lengths, loads and moduli as the case declares them (Young's modulus 1 unless stated)",
            "levels": records, "labels": labels,
            "nitsche": {"gamma0": GAMMA0, "theta": 1.0,
                        "epsilon": "gamma0 * h / modulus",
                        "h": "2D: the contact edge's length; 3D: the longest edge of the contact triangle",
                        "modulus": physics.modulus if elastic else 1.0,
                        "contact_quadrature": "the q_* points: 4 Gauss-Legendre points per edge (2D), "
                                              "NGSolve's degree-7 rule per triangle (3D)"},
            "contact_variable": "scalar: c(v) = v, flux(v) = dn v, c >= gap; elasticity: c(v) = -v . n, "
                                "flux(v) = -n . sigma(v) n, v . n <= gap (q_obstacle: the bound of c; q_load: its load)"}


def solution_writer(folder, case_name: str, method_name: str, code: str = "the harness", like: str | None = None):
    """An ``on_level`` hook (``harness.run``) that writes each solve of ``method_name`` on
    ``case_name`` as an external solution folder (``methods.external``): the values of u_h at
    the level's Lagrange nodes, the solve's seconds and iterations. The harness's own solutions
    in the format another code writes: the round trip of the format, and a baseline of node
    values to compare a code with before measuring it."""
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    _atomic_text(folder / "manifest.json", json.dumps(
        {"format": SOLUTION_FORMAT, "format_version": SOLUTION_FORMAT_VERSION, "code": code, "method": f"{method_name}-points",
         "like": like or method_name, "case": case_name, "order": None}, indent=1))

    def write(case, method, level, problem, solve):
        if case.name != case_name or method.name != method_name:
            return None
        manifest_path = folder / "manifest.json"
        written = json.loads(manifest_path.read_text())
        if written["order"] is None:
            written["order"] = method.order
            _atomic_text(manifest_path, json.dumps(written, indent=1))
        nodes = LagrangeNodes.of(problem.fes)
        components = problem.physics.components if problem.physics.rotated_frame else 1
        fields = solve.fields
        tmp = folder / f".level-{level}.npz"
        np.savez(tmp, points=nodes.points, values=nodes.values(problem.cartesian(solve.u), components),
                 seconds=fields.solve_seconds, iterations=fields.solver_iterations, residual=fields.kkt_residual,
                 status=str(fields.status))
        os.replace(tmp, folder / f"level-{level}.npz")
        return None
    return write


def _atomic_text(path: Path, text: str) -> None:
    tmp = path.with_name(f".{path.name}")
    tmp.write_text(text)
    os.replace(tmp, path)
