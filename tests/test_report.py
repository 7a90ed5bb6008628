"""`make report` pieces: results with provenance, reuse of unchanged results, figures, documents."""
import json
import re
from pathlib import Path

import pandas as pd
import pytest

from harness.methods import GROUPS, METHODS
from harness.report.build import make_report
from harness.study.chain import PROFILES
from harness.study.planning.sweep import REPORT_SWEEP

CASES = ["transition-r32", "corner-r12"]            # the cases the report sweeps and studies on other meshes
# and a case without u, the Remark 4.3 case and a two-body case, for what the report says of them
# (one report: its figure processes and its fixed costs once)
ALL = CASES + ["oscillating-r34", "smooth-obstacle", "two-body-transition-r32"]
# a report of all methods runs those of its profile's orders (P1, P2)
REPORTED = {name: m for name, m in METHODS.items() if m.order in PROFILES["default"]["orders"]}


def test_a_report_of_one_case_and_one_method_writes_its_rows_rates_and_page(tmp_path):
    """The fast tier's report, end to end (the module's whole report, 45 s, is `make test-full`'s):
    one case, nodal, two levels."""
    html = make_report("default", tmp_path / "results", tmp_path / "report", ["transition-r32"], show_progress=False,
                       levels=2, methods=("nodal",))
    rows = pd.read_csv(tmp_path / "results" / "results.csv")
    assert set(rows.method) == {"nodal"} and sorted(rows.level.unique()) == [0, 1], rows[["method", "level"]]
    assert (rows.status == "converged").all() and (rows.kkt_residual <= 1e-10).all()
    assert (tmp_path / "results" / "rates.csv").exists()
    page = html.read_text()
    assert "transition-r32" in page and "nodal" in page


@pytest.fixture(scope="module")
def report(tmp_path_factory):
    root = tmp_path_factory.mktemp("study")
    html = make_report("default", root / "results", root / "report", ALL, show_progress=False, levels=3)
    return root, html


@pytest.mark.slow          # the module's report: 45 s
def test_results_rates_and_provenance_are_written(report):
    root, _ = report
    results = pd.read_csv(root / "results" / "results.csv")
    # the P2 methods on 3 levels, the P1 methods on 4
    per_case = {bodies: sum(3 + m.extra_levels for m in REPORTED.values() if 2 in m.dimensions and bodies in m.bodies)
                for bodies in (1, 2)}
    two_body = [name for name in ALL if name.startswith("two-body")]
    assert set(results.case) == set(ALL)
    assert len(results) == (len(ALL) - len(two_body)) * per_case[1] + len(two_body) * per_case[2]
    rates = pd.read_csv(root / "results" / "rates.csv")
    assert {"fitted_rate", "fitted_rate_se", "pairwise_rates", "verdict"} <= set(rates.columns)
    meta = json.loads((root / "results" / "provenance.json").read_text())
    for key in ("harness_version", "git_commit", "ngsolve_version", "date", "machine", "settings", "solver_options"):
        assert key in meta
    assert meta["settings"]["levels"] == 3
    # the solver settings every registered method solved with (none of them has others)
    from harness.solvers.options import SolverOptions
    assert meta["solver_options"] == {"default": SolverOptions().as_dict()}


@pytest.mark.slow          # the module's report: 45 s
def test_report_has_the_two_body_section_with_both_meshes_at_the_interface(report):
    root, html = report
    text = Path(html).read_text()
    assert "Two bodies, non-matching meshes (Section 6)" in text
    section = text[text.rindex("Two bodies, non-matching meshes"):]          # the heading, not the contents
    for method in ("mortar-mean", "mortar-nodal", "mortar-p1"):
        assert method in section[:section.index("<h2", 10)]
    assert (root / "report" / "figures" / "two-body-transition-r32_interface.png").is_file()
    assert "opening [u_h] - 2α" in text


