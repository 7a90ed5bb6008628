"""The report's section "Is P2 the sweet spot?": the degree study's rows, their rates in h and in
N against each method's theory, the cost at equal accuracy across the degree, per case and mesh
strategy, and its figure (``queue_figures``: the error against dofs and against seconds,
``degree_errors``). What the degree study runs (its cases, mesh strategies, methods and levels)
and how its rows are stored is planned by ``study.planning.degree_study``, run by
``study.planning.cache``; which methods it studies, ``report.build.make_report``."""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd

from ...measure.efficiency import efficiency_table
from ...measure.rates import is_hp, rate_table
from ...methods import REFERENCE, role_names
from ..document import Document
from ..plan import ReportPlan
from ..tables import _fmt, efficiency_view
from .meshes import LINESTYLE

GROUP = "degree_study"      # the figures' group (``report.figure_jobs.FigurePool``)

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

HP_NOTE = (
    "hp meshes (`--mesh hp`): geometric layers of ratio σ = 0.15 toward the singular points, the "
    "element degree k + μ j growing with the layers j away from them (μ = 1; k, each method's "
    "degree, at the singular points), one layer more per level; Nitsche of every degree and the nodal "
    "cone of degree 3 and 4 (each edge at its own degree's Gauss–Lobatto points). For elliptic problems with "
    "point singularities the hp theory (Babuška and Guo) gives err ≤ C exp(−b N^{1/3}); no theorem covers "
    "Signorini's problem, so the table fits ln(err) against N^{1/3} (b, R², the algebraic fit's R² "
    "beside) and gives the verdict of the fit. The last columns set each hp chain's finest error "
    "against the best adaptive P2 error at the same number of dofs (log-log interpolation between "
    "its levels; blank where the adaptive chain does not reach that many dofs).")


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


def write(doc: Document, plan: ReportPlan) -> None:
    """The section, where the report ran a degree study."""
    if plan.degrees is not None:
        add_degree_section(doc, plan.degrees, plan.figs)


def add_degree_section(doc, degrees: pd.DataFrame, figs: dict) -> None:
    """The section from the degree study's rows and figures (nothing if it ran none)."""
    if degrees.empty:
        return
    doc.heading("Is P2 the sweet spot? The degree k = 1 … 4")
    doc.paragraph(DEGREE_NOTE)
    doc.table(degree_rates_view(rate_table(degrees)))
    for case in dict.fromkeys(degrees.case):
        pictures = figs.get(GROUP, {}).get(case, {})
        if "errors" in pictures:
            doc.figures([(pictures["errors"]["png"], f"{case}: H¹ error against the dofs N (left) and against the "
                          "seconds spent up to each level (right), each degree in its colour; dotted uniform, solid "
                          "adaptive, dashed hp meshes (an hp level is made anew: its own seconds).")], wide=True)
    hp = hp_view(degrees)
    if not hp.empty:
        doc.heading("hp meshes: exponential convergence?", level=3)
        doc.paragraph(HP_NOTE)
        doc.table(hp)
    for (case, mesh), frame in degrees.groupby(["case", "mesh"], sort=False):
        if is_hp(str(mesh)):
            continue            # no cone runs on hp meshes: the target (nodal P2's error) is not there
        doc.heading(f"{case}, {mesh} meshes: cost at equal accuracy", level=3)
        reference = next(iter(role_names(REFERENCE)), None)
        doc.table(efficiency_view(efficiency_table(frame, target_method=reference)))


