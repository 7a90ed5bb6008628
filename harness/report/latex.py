"""Rate tables for a paper: booktabs LaTeX, as deal.II's ``ConvergenceTable`` writes them.

Three tables from the tidy rows and the fitted rates:

* ``convergence_table``: one case, each method's levels (level, h, ndof, the H^1 error and
  the rate between consecutive levels against h and against the number of dofs N, e ~ N^-r,
  the measure of ``measure.rates.ndof_rates``);
* ``summary_table``: every case x method, the fitted H^1 rate (least squares over the finest
  levels, ± its standard error) against the rate its theory bounds, and the verdict;
* ``efficiency_table``: the cost at equal accuracy (``measure.efficiency``).

Each is a ``table`` float holding a ``tabular`` with \\toprule, \\midrule and \\bottomrule (the
booktabs package), a caption and a label; the numbers in math mode. ``document`` wraps tables
in a minimal compilable document (what the test compiles where a LaTeX is installed).
"""
from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np
import pandas as pd

from ..measure.rates import pairwise_rates
from ..problem.case import fraction
from ..study.storage.files import ensure_writable, write_atomic

_SPECIAL = {"&": r"\&", "%": r"\%", "$": r"\$", "#": r"\#", "_": r"\_", "{": r"\{", "}": r"\}",
            "~": r"\textasciitilde{}", "^": r"\textasciicircum{}", "\\": r"\textbackslash{}"}


def escape(text) -> str:
    """``text`` as LaTeX text (its special characters escaped)."""
    return re.sub(r"[&%$#_{}~^\\]", lambda m: _SPECIAL[m.group()], str(text))


def scientific(value: float, digits: int = 3) -> str:
    """$1.234 \\cdot 10^{-3}$; an empty cell for NaN."""
    if value is None or not np.isfinite(value):
        return ""
    if value == 0:
        return "$0$"
    exponent = int(math.floor(math.log10(abs(value))))
    mantissa = value / 10.0**exponent
    if round(abs(mantissa), digits) >= 10:               # 9.9996 rounds to 10.000
        mantissa, exponent = mantissa / 10, exponent + 1
    return f"${mantissa:.{digits}f} \\cdot 10^{{{exponent}}}$"


def fixed(value: float, digits: int = 2) -> str:
    """$1.50$; an empty cell for NaN."""
    return "" if value is None or not np.isfinite(value) else f"${value:.{digits}f}$"


def bound(rate: float, log_exponent: float = 0.0) -> str:
    """The bound h^p |log h|^q in math mode (``problem.case.bound_text`` in words)."""
    if not np.isfinite(rate):
        return "none proven"
    log = f" \\lvert\\log h\\rvert^{{{fraction(log_exponent)}}}" if log_exponent else ""
    return f"$h^{{{fraction(rate)}}}{log}$"


def tabular(frame: pd.DataFrame, align: str, caption: str, label: str, groups: str | None = None) -> str:
    """A booktabs ``table`` of ``frame``'s cells (already LaTeX); the column heads escaped
    unless they hold math. ``groups``: a column whose change of value starts a \\midrule,
    its value written on the group's first row."""
    heads = " & ".join(h if "$" in h else escape(h) for h in frame.columns)
    lines = ["\\begin{table}[htbp]", "\\centering", f"\\caption{{{caption}}}", f"\\label{{{label}}}",
             f"\\begin{{tabular}}{{{align}}}", "\\toprule", heads + " \\\\", "\\midrule"]
    previous = None
    for _, row in frame.iterrows():
        cells = [str(cell) for cell in row]
        if groups is not None:
            if previous is not None and row[groups] != previous:
                lines.append("\\midrule")
            if row[groups] == previous:          # a group names itself on its first row only
                cells[list(frame.columns).index(groups)] = ""
            previous = row[groups]
        lines.append(" & ".join(cells) + " \\\\")
    lines += ["\\bottomrule", "\\end{tabular}", "\\end{table}"]
    return "\n".join(lines) + "\n"