@pytest.mark.slow          # the module's report: 45 s
def test_every_figure_exists_as_png_and_pdf(report):
    root, _ = report
    figures = root / "report" / "figures"
    stems = ["summary_rates", "verdict_matrix"] + [f"{c}_{kind}" for c in ALL for kind in ("convergence", "contact", "solution", "efficiency")] \
        + [f"sweep_{c}" for c in CASES]
    for stem in stems:
        for ext in ("png", "pdf"):
            assert (figures / f"{stem}.{ext}").stat().st_size > 1000, stem


@pytest.mark.slow          # the module's report: 45 s
def test_report_answers_whether_p2_is_the_sweet_spot_across_the_degree(report):
    """The degree study (``study.planning.degree_study``) of the named cases it plans: Nitsche and the
    nodal cone of every degree k = 1 ... 4 on uniform and adaptive meshes, and on hp meshes those
    of them whose space may vary in degree (Nitsche, the nodal cones of k >= 3), each solve exact,
    its rows in degrees.csv, and the section with its figure, cost tables and hp fits."""
    root, html = report
    degrees = pd.read_csv(root / "results" / "degrees.csv")
    assert set(degrees.case) == {"transition-r32"} and set(degrees["mesh"]) == {"uniform", "adaptive", "hp"}
    assert set(degrees.order) == {1, 2, 3, 4} and set(degrees.method) == set(GROUPS["degrees"])
    hp = degrees[degrees["mesh"] == "hp"]
    assert set(hp.method) == {m for m in GROUPS["degrees"] if METHODS[m].variable_degree}
    assert hp.groupby("method")["level"].max().nunique() == 1       # as many levels at every degree
    assert (degrees.kkt_residual <= 1e-10).all() and (degrees.status == "converged").all()
    text = html.read_text()
    assert "Is P2 the sweet spot? The degree k = 1 … 4" in text and "transition-r32, adaptive meshes: cost at equal accuracy" in text
    assert "hp meshes: exponential convergence?" in text
    assert (root / "report" / "figures" / "transition-r32-degrees.png").stat().st_size > 1000


@pytest.mark.slow          # the module's report: 45 s
def test_report_sets_measured_rates_against_theorems(report):
    root, html = report
    text = html.read_text()
    assert "Theorem 4.1 ii, 5.1 ii" in text and "verdict" in text and "data:image/webp;base64" in text
    markdown = (root / "report" / "report.md").read_text()
    assert "| case | method | theory | expected |" in markdown and "figures/transition-r32_convergence.png" in markdown


@pytest.mark.slow          # the module's report: 45 s
def test_report_answers_whether_p2_is_worth_it(report):
    root, html = report
    text = html.read_text()
    assert "Is P2 worth it?" in text and "transition-r32: The claim" in text
    efficiency = pd.read_csv(root / "results" / "efficiency.csv")
    assert set(efficiency.method) == {name for name, m in REPORTED.items() if 2 in m.dimensions}
    assert (efficiency.ndof > 0).all() and (efficiency.total_seconds > 0).all()


def test_rewording_the_report_keeps_the_study_cache_key_and_changing_a_solver_does_not(tmp_path):
    """The cache key hashes the computing code only: a sentence of the report's prose, a comment
    in a report module and in a planning module (``study.planning``), a benchmark, edited in a copy
    of the package, leave it unchanged; a solver's code does not. A comment or docstring edited in
    the computing code leaves it unchanged too (its syntax is hashed), and the figures' key with it."""
    import shutil

    from harness.study.storage.digest import COMPUTING, PACKAGE, code_digest
    copy = tmp_path / "harness"
    shutil.copytree(PACKAGE, copy, ignore=shutil.ignore_patterns("__pycache__"))
    before, drawing = code_digest(copy), code_digest(copy, ("report",))
    assert before == code_digest(PACKAGE) == code_digest(PACKAGE, COMPUTING)
    build = copy / "report" / "build.py"
    build.write_text(build.read_text().replace("Fitted H¹ rates", "Fitted H1 rates"))
    for path in [copy / "bench" / "solvers.py", *(copy / "study" / "planning").glob("*.py"), *(copy / "report").rglob("*.py")]:
        path.write_text("# a note\n" + path.read_text() + "\n# a note\n")
    newton = copy / "solvers" / "newton.py"
    newton.write_text(newton.read_text().replace('"""', '"""A reworded docstring. ', 1) + "\n# a comment\n")
    code_digest.cache_clear()
    assert code_digest(copy) == before
    build.write_text(build.read_text().replace("Fitted H1 rates", "Fitted H¹ rates"))
    code_digest.cache_clear()
    assert code_digest(copy, ("report",)) == drawing            # comments only: no figure drawn again
    newton.write_text(newton.read_text() + "\nCHANGE = 1\n")
    code_digest.cache_clear()
    assert code_digest(copy) != before


