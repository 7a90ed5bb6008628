"""The report's section "Is P2 worth it? Cost at equal accuracy": each case's claim read off the
cost tables (``measure.efficiency.verdicts``) and the table (``measure.efficiency.efficiency_table``)."""
from __future__ import annotations

from ...measure.efficiency import verdicts
from ..document import Document
from ..plan import ReportPlan
from ..prose import EFFICIENCY_NOTE
from ..tables import efficiency_view


def write(doc: Document, plan: ReportPlan) -> None:
    """The claims per case and the cost table, where a method's cost could be compared."""
    claims = verdicts(plan.efficiency, plan.rates, methods=plan.methods)
    if claims:
        doc.heading("Is P2 worth it? Cost at equal accuracy")
        doc.paragraph(EFFICIENCY_NOTE)
        for case in plan.cases:
            if case.name in claims:
                doc.paragraph(f"{case.name}: {claims[case.name]}")
        doc.table(efficiency_view(plan.efficiency))
