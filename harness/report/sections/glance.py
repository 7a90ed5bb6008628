"""The report's section "At a glance": every verdict (``measure.rates``) in one case × method
matrix, first: the answer before the detail; its figure is the summary's
(``report.sections.summary``)."""
from __future__ import annotations

import pandas as pd

from ...methods import left_out
from ..document import Document
from ..plan import ReportPlan
from ..plots import verdict_cells
from ..prose import MATRIX_NOTE


def write(doc: Document, plan: ReportPlan) -> None:
    """Every verdict in one matrix, and the same as a figure (for a paper)."""
    doc.heading("At a glance: every case × method")
    cells = verdict_cells(plan.rates)
    reasons = mark_not_applicable(cells, plan.cases, plan.methods)
    doc.paragraph(MATRIX_NOTE + " " + verdict_counts(plan.rates) + ".")
    doc.matrix(cells, cells.attrs["verdicts"])
    if reasons:
        doc.paragraph("n/a: the method does not discretise the case, for its own reason: "
                      + "; ".join(f"{method} on {', '.join(cases)}: {why}" for (method, why), cases in reasons.items()) + ".")
    with doc.details("The same as a figure (report/figures/verdict_matrix.pdf, for a paper)", "verdict-matrix-figure"):
        doc.figures([(plan.figs["summary"]["matrix"]["png"], "Fitted / expected H¹ rate, coloured by verdict.")], wide=True)


def mark_not_applicable(cells: pd.DataFrame, cases, methods) -> dict:
    """Mark "n/a" (verdict "not applicable") each empty cell of ``cells`` whose method leaves its
    case out (``methods.left_out``: a friction law, physics, dimension or bodies it does not
    discretise); gives the cases of each (method, reason)."""
    verdicts, by_name = cells.attrs["verdicts"], {case.name: case for case in cases}
    reasons: dict[tuple[str, str], list[str]] = {}
    for name in cells.index:
        shown = [m for m in methods if m.name in cells.columns and cells.loc[name, m.name] == ""]
        for method, why in left_out(by_name[name], shown) if name in by_name else ():
            cells.loc[name, method], verdicts.loc[name, method] = "n/a", "not applicable"
            reasons.setdefault((method, why), []).append(name)
    return reasons


def verdict_counts(rates: pd.DataFrame) -> str:
    """"5 meet, 1 above, 1 no theory": the verdicts of some rate rows."""
    counts = rates.verdict.value_counts()
    return ", ".join(f"{n} {'meet' if v == 'meets' and n > 1 else v}" for v, n in counts.items())