def test_the_case_cache_the_checkpoints_and_the_figures_share_one_digest(tmp_path, monkeypatch):
    """``cache_key``, ``chain_key`` and ``figure_cache.job_key`` all begin with
    ``digest.code_hash``: NGSolve's version is in each of them, the report's code in none but
    the figures'."""
    from harness.methods import METHODS
    from harness.problem.case import load_case
    from harness.report import figure_cache
    from harness.study.planning.cache import cache_key
    from harness.study.storage import digest
    from harness.study.storage.checkpoint import chain_key
    case = load_case("transition-r32")

    def keys():
        return (cache_key(case, {"levels": 3}), chain_key(case, METHODS["nodal"], 3),
                figure_cache.job_key(figure_cache.job_key, {}, ()))
    before = keys()
    monkeypatch.setattr(digest, "ngsolve_version", lambda: "0.0")
    assert all(a != b for a, b in zip(before, keys()))


def test_a_figure_is_drawn_again_when_its_rows_its_files_or_the_styles_change(tmp_path):
    from harness.report import figure_cache
    from harness.report.sections.cases import case_figures as _case_figures
    from harness.report.sections.summary import summary_figures as _summary
    frame = pd.DataFrame({"case": ["a"], "err_h1": [0.1]})
    rows = tmp_path / "a.csv"
    rows.write_text("level\n0\n")
    key = figure_cache.job_key(_summary, {"nodal": {"color": "k"}}, (frame,), (rows,))
    assert key == figure_cache.job_key(_summary, {"nodal": {"color": "k"}}, (frame.copy(),), (rows,))
    assert key != figure_cache.job_key(_summary, {"nodal": {"color": "k"}}, (frame.assign(err_h1=0.2),), (rows,))
    assert key != figure_cache.job_key(_summary, {"nodal": {"color": "r"}}, (frame,), (rows,))
    assert key != figure_cache.job_key(_case_figures, {"nodal": {"color": "k"}}, (frame,), (rows,))
    rows.write_text("level\n1\n")
    assert key != figure_cache.job_key(_summary, {"nodal": {"color": "k"}}, (frame,), (rows,))
    # kept only while every figure it names is on disk
    png = tmp_path / "f.png"
    png.write_bytes(b"x")
    figure_cache.store(tmp_path, "a", key, {"convergence": {"png": png}, "solution": None})
    assert figure_cache.stored(tmp_path, "a", key) == {"convergence": {"png": png}, "solution": None}
    assert figure_cache.stored(tmp_path, "a", "another key") is None
    png.unlink()
    assert figure_cache.stored(tmp_path, "a", key) is None


def test_markdown_table_cells_keep_a_literal_bar_inside():
    from harness.report.document import Document
    doc = Document("t")
    doc.table(pd.DataFrame({"case": ["borderline-h2"], "expected": ["h^1 |log h|^1/4"]}))
    header, _, row = doc.markdown(Path(".")).splitlines()[2:5]

    def unescaped_bars(line):
        return len(re.findall(r"(?<!\\)\|", line))
    assert unescaped_bars(row) == unescaped_bars(header) == 3


