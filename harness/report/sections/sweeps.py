"""The report's section "Penalty and Nitsche: where their parameter is safe": the errors of the
swept methods over their parameter, per case the report sweeps. What is swept, on which cases and
at which level, is planned by ``study.planning.sweep`` (``REPORT_SWEEP``) and run and stored by
``study.planning.cache``; the figures (``figures.sweep``) are this section's jobs
(``queue_figures``)."""
from __future__ import annotations

from pathlib import Path

import pandas as pd

from ..document import Document
from ..plan import ReportPlan
from ..prose import SWEEP_NOTE
from ..tables import sweep_view

GROUP = "sweeps"        # the figures' group (``report.figure_jobs.FigurePool``)


def write(doc: Document, plan: ReportPlan) -> None:
    """Each swept case's figure and table."""
    if not plan.sweeps:
        return
    doc.heading("Penalty and Nitsche: where their parameter is safe")
    doc.paragraph(SWEEP_NOTE)
    for name, frame in plan.sweeps.items():
        doc.figures([(plan.figs[GROUP][name]["png"], f"{name}: H¹ error and largest penetration against ε₀ / γ₀.")],
                    wide=True)
        doc.table(sweep_view(frame))


def queue_figures(pool, plan: ReportPlan, known: dict, results_dir: Path) -> None:
    """One figure per swept case."""
    for name, frame in (plan.sweeps or {}).items():
        case = known[name]
        pool.job(f"sweep-{case.name}", sweep_figures, str(case.source), frame, group=GROUP, key=case.name)


def sweep_figures(source: str, frame: pd.DataFrame, folder: str) -> dict:
    """The job: ``figures.sweep`` of the case in file ``source``, in a worker."""
    from ...problem.case import load_case
    from .. import figures
    return figures.sweep(load_case(source), frame, Path(folder))
