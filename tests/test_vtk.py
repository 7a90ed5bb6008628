"""`run --vtk`: the ParaView files hold the solutions the study computed. Read back with VTK's
own XML reader (the one ParaView uses), not with meshio, which wrote them."""
import xml.etree.ElementTree as ET

import ngsolve as ngs
import numpy as np
import pytest

vtk = pytest.importorskip("vtk")
from vtk.util.numpy_support import vtk_to_numpy  # noqa: E402

from harness import api  # noqa: E402
from harness.problem.case import registered_cases  # noqa: E402
from harness.report.vtk import VtkWriter, level_files  # noqa: E402

LEVELS = 2
# (case, method): every order, physics and dimension, a case without u, a method without constraints
RUNS = [("transition-r32", "nodal"), ("transition-r32", "mean"), ("transition-r32", "p1"), ("transition-r32", "nitsche"),
        ("smooth-obstacle", "nodal"), ("elastic-transition-r32", "nodal"), ("transition-line-3d", "nodal")]
# VTK cell types: quadratic and linear triangles, tetrahedra, edges
CELL_TYPES = {("omega", 2, 2): vtk.VTK_QUADRATIC_TRIANGLE, ("omega", 2, 1): vtk.VTK_TRIANGLE,
              ("omega", 3, 2): vtk.VTK_QUADRATIC_TETRA, ("gamma_c", 2, 2): vtk.VTK_QUADRATIC_EDGE,
              ("gamma_c", 2, 1): vtk.VTK_LINE, ("gamma_c", 3, 2): vtk.VTK_QUADRATIC_TRIANGLE}


class KeepingWriter(VtkWriter):
    """The writer, noting right after each write (the mesh is refined in place later) what
    NGSolve itself says of the solution at some of the written points: u_h (and u) found by
    NGSolve's own point search, the dofs, the cells of Gamma_C."""

    kept = {}

    def __call__(self, case, method, level, problem, solve):
        super().__call__(case, method, level, problem, solve)
        omega, _ = level_files(self.directory, case.name, method.name, level)
        _, points, _, _, _ = read(omega)
        pick = np.random.default_rng(level).choice(len(points), 25, replace=False)
        mesh, gf = problem.mesh, problem.gridfunction(solve.u)
        at = [mesh(*p[:mesh.dim]) for p in points[pick]]
        trace = problem.trace
        KeepingWriter.kept[case.name, method.name, level] = {
            "pick": pick, "u_h": np.array([gf(p) for p in at]).reshape(len(pick), -1),
            "u": np.array([case.u(p) for p in at]).reshape(len(pick), -1) if case.u is not None else None,
            "ndof": problem.ndof, "cells": len(trace.edges) if trace.faces is None else len(trace.faces.vertices)}


@pytest.fixture(scope="module")
def written(tmp_path_factory):
    folder = tmp_path_factory.mktemp("vtk")
    for case in dict.fromkeys(c for c, _ in RUNS):
        methods = [m for c, m in RUNS if c == case]
        frame = api.run([case], methods, levels=LEVELS, show_progress=False, on_level=KeepingWriter(folder))
        assert (frame.status == "converged").all()
    return folder


def read(path):
    reader = vtk.vtkXMLUnstructuredGridReader()
    reader.SetFileName(str(path))
    reader.Update()
    grid = reader.GetOutput()
    assert grid.GetNumberOfPoints() > 0, f"VTK read nothing from {path}"
    points = vtk_to_numpy(grid.GetPoints().GetData())
    point_data = {grid.GetPointData().GetArrayName(i): vtk_to_numpy(grid.GetPointData().GetArray(i))
                  for i in range(grid.GetPointData().GetNumberOfArrays())}
    cell_data = {grid.GetCellData().GetArrayName(i): vtk_to_numpy(grid.GetCellData().GetArray(i))
                 for i in range(grid.GetCellData().GetNumberOfArrays())}
    types = {grid.GetCellType(i) for i in range(grid.GetNumberOfCells())}
    return grid, points, point_data, cell_data, types


def levels_of(case, method):
    return LEVELS + (1 if method.endswith("p1") else 0)


@pytest.mark.parametrize("case,method", RUNS)
@pytest.mark.parametrize("stem", ["omega", "gamma_c"])
def test_the_collection_lists_every_level_and_vtk_reads_each(written, case, method, stem):
    folder = written / case / method
    entries = ET.parse(folder / f"{stem}.pvd").getroot().find("Collection").findall("DataSet")
    assert [int(e.get("timestep")) for e in entries] == list(range(levels_of(case, method)))
    dim = registered_cases()[case].dimension
    order = 1 if method.endswith("p1") else 2
    for entry in entries:
        _, _, _, _, types = read(folder / entry.get("file"))
        assert types == {CELL_TYPES[stem, dim, order]}


