"""The report's section on three dimensions (the paper's Section 6 names 3D as open): the 3D
cases' rates, with their own number of levels (the profile's ``levels_3d``,
``study.chain.PROFILES``)."""
from __future__ import annotations

from ..document import Document
from ..plan import ReportPlan
from ..prose import THREE_D_NOTE
from ..tables import three_d_view


def write(doc: Document, plan: ReportPlan) -> None:
    """The 3D cases' table, where the report has one."""
    cases, settings = plan.cases, plan.settings
    if not any(case.dimension == 3 for case in cases):
        return
    doc.heading("Three dimensions (Section 6)")
    doc.paragraph(THREE_D_NOTE + f" Levels: {settings.get('levels_3d', settings['levels'])} per 3D case.")
    doc.table(three_d_view(cases, plan.rates, plan.results), verdict_column="verdict")
