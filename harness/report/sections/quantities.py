"""The report's section on quantities of interest (``measure.quantities``): each chain's finest
value with its grid convergence index (``measure.richardson``), and on the cases with u, how often
the band holds the exact value."""
from __future__ import annotations

import numpy as np
import pandas as pd

from ...measure.quantities import QUANTITY_COLUMNS, QUANTITY_MEANINGS
from ...measure.richardson import ORDER_AGREEMENT, coverage
from ..document import Document
from ..plan import ReportPlan

QUANTITY_NOTE = (
    "What an engineer reads off a contact computation, for every method and level (results.csv `qoi_*`): "
    + "; ".join(f"`{name}`, {meaning}" for name, meaning in QUANTITY_MEANINGS.items())
    + ". Each chain's three finest levels give Celik et al.'s observed order p, Richardson's extrapolated value "
    "and the grid convergence index (J. Fluids Eng. 130 (2008) 078001; safety factor 1.25; h = N^{-1/d} on graded "
    "and adaptive meshes): the band φ₁ ± GCI is meant to hold the exact value. It can only be trusted in the "
    f"asymptotic range: monotone convergence, and the order of the second to fourth finest levels agreeing within "
    f"{ORDER_AGREEMENT:.0%}. "
    "quantities.csv has every column; `harness rates RESULTS.csv --qoi` prints it.")


# the quantities whose cost at equal error the report shows (the contact zone's error is O(h) for
# every method, and the penetration's exact value 0 is met exactly by the cones)
COMPARED = ("force", "peak_pressure", "energy")


def write(doc: Document, plan: ReportPlan) -> None:
    """The section, where the report's plan has the quantities' table."""
    if plan.quantities is not None:
        add_quantity_section(doc, plan.quantities, plan.quantity_costs)


def add_quantity_section(doc, table: pd.DataFrame, costs: pd.DataFrame | None = None) -> None:
    """The section from the quantities' table (``measure.richardson.quantity_table``) and their
    costs (``measure.efficiency.quantity_efficiency_table``); nothing if the table is empty."""
    if table.empty:
        return
    doc.heading("Quantities of interest with error bars (Richardson, GCI)")
    doc.paragraph(QUANTITY_NOTE)
    doc.paragraph(coverage_sentence(table))
    misses = coverage_misses(table)
    if not misses.empty:
        doc.paragraph("Where the band misses the exact value in the asymptotic range" + miss_reason(table) + ":")
        doc.table(misses)
    if costs is not None and not costs.empty:
        doc.paragraph("Is P2 worth it for what an engineer reads? Per case with u and quantity, the baseline's dofs over "
                      "each method's to reach the same error |Q_h − Q| (the largest of the methods' finest errors; read "
                      "off the level from which the error stays below it; quantity_efficiency.csv): above 1 the method "
                      "needs fewer dofs than P1.")
        doc.table(cost_view(costs))
    uniform = table[table.mesh == "uniform"]
    with doc.details(f"Every chain on uniform meshes: the finest value ± GCI (observed order; * outside the asymptotic "
                     f"range) ({uniform[['case', 'method']].drop_duplicates().shape[0]} rows)", "quantities-table"):
        doc.table(band_view(uniform))
    others = table[table.mesh != "uniform"]
    if not others.empty:
        with doc.details(f"Graded and adaptive chains ({others[['case', 'mesh', 'method']].drop_duplicates().shape[0]} rows)",
                         "quantities-meshes"):
            doc.table(band_view(others, with_mesh=True))


def coverage_sentence(table: pd.DataFrame) -> str:
    """How many judged bands hold the exact value, and what the others are."""
    judged = coverage(table)
    exact = table[table.covered.notna()]
    outside = exact[~exact.asymptotic.astype(bool)]
    kinds = outside.convergence.where(outside.convergence != "monotone", "monotone, orders disagreeing").value_counts()
    held = int(outside.covered.astype(bool).sum())
    if not judged["judged"]:
        return "No chain of a case with u is in the asymptotic range: the coverage of the bands is not measured."
    return (f"On the cases with u, {judged['judged']} (case, mesh, method, quantity) are in the asymptotic range, and the "
            f"band holds the exact value in {judged['covered']} of them ({judged['fraction']:.0%}). Outside it "
            f"({len(outside)}: " + ", ".join(f"{n} {kind}" for kind, n in kinds.items()) +
            f") the band holds it in {held}: the index is not made for them, and says so.")


def coverage_misses(table: pd.DataFrame) -> pd.DataFrame:
    judged = table[table.covered.notna() & table.asymptotic.astype(bool) & ~table.covered.fillna(True).astype(bool)]
    return pd.DataFrame({
        "case": judged.case, "mesh": judged.mesh, "method": judged.method, "quantity": judged.quantity,
        "φ₁": judged.value.map(lambda v: f"{v:.6g}"), "exact": judged.exact.map(lambda v: f"{v:.6g}"),
        "|error| / GCI": (judged.error / judged.gci).map(lambda v: f"{v:.2f}"),
        "p observed": judged.observed_order.map(lambda v: f"{v:.2f}"),
        "error's rate": judged.fitted_rate.map(lambda v: f"{v:.2f}")}).reset_index(drop=True)


def miss_reason(table: pd.DataFrame) -> str:
    """Why the judged bands that miss do, where one reason covers them all: their three finest
    levels' order above the rate at which the error itself falls, so that the index takes the
    remaining error for smaller than it is."""
    judged = table[table.covered.notna() & table.asymptotic.astype(bool) & ~table.covered.fillna(True).astype(bool)]
    if len(judged) and (judged.observed_order > judged.fitted_rate).all():
        return (f" (in all {len(judged)}, the observed order p of the three finest levels is above the rate at which "
                "the error itself falls: Richardson then takes the remaining error for smaller than it is, and the "
                "misses are by little)")
    return ""


def cost_view(costs: pd.DataFrame) -> pd.DataFrame:
    """Rows (case, quantity), one column per method: the baseline's dofs over its dofs."""
    shown = costs[costs.quantity.isin(COMPARED) & costs.p1_over_ndof.notna()]
    view = shown.pivot_table(index=["case", "quantity"], columns="method", values="p1_over_ndof", sort=False)
    order = [m for m in dict.fromkeys(shown.method) if m in view.columns]
    return view[order].map(lambda v: "" if not np.isfinite(v) else f"{v:.3g}").reset_index()


def band_view(table: pd.DataFrame, with_mesh: bool = False) -> pd.DataFrame:
    """One row per chain, one column per quantity: "φ₁ ± GCI (p)"."""
    keys = ["case", "mesh", "method"] if with_mesh else ["case", "method"]
    rows = []
    for key, group in table.groupby(keys, sort=False):
        row = dict(zip(keys, key))
        for quantity in QUANTITY_COLUMNS:
            found = group[group.quantity == quantity]
            row[quantity] = band_text(found.iloc[0]) if len(found) else ""
        rows.append(row)
    return pd.DataFrame(rows)


def band_text(row) -> str:
    if row.convergence == "settled":
        return f"{row.value:.6g} (settled)"
    if not np.isfinite(row.gci):
        return f"{row.value:.6g} ({row.convergence})"
    mark = "" if row.asymptotic else "*"
    return f"{row.value:.6g} ± {row.gci:.1e} (p {row.observed_order:.2f}){mark}"