@pytest.mark.parametrize("case,method", RUNS)
def test_omega_holds_u_h_at_the_nodes_of_its_space(written, case, method):
    """One point per scalar dof (vertices, and edge midpoints for P2), u_h there as NGSolve
    evaluates the solution; u and u - u_h for a case with an exact solution."""
    known = registered_cases()[case]
    level = levels_of(case, method) - 1
    kept = KeepingWriter.kept[case, method, level]
    grid, points, data, _, _ = read(written / case / method / f"omega_level{level}.vtu")
    components = 2 if known.physics.elastic else 1
    assert grid.GetNumberOfPoints() == kept["ndof"] // components
    name = "displacement" if known.physics.elastic else "u_h"
    assert set(data) == {name} | ({"u", "error"} if known.u is not None else set())
    stored = data[name][kept["pick"]].reshape(len(kept["pick"]), -1)
    assert np.allclose(stored[:, :components], kept["u_h"], rtol=1e-12, atol=1e-12)
    if known.physics.elastic:
        assert stored.shape[1] == 3 and not stored[:, 2].any()        # ParaView warps by 3-vectors
    if known.u is not None:
        exact = data["u"][kept["pick"]].reshape(len(kept["pick"]), -1)[:, :components]
        assert np.allclose(exact, kept["u"], rtol=1e-12, atol=1e-12)
        assert np.allclose(data["error"], data["u"] - data[name], atol=1e-14)


@pytest.mark.parametrize("case,method", RUNS)
def test_gamma_c_holds_the_contact_fields(written, case, method):
    """One cell per edge (2D) or triangle (3D) of Gamma_C with the discrete pressure; the gap
    of u_h; where a constraint of the cones is active the gap closes (complementarity), and
    `nodal` keeps every node out of the obstacle."""
    known = registered_cases()[case]
    level = levels_of(case, method) - 1
    cells = KeepingWriter.kept[case, method, level]["cells"]
    grid, points, point_data, cell_data, _ = read(written / case / method / f"gamma_c_level{level}.vtu")
    assert grid.GetNumberOfCells() == cells
    assert {"gap_h", "active"} <= set(point_data) and {"pressure", "in_contact"} <= set(cell_data)
    assert np.array_equal(cell_data["in_contact"], (cell_data["pressure"] > 0).astype(np.uint8))
    gap, active = point_data["gap_h"], point_data["active"].astype(bool)
    scale = max(1.0, np.abs(gap).max())
    if method in ("nodal", "p1"):
        assert active.any()
        assert np.abs(gap[active]).max() <= 1e-9 * scale
        assert gap.min() >= -1e-9 * scale
    if method == "nitsche":
        assert not active.any()             # no constraints: its contact is in the pressure only
    if known.u is not None:
        assert {"gap", "exact_pressure"} <= set(point_data) | set(cell_data)
        assert point_data["gap"].min() >= -1e-12 and cell_data["exact_pressure"].min() >= -1e-9


def test_the_writer_knows_which_cases_it_wrote(written):
    from harness.methods import methods_named
    case = registered_cases()["transition-r32"]
    writer = VtkWriter(written)
    assert writer.written(case, methods_named(["nodal", "p1"]), LEVELS)
    assert not writer.written(case, methods_named(["nodal"]), LEVELS + 1)
    assert not writer.written(registered_cases()["smooth"], methods_named(["nodal"]), LEVELS)


def test_run_vtk_writes_the_files_from_the_command_line(tmp_path, capsys):
    from harness.cli import main
    assert main(["run", "--case", "transition-r32", "--method", "nodal", "--levels", "2", "--out", str(tmp_path),
                 "--quiet", "--vtk"]) == 0
    assert "omega.pvd" in capsys.readouterr().out
    assert sorted(p.name for p in (tmp_path / "vtk" / "transition-r32" / "nodal").glob("*.pvd")) == ["gamma_c.pvd", "omega.pvd"]
    ngs.ngsglobals.msg_level = 0


def test_the_writer_can_keep_to_the_levels_it_is_given(tmp_path):
    """``finest``: {method: level} writes only those levels (the rest of the chain unwritten)."""
    api.run(["transition-r32"], ["nodal"], levels=3, show_progress=False, on_level=VtkWriter(tmp_path, finest={"nodal": 2}))
    folder = tmp_path / "transition-r32" / "nodal"
    assert sorted(p.name for p in folder.glob("*.vtu")) == ["gamma_c_level2.vtu", "omega_level2.vtu"]
    entries = ET.parse(folder / "omega.pvd").getroot().find("Collection").findall("DataSet")
    assert [e.get("file") for e in entries] == ["omega_level2.vtu"]


@pytest.mark.slow          # 2 s: a 3D study
def test_the_3d_mean_writes_its_triangle_conditions_as_cell_data():
    """The 3D `mean` constrains triangle means, not midpoints: Gamma_C's file marks the
    triangles whose condition was active (cell data ``active``; on them the mean of u_h - alpha
    vanishes, the discrete complementarity) and no midpoint (transition-line-3d, level 0)."""
    from conftest import problem_at

    from harness.methods import METHODS
    from harness.report.vtk import contact_fields
    case = registered_cases()["transition-line-3d"]
    problem = problem_at("transition-line-3d", 0, 2)
    solve = METHODS["mean"].solve(case, problem, None, None)
    points, _, point_data, cell_data = contact_fields(case, problem, solve)
    nv = len(problem.trace.vertices)
    active = cell_data["active"].astype(bool)
    assert active.any() and not point_data["active"][nv:].any()
    # a P2 triangle's mean is the average of its three midside values (MATH.md, Section 8)
    midside = point_data["gap_h"][nv + problem.trace.faces.edges]
    assert np.abs(midside[active].mean(axis=1)).max() <= 1e-9
