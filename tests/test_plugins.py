"""Methods and cases from outside the package (issue 51): a method by its file, by file:name,
by a dotted name, by an installed package's entry point and as an object, each checked as a
registered method is, each refused in one line when it cannot be used; cases from an installed
package's entry point. Everything from a folder outside the repository, as a user would."""
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pandas as pd
import pytest

import harness
from harness.methods import MethodError, check_method, get_method, methods_named

ROOT = Path(__file__).resolve().parent.parent
EXAMPLES = ROOT / "examples" / "methods"


def harness_cli(*args, cwd, pythonpath=None):
    env = dict(os.environ)
    if pythonpath:
        env["PYTHONPATH"] = os.pathsep.join([str(pythonpath), env.get("PYTHONPATH", "")])
    return subprocess.run([sys.executable, "-m", "harness", *args], capture_output=True, text=True, cwd=cwd, env=env)


@pytest.fixture
def outside(tmp_path):
    """A folder outside the repository holding the example method files."""
    for path in EXAMPLES.glob("*.py"):
        shutil.copy(path, tmp_path / path.name)
    return tmp_path


def rows_of(folder: Path) -> pd.DataFrame:
    return pd.read_csv(folder / "results.csv")


def assert_exact(rows: pd.DataFrame, methods: set[str]):
    assert set(rows.method) == methods
    assert (rows.status == "converged").all() and (rows.kkt_residual <= 1e-10).all()


def test_a_method_file_runs_by_its_path_and_is_rated_like_a_registered_one(outside):
    done = harness_cli("run", "--case", "transition-r32", "--method", "nitsche_small_gamma.py", "--method", "nodal",
                       "--levels", "3", "--out", "out", "--quiet", cwd=outside)
    assert done.returncode == 0, done.stderr
    rows = rows_of(outside / "out")
    assert_exact(rows, {"nitsche-g002", "nodal"})
    mine = rows[rows.method == "nitsche-g002"]
    # the theory it declares (Nitsche's, CHR 2015 Thm 3.8: h^{3/2} on transition-r32), in its rows
    assert (mine.expected_rate == 1.5).all() and mine.reference.str.contains("Chouly").all()
    done = harness_cli("rates", "out/results.csv", cwd=outside)
    assert done.returncode == 0 and "nitsche-g002" in pd.read_csv(outside / "out" / "rates.csv").method.tolist()


def test_one_method_of_a_file_is_picked_by_file_colon_name(outside):
    done = harness_cli("run", "--case", "corner-r12", "--method", f"{outside / 'weak_variants.py'}:nitsche_skew", "--levels", "2",
                       "--out", "out", "--quiet", cwd=outside)
    assert done.returncode == 0, done.stderr
    assert_exact(rows_of(outside / "out"), {"nitsche-skew"})
    assert [m.name for m in methods_named(str(outside / "weak_variants.py"))] == ["nitsche-skew", "penalty-stiff"]


@pytest.mark.slow          # 3 s: two worker processes
def test_a_method_of_an_importable_module_runs_by_its_dotted_name_on_two_workers(outside):
    package = outside / "mypkg"
    package.mkdir()
    (package / "__init__.py").write_text("")
    shutil.copy(EXAMPLES / "weak_variants.py", package / "contact.py")
    work = outside / "work"
    work.mkdir()
    done = harness_cli("run", "--case", "transition-r32", "--method", "mypkg.contact:penalty_stiff", "--levels", "2",
                       "--workers", "2", "--out", "out", "--quiet", cwd=work, pythonpath=outside)
    assert done.returncode == 0, done.stderr
    assert_exact(rows_of(work / "out"), {"penalty-stiff"})


def installed_package(site: Path, name: str, modules: dict[str, str], group: str, entry: str) -> Path:
    """A tiny installed package under ``site`` (put it on PYTHONPATH): the ``modules`` (name ->
    source), and a dist-info that declares ``entry`` in the entry-point ``group``."""
    (site / name).mkdir(parents=True)
    (site / name / "__init__.py").write_text("")
    for module, source in modules.items():
        (site / name / f"{module}.py").write_text(source)
    info = site / f"{name}-0.1.dist-info"
    info.mkdir()
    (info / "METADATA").write_text(f"Metadata-Version: 2.1\nName: {name}\nVersion: 0.1\n")
    (info / "entry_points.txt").write_text(f"[{group}]\n{entry}\n")
    return site


