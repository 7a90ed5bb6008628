"""The report's section "Problem and methods": the problem, and each method studied with its
order, contact condition, parameters and reference (``methods.method.Method``), and where a method
of your own comes from."""
from __future__ import annotations

import pandas as pd

from ...methods import METHODS
from ..document import Document
from ..plan import ReportPlan
from ..prose import INTRO


def write(doc: Document, plan: ReportPlan) -> None:
    """The problem and the table of the report's methods."""
    methods = plan.methods
    doc.heading("Problem and methods")
    doc.paragraph(INTRO)
    own = own_methods_sentence(methods)
    if own:
        doc.paragraph(own)
    doc.table(pd.DataFrame([{"method": m.name, "order": m.order, "contact condition": m.contact,
                             "parameters": m.parameter_text, "reference": m.reference}
                            for m in methods]))


def own_methods_sentence(methods) -> str:
    """A sentence naming the methods of the report that are not the harness's own (from a file,
    a module, an installed package or Python), and where each comes from; "" if none."""
    own = [m for m in methods if METHODS.get(m.name.split(":")[0]) is None]
    if not own:
        return ""
    described = "; ".join(f"`{m.name}` (P{m.order}: {m.contact}; {m.reference}"
                          + (f"; from {m.source}" if m.source else "") + ")" for m in own)
    return (f"Beside the harness's methods, this report studies {'a method' if len(own) == 1 else 'methods'} "
            f"of your own: {described}. Every table, figure and verdict below treats "
            f"{'it' if len(own) == 1 else 'them'} as the harness's own.")
