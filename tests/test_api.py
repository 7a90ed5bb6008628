"""The public API the docs show: names and signatures pinned, the hook, and `harness.run(out=...)`
writing what `python -m harness run --out` writes."""
import importlib
import inspect
import re
from pathlib import Path

import harness
from harness import DaskEngine, InProcess, LocalProcesses, VtkWriter
from harness.methods import LevelSolve

E = inspect.Parameter.empty
# parameter names and defaults, in order (annotations are strings under `from __future__ import annotations`)
SIGNATURES = {
    harness.run: [("cases", E), ("methods", "all"), ("levels", 5), ("meshes", "uniform"), ("out", None),
                  ("reference_levels", None), ("engine", None), ("checkpoints", None), ("vtk", False),
                  ("show_progress", True), ("on_level", None), ("check_memory", True)],
    harness.rates: [("rows", E), ("fit_levels", 3), ("out", None)],
    harness.quantities: [("rows", E), ("out", None)],
    harness.efficiency: [("rows", E), ("mesh", "uniform"), ("baseline", None), ("methods", ())],
    harness.plot: [("rows", E), ("case", None), ("kind", "convergence"), ("ax", None)],
    harness.store: [("rows", E), ("folder", E)],
    harness.report: [("cases", None), ("methods", ("all",)), ("levels", None), ("profile", "default"),
                     ("results", "results"), ("out", "report"), ("engine", None), ("show_progress", True), ("vtk", False),
                     ("check_memory", True)],
    harness.sweep: [("case", E), ("methods", E), ("values", None), ("level", 4), ("reference", True), ("out", None),
                    ("engine", None), ("show_progress", True)],
    harness.latex_tables: [("rows", E), ("fit_levels", 3)],
    harness.coulomb_axis: [("case", "elastic-coulomb-r32"), ("coefficients", (0.1, 0.3, 0.5, 1.0, 2.0, 5.0)), ("level", 3),
                           ("method", None), ("show_progress", False)],
    harness.case_table: [("cases", None)],
    harness.method_table: [],
    harness.load_case: [("spec", E)],
    harness.registered_cases: [("dimension", None)],
    harness.methods_named: None,
    # the ParaView writer as an on_level hook
    VtkWriter: [("directory", E), ("finest", None)],
}


def test_the_citation_cites_this_version_on_its_changelog_date():
    """CITATION.cff's version and release date are the CHANGELOG's latest entry's (the version
    is written once in the code, ``harness.__version__``; a static file can only be checked)."""
    root = Path(harness.__file__).parents[1]
    version, date = re.search(r"^## (\S+) — (\d{4}-\d{2}-\d{2})", (root / "CHANGELOG.md").read_text(), re.M).groups()
    citation = (root / "CITATION.cff").read_text()
    assert re.search(r"^version: (\S+)$", citation, re.M)[1] == version == harness.__version__
    assert re.search(r'^date-released: "(\S+)"$', citation, re.M)[1] == date


def test_the_api_readme_shows_exists_with_its_signatures():
    # the version is the CHANGELOG's latest entry
    assert re.search(r"^## (\S+) — ", (Path(harness.__file__).parents[1] / "CHANGELOG.md").read_text(), re.M)[1] == harness.__version__
    for function, expected in SIGNATURES.items():
        parameters = inspect.signature(function).parameters.values()
        if expected is not None:
            assert [(p.name, p.default) for p in parameters] == expected, function.__name__
    assert {"workers", "scheduler", "threads"} <= set(inspect.signature(DaskEngine).parameters)
    assert "threads" in inspect.signature(InProcess).parameters
    assert {"workers", "threads"} <= set(inspect.signature(LocalProcesses).parameters)
    assert set(harness.__all__) >= {"run", "rates", "quantities", "efficiency", "plot", "report", "store", "cases",
                                    "case_table", "method_table", "load_case", "registered_cases", "Case", "CaseError",
                                    "METHODS", "methods_named"}
    plots = importlib.import_module("harness.report.plots")
    assert inspect.isfunction(harness.report) and plots.__name__ == "harness.report.plots"
    assert all(isinstance(engine, harness.Engine) for engine in (InProcess(), LocalProcesses(2), DaskEngine(2)))


def test_report_is_a_function_after_its_package_is_imported_in_a_fresh_process():
    """``harness.report`` is ``harness.api.report``, not the package the import system binds
    under that name (the package is imported once by ``harness/__init__``, and unbound)."""
    import subprocess
    import sys
    code = ("import harness.report.plots, harness.report.build, harness, inspect; "
            "from harness.report import latex; assert inspect.isfunction(harness.report), harness.report; "
            "assert harness.report is harness.api.report")
    subprocess.run([sys.executable, "-c", code], check=True)


def test_cases_is_case_table_deprecated():
    import pytest
    with pytest.warns(DeprecationWarning, match="case_table"):
        assert harness.cases().equals(harness.case_table())


