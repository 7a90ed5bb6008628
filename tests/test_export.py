"""The exchange with other codes: ``harness.export`` writes a case's discrete problems, and
``external:DIR`` measures solutions given as values at the Lagrange nodes (docs/guide/export-format.md)."""
import json
import subprocess
import sys

import ngsolve as ngs
import numpy as np
import pytest

import harness
from harness import StudyFailed
from harness.methods import ExternalError, external
from harness.study.export import ExportError, solution_writer


def _round_trip(tmp_path, case, levels, method="nodal"):
    folder = tmp_path / f"{case}-{method}"
    own = harness.run(case, methods=[method], levels=levels, show_progress=False,
                      on_level=solution_writer(folder, case, method))
    imported = harness.run(case, methods=[f"external:{folder}"], levels=levels, show_progress=False)
    return own.sort_values("level"), imported.sort_values("level"), folder


@pytest.mark.parametrize("case, levels", [("transition-r32", 3), ("elastic-transition-r32", 2),
                                          pytest.param("transition-line-3d", 1, marks=pytest.mark.slow)])
def test_the_harness_own_solution_as_point_values_measures_the_same_errors(tmp_path, case, levels):
    own, imported, _ = _round_trip(tmp_path, case, levels)
    assert (imported.method == "nodal-points").all() and (imported.status == "converged").all()
    for column in ("err_h1", "err_l2"):
        np.testing.assert_allclose(imported[column].to_numpy(), own[column].to_numpy(), rtol=1e-12, atol=0)
    np.testing.assert_array_equal(imported.ndof.to_numpy(), own.ndof.to_numpy())


@pytest.fixture(scope="module")
def exported(tmp_path_factory):
    out = tmp_path_factory.mktemp("export") / "transition"
    harness.export("transition-r32", levels=2, out=out)
    return out


def _level(folder, level):
    with np.load(folder / f"level-{level}.npz") as data:
        return {key: data[key] for key in data.files}


@pytest.mark.parametrize("case", ["corner-r12", "elastic-transition-r32", pytest.param("transition-line-3d", marks=pytest.mark.slow)])
def test_the_load_moments_integrate_the_load_of_one_and_of_x(tmp_path, case):
    """Sum_i L(psi_i) = L(1) and sum_i L(psi_i) x_i = L(x) (the Lagrange basis reproduces 1 and
    x), against NGSolve's integrals of the case's data, computed here independently."""
    loaded = harness.load_case(case)
    harness.export(loaded, levels=1, out=tmp_path / "e")
    arrays = _level(tmp_path / "e", 0)
    mesh = ngs.Mesh(loaded.geometry.GenerateMesh(maxh=loaded.maxh))
    n = ngs.specialcf.normal(mesh.dim)
    for weight, at_nodes in ((ngs.CF(1.0), np.ones(len(arrays["nodes"]))), (ngs.x, arrays["nodes"][:, 0])):
        expected = []
        for j in range(arrays["load"].shape[1]):
            pick = (lambda g: g) if arrays["load"].shape[1] == 1 else (lambda g, j=j: g[j])
            total = ngs.Integrate(pick(loaded.f) * weight, mesh, order=12)
            total += ngs.Integrate(pick(loaded.neumann_data(n)) * weight, mesh, ngs.BND, order=12,
                                   definedon=mesh.Boundaries("neumann"))
            if loaded.contact_load is not None:
                total += ngs.Integrate(pick(loaded.contact_load) * weight, mesh, ngs.BND, order=12,
                                       definedon=mesh.Boundaries("contact"))
            expected.append(total)
        got = at_nodes @ arrays["load"]
        np.testing.assert_allclose(got, expected, rtol=1e-6, atol=1e-9 * np.abs(arrays["load"]).sum())


def test_an_export_holds_the_format_the_manifest_describes(exported):
    manifest = json.loads((exported / "manifest.json").read_text())
    assert manifest["format"] == "signorini-harness-export" and manifest["format_version"] == 1
    assert manifest["case"]["name"] == "transition-r32" and manifest["case"]["expected_rate"] == 1.5
    arrays = _level(exported, 1)
    nodes = arrays["nodes"]
    assert len(nodes) == manifest["levels"][1]["nodes"] and np.array_equal(nodes[:len(arrays["vertices"])], arrays["vertices"])
    # midpoints: node 3..5 of each cell sit halfway between corners (0,1), (1,2), (2,0)
    corners, mids = nodes[arrays["cell_nodes"][:, :3]], nodes[arrays["cell_nodes"][:, 3:]]
    np.testing.assert_allclose(mids, 0.5 * (corners + np.roll(corners, -1, axis=1)), atol=1e-15)
    # the discrete Dirichlet values interpolate the exact u on Gamma_u at this level to O(h^3)
    on = arrays["on_dirichlet"]
    assert on.any() and np.abs(arrays["u_dirichlet"][on] - arrays["u_exact"][on]).max() < 1e-3
    assert set(np.unique(arrays["facet_labels"])) == {1, 2, 3}
    assert np.all(np.isfinite(arrays["gap"][arrays["on_contact"]])) and np.isnan(arrays["gap"][~arrays["on_contact"]]).all()


