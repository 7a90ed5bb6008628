"""Command line: results written atomically; bad input gives one line and a non-zero exit."""
import contextlib
import io
import subprocess
import sys
from pathlib import Path

import pandas as pd
import pytest

from harness.measure.quantities import FRICTION_QUANTITIES, QUANTITY_COLUMNS
from harness.measure.rates import RATE_COLUMNS
from harness.measure.richardson import QUANTITY_TABLE_COLUMNS
from harness.methods import METHODS
from harness.study.chain.rows import COLUMNS

# the methods of a 2D scalar case (`mean-edges` is 3D only)
METHODS_2D = [name for name, m in METHODS.items() if 2 in m.dimensions and 1 in m.bodies]   # one body

ROOT = Path(__file__).resolve().parent.parent


def harness(*args, cwd=None):
    """The command as a user runs it: a fresh ``python -m harness`` process."""
    return subprocess.run([sys.executable, "-m", "harness", *args], capture_output=True, text=True, cwd=ROOT)


def harness_here(*args) -> subprocess.CompletedProcess:
    """The same command line through ``cli.main`` in this process, for the refusals and listings
    (a fresh interpreter's 2 s of imports each, and the entry point is the runs' above)."""
    from harness.cli import main
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err), contextlib.chdir(ROOT):
        try:
            code = main(list(args))
        except SystemExit as stop:              # argparse's refusals
            code = stop.code if isinstance(stop.code, int) else 1
    return subprocess.CompletedProcess(list(args), code, out.getvalue(), err.getvalue())


def test_run_writes_one_tidy_row_per_case_method_level(tmp_path):
    done = harness("run", "--case", "transition-r32", "--method", "all", "--levels", "2", "--out", str(tmp_path), "--quiet")
    assert done.returncode == 0, done.stderr
    frame = pd.read_csv(tmp_path / "results.csv")
    assert list(frame.columns) == COLUMNS
    # P1 runs one level more, to reach the dofs of P2's finest level
    # P4 one level less (its dofs per level four times P2's); P3 on P2's levels
    assert frame.groupby("method")["level"].max().to_dict() == {"mean": 1, "nodal": 1, "p1": 2, "nitsche": 1, "penalty": 1,
                                                                 "nitsche-p1": 2, "penalty-p1": 2, "nitsche-p3": 1,
                                                                 "nodal-p3": 1, "penalty-p3": 1, "mean-p3": 1, "nitsche-p4": 0,
                                                                 "nodal-p4": 0, "penalty-p4": 0, "mean-p4": 0}
    assert (frame.kkt_residual <= 1e-10).all() and (frame.status == "converged").all()
    # `all`'s methods for other kinds of case (mean-edges, the mortar methods) are no mistake: no line
    assert "skipped" not in done.stderr, done.stderr


def test_a_named_method_that_serves_none_of_the_cases_is_named_in_one_line(tmp_path):
    done = harness("run", "--case", "elastic-wedge", "--method", "mortar-nodal", "--method", "nodal", "--levels", "1",
                   "--out", str(tmp_path), "--quiet")
    assert done.returncode == 0, done.stderr
    assert done.stderr.strip().splitlines() == [
        "harness: mortar-nodal skipped: it couples 2 bodies, not 1"]
    assert set(pd.read_csv(tmp_path / "results.csv").method) == {"nodal"}


@pytest.mark.parametrize("option, methods", [(["--method", "weak"], {"nitsche", "penalty", "nitsche-p1", "penalty-p1"}),
                                             (["--method", "nitsche:theta=-1,gamma0=0.5"], {"nitsche:gamma0=0.5,theta=-1"}),
                                             (["--method", "paper"], {"mean", "nodal"}),
                                             (["--method", "p1", "--method", "mean"], {"mean", "p1"})])
def test_method_options_select_methods(tmp_path, option, methods):
    # in this process (``cli.main``): the other tests here run the command as a user does
    from harness.cli import main
    assert main(["run", "--case", "transition-r32", *option, "--levels", "1", "--out", str(tmp_path), "--quiet"]) == 0
    assert set(pd.read_csv(tmp_path / "results.csv").method) == methods


def test_methods_lists_order_contact_condition_and_reference():
    done = harness_here("methods")
    assert done.returncode == 0
    for text in ("mean", "nodal", "p1", "Section 3", "Section 5", "Drouet & Hild"):
        assert text in done.stdout