@pytest.mark.slow          # 3 s: a package installed in a fresh venv
def test_an_installed_packages_entry_point_method_runs_by_its_name(outside):
    site = installed_package(outside / "site", "userpkg", {"methods": (EXAMPLES / "nitsche_small_gamma.py").read_text()},
                             "signorini_harness.methods", "small-gamma = userpkg.methods:method")
    done = harness_cli("run", "--case", "transition-r32", "--method", "nitsche-g002", "--levels", "2", "--out", "out",
                       "--quiet", cwd=outside, pythonpath=site)
    assert done.returncode == 0, done.stderr
    assert_exact(rows_of(outside / "out"), {"nitsche-g002"})
    listed = harness_cli("run", "--case", "transition-r32", "--method", "no-such", "--out", "x", cwd=outside, pythonpath=site)
    assert listed.returncode == 2 and "nitsche-g002" in listed.stderr


def test_a_method_object_runs_in_the_python_api_beside_a_name(outside):
    from dataclasses import replace
    mine = replace(get_method("nodal"), name="my-nodal")
    rows = harness.run(["transition-r32"], methods=[mine, "p1"], levels=2, show_progress=False)
    assert_exact(rows, {"my-nodal", "p1"})
    nodal = harness.run(["transition-r32"], methods=["nodal"], levels=2, show_progress=False)
    pd.testing.assert_series_equal(rows[rows.method == "my-nodal"].err_h1.reset_index(drop=True),
                                   nodal.err_h1.reset_index(drop=True))


@pytest.mark.parametrize("source, message", [
    ("broken = (\n", "failed to import: SyntaxError"),
    ("x = 1\n", "defines no method"),
    ("from dataclasses import replace\nfrom harness.methods import get_method\n"
     "method = replace(get_method('nodal'), name='bad name', order=3)\n", "is malformed: name 'bad name'"),
    ("method = 42\n", "is not a method"),
])
def test_a_method_file_that_cannot_be_used_is_refused_in_one_line_before_anything_is_written(outside, source, message, capsys):
    from harness.cli import main
    (outside / "mine.py").write_text(source)
    code = main(["run", "--case", "transition-r32", "--method", str(outside / "mine.py"), "--out", str(outside / "out")])
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1 and message in err, err
    assert not (outside / "out").exists()


def test_a_method_named_like_a_registered_one_is_refused():
    from dataclasses import replace
    with pytest.raises(MethodError, match="two methods named 'nodal'"):
        methods_named([replace(get_method("mean"), name="nodal"), "nodal"])


def test_every_registered_method_passes_the_checks_a_plugin_passes():
    for method in harness.METHODS.values():
        assert check_method(method, "registered") is method


@pytest.mark.slow          # 4 s: a package installed in a fresh venv
def test_a_case_of_an_installed_package_is_registered_by_its_entry_point(tmp_path):
    text = (ROOT / "cases" / "transition_r32.py").read_text().replace('name = "transition-r32"', 'name = "my-transition"')
    assert 'name = "my-transition"' in text
    site = installed_package(tmp_path / "site", "usercases", {"mine": text}, "signorini_harness.cases",
                             "my-transition = usercases.mine")
    done = harness_cli("run", "--case", "my-transition", "--method", "nodal", "--levels", "2", "--out", "out", "--quiet",
                       cwd=tmp_path, pythonpath=site)
    assert done.returncode == 0, done.stderr
    assert set(rows_of(tmp_path / "out").case) == {"my-transition"}
    assert "my-transition" in harness_cli("cases", cwd=tmp_path, pythonpath=site).stdout


# --- mesh strategies (``harness.mesh.strategies.Strategy``)