def test_an_export_refuses_a_folder_of_other_files(tmp_path):
    (tmp_path / "results.csv").write_text("keep me")
    with pytest.raises(ExportError, match="not an export"):
        harness.export("transition-r32", levels=1, out=tmp_path)
    assert (tmp_path / "results.csv").read_text() == "keep me"


def _broken(tmp_path, exported_solution, change):
    folder = tmp_path / "broken"
    folder.mkdir()
    for path in exported_solution.iterdir():
        (folder / path.name).write_bytes(path.read_bytes())
    change(folder)
    return folder


def _rewrite(folder, level, **changes):
    arrays = _level(folder, level)
    arrays.update({key: value(arrays) for key, value in changes.items()})
    np.savez(folder / f"level-{level}.npz", **arrays)


@pytest.fixture(scope="module")
def own_solution(tmp_path_factory):
    folder = tmp_path_factory.mktemp("own") / "nodal"
    harness.run("transition-r32", methods=["nodal"], levels=2, show_progress=False,
                on_level=solution_writer(folder, "transition-r32", "nodal"))
    return folder


@pytest.mark.parametrize("change, message", [
    (lambda f: _rewrite(f, 1, points=lambda a: a["points"][:-1], values=lambda a: a["values"][:-1]), "no solution on the level"),
    (lambda f: _rewrite(f, 1, points=lambda a: a["points"] + np.array([0.01, 0.0])), "match no node"),
    (lambda f: _rewrite(f, 1, values=lambda a: np.where(np.arange(len(a["values"]))[:, None] == 3, np.nan, a["values"])), "NaN"),
    (lambda f: (f / "level-1.npz").unlink(), "a level is missing"),
    (lambda f: _rewrite(f, 0, values=lambda a: np.repeat(a["values"], 2, axis=1)), "components"),
])
def test_a_bad_solution_file_is_refused_in_one_line(tmp_path, own_solution, change, message):
    folder = _broken(tmp_path, own_solution, change)
    # what needs no mesh is refused before the study (ExternalError), the rest when its level is reached
    with pytest.raises((ExternalError, StudyFailed), match=message) as refused:
        harness.run("transition-r32", methods=[f"external:{folder}"], levels=2, show_progress=False)
    assert "\n" not in str(refused.value)


@pytest.mark.parametrize("manifest, message", [(None, "no manifest.json"), ({"format": "other"}, "format is not"),
                                               ({"format": "signorini-harness-solution", "format_version": 1}, "lacks method")])
def test_a_folder_that_is_no_solution_folder_is_refused(tmp_path, manifest, message):
    (tmp_path / "level-0.npz").write_bytes(b"")
    if manifest is not None:
        (tmp_path / "manifest.json").write_text(json.dumps(manifest))
    with pytest.raises(ExternalError, match=message):
        external(tmp_path)


def test_the_command_line_refuses_a_bad_external_folder_with_exit_status_2(tmp_path):
    done = subprocess.run([sys.executable, "-m", "harness", "run", "--case", "transition-r32", "--method",
                           f"external:{tmp_path}", "--levels", "2", "--out", str(tmp_path / "out")],
                          capture_output=True, text=True)
    assert done.returncode == 2 and done.stderr.count("\n") == 1 and "no manifest.json" in done.stderr


def test_the_command_line_exports(tmp_path):
    done = subprocess.run([sys.executable, "-m", "harness", "export", "--case", "corner-r12", "--levels", "2", "--out",
                           str(tmp_path / "e"), "--quiet"], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert sorted(p.name for p in (tmp_path / "e").iterdir()) == [
        "level-0.msh", "level-0.npz", "level-0.vtu", "level-1.msh", "level-1.npz", "level-1.vtu", "manifest.json"]


def test_another_case_leaves_the_external_method_out_with_its_reason(own_solution):
    method = external(own_solution)
    assert "transition-r32" in method.refusal(harness.load_case("corner-r12"))
    assert method.refusal(harness.load_case("transition-r32")) is None


def test_one_method_holds_a_code_s_solutions_of_several_cases(tmp_path):
    """A folder of case folders (or external:DIR given once per case) is one method over those cases."""
    for case in ("transition-r32", "corner-r12"):
        harness.run(case, methods=["nodal"], levels=2, show_progress=False,
                    on_level=solution_writer(tmp_path / "all" / case, case, "nodal"))
    method = external(tmp_path / "all")
    assert method.cases == ("corner-r12", "transition-r32")
    given = harness.methods_named([f"external:{tmp_path / 'all' / case}" for case in ("transition-r32", "corner-r12")])
    assert len(given) == 1 and set(given[0].cases) == {"transition-r32", "corner-r12"}
    rows = harness.run(["transition-r32", "corner-r12"], methods=["nodal", f"external:{tmp_path / 'all'}"], levels=2,
                       show_progress=False)
    mine, theirs = (rows[rows.method == name].sort_values(["case", "level"]).err_h1.to_numpy() for name in ("nodal", "nodal-points"))
    np.testing.assert_allclose(theirs, mine, rtol=1e-12)