def test_the_hook_sees_every_studied_solve_and_keeps_what_it_returns():
    seen = []

    def on_level(case, method, level, problem, solve):
        assert isinstance(solve, LevelSolve) and solve.u.shape == (problem.ndof,)
        seen.append((method.name, level, solve.fields["status"]))

    frame = harness.run("transition-r32", methods="nodal", levels=2, show_progress=False, on_level=on_level)
    assert seen == [("nodal", 0, "converged"), ("nodal", 1, "converged")] and len(frame) == 2


def test_run_into_a_folder_writes_what_the_command_line_writes(tmp_path):
    """`harness.run(out=...)` and `python -m harness run --out` store the same rows the same way:
    the same results.csv but for the timing columns (and each refuses a folder another owns:
    tests/test_shared_folder.py runs both)."""
    import pandas as pd

    from harness.cli import main
    frame = harness.run("transition-r32", methods="nodal", levels=2, out=tmp_path / "api", show_progress=False)
    assert frame.attrs["stored"] == f"wrote {tmp_path / 'api' / 'results.csv'}: 2 rows of this run"
    assert main(["run", "--case", "transition-r32", "--method", "nodal", "--levels", "2", "--out", str(tmp_path / "cli"),
                 "--quiet"]) == 0
    api, cli = (pd.read_csv(tmp_path / name / "results.csv") for name in ("api", "cli"))
    timing = [c for c in api.columns if c.endswith("seconds") or c in ("threads", "started", "wall_seconds")]
    assert list(api.columns) == list(cli.columns)
    pd.testing.assert_frame_equal(api.drop(columns=timing), cli.drop(columns=timing))
    assert sorted(p.name for p in (tmp_path / "api").iterdir()) == sorted(p.name for p in (tmp_path / "cli").iterdir())


def test_run_takes_one_method_object_and_warns_of_a_method_no_case_needs():
    """``methods`` as the command line takes them, or one ``Method``; a method named one by one
    that discretises none of the cases is a ``StudyWarning`` (the command line's `harness:` line)."""
    import pytest

    nodal = harness.METHODS["nodal"]
    assert harness.run("transition-r32", methods=nodal, levels=1, show_progress=False).method.tolist() == ["nodal"]
    with pytest.warns(harness.StudyWarning, match="mortar-nodal skipped: it couples 2 bodies, not 1"):
        rows = harness.run("transition-r32", methods=["nodal", "mortar-nodal"], levels=1, show_progress=False)
    assert rows.method.tolist() == ["nodal"]


PAPER = ["corner-r12", "wedge-r23", "oscillating-r34", "borderline-h2", "smooth-obstacle", "transition-r32", "smooth"]


def test_a_group_of_cases_expands_to_its_cases_in_registry_order_each_once():
    """``--case GROUP`` and ``harness.run([GROUP])``: "all", the groups derived from what a case
    is, and those cases declare ("paper": one scalar 2D case per regime of the paper)."""
    from harness.problem.case import case_groups, expand_groups
    registry, groups = harness.registered_cases(), case_groups()
    assert groups["all"] == list(registry) and groups["paper"] == PAPER
    assert all(registry[n].dimension == 2 and registry[n].physics.name == "scalar" and registry[n].bodies == 1
               for n in groups["paper"])
    assert groups["3d"] == [n for n, c in registry.items() if c.dimension == 3]
    assert groups["two-body"] == [n for n, c in registry.items() if c.bodies == 2]
    assert groups["reference"] == [n for n, c in registry.items() if not c.exact]
    own = "tests/data/gap_case.py"
    assert expand_groups(["smooth", "paper", own, "two-body", own]) == (
        ["smooth", *[n for n in PAPER if n != "smooth"], own, *groups["two-body"]])


def test_declared_groups_are_names_and_none_derived_or_a_case_name(tmp_path):
    import pytest

    from harness.problem.case import CaseError, case_groups, load_case
    text = (Path(__file__).parent / "data" / "gap_case.py").read_text()
    for groups, message in [('"paper"', "list of names"), ('["two words"]', "list of names"),
                            ('["3d"]', "derived from what the case declares")]:
        path = tmp_path / f"case_{len(list(tmp_path.iterdir()))}.py"
        path.write_text(text + f"\ngroups = {groups}\n")
        with pytest.raises(CaseError, match=message):
            load_case(str(path))
    path = tmp_path / "clash.py"
    path.write_text(text + '\ngroups = ["smooth"]\n')
    own, smooth = load_case(str(path)), harness.registered_cases()["smooth"]
    assert "smooth" in own.groups
    with pytest.raises(CaseError, match="share a case's name"):
        case_groups({own.name: own, "smooth": smooth})
    with pytest.raises(CaseError, match="is a group of cases"):
        load_case("paper")