@pytest.mark.slow          # the module's report: 45 s
def test_report_shows_where_penalty_and_nitsche_parameters_are_safe(report):
    """The sweep of every theta of Nitsche and of the penalty over eps0 / gamma0, beside nodal."""
    root, html = report
    assert "Penalty and Nitsche: where their parameter is safe" in html.read_text()
    for case in CASES:
        sweep = pd.read_csv(root / "results" / "sweeps" / f"{case}.csv")
        swept = sweep[sweep.sweep_parameter.notna()]
        assert set(swept.sweep_method) == set(REPORT_SWEEP["methods"]) and "nodal" in set(sweep.method)
        assert (swept.groupby("sweep_method").sweep_value.nunique() == len(REPORT_SWEEP["values"])).all()
        # theta = -1 is coercive for every gamma0 (CHR 2015 Thm 3.4): Newton converges over the whole range
        assert (swept[swept.sweep_method == "nitsche:theta=-1"].status == "converged").all()


@pytest.mark.slow          # the module's report: 45 s
def test_report_has_both_verdicts_the_regularity_check_and_the_gamma_c_errors(report):
    root, html = report
    text = html.read_text()
    for heading in ("Regularity check: best approximation", "Errors on Γ_C", "verdict (D–H)", "Drouet &amp; Hild"):
        assert heading in text, heading
    rates = pd.read_csv(root / "results" / "rates.csv")
    cones = rates[rates.method.isin(["mean", "nodal", "p1"])]
    # the best approximation needs u: every case but smooth-obstacle
    exact = rates[rates.case != "smooth-obstacle"]
    assert cones.sharper_verdict.notna().all() and exact.fitted_rate_best.notna().all()


@pytest.mark.slow          # the module's report: 45 s
def test_report_states_reference_and_remark_43_findings(report):
    """A reference case says what its errors are measured against; the Remark 4.3 case says
    whether the data support the belief (3 levels: the wording, not the finding)."""
    root, html = report
    text = html.read_text()
    assert "No closed-form solution: every error is measured against the nodal solution 2 levels finer" in text
    assert "with 16 times the dofs of every method" in text
    assert "Remark 4.3" in text and "question. The data " in text and "the authors believe (no theorem)" in text
    assert (root / "report" / "figures" / "smooth-obstacle_contact.png").stat().st_size > 1000
    # the LaTeX tables beside the figures (issue 32): one per case, the summary, the efficiency, a document
    tables = {p.name for p in (root / "report" / "tables").glob("*.tex")}
    assert tables == {f"{case}.tex" for case in ALL} | {"summary.tex", "efficiency.tex", "all.tex"}


def test_report_goals_are_judged_on_the_engine_make_report_uses():
    """The goals of `bench --only report` from its rows: make report's variant (one process per
    core) within 3 minutes and 3 GB, 2 processes at least 1.2x faster than one."""
    from harness.bench.report import report_goals
    frame = pd.DataFrame({"engine": ["in one process", "on 2 local processes"], "workers": [0, 2],
                          "wall_seconds": [240.0, 170.0], "peak_rss_mb": [2000.0, 3500.0], "speedup": [1.0, 240 / 170]})
    goals = report_goals(frame, make_workers=2)
    assert [(goal, met) for goal, met, _ in goals] == [
        ("make report <= 3 min", True), ("make report peak RSS <= 3 GB (largest process)", False),
        ("report on 2 local processes against the first variant >= 1.2x", True)]
    assert report_goals(frame, make_workers=1)[0][2] == "240 s (in one process)"       # no such variant: the first


@pytest.mark.slow          # two whole (small) reports in fresh processes: 24 s
def test_bench_report_profiles_the_report_and_compares_engines():
    """`bench --only report` (here a 2-level report of one case): one row per engine with its
    wall time and peak memory, the speedup against the first, and where the time went."""
    from harness.bench.report import profile_tables, report_goals, run_report_bench
    frame, profile = run_report_bench((0, 2), cases=["transition-r32"], levels=2, progress=lambda *_: None)
    assert list(frame.workers) == [0, 2] and (frame.wall_seconds > 0).all() and (frame.peak_rss_mb > 100).all()
    assert frame.speedup.iloc[0] == 1.0
    sections, phases = profile_tables(profile)
    assert {"study", "sweeps", "figures", "jobs (wall)", "document"} <= set(sections.section)
    assert ("study", "transition-r32") in phases.index and phases.loc[("study", "transition-r32"), "solve"] > 0
    assert (frame.job_seconds > 0).all() and (frame.jobs_wall > 0).all() and (frame.figures_wall > 0).all()
    goals = report_goals(frame, make_workers=2)
    assert [goal for goal, _, _ in goals][:2] == ["make report <= 3 min", "make report peak RSS <= 3 GB (largest process)"]
    assert "2 local processes" in goals[0][2]          # the goal is judged on the engine make report uses