def convergence_table(results: pd.DataFrame, case: str, error: str = "err_h1") -> str:
    """One case: every method's levels, its error and the rates between consecutive levels
    against h and against N (the first level of a method has none)."""
    rows = []
    for method, group in results[results.case == case].groupby("method", sort=False):
        group = group.sort_values("level")
        rate_h = np.concatenate([[np.nan], pairwise_rates(group.h, group[error])])
        rate_n = np.concatenate([[np.nan], -pairwise_rates(group.ndof, group[error])])
        for (_, r), p, q in zip(group.iterrows(), rate_h, rate_n):
            rows.append({"method": escape(method), "level": f"${int(r.level)}$", "$h$": scientific(r.h, 2),
                         "$N$": f"${int(r.ndof)}$", _ERROR_HEADS.get(error, escape(error)): scientific(r[error]),
                         "rate ($h$)": fixed(p), "rate ($N$)": fixed(q)})
    frame = pd.DataFrame(rows)
    return tabular(frame, "llrrrrr", f"{escape(case)}: {_ERROR_WORDS.get(error, escape(error))} by level; "
                   "rates between consecutive levels, against $h$ and against the number of dofs $N$ "
                   "($e \\sim N^{-r}$).", f"tab:{_label(case)}", groups="method")


_ERROR_HEADS = {"err_h1": "$\\lVert u - u_h\\rVert_{H^1}$", "err_l2": "$\\lVert u - u_h\\rVert_{L^2}$",
                "err_energy": "$a(e, e)^{1/2}$"}
_ERROR_WORDS = {"err_h1": "$H^1$ error", "err_l2": "$L^2$ error", "err_energy": "energy error"}


def summary_table(rates: pd.DataFrame) -> str:
    """Every case x method: the rate its theory bounds, the fitted H^1 rate ± its standard error,
    the verdict."""
    frame = pd.DataFrame({
        "case": [escape(c) for c in rates.case], "method": [escape(m) for m in rates.method],
        "expected": [bound(p, q) for p, q in zip(rates.expected_rate, rates.expected_log_exponent)],
        "fitted rate": [f"${p:.3f} \\pm {se:.3f}$" if np.isfinite(p) else "" for p, se in
                        zip(rates.fitted_rate, rates.fitted_rate_se)],
        "verdict": [escape(v) for v in rates.verdict],
    })
    return tabular(frame, "lllrl", "Fitted $H^1$ rates against the rates the theorems bound "
                   "(least squares over the finest levels; verdict within $\\pm 0.1$).", "tab:summary", groups="case")


def efficiency_table(efficiency: pd.DataFrame) -> str:
    """The cost at equal accuracy: per case x method, the dofs and seconds to reach the case's
    target H^1 error, and P1's dofs and seconds over them."""
    frame = pd.DataFrame({
        "case": [escape(c) for c in efficiency.case], "method": [escape(m) for m in efficiency.method],
        "target": [scientific(v, 2) for v in efficiency.target_err_h1],
        "$N$": [scientific(v, 2) for v in efficiency.ndof],
        "seconds": [fixed(v, 2) for v in efficiency.total_seconds],
        "P1 / $N$": [fixed(v, 1) for v in efficiency.get("p1_over_ndof", pd.Series(np.nan, efficiency.index))],
        "P1 / seconds": [fixed(v, 1) for v in efficiency.get("p1_over_seconds", pd.Series(np.nan, efficiency.index))],
    })
    return tabular(frame, "llrrrrr", "Cost at equal accuracy: dofs $N$ and seconds (refinement, assembly, "
                   "set-up and solve, summed over the levels) to reach each case's target $H^1$ error, "
                   "and P1's over them.", "tab:efficiency", groups="case")


def _label(name: str) -> str:
    return re.sub(r"[^A-Za-z0-9]+", "-", name)


def document(*tables: str) -> str:
    """A minimal document holding ``tables`` (what a paper's preamble needs: booktabs, amsmath)."""
    return ("\\documentclass{article}\n\\usepackage{booktabs}\n\\usepackage{amsmath}\n\\begin{document}\n"
            + "\n".join(tables) + "\\end{document}\n")


def write_tables(results: pd.DataFrame, rates: pd.DataFrame, efficiency: pd.DataFrame, folder: Path) -> list[Path]:
    """The report's tables as .tex files in ``folder``: one per case, the summary, the
    efficiency table, and ``all.tex``, a document that \\input's them."""
    folder = ensure_writable(Path(folder))
    written = {f"{_label(case)}.tex": convergence_table(results, case) for case in results.case.unique()}
    written["summary.tex"] = summary_table(rates)
    if not efficiency.empty:
        written["efficiency.tex"] = efficiency_table(efficiency)
    paths = [write_atomic(folder / name, text) for name, text in written.items()]
    inputs = [f"\\input{{{name}}}\n\\clearpage\n" for name in written]
    paths.append(write_atomic(folder / "all.tex", document(*inputs)))
    return paths
