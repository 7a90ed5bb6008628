"""The public API the docs show (harness 0.3): names and signatures pinned, the hook's two forms."""
import inspect
import re
import warnings
from pathlib import Path

import pytest

import harness
from harness.measure.rates import rate_table
from harness.methods.base import LevelSolve
from harness.report import plots
from harness.report.vtk import VtkWriter
from harness.study import DaskEngine, InProcess, LocalProcesses

E = inspect.Parameter.empty
# parameter names and defaults, in order (annotations are strings under `from __future__ import annotations`)
SIGNATURES = {
    harness.run: [("cases", E), ("methods", "all"), ("levels", 5), ("show_progress", True), ("on_level", None),
                  ("models", None), ("engine", None), ("checkpoints", None), ("meshes", "uniform")],
    harness.case_table: [("cases", None)],
    harness.method_table: [],
    harness.load_case: [("spec", E)],
    harness.registered_cases: [("dimension", None)],
    rate_table: None,
    harness.methods_named: None,
    # the report's figures from DataFrames, and the ParaView writer as an on_level hook (0.3.2)
    plots.convergence: [("results", E), ("case", None), ("ax", None), ("title", None)],
    plots.verdict_matrix: [("rates", E), ("ax", None)],
    plots.rate_summary: [("rates", E), ("ax", None), ("band", 0.1)],
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
    assert re.search(r"^## (\S+)", (Path(harness.__file__).parents[1] / "CHANGELOG.md").read_text(), re.M)[1] == harness.__version__
    assert harness.cases is harness.case_table
    for function, expected in SIGNATURES.items():
        parameters = inspect.signature(function).parameters.values()
        if expected is not None:
            assert [(p.name, p.default) for p in parameters] == expected, function.__name__
    assert {"workers", "scheduler", "threads"} <= set(inspect.signature(DaskEngine).parameters)
    assert "threads" in inspect.signature(InProcess).parameters
    assert {"workers", "threads"} <= set(inspect.signature(LocalProcesses).parameters)
    assert set(harness.__all__) >= {"run", "cases", "case_table", "method_table", "load_case", "registered_cases",
                                    "Case", "CaseError", "METHODS", "methods_named"}


def test_the_hook_sees_every_studied_solve_and_keeps_what_it_returns():
    seen = []

    def on_level(case, method, level, problem, solve):
        assert isinstance(solve, LevelSolve) and solve.u.shape == (problem.ndof,)
        seen.append((method.name, level, solve.fields["status"]))

    frame = harness.run("transition-r32", methods="nodal", levels=2, show_progress=False, on_level=on_level)
    assert seen == [("nodal", 0, "converged"), ("nodal", 1, "converged")] and len(frame) == 2


def test_a_hook_of_version_0_1_is_refused_in_one_line_since_0_4():
    def old_hook(case, model, level, problem, u, solution, trace_u):
        raise AssertionError("never called")

    with pytest.raises(ValueError, match=r"removed in 0.4.0: write on_level\(case, method, level, problem, solve\)"):
        harness.run("transition-r32", methods="nodal", levels=2, show_progress=False, on_level=old_hook)
    with warnings.catch_warnings():
        warnings.simplefilter("error")          # the current form warns about nothing
        harness.run("transition-r32", methods="nodal", levels=1, show_progress=False,
                    on_level=lambda case, method, level, problem, solve: None)

