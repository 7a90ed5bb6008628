"""The report's section "Is P2 the sweet spot?": the degree study's rows (``study.degree_study``),
their rates in h and in N against each method's theory, the cost at equal accuracy across the
degree, per case and mesh strategy, and the error against dofs and against seconds."""
from __future__ import annotations

import pandas as pd

from ..measure.efficiency import efficiency_table
from ..measure.rates import rate_table
from ..methods import REFERENCE, role_names
from .tables import _fmt, efficiency_view

DEGREE_NOTE = (
    "The paper asks whether quadratic elements are worth it for Signorini's problem; the next "
    "question is whether any degree beyond 2 pays where the contact set limits the solution's "
    "regularity. Nitsche's method of degree k (γ₀ = 0.05 (2/k)², P2's coercivity margin at every "
    "degree) is expected at h^{min(ν−1, k)}; the nodal cone at the vertices and the k − 1 interior "
    "Gauss–Lobatto points of each edge of Γ_C has no theorem beyond k = 2 (its declared "
    "min(ν−1, k) is a conjecture). On uniform meshes a transition point caps every degree at "
    "h^{3/2} (transition-r32); on a smooth solution (smooth-quintic, ν = 11/2) each degree shows "
    "its h^k; adaptive meshes (the residual estimator of each degree) recover N^{−k/2} in 2D. The "
    "cost tables give the dofs and the seconds (assembly, solves, estimator and errors of every "
    "level up to it) each method needs to reach the finest error of the paper's nodal P2 on the "
    "same meshes (a method that does not reach it shows none), per mesh strategy, and P1's cost "
    "over each method's.")


def degree_rates_view(rates: pd.DataFrame) -> pd.DataFrame:
    """Per case, mesh and method: the degree, the fitted rate in h (uniform meshes) and in N,
    the expected rate and the verdict, the optimal rate in N."""
    h_rate = rates.fitted_rate if "fitted_rate" in rates else pd.Series(float("nan"), index=rates.index)
    return pd.DataFrame({
        "case": rates.case, "mesh": rates.mesh, "method": rates.method, "k": rates.order,
        "fitted h-rate": [_fmt(v, ".3f") for v in h_rate],
        "expected (h)": [_fmt(v, ".3g") for v in rates.expected_rate],
        "fitted N-rate": [_fmt(v, ".3f") for v in rates.fitted_rate_ndof],
        "optimal k/d": [_fmt(v, ".3g") for v in rates.optimal_rate_ndof],
        "verdict": rates.verdict,
    })


def add_degree_section(doc, degrees: pd.DataFrame, figs: dict) -> None:
    if degrees.empty:
        return
    doc.heading("Is P2 the sweet spot? The degree k = 1 … 4")
    doc.paragraph(DEGREE_NOTE)
    doc.table(degree_rates_view(rate_table(degrees)))
    for case in dict.fromkeys(degrees.case):
        pictures = figs.get("degree_study", {}).get(case, {})
        if "errors" in pictures:
            doc.figures([(pictures["errors"]["png"], f"{case}: H¹ error against the dofs N (left) and against the "
                          "seconds spent up to each level (right), each degree in its colour; dotted uniform, solid "
                          "adaptive meshes.")], wide=True)
    for (case, mesh), frame in degrees.groupby(["case", "mesh"], sort=False):
        doc.heading(f"{case}, {mesh} meshes: cost at equal accuracy", level=3)
        reference = next(iter(role_names(REFERENCE)), None)
        doc.table(efficiency_view(efficiency_table(frame, target_method=reference)))
