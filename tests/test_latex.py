"""LaTeX tables (issue 32): booktabs structure, the numbers of the rows, `rates --latex`, and
a real compile where a LaTeX is installed."""
import re
import shutil
import subprocess
import sys

import pytest

from harness import run
from harness.measure.efficiency import efficiency_table
from harness.measure.rates import pairwise_rates, rate_table
from harness.report import latex


@pytest.fixture(scope="module")
def study():
    return run(["transition-r32", "smooth-obstacle"], methods=["nodal", "p1"], levels=3, show_progress=False)


def _rows(table: str) -> list[list[str]]:
    """The body rows of a booktabs tabular, split into cells."""
    body = table.split("\\midrule", 1)[1].split("\\bottomrule")[0]
    lines = [line.strip() for line in body.splitlines() if line.strip() and line.strip() != "\\midrule"]
    assert all(line.endswith("\\\\") for line in lines)
    rows = [[c.strip() for c in line[:-2].split("&")] for line in lines]
    for previous, row in zip(rows, rows[1:]):          # a group's name on its first row only
        row[0] = row[0] or previous[0]
    return rows


def _number(cell: str) -> float:
    """$1.234 \\cdot 10^{-3}$ or $1.50$ as a float."""
    m = re.fullmatch(r"\$(-?[\d.]+)(?: \\cdot 10\^\{(-?\d+)\})?\$", cell)
    assert m, cell
    return float(m.group(1)) * 10.0 ** int(m.group(2) or 0)


def test_convergence_table_is_booktabs_with_every_level_and_its_rates(study):
    table = latex.convergence_table(study, "transition-r32")
    for command in ("\\begin{table}", "\\toprule", "\\midrule", "\\bottomrule", "\\caption{", "\\label{tab:transition-r32}"):
        assert command in table
    rows = _rows(table)
    mine = study[study.case == "transition-r32"].sort_values(["method", "level"])
    assert len(rows) == len(mine) and all(len(r) == 7 for r in rows)
    nodal = [r for r in rows if r[0] == "nodal"]
    group = mine[mine.method == "nodal"]
    assert [_number(r[4]) for r in nodal] == pytest.approx(group.err_h1.values, rel=1e-3)
    assert nodal[0][5] == "" and [_number(r[5]) for r in nodal[1:]] == pytest.approx(
        pairwise_rates(group.h, group.err_h1), abs=0.006)
    assert [_number(r[6]) for r in nodal[1:]] == pytest.approx(-pairwise_rates(group.ndof, group.err_h1), abs=0.006)


def test_summary_and_efficiency_tables_hold_every_case_and_method(study):
    rates = rate_table(study)
    summary = _rows(latex.summary_table(rates))
    assert [(r[0], r[1]) for r in summary] == list(zip(rates.case, rates.method))
    assert summary[0][2].startswith("$h^{") and "\\pm" in summary[0][3]
    efficiency = _rows(latex.efficiency_table(efficiency_table(study)))
    assert len(efficiency) == len(efficiency_table(study))


@pytest.mark.parametrize("text, escaped", [("nitsche:gamma0=0.1,theta=-1", "nitsche:gamma0=0.1,theta=-1"),
                                           ("a_b & 50%", "a\\_b \\& 50\\%"), ("x^2 {y}", "x\\textasciicircum{}2 \\{y\\}")])
def test_text_is_escaped(text, escaped):
    assert latex.escape(text) == escaped


@pytest.mark.parametrize("value, cell", [(1.23456e-3, "$1.235 \\cdot 10^{-3}$"), (9.99996, "$1.000 \\cdot 10^{1}$"),
                                         (float("nan"), "")])
def test_numbers_in_math_mode(value, cell):
    assert latex.scientific(value) == cell


def test_rates_command_prints_booktabs_tables(study, tmp_path):
    study.to_csv(tmp_path / "results.csv", index=False)
    done = subprocess.run([sys.executable, "-m", "harness", "rates", "--latex", str(tmp_path / "results.csv")],
                          capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert done.stdout.count("\\begin{tabular}") == 3 and "\\label{tab:summary}" in done.stdout
    assert (tmp_path / "rates.csv").exists()


def test_written_tables_compile(study, tmp_path):
    """The report's .tex files and the document that inputs them; compiled by pdflatex where
    one is installed (Debian: texlive-latex-recommended), else checked for balance only."""
    paths = latex.write_tables(study, rate_table(study), efficiency_table(study), tmp_path)
    assert sorted(p.name for p in paths) == ["all.tex", "efficiency.tex", "smooth-obstacle.tex", "summary.tex",
                                             "transition-r32.tex"]
    for path in paths:
        text = path.read_text()
        assert text.count("\\begin{") == text.count("\\end{") and text.count("{") == text.count("}")
    if shutil.which("pdflatex") is None:
        pytest.skip("no pdflatex here: structure checked only")
    done = subprocess.run(["pdflatex", "-interaction=nonstopmode", "-halt-on-error", "all.tex"], cwd=tmp_path,
                          capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stdout[-3000:]
    assert (tmp_path / "all.pdf").stat().st_size > 1000