@pytest.mark.parametrize("args, message", [
    (["--case", "no-such-case"], "known cases"),
    (["--case", "no-such-case"], "groups: all, 2d, 3d"),
    (["--case", "transition-r32", "--model", "both"], "--model"),
    (["--case", "transition-r32", "--method", "p3"], "--method"),
    (["--case", "transition-r32", "--levels", "0"], "positive integer"),
    (["--case", "transition-r32", "--levels", "three"], "positive integer"),
    (["--case", "tests/data/bad_sign_case.py"], "violates the Signorini condition"),
    (["--case", "tests/data/missing.py"], "not found"),
])
def test_bad_input_gives_one_line_and_keeps_existing_results(tmp_path, args, message):
    existing = tmp_path / "results.csv"
    existing.write_text("precious\n")
    done = harness_here("run", *args, "--out", str(tmp_path), "--quiet")
    assert done.returncode != 0
    lines = done.stderr.strip().splitlines()
    assert len(lines) == 1 and message in lines[0], done.stderr
    assert existing.read_text() == "precious\n"


def test_unwritable_output_folder_is_refused(tmp_path):
    blocker = tmp_path / "file"
    blocker.write_text("x")
    done = harness_here("run", "--case", "transition-r32", "--levels", "1", "--out", str(blocker / "sub"), "--quiet")
    assert done.returncode != 0 and "not writable" in done.stderr and len(done.stderr.strip().splitlines()) == 1


def test_cases_lists_regime_and_expected_rate():
    done = harness_here("cases")
    assert done.returncode == 0 and "transition-r32" in done.stdout and "h^3/2" in done.stdout and "h^1 |log h|^1/4" in done.stdout


def test_cases_lists_the_groups_case_takes():
    done = harness_here("cases")
    groups = done.stdout.split("groups (--case GROUP")[1]
    assert done.returncode == 0 and "paper " in groups and "reference " in groups and "two-body " in groups


def test_a_group_of_cases_runs_each_of_its_cases_once(tmp_path):
    done = harness_here("run", "--case", "paper", "--case", "smooth", "--method", "nodal", "--levels", "1",
                        "--out", str(tmp_path), "--quiet")
    assert done.returncode == 0, done.stderr
    frame = pd.read_csv(tmp_path / "results.csv")
    assert sorted(frame.case) == sorted(["corner-r12", "wedge-r23", "oscillating-r34", "borderline-h2",
                                         "smooth-obstacle", "transition-r32", "smooth"])


def test_rates_of_missing_or_malformed_results_is_one_line(tmp_path):
    done = harness_here("rates", str(tmp_path / "nothing.csv"))
    assert done.returncode != 0 and "not found" in done.stderr and len(done.stderr.strip().splitlines()) == 1
    bad = tmp_path / "results.csv"
    bad.write_text("a,b\n1,2\n")
    done = harness_here("rates", str(bad))
    assert done.returncode != 0 and "missing column" in done.stderr and len(done.stderr.strip().splitlines()) == 1


@pytest.mark.slow          # 7 s: a 3-level study in a fresh process
def test_rates_command_writes_rates_beside_results(tmp_path):
    assert harness("run", "--case", "smooth", "--levels", "3", "--out", str(tmp_path), "--quiet").returncode == 0
    # `rates` is table work: in this process (the run above is the real command)
    done = harness_here("rates", str(tmp_path / "results.csv"))
    assert done.returncode == 0, done.stderr
    rates = pd.read_csv(tmp_path / "rates.csv")
    assert list(rates.columns) == RATE_COLUMNS
    assert {"fitted_rate", "verdict", "sharper_verdict", "fitted_rate_l2", "fitted_rate_best", "best_verdict",
            "fitted_rate_trace", "fitted_rate_pressure_h12"} <= set(rates.columns)
    assert len(rates) == len(METHODS_2D)
    done = harness_here("rates", str(tmp_path / "results.csv"), "--qoi")
    assert done.returncode == 0, done.stderr
    quantities = pd.read_csv(tmp_path / "quantities.csv")
    assert list(quantities.columns) == QUANTITY_TABLE_COLUMNS
    # Richardson needs three levels: P4 runs two here (one fewer than P2, at about its dofs)
    levels = pd.read_csv(tmp_path / "results.csv").groupby("method")["level"].nunique()
    # a frictionless case: every quantity but the friction cases' own
    frictionless = set(QUANTITY_COLUMNS) - set(FRICTION_QUANTITIES)
    assert set(quantities.quantity) == frictionless and len(quantities) == (levels >= 3).sum() * len(frictionless)
    assert "bands holding the exact value" in done.stdout


