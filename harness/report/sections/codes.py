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
    doc.paragraph("Beside the harness method each code discretises, on the same levels: the largest relative "
                  "difference of the H¹ errors over the levels, and on the finest level the seconds per solve (the "
                  "code's own, assembly included, from zero; the harness's from the coarser level's solution, as its "
                  "study solves) and their ratio:")
    doc.table(codes_levels_view(codes, plan.results))


def codes_rates_view(codes: list[External], rates: pd.DataFrame) -> pd.DataFrame:
    """Per case: the harness methods the codes discretise, then each code, with its fitted H¹
    rate and verdict."""
    rows, seen = [], set()
    for method, case in ((method, case) for method in codes for case in method.cases):
        for name, code in ((method.like, "the harness"), (method.name, method.code)):
            if not name or (case, name) in seen:
                continue
            seen.add((case, name))
            for rate in rates[(rates.method == name) & (rates.case == case)].itertuples():
                rows.append({"case": case, "method": name, "code": code,
                             "expected": bound_text(rate.expected_rate, rate.expected_log_exponent),
                             "H¹ rate": f"{rate.fitted_rate:.3f} ± {rate.fitted_rate_se:.3f}", "verdict": rate.verdict})
    frame = pd.DataFrame(rows, columns=["case", "method", "code", "expected", "H¹ rate", "verdict"])
    return frame.sort_values("case", kind="stable")


def codes_levels_view(codes: list[External], results: pd.DataFrame) -> pd.DataFrame:
    """Per code and case, on the same levels as the harness method it discretises (``like``): the
    largest relative difference of the H¹ errors over the levels, and on the finest level the
    ndof, the code's H¹ error and the seconds per solve of both."""
    rows = []
    for method, case in ((method, case) for method in codes for case in method.cases):
        own = results[(results.method == method.name) & (results.case == case)].set_index("level").sort_index()
        theirs = results[(results.method == method.like) & (results.case == case)].set_index("level")
        if own.empty:
            continue
        shared = own.index.intersection(theirs.index)
        difference = (np.abs(own.err_h1[shared] - theirs.err_h1[shared]) / theirs.err_h1[shared]).max() if len(shared) else np.nan
        finest = own.iloc[-1]
        harness_seconds = theirs.solve_seconds.get(own.index[-1], np.nan)
        rows.append({"case": case, "method": method.name, "like": method.like or "—", "levels": len(own),
                     "largest relative difference": _fmt(difference, ".1e"), "finest ndof": _fmt(finest.ndof, ".3g"),
                     "err_h1": _fmt(finest.err_h1, ".4e"), "seconds": _fmt(finest.solve_seconds, ".3g"),
                     "harness seconds": _fmt(harness_seconds, ".3g"),
                     "ratio": _fmt(finest.solve_seconds / harness_seconds, ".3g")})
    return pd.DataFrame(rows)
