"""The report's section on two bodies (the paper's Section 6 names them as the next step): the
two-body cases' rates (``study.chain.two_body``), with the first one's non-matching meshes at the
interface (its case figure, ``report.sections.cases``)."""
from __future__ import annotations

from ..document import Document
from ..plan import ReportPlan
from ..prose import TWO_BODY_NOTE
from ..tables import two_body_view


def write(doc: Document, plan: ReportPlan) -> None:
    """The two-body cases' table and the first one's interface, where the report has one."""
    cases, figs = plan.cases, plan.figs
    if not any(case.bodies == 2 for case in cases):
        return
    doc.heading("Two bodies, non-matching meshes (Section 6)")
    doc.paragraph(TWO_BODY_NOTE)
    doc.table(two_body_view(cases, plan.rates, plan.results), verdict_column="verdict")
    first = next(case for case in cases if case.bodies == 2)
    if figs.get(first.name, {}).get("interface") is not None:
        doc.figures([(figs[first.name]["interface"]["png"], f"{first.name}: the two meshes at the interface on level 1.")],
                    wide=True)