@pytest.mark.slow          # 5 s: every method on 3 levels
def test_case_file_by_path_runs_every_method_and_rates_needs_no_case_option(tmp_path):
    """The results carry each row's theory, so `rates` fits a CSV of an unregistered case alone."""
    case = str(ROOT / "tests" / "data" / "gap_case.py")
    assert harness("run", "--case", case, "--method", "all", "--levels", "3", "--out", str(tmp_path), "--quiet").returncode == 0
    done = harness_here("rates", str(tmp_path / "results.csv"))
    assert done.returncode == 0, done.stderr
    rates = pd.read_csv(tmp_path / "rates.csv")
    assert set(rates.method) == set(METHODS_2D) and (rates.case == "gap-transition").all()
    assert dict(zip(rates.method, rates.expected_rate)) == {"mean": 1.5, "nodal": 1.5, "p1": 1.0, "nitsche": 1.5,
                                                            "penalty": 1.0, "nitsche-p1": 1.0, "penalty-p1": 1.0,
                                                            "nitsche-p3": 1.5, "nodal-p3": 1.5, "penalty-p3": 1.0,
                                                            "mean-p3": 1.5, "nitsche-p4": 1.5, "nodal-p4": 1.5,
                                                            "penalty-p4": 1.0, "mean-p4": 1.5}


def test_results_of_harness_0_1_are_refused_in_one_line(tmp_path):
    """A `model` column and no theory in the rows (harness 0.1): not read any more."""
    old = tmp_path / "results.csv"
    pd.DataFrame({"case": "smooth", "model": "nodal", "level": [0, 1, 2], "h": [0.4, 0.2, 0.1],
                  "err_h1": [1e-2, 2.5e-3, 6.25e-4]}).to_csv(old, index=False)
    done = harness_here("rates", str(old))
    assert done.returncode == 2 and "is not a results CSV: missing column(s) method" in _one_line(done.stderr)
    assert not (tmp_path / "rates.csv").exists()


@pytest.mark.slow          # 3.5 s: a sweep in a fresh process; the sweep's planning is test_profiles'
def test_sweep_writes_one_row_per_value_and_method_beside_the_reference(tmp_path):
    done = harness("sweep", "--case", "transition-r32", "--method", "nitsche:theta=-1", "--method", "penalty-p1",
                   "--values", "0.01,0.1", "--level", "1", "--out", str(tmp_path), "--quiet")
    assert done.returncode == 0, done.stderr
    frame = pd.read_csv(tmp_path / "sweep_transition-r32.csv")
    assert sorted(frame.method) == sorted(["nitsche:gamma0=0.01,theta=-1", "nitsche:gamma0=0.1,theta=-1",
                                           "penalty-p1:epsilon0=0.01", "penalty-p1:epsilon0=0.1", "nodal"])
    # P1 is compared at the level with P2's dofs
    assert frame.ndof.nunique() == 1 and (frame.status == "converged").all()
    assert (tmp_path / "sweep_transition-r32.png").is_file()


@pytest.mark.parametrize("args, message", [(["--values", "0,1"], "positive"), (["--method", "nodal"], "no parameter"),
                                           (["--method", "nitsche:gamma=1"], "parameters"), (["--level", "-1"], "level")])
def test_sweep_refuses_bad_input_in_one_line(tmp_path, args, message):
    base = {"--method": "nitsche", "--values": "0.1", "--level": "1"}
    for flag, value in zip(args[::2], args[1::2]):
        base[flag] = value
    done = harness_here("sweep", "--case", "transition-r32", *[x for kv in base.items() for x in kv], "--out", str(tmp_path / "s"))
    assert done.returncode == 2 and message in done.stderr and len(done.stderr.strip().splitlines()) == 1
    assert not (tmp_path / "s").exists()


def _one_line(err: str) -> str:
    lines = [line for line in err.splitlines() if line.strip()]
    assert len(lines) == 1 and "Traceback" not in err, err
    return lines[0]


@pytest.mark.parametrize("spec, message", [("nitsche:theta=5", "theta must be 1, 0 or -1"),
                                           ("penalty:epsilon0=-1", "epsilon0 must be a finite positive number"),
                                           ("nitsche:gamma0=nan", "gamma0 must be a finite positive number")])
