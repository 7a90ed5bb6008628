"""The report's section "At a glance": every verdict (``measure.rates``) in one case × method
matrix, first: the answer before the detail; its figure is the summary's
(``report.sections.summary``)."""
from __future__ import annotations

import pandas as pd

from ..document import Document
from ..plan import ReportPlan
from ..plots import verdict_cells
from ..prose import MATRIX_NOTE


def write(doc: Document, plan: ReportPlan) -> None:
    """Every verdict in one matrix, and the same as a figure (for a paper)."""
    doc.heading("At a glance: every case × method")
    cells = verdict_cells(plan.rates)
    doc.paragraph(MATRIX_NOTE + " " + verdict_counts(plan.rates) + ".")
    doc.matrix(cells, cells.attrs["verdicts"])
    with doc.details("The same as a figure (report/figures/verdict_matrix.pdf, for a paper)", "verdict-matrix-figure"):
        doc.figures([(plan.figs["summary"]["matrix"]["png"], "Fitted / expected H¹ rate, coloured by verdict.")], wide=True)


def verdict_counts(rates: pd.DataFrame) -> str:
    """"5 meet, 1 above, 1 no theory": the verdicts of some rate rows."""
    counts = rates.verdict.value_counts()
    return ", ".join(f"{n} {'meet' if v == 'meets' and n > 1 else v}" for v, n in counts.items())
