"""The report's section on cases read against a closed-form theory (``Case.prediction``,
Hertz's for hertz-line; the theory's quantities, ``Case.predicted_quantities``): every row's quantities of interest set against the theory's at the
row's own contact force, and the dofs each method needs to come within 1 % of it."""
from __future__ import annotations

import numpy as np
import pandas as pd

from ...measure.efficiency import at_target
from ...measure.quantities import QUANTITY_MEANINGS
from ..document import Document
from ..plan import ReportPlan

# the deviation from the theory that the dofs table asks each method to reach
WITHIN = 0.01
NAMES = {f"qoi_{name}": name for name in QUANTITY_MEANINGS}
# what the case's contact figure shows of the theory, by dimension (``figures.contact``, ``contact_faces``)
FIGURE_NOTE = {2: "The contact figure in the case's section draws the theory's pressure beside the discrete ones.",
               3: "The contact figure in the case's section maps each method's discrete pressure over Γ_C; the "
                  "contact measure is an area (π a² for a disc), whose deviation is about twice the radius's."}


def deviations(case, rows: pd.DataFrame) -> pd.DataFrame:
    """``rows`` (one case's) with, per predicted column c, ``c_predicted`` and
    ``c_deviation`` = value / predicted - 1, at each row's ``qoi_force``."""
    predicted = pd.DataFrame([case.predicted_quantities(force) for force in rows.qoi_force], index=rows.index)
    out = rows.copy()
    for column in predicted:
        out[f"{column}_predicted"] = predicted[column]
        out[f"{column}_deviation"] = rows[column] / predicted[column] - 1.0
    return out


def level_view(case, rows: pd.DataFrame) -> pd.DataFrame:
    """Method, level, dofs, force, and per predicted quantity its value, the theory's and the
    deviation in percent."""
    table = deviations(case, rows.sort_values(["method", "level"]))
    view = {"method": table.method, "level": table.level, "ndof": table.ndof, "force": table.qoi_force.map(lambda v: f"{v:.5g}")}
    for column in case.predicted_quantities(float(rows.qoi_force.iloc[-1])):
        name = NAMES.get(column, column)
        view[name] = table[column].map(lambda v: f"{v:.5g}")
        view[f"{name} ({case.prediction.split(' (')[0]})"] = table[f"{column}_predicted"].map(lambda v: f"{v:.5g}")
        view[f"{name} deviation"] = table[f"{column}_deviation"].map(lambda v: f"{100 * v:+.2f} %")
    return pd.DataFrame(view).reset_index(drop=True)


def dofs_view(case, rows: pd.DataFrame) -> pd.DataFrame:
    """Per method and predicted quantity, the dofs from which its deviation stays within
    ``WITHIN`` (interpolated between levels, ``measure.efficiency.at_target``; empty: not on these levels)."""
    table = deviations(case, rows)
    out = []
    for method, group in table.groupby("method", sort=False):
        group = group.sort_values("level")
        row = {"method": method}
        for column in case.predicted_quantities(float(group.qoi_force.iloc[-1])):
            needed = at_target(np.abs(group[f"{column}_deviation"]).to_numpy(), group.ndof.to_numpy(float), WITHIN)
            row[f"dofs to {WITHIN:.0%}: {NAMES.get(column, column)}"] = "" if not np.isfinite(needed) else f"{needed:.3g}"
        out.append(row)
    return pd.DataFrame(out)


def write(doc: Document, plan: ReportPlan) -> None:
    """A section per case of the report read against a closed-form theory."""
    add_prediction_section(doc, plan.cases, plan.results)


def add_prediction_section(doc, cases, results: pd.DataFrame) -> None:
    """The sections of those of ``cases`` that declare a theory (``Case.prediction``) and have rows."""
    predicted = [case for case in cases if case.predicted_quantities is not None and (results.case == case.name).any()]
    for case in predicted:
        rows = results[(results.case == case.name) & (results["mesh"] == "uniform" if "mesh" in results else True)]
        doc.heading(f"{case.name} against {case.prediction}")
        doc.paragraph(f"{case.description}. Each row's quantities of interest set against {case.prediction.split(' (')[0]}'s "
                      "at the row's own computed contact force (the prescribed motion sets the force, the theory "
                      "the rest); what is left is discretisation and the body's finite size (the case file measures "
                      f"the latter). {FIGURE_NOTE[case.dimension]}")
        doc.table(dofs_view(case, rows))
        with doc.details(f"Every level ({len(rows)} rows)", f"{case.name}-prediction"):
            doc.table(level_view(case, rows))