@pytest.mark.slow          # 4 s: two worker processes
def test_a_mesh_strategy_file_runs_from_outside_on_two_workers_and_labels_its_rows(tmp_path):
    shutil.copy(ROOT / "examples" / "meshes" / "strong_grading.py", tmp_path / "grading.py")
    done = harness_cli("run", "--case", "corner-r12", "--method", "nodal", "--method", "p1", "--mesh", "grading.py", "--levels", "3",
                       "--workers", "2", "--out", "out", "--quiet", cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    rows = rows_of(tmp_path / "out")
    assert set(rows["mesh"]) == {"graded-mu0.1"} and set(rows.method) == {"nodal", "p1"}
    assert (rows.kkt_residual <= 1e-10).all() and rows.effectivity.notna().all()


def test_a_mesh_strategy_object_and_an_installed_one_run_by_the_api_and_by_label(tmp_path):
    sys.path.insert(0, str(ROOT / "examples" / "meshes"))
    try:
        from strong_grading import Grading
    finally:
        sys.path.pop(0)
    rows = harness.run("corner-r12", methods="nodal", levels=2, meshes=[Grading(mu=0.2), "uniform"], show_progress=False)
    assert sorted(set(rows["mesh"])) == ["graded-mu0.2", "uniform"] and (rows.status == "converged").all()
    site = installed_package(tmp_path / "site", "usermeshes", {"grading": (ROOT / "examples" / "meshes" / "strong_grading.py").read_text()},
                             "signorini_harness.meshes", "strong = usermeshes.grading:strategy")
    done = harness_cli("run", "--case", "corner-r12", "--method", "nodal", "--mesh", "graded-mu0.1", "--levels", "2", "--out", "out",
                       "--quiet", cwd=tmp_path, pythonpath=site)
    assert done.returncode == 0, done.stderr
    assert set(rows_of(tmp_path / "out")["mesh"]) == {"graded-mu0.1"}


@pytest.mark.parametrize("source, message", [("strategy = 3\n", "is not a mesh strategy"),
                                             ("x = 1\n", "defines no mesh strategy")])
def test_a_mesh_strategy_that_cannot_be_used_is_refused_in_one_line(tmp_path, source, message, capsys):
    from harness.cli import main
    (tmp_path / "mine.py").write_text(source)
    code = main(["run", "--case", "corner-r12", "--mesh", str(tmp_path / "mine.py"), "--out", str(tmp_path / "out")])
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1 and message in err, err
    assert not (tmp_path / "out").exists()


def test_a_variant_takes_none_of_the_roles_of_the_method_it_varies():
    """``dataclasses.replace`` under another name and ``with_parameters`` make variants that join
    no sweep or study of the report unasked; ``with_roles`` gives a variant roles of its own, and
    a copy under the same name (``with_extra_levels``) keeps them."""
    from dataclasses import replace

    from harness.methods import METHODS, SWEPT, Nitsche, with_role
    nitsche = METHODS["nitsche"]
    assert SWEPT in nitsche.roles
    renamed = replace(nitsche, name="my-nitsche", law=Nitsche(0.02, -1.0))
    variant = nitsche.with_parameters(gamma0=0.02)
    assert renamed.roles == variant.roles == frozenset() and with_role(SWEPT, [renamed, variant]) == []
    assert renamed.with_roles(SWEPT).roles == {SWEPT} and replace(renamed.with_roles(SWEPT), order=2).roles == {SWEPT}
    assert nitsche.with_extra_levels(1).roles == nitsche.roles
    with pytest.raises(ValueError, match="unknown role"):
        nitsche.with_roles("favourite")


@pytest.mark.parametrize("case", ["tresca-r32", "elastic-tresca-r32"])
def test_a_friction_law_from_a_file_outside_the_repository_runs_on_the_scalar_and_the_elastic_case(outside, case):
    """``examples/methods/tresca_law.py`` (Nitsche-Tresca with theta = 1/2, a ``FrictionLaw`` of
    its own), from a folder outside the repository: every row converged beside the built-in
    cone, its errors within a few per cent of the cone's (both converge to the same u)."""
    done = harness_cli("run", "--case", case, "--method", "tresca_law.py", "--method", "nodal", "--levels", "3",
                       "--out", "out", "--quiet", cwd=outside)
    assert done.returncode == 0, done.stderr
    rows = rows_of(outside / "out")
    assert (rows.status == "converged").all() and (rows.kkt_residual <= 1e-10).all()
    errors = rows.pivot(index="level", columns="method", values="err_h1")
    mine = [name for name in errors.columns if name != "nodal"]
    assert len(mine) == 1 and (abs(errors[mine[0]] / errors["nodal"] - 1.0) < 0.2).all(), errors


def test_a_contact_law_between_two_bodies_from_a_file_outside_the_repository_runs_beside_the_mortar(outside):
    """``examples/methods/two_body_penalty.py`` (``TwoBodyLaw`` with the penalty law), from a folder
    outside the repository, on the two-body transition (non-matching meshes) beside `mortar-nodal`:
    every row converged, its errors above the mortar's (the penalty's consistency error) and
    falling level by level."""
    done = harness_cli("run", "--case", "two-body-transition-r32", "--method", "two_body_penalty.py", "--method",
                       "mortar-nodal", "--levels", "3", "--out", "out", "--quiet", cwd=outside)
    assert done.returncode == 0, done.stderr
    rows = rows_of(outside / "out")
    assert (rows.status == "converged").all() and (rows.kkt_residual <= 1e-10).all()
    errors = rows.pivot(index="level", columns="method", values="err_h1")
    assert (errors["two-body-penalty"] >= errors["mortar-nodal"]).all() and (errors["two-body-penalty"].diff().dropna() < 0).all(), errors