@pytest.mark.slow       # three reports (about 20 s); `run --vtk` and the writer's check are in make test
def test_report_vtk_reruns_a_stored_case_without_its_files_once(tmp_path, capsys):
    """`report --vtk` over a stored study: the case is run again to write its ParaView files,
    then reused while they are there; the rows are the same."""
    run = dict(show_progress=False, levels=2, methods=("nodal",))
    make_report("default", tmp_path / "results", tmp_path / "report", ["transition-r32"], **run)
    first = pd.read_csv(tmp_path / "results" / "results.csv")
    capsys.readouterr()
    make_report("default", tmp_path / "results", tmp_path / "report", ["transition-r32"], vtk=True, **run)
    assert "transition-r32: reusing results" not in capsys.readouterr().out
    assert (tmp_path / "results" / "vtk" / "transition-r32" / "nodal" / "omega_level1.vtu").is_file()
    again = pd.read_csv(tmp_path / "results" / "results.csv")
    columns = ["level", "ndof", "err_h1", "err_l2", "kkt_residual"]
    pd.testing.assert_frame_equal(first[columns], again[columns])
    make_report("default", tmp_path / "results", tmp_path / "report", ["transition-r32"], vtk=True, **run)
    assert "transition-r32: reusing results" in capsys.readouterr().out


@pytest.mark.slow          # the module's report: 45 s
def test_report_is_navigable_contents_link_to_anchors_and_cases_collapse(report):
    """A table of contents whose every link has its target, the verdict matrix at the top, each
    case collapsible, no heading "Theorem Remark"."""
    root, html = report
    text = html.read_text()
    assert "<nav class='contents'>" in text and "<table class='matrix'>" in text
    assert text.index("<table class='matrix'>") < text.index("id='problem-and-methods'")
    links = set(re.findall(r"href='#([^']+)'", text))
    ids = set(re.findall(r"id='([^']+)'", text))
    assert links and links <= ids, links - ids
    for case in CASES:
        assert f"<details id='{case}'>" in text
    assert "Theorem Remark" not in text and "Theorem Section" not in text
    markdown = (root / "report" / "report.md").read_text()
    assert "**Contents**" in markdown and "](#at-a-glance-every-case-method)" in markdown


@pytest.mark.slow          # the module's report: 45 s
def test_report_embeds_compact_images_and_keeps_full_pngs(report):
    root, html = report
    text = html.read_text()
    assert "data:image/webp;base64" in text and "data:image/png;base64" not in text
    embedded = sum(len(m) for m in re.findall(r"data:image/webp;base64,([A-Za-z0-9+/=]+)", text)) * 3 / 4
    pngs = sum(p.stat().st_size for p in (root / "report" / "figures").glob("*.png"))
    assert embedded < 0.5 * pngs


@pytest.mark.slow          # the module's report: 45 s
def test_unchanged_results_are_reused(report, capsys):
    """Last in this file: it rewrites the module's report with one of its cases."""
    root, _ = report
    stored = (root / "results" / "cases" / "corner-r12.csv").stat().st_mtime_ns
    figure = root / "report" / "figures" / "corner-r12_convergence.png"
    drawn = figure.stat().st_mtime_ns
    # one of the two cases: the reuse is per case; its figures are kept (same rows, same code)
    make_report("default", root / "results", root / "report", ["corner-r12"], show_progress=False, levels=3)
    assert "corner-r12: reusing" in capsys.readouterr().out
    assert (root / "results" / "cases" / "corner-r12.csv").stat().st_mtime_ns == stored
    assert figure.stat().st_mtime_ns == drawn
    # the header says so, instead of the wall time of a run that computed nothing
    assert "study reused from results/cases" in (root / "report" / "report.md").read_text()