def test_a_parameter_outside_what_the_method_allows_is_refused_in_one_line(tmp_path, spec, message):
    done = harness_here("run", "--case", "transition-r32", "--method", spec, "--levels", "1", "--out", str(tmp_path / "out"))
    assert done.returncode == 2 and message in _one_line(done.stderr)
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("body, what, line", [("x = 1\nraise SystemExit(3)\n", "SystemExit: 3", 2),
                                              ("import math\n\ny = 1 / 0\n", "ZeroDivisionError", 3),
                                              ("def f(:\n", "SyntaxError", 1)])
def test_a_case_file_that_exits_or_raises_at_import_is_one_line_naming_file_and_line(tmp_path, body, what, line):
    case = tmp_path / "broken.py"
    case.write_text(body)
    done = harness_here("run", "--case", str(case), "--levels", "1", "--out", str(tmp_path / "out"))
    assert done.returncode == 2
    assert f"{case}, line {line} failed to import: {what}" in _one_line(done.stderr)


def test_an_unreachable_scheduler_is_one_line_within_its_timeout(tmp_path, capsys, monkeypatch):
    from harness import cli
    from harness.study.execution import dask_engine
    monkeypatch.setattr(dask_engine, "SCHEDULER_TIMEOUT", 1)
    code = cli.main(["run", "--case", "transition-r32", "--method", "nodal", "--levels", "1", "--out", str(tmp_path),
                     "--scheduler", "tcp://127.0.0.1:1", "--quiet"])
    assert code == cli.EXIT_STUDY_FAILED == 3
    assert "no Dask scheduler answered at tcp://127.0.0.1:1 within 1 s" in _one_line(capsys.readouterr().err)


def test_every_failed_solve_is_one_line_on_stderr_even_with_quiet(tmp_path, capsys, monkeypatch):
    """A solver that never meets its test (forced here): the run still writes its rows, says on
    stderr which case, method and level failed and why, one line each, and exits 1."""
    from harness import cli
    from harness.solvers.bound_constraints import KKT
    monkeypatch.setattr(KKT, "converged", lambda self, tol: False)
    code = cli.main(["run", "--case", "transition-r32", "--method", "nodal", "--levels", "2", "--out", str(tmp_path), "--quiet"])
    err = capsys.readouterr().err.splitlines()
    assert code == 1 and (tmp_path / "results.csv").is_file()
    assert len(err) == 2
    for line, level in zip(err, (0, 1)):
        assert line.startswith(f"harness: case transition-r32, method nodal, level {level}: stalled: KKT residual")


def test_an_unexpected_error_is_one_line_and_debug_shows_its_traceback(tmp_path, capsys, monkeypatch):
    from harness import cli
    from harness.study.execution import engines

    def broken(*args, **kwargs):
        raise RuntimeError("something inside")
    monkeypatch.setattr(engines, "run_chain", broken)
    args = ["run", "--case", "transition-r32", "--method", "nodal", "--levels", "1", "--out", str(tmp_path), "--quiet"]
    assert cli.main(args) == cli.EXIT_STUDY_FAILED
    assert _one_line(capsys.readouterr().err) == "harness: error: RuntimeError: something inside (run with --debug for the traceback)"
    with pytest.raises(Exception, match="something inside"):
        cli.main(args + ["--debug"])


HEAVY = ("ngsolve", "pandas", "scipy", "matplotlib")


def _modules_after(code: str) -> set:
    done = subprocess.run([sys.executable, "-c", f"import sys\n{code}\nprint(' '.join(sys.modules))"],
                          capture_output=True, text=True, cwd=Path(__file__).resolve().parent.parent)
    assert done.returncode == 0, done.stderr
    return set(done.stdout.split())


def test_import_harness_imports_no_solver_table_or_plot_library():
    """Issue 61: `import harness` costs the standard library; its public names load on use."""
    assert not _modules_after("import harness") & set(HEAVY)
    # the subprocess fails (and _modules_after with it) unless the names resolve
    assert "harness.methods" in _modules_after("import harness\nassert callable(harness.run) and 'mean' in harness.METHODS")