def hp_view(degrees: pd.DataFrame) -> pd.DataFrame:
    """Per case and hp method: its levels, finest dofs and relative error, the exponential fit,
    and the best adaptive P2 error at the same dofs (``adaptive_at``)."""
    rows = []
    rates = rate_table(degrees)
    for _, fit in rates[[is_hp(str(m)) for m in rates.mesh]].iterrows():
        chain = degrees[(degrees.case == fit.case) & (degrees.mesh == fit.mesh) & (degrees.method == fit.method)]
        finest = chain.sort_values("level").iloc[-1]
        adaptive = adaptive_at(degrees[degrees.case == fit.case], float(finest.ndof))
        rows.append({"case": fit.case, "method": fit.method, "k": int(fit.order), "levels": len(chain),
                     "finest N": f"{int(finest.ndof):,}", "relative H¹ error": _fmt(fit.finest_relative_error, ".2e"),
                     "b": _fmt(fit.exponential_b, ".3f"), "R²": _fmt(fit.exponential_r2, ".4f"),
                     "algebraic R²": _fmt(fit.algebraic_r2, ".4f"), "verdict": fit.exponential_verdict,
                     "adaptive P2 at N": _fmt(adaptive, ".2e"),
                     "adaptive P2 / hp": _fmt(adaptive / float(finest.err_h1), ".3g")})
    return pd.DataFrame(rows)


def adaptive_at(frame: pd.DataFrame, ndof: float) -> float:
    """The smallest H^1 error of the case's adaptive P2 chains at ``ndof`` dofs, interpolated in
    log-log between their levels (NaN outside every chain's range)."""
    best = np.nan
    adaptive = frame[np.array([str(m).split(":")[0] == "adaptive" for m in frame.mesh]) & (frame.order == 2).to_numpy()]
    for _, chain in adaptive.groupby("method"):
        chain = chain.sort_values("ndof")
        if chain.ndof.min() <= ndof <= chain.ndof.max():
            value = float(np.exp(np.interp(np.log(ndof), np.log(chain.ndof), np.log(chain.err_h1))))
            best = value if np.isnan(best) else min(best, value)
    return best


def queue_figures(pool, plan: ReportPlan, known: dict, results_dir: Path) -> None:
    """One figure per case of the degree study."""
    degrees = plan.degrees
    if degrees is None or degrees.empty:
        return
    for name in dict.fromkeys(degrees.case):
        case = known[name]
        pool.job(f"degrees-{case.name}", degree_figures, str(case.source), degrees[degrees.case == name],
                 group=GROUP, key=case.name)


def degree_figures(source: str, frame: pd.DataFrame, folder: str) -> dict:
    """The job: the degree study's figure of the case in file ``source``, in a worker."""
    from ...problem.case import load_case
    return {"errors": degree_errors(load_case(source), frame, Path(folder))}


def degree_errors(case, frame: pd.DataFrame, folder: Path) -> dict[str, Path]:
    """The degree study's figure of one case: the H^1 error against N and against the seconds
    spent up to each level (the rows' total_seconds, summed along each chain), every method on
    every mesh strategy."""
    from ..figures import plt, save, style
    chains = frame.groupby(["mesh", "method"], sort=False)
    rows = -(-chains.ngroups // 4)          # the legend's rows below the panels, four chains a row
    fig, (left, right) = plt.subplots(1, 2, figsize=(11, 4.2 + 0.16 * rows))
    for (mesh, method), g in chains:
        g = g.sort_values("level")
        kind = str(mesh).split(":")[0]
        s = style(method)
        line = dict(color=s["color"], linestyle=LINESTYLE.get(kind, "-."), lw=1.2, marker=s["marker"], ms=3)
        label = f"{method} (k = {int(g.order.iloc[0])}), {mesh}"
        left.loglog(g.ndof, g.err_h1, **line, label=label)
        # a level of an hp chain is made anew from the coarse mesh: its own seconds, not a sum
        seconds = g.total_seconds if kind == "hp" else g.total_seconds.cumsum()
        right.loglog(seconds, g.err_h1, **line)
    left.set_xlabel("ndof N")
    left.set_ylabel("H¹ error")
    left.set_title(f"{case.name}: error against N")
    right.set_xlabel("seconds up to the level")
    right.set_title("error against time")
    # below the panels, not over the curves (hp's fall where a corner legend sits)
    fig.legend(*left.get_legend_handles_labels(), fontsize=6.5, ncol=4, loc="lower center", frameon=False)
    fig.subplots_adjust(bottom=0.12 + 0.16 * rows / (4.2 + 0.16 * rows), wspace=0.22)
    return save(fig, folder, f"{case.name}-degrees")
