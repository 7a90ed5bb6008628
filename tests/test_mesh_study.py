"""The report's mesh study on every kind of case (issue 53): what it runs on a 3D case and on a
case without u, and the picture of a 3D adaptive mesh (its triangles on Gamma_C)."""
import numpy as np
import pytest

from harness.mesh.strategies import MeshStrategy
from harness.mesh.trace import contact_trace
from harness.methods import methods_for, methods_named
from harness.problem.case import load_case, registered_cases
from harness.report.figures import plt
from harness.report.sections.meshes import adaptive_mesh
from harness.study.chain import PROFILES, run_chain
from harness.study.planning.mesh_study import (
    PICTURE_METHOD,
    PLAN,
    FinestMesh,
    load_finest_mesh,
    mesh_config,
    mesh_jobs_plan,
    mesh_levels,
    save_finest_mesh,
)


def default_config():
    return mesh_config({"profile": "default", "methods": ["all"], **PROFILES["default"]})


def test_the_mesh_study_has_a_case_of_every_kind():
    """A scalar and an elastic body, two bodies, 3D (the fine profile's), and a case without u:
    every kind the graded and adaptive meshes apply to (issue 53)."""
    cases = [registered_cases()[name] for name in default_config()["cases"] + list(PLAN["fine_cases"])]
    assert {case.physics.name for case in cases} >= {"scalar", "elasticity"}
    assert {case.bodies for case in cases} == {1, 2}
    assert {case.dimension for case in cases} == {2, 3}
    assert any(case.exact for case in cases) and any(not case.exact for case in cases)


@pytest.mark.parametrize("profile", ["default", "fine"])
def test_a_3d_case_runs_its_own_level_count_and_p1_within_p2s_elements(profile):
    """A 3D level has 8 times the elements: the 3D chains (the fine profile's) stop at its
    ``mesh_levels_3d`` and P1 gets no level past P2's (its 2D extra level is kept)."""
    config = mesh_config({"profile": profile, "methods": ["all"], **PROFILES[profile]})
    plans = list(mesh_jobs_plan(registered_cases().values(), config))
    three_d = [(case, methods) for case, _, methods in plans if case.dimension == 3]
    two_d = [(case, methods) for case, _, methods in plans if case.dimension == 2]
    assert two_d and bool(three_d) == (profile == "fine")        # 3D: the fine profile's (its cost)
    for case, methods in three_d:
        assert mesh_levels(case, config) == PROFILES[profile]["mesh_levels_3d"]
        assert {"nodal", "p1"} <= {m.name for m in methods_for(case, methods)}
        assert all(m.extra_levels == 0 for m in methods)
    for case, methods in two_d:
        assert mesh_levels(case, config) == PROFILES[profile]["mesh_levels"]
        assert any(m.order == 1 and m.extra_levels == 1 for m in methods)


def mean_areas(points, triangles, near: float = 0.1) -> tuple[float, float]:
    """Mean area of the triangles of Gamma_C within ``near`` of the line x = 0, and of the others."""
    corners = points[triangles][:, :, :2]
    sides = corners[:, 1:] - corners[:, :1]
    areas = 0.5 * np.abs(sides[:, 0, 0] * sides[:, 1, 1] - sides[:, 0, 1] * sides[:, 1, 0])
    close = np.abs(corners[:, :, 0].mean(axis=1)) < near
    return areas[close].mean(), areas[~close].mean()


@pytest.mark.slow          # 2 s: a 3D adaptive chain
def test_a_3d_adaptive_meshs_picture_is_its_triangles_on_gamma_c(tmp_path):
    """The finest 3D adaptive mesh is kept as the triangles of Gamma_C (z = 0), covering it
    once, refined from the coarse mesh more at the transition line x = 0 than away from it, and
    drawn."""
    case = load_case("transition-line-3d")
    output = run_chain(case, methods_named([PICTURE_METHOD]), 2, mesh=MeshStrategy("adaptive"), on_level=FinestMesh())
    save_finest_mesh(output.kept, tmp_path / "finest.npz")
    points, triangles = load_finest_mesh(tmp_path / "finest.npz")
    assert points.shape[1] == 3 and np.abs(points[:, 2]).max() == 0.0        # Gamma_C is the bottom face
    assert triangles.shape[1] == 3 and triangles.max() < len(points)
    corners = points[triangles][:, :, :2]
    sides = corners[:, 1:] - corners[:, :1]
    assert 0.5 * np.abs(sides[:, 0, 0] * sides[:, 1, 1] - sides[:, 0, 1] * sides[:, 1, 0]).sum() == pytest.approx(4.0)
    coarse = mean_areas(*output.kept[(PICTURE_METHOD, 0)])
    finest = mean_areas(points, triangles)
    assert coarse[0] / finest[0] > coarse[1] / finest[1] > 1       # refined everywhere, most at the line
    paths = adaptive_mesh(case, points, triangles, tmp_path, PICTURE_METHOD)
    assert paths["png"].stat().st_size > 1000
    plt.close("all")


def test_the_mesh_studys_picture_method_keeps_the_2d_triangles_and_a_3d_trace():
    """The kept mesh is the level's own: in 3D exactly the trace's triangles on Gamma_C."""
    case = load_case("transition-line-3d")
    kept = []

    def hook(case, method, level, problem, solve):
        kept.append((FinestMesh()(case, method, level, problem, solve), contact_trace(problem.mesh)))

    run_chain(case, methods_named([PICTURE_METHOD]), 1, on_level=hook)
    (points, triangles), trace = kept[0]
    assert len(triangles) == len(trace.faces.vertices)
    assert np.array_equal(np.sort(points[triangles].reshape(-1, 3), axis=0),
                          np.sort(trace.faces.corners(trace).reshape(-1, 3), axis=0))
