"""The report's section on linear elasticity (the paper's Remark 2.3): the elastic cases' rates
in one table, apart from the scalar cases' (``problem.physics``)."""
from __future__ import annotations

from ..document import Document
from ..plan import ReportPlan
from ..prose import ELASTICITY_NOTE
from ..tables import elasticity_view


def write(doc: Document, plan: ReportPlan) -> None:
    """The elastic cases' table, where the report has one."""
    if not any(case.physics.elastic for case in plan.cases):
        return
    doc.heading("Unilateral contact in linear elasticity (Remark 2.3)")
    doc.paragraph(ELASTICITY_NOTE)
    doc.table(elasticity_view(plan.cases, plan.rates))
