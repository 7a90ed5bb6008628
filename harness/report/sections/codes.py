"""The report's section on other codes (``methods.external``: another finite element code's
solutions of the harness's exported levels, ``study.export``), beside the harness's own: per code
its fitted rate and verdict, and level by level its H¹ error and seconds per solve against the
harness method it discretises (its ``like``), on the same meshes. A report without an external
method writes nothing."""
from __future__ import annotations

import numpy as np
import pandas as pd

from ...methods import External
from ..document import Document
from ..plan import ReportPlan
from ..tables import _fmt, bound_text

CODES_NOTE = (
    "Other finite element codes on the harness's own levels: each solved the discrete problems `python -m harness "
    "export` wrote (the same meshes, data and right-hand side, as moments against the Lagrange basis) and gave back "
    "its solution's values at the P_k Lagrange nodes (`--method external:DIR`, docs: guide/measure-your-code). The "
    "harness rebuilds u_h exactly from them and measures it as its own. Where a code solves the same discrete "
    "problem as a harness method, the H¹ errors agree to the solvers' tolerance (the relative difference below); "
    "seconds are each code's own solve, on the machine and with the threads that ran it (the manifest's options).")


def external_methods(plan: ReportPlan) -> list[External]:
    return [method for method in plan.methods if isinstance(method, External)]


def write(doc: Document, plan: ReportPlan) -> None:
    """The section, where the report measured another code."""
    codes = external_methods(plan)
    if not codes:
        return
    doc.heading("Other codes")
    doc.paragraph(CODES_NOTE)
    doc.table(codes_rates_view(codes, plan.rates), verdict_column="verdict")
    doc.paragraph("Level by level, beside the harness method each code discretises (relative difference of the H¹ "
                  "errors; seconds per solve, the code's against the harness's):")
    doc.table(codes_levels_view(codes, plan.results))


def codes_rates_view(codes: list[External], rates: pd.DataFrame) -> pd.DataFrame:
    """Per code and case: its fitted H¹ rate and verdict, and the harness method's beside it."""
    rows = []
    for method, case in ((method, case) for method in codes for case in method.cases):
        for name in filter(None, (method.name, method.like)):
            found = rates[(rates.method == name) & (rates.case == case)]
            for rate in found.itertuples():
                rows.append({"case": rate.case, "method": name, "code": method.code if name == method.name else "the harness",
                             "expected": bound_text(rate.expected_rate, rate.expected_log_exponent),
                             "H¹ rate": f"{rate.fitted_rate:.3f} ± {rate.fitted_rate_se:.3f}", "verdict": rate.verdict})
    return pd.DataFrame(rows, columns=["case", "method", "code", "expected", "H¹ rate", "verdict"])


def codes_levels_view(codes: list[External], results: pd.DataFrame) -> pd.DataFrame:
    """Per code, case and level: ndof, the code's H¹ error, its relative difference from the
    harness method it discretises (``like``), and the seconds per solve of both."""
    rows = []
    for method, case in ((method, case) for method in codes for case in method.cases):
        own = results[(results.method == method.name) & (results.case == case)].set_index("level")
        theirs = results[(results.method == method.like) & (results.case == case)].set_index("level")
        for level, row in own.sort_index().iterrows():
            harness_row = theirs.loc[level] if level in theirs.index else None
            difference = np.nan if harness_row is None else abs(row.err_h1 - harness_row.err_h1) / harness_row.err_h1
            rows.append({"case": case, "method": method.name, "level": level, "ndof": _fmt(row.ndof, ".3g"),
                         "err_h1": _fmt(row.err_h1, ".4e"), "like": method.like or "—",
                         "relative difference": _fmt(difference, ".1e"), "seconds": _fmt(row.solve_seconds, ".3g"),
                         "harness seconds": "—" if harness_row is None else _fmt(harness_row.solve_seconds, ".3g")})
    return pd.DataFrame(rows)
