"""The report's section "Summary": the fitted rates against the theorems' (``measure.rates``;
its figure, and every row on demand), then the regularity check by the best approximation and
the errors on Γ_C when the study measured them. Its figures (the rates and the verdict matrix,
``figures.summary``) are drawn from the rates once the study is done (``queue_figures``); the
matrix is shown "At a glance" (``report.sections.glance``)."""
from __future__ import annotations

from pathlib import Path

import pandas as pd

from ..document import Document
from ..plan import ReportPlan
from ..prose import GAMMA_C_NOTE, RATES_NOTE, REGULARITY_NOTE
from ..tables import regularity_view, summary_table


def write(doc: Document, plan: ReportPlan) -> None:
    """The fitted rates against the theorems', and the regularity check."""
    rates, results = plan.rates, plan.results
    doc.heading("Summary: fitted against expected rates")
    doc.paragraph(RATES_NOTE)
    doc.figures([(plan.figs["summary"]["rates"]["png"],
                  "Fitted against theory rates; grey band: ±0.1; the points outside it named.")], wide=True)
    with doc.details(f"Every case × method: both theories, fitted rate ± standard error, pairwise rates, L² rate "
                     f"({len(rates)} rows)", "summary-table"):
        doc.table(summary_table(rates), verdict_column="verdict")
    if "fitted_rate_best" in rates and rates.fitted_rate_best.notna().any():
        doc.heading("Regularity check: best approximation")
        doc.paragraph(REGULARITY_NOTE)
        doc.table(regularity_view(rates, results), verdict_column="verdict")
        doc.heading("Errors on Γ_C")
        doc.paragraph(GAMMA_C_NOTE)


def queue_figures(pool, plan: ReportPlan, known: dict, results_dir: Path) -> None:
    """The rates figure and the verdict matrix (``report.figure_jobs.FigurePool.job``)."""
    pool.job("summary", summary_figures, plan.rates)


def summary_figures(rates: pd.DataFrame, folder: str) -> dict:
    """The job: ``figures.summary`` in a worker."""
    from .. import figures
    return figures.summary(rates, Path(folder))