def test_listing_the_cases_imports_neither_pandas_nor_scipy_nor_matplotlib():
    """`python -m harness cases` needs the case files (which use NGSolve), nothing else heavy."""
    loaded = _modules_after("from harness.cli import main\nmain(['cases'])")
    assert not loaded & {"pandas", "scipy", "matplotlib"}, loaded & {"pandas", "scipy", "matplotlib"}


@pytest.mark.slow          # 7 s: two reports
def test_report_answers_for_its_own_rows_not_for_other_runs_kept_in_the_folder(tmp_path):
    """A row that did not converge, of another case, kept in results.csv by an earlier run: the
    report of transition-r32 still exits 0; a failed row of its own makes it exit 1."""
    from harness.cli import main
    args = ["report", "--case", "transition-r32", "--method", "nodal", "--levels", "2", "--quiet",
            "--results", str(tmp_path / "results"), "--report", str(tmp_path / "report")]
    assert main(args) == 0
    rows = pd.read_csv(tmp_path / "results" / "results.csv")
    other = rows.iloc[:1].assign(case="smooth", status="stalled: KKT residual 1e-3 with a consistent active set")
    pd.concat([rows, other]).to_csv(tmp_path / "results" / "results.csv", index=False)
    assert main(args) == 0
    own = rows.assign(status="stalled: forced")
    own.to_csv(tmp_path / "results" / "results.csv", index=False)
    from harness.cli import _report_failures, _report_rows, build_parser
    parsed = build_parser(args).parse_args(args)
    assert _report_failures(_report_rows(parsed, own)) == 1


def test_a_method_that_a_mesh_strategy_cannot_carry_is_refused_alone_and_named_with_others(tmp_path):
    """hp meshes carry only methods of variable degree: nodal alone is refused in one line
    (exit 2, nothing written); beside penalty, which runs, it is named in one line, under
    --quiet too, and in the run's summary."""
    done = harness_here("run", "--case", "transition-r32", "--method", "nodal", "--mesh", "hp", "--levels", "1",
                        "--out", str(tmp_path / "alone"))
    assert done.returncode == 2 and "nodal skipped on hp meshes" in _one_line(done.stderr)
    assert not (tmp_path / "alone" / "results.csv").exists()
    done = harness_here("run", "--case", "transition-r32", "--method", "nodal", "--method", "penalty", "--mesh", "hp",
                        "--levels", "1", "--out", str(tmp_path / "both"), "--quiet")
    assert done.returncode == 0 and "nodal skipped on hp meshes" in _one_line(done.stderr)
    assert "left out: nodal skipped on hp meshes" in done.stdout


def test_an_on_level_hook_of_another_signature_is_refused_naming_the_expected_one():
    import harness

    def old_hook(case, method, level, problem, solve, u, fields):
        pass
    with pytest.raises(ValueError, match=r"on_level must take \(case, method, level, problem, solve\); .*old_hook"):
        harness.run("transition-r32", "nodal", 1, on_level=old_hook, show_progress=False)


def test_more_hp_levels_than_round_off_allows_are_refused_before_the_first_solve(tmp_path):
    """corner-r12's hp layers (sigma = 0.15) reach below 1e-13 of the coordinates past 14 levels
    (``mesh.hp.SMALLEST_RELATIVE_EDGE``): 30 levels are refused in one line, exit 2, nothing written."""
    done = harness_here("run", "--case", "corner-r12", "--method", "nitsche", "--mesh", "hp", "--levels", "30",
                        "--out", str(tmp_path))
    assert done.returncode == 2
    assert "--mesh hp: case corner-r12: hp meshes with sigma=0.15 reach at most 14 levels" in _one_line(done.stderr)
    assert not (tmp_path / "results.csv").exists()


def test_a_method_that_discretises_some_of_the_cases_only_is_named_in_the_summary():
    """nodal-p3 needs an exact solution: beside a reference-solution case the study says which
    case it left out and why (``attrs['left_out']``), runs the others, and warns of nothing (a
    method that discretises some of the cases is the run's mix, not a mistake)."""
    import warnings

    import harness
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        rows = harness.run(["transition-r32", "smooth-obstacle"], methods=["nodal", "nodal-p3"], levels=1,
                           show_progress=False)
    assert not [w for w in caught if issubclass(w.category, harness.StudyWarning)]
    assert "nodal-p3 not run on smooth-obstacle: P3 needs the case's exact solution (a reference solution is P2)" \
        in rows.attrs["left_out"]
    assert set(rows[rows.case == "transition-r32"].method) == {"nodal", "nodal-p3"}
