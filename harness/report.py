"""`make report`: the default study, its rates, figures and report (Markdown and HTML).

The computations and their cache are ``report_cache``'s: results of a case are reused when the
code, the case file and the settings that produced them are unchanged.
"""
from __future__ import annotations

import json
import time
from pathlib import Path

import numpy as np
import pandas as pd

from . import figures
from .case import Case, bound_text, fraction, registered_cases
from .document import Document
from .efficiency import efficiency_table, verdicts
from .execution import InProcess
from .figure_jobs import FIGURE_WORKERS, FigurePool
from .methods import methods_named
from .rates import TOLERANCE, normalised_errors, pairwise_rates, rate_table
from .report_cache import compute, provenance
from .results import ensure_writable, write_atomic, write_csv
from .study import PROFILES
from .timing import Timings


def _fmt(value, spec=".3e"):
    return "" if value is None or (isinstance(value, float) and not np.isfinite(value)) else format(value, spec)


def level_table(group: pd.DataFrame, energy: bool = False) -> pd.DataFrame:
    """One method's levels; ``energy``: with the energy-norm error (elasticity, where it is not
    the H^1 seminorm)."""
    group = group.sort_values("level")
    rates = np.concatenate([[np.nan], pairwise_rates(group.h, group.err_h1)])
    p, q = group.expected_rate.iloc[0], group.expected_log_exponent.iloc[0]
    normalised = normalised_errors(group.h, group.err_h1, p, q)
    return pd.DataFrame({
        "level": group.level, "h": [_fmt(v, ".4f") for v in group.h], "ndof": group.ndof,
        "err_h1": [_fmt(v) for v in group.err_h1], "rate": [_fmt(v, ".3f") for v in rates],
        f"err / {bound_text(p, q)}": [_fmt(v) for v in normalised],
        "err_l2": [_fmt(v) for v in group.err_l2],
        **({"err_energy": [_fmt(v) for v in group.err_energy]} if energy else {}),
        "err_best_h1": [_fmt(v) for v in group.err_best_h1] if "err_best_h1" in group else "",
        "err / best": [_fmt(v, ".3f") for v in group.err_h1_over_best] if "err_h1_over_best" in group else "",
        "max penetration": [_fmt(v, ".2e") for v in group.max_penetration],
        "max tension": [_fmt(v, ".2e") for v in group.max_tension] if "max_tension" in group else "",
        "active / constraints": [f"{a} / {n}" if n else f"{a} Gauss points" for a, n in zip(group.active_constraints, group.n_contact_constraints)],
        "min pressure": [_fmt(v, ".1e") for v in group.min_pressure] if "min_pressure" in group else "",
        "iterations": group.solver_iterations, "KKT / Newton residual": [_fmt(v, ".1e") for v in group.kkt_residual],
        "solve s": [_fmt(v, ".2f") for v in group.solve_seconds],
        "total s": [_fmt(v, ".2f") for v in group.total_seconds],
    })


def summary_table(rates: pd.DataFrame) -> pd.DataFrame:
    """Every case x method against both theories: the method's own (the paper's for mean and
    nodal) and the sharper one (Drouet & Hild 2015 for the cones), with the L^2 rate beside."""
    return pd.DataFrame({
        "case": rates.case, "method": rates.method, "theory": rates.reference,
        "expected": [bound_text(p, q) for p, q in zip(rates.expected_rate, rates.expected_log_exponent)],
        "fitted rate": [f"{p:.3f} ± {se:.3f}" for p, se in zip(rates.fitted_rate, rates.fitted_rate_se)],
        "pairwise rates": rates.pairwise_rates, "verdict": rates.verdict,
        "Drouet–Hild": [bound_text(p) if isinstance(r, str) and r else "" for p, r in zip(rates.sharper_rate, rates.sharper_reference)],
        "verdict (D–H)": rates.sharper_verdict.fillna(""),
        "L² rate": [_fmt(v, ".2f") for v in rates.fitted_rate_l2],
    })


REGULARITY_NOTE = (
    "Does each case have the regularity ν it declares? The Ritz projection R_h u (the Galerkin "
    "solution with u's own flux on Γ_C as Neumann data: the best approximation in |·|₁ with the "
    "methods' Dirichlet lift; no contact involved) converges at min(ν − 1, k) for P_k. Its fitted "
    "rate is set against that (verdict within ±0.1); err / best, the methods' H¹ error over R_h u's "
    "on the finest level, is what the contact discretisation costs beyond best approximation "
    "(Falk's lemma's extra terms, Remark 4.6)."
)
GAMMA_C_NOTE = (
    "Section 5 of the paper: `mean` is \"suitable for checking the contact condition on the normal "
    "constraint\", `nodal` \"for the normal displacement\". Measured on Γ_C, finest level: the trace "
    "error ‖u − u_h‖ in L²(Γ_C); the pressure error, λ_h being for every method the Riesz "
    "representative in the trace space of the residual a(u_h, ·) − L(·) (the discrete contact force: "
    "the multipliers of the cones, the contact terms of penalty and Nitsche), against λ = ∂ₙu − g_C, "
    "in L²(Γ_C) and in ‖h^{1/2}·‖_{L²(Γ_C)}; the largest penetration max(α − u_h) and the largest "
    "tension max(−λ_h). Rates: fitted over the last three levels. Where λ ∉ L²(Γ_C) (λ ~ r^{-1/2}: "
    "corner-r12) the L² pressure error cannot converge (its rate is 0), only the h^{1/2}-weighted one."
)


ELASTICITY_NOTE = (
    "Frictionless unilateral contact of a plane-strain elastic body on a rigid foundation: "
    "−div σ(u) = f, σ = 2μ ε(u) + λ tr ε(u) I; on Γ_C, with n the outward normal and σ_n = n·σ(u)n, "
    "u·n − α ≤ 0, σ_n − g_n ≤ 0, (u·n − α)(σ_n − g_n) = 0 and σ_t = g_t. Both P2 models constrain "
    "the normal displacement: written in the variables (−u·n, u·t) at the nodes of Γ_C, the contact "
    "variable c = −u·n has the scalar problem's trace, so `mean` (vertex values and edge means of "
    "c ≥ −α) and `nodal` (vertex and midpoint values) are again bounds, solved exactly by the same "
    "active-set solver (sparse Cholesky with bordered updates: the scalar V-cycle does not transfer). "
    "The pressure p = −(σ_n − g_n) plays λ's part. Singular exponents: a roller (binding, frictionless) "
    "face next to a traction-free one at angle ω reflects to a traction-free wedge of angle 2ω, whose "
    "symmetric exponents solve sin(2lω) + l sin(2ω) = 0 — with no elastic constant in it: l = 3/2 at "
    "a transition (ω = π; 1/2 is excluded by the signs), l = 0.5445 at ω = 3π/4, for every Poisson "
    "ratio. The energy norm a(e, e)^{1/2} is equivalent to the H¹ norm (Korn): same theorem rate; "
    "R_h u is the best approximation in energy, so err / best in H¹ may fall below 1."
)


THREE_D_NOTE = (
    "The paper's Section 6 names 3D as open. Here Ω = (−1, 1)² × (0, 1) in tetrahedra (netgen, red "
    "refinement: every edge halves, 8 children per tetrahedron), Γ_C its bottom face. Both cones are "
    "imposed edge by edge on the triangles of Γ_C: on each edge the P2 trace is a 1D quadratic, and the "
    "same local change of variables as in 2D makes `nodal` (vertex and edge-midpoint values ≥ α: the P2 "
    "Lagrange cone of the 3D analyses, Drouet & Hild 2015) and `mean` (vertex values and edge means ≥ α: "
    "our extension of K_h, for which no theorem exists) bounds on single variables; P1 bounds its vertex "
    "values. Solved exactly by the same active set method with the truncated P1 multigrid of the "
    "tetrahedral hierarchy. In 3D an edge-wise cone does not control the trace inside the triangles: with "
    "all vertex values v > 0 and all edge means 0, the P2 trace of a triangle is −v at its centroid and its "
    "mean is −v/2, yet every constraint of `mean` holds. The table shows what the discrete solutions do with "
    "that freedom (the smallest value of u_h − α over Γ_C: penetration is negative). The pictures show Γ_C "
    "from below: red where u_h dips below the obstacle."
)


def three_d_view(cases, rates: pd.DataFrame, results: pd.DataFrame) -> pd.DataFrame:
    """The 3D cases: per case x method, its finest size, rates (pairwise and fitted), err/best
    and the largest penetration on the finest level."""
    solid = [case.name for case in cases if case.dimension == 3]
    rows = []
    for _, rate in rates[rates.case.isin(solid)].iterrows():
        finest = results[(results.case == rate.case) & (results.method == rate.method)].sort_values("level").iloc[-1]
        rows.append({"case": rate.case, "method": rate.method, "finest ndof": _fmt(finest.ndof, ".3g"),
                     "expected": bound_text(rate.expected_rate, rate.expected_log_exponent),
                     "pairwise H¹ rates": rate.pairwise_rates, "H¹ rate": _fmt(rate.fitted_rate, ".3f"),
                     "err / best": _fmt(finest.err_h1_over_best, ".3g"),
                     "max penetration": _fmt(finest.max_penetration, ".2e"), "kkt": _fmt(finest.kkt_residual, ".1e"),
                     "verdict": rate.verdict})
    return pd.DataFrame(rows)


def elasticity_view(cases, rates: pd.DataFrame) -> pd.DataFrame:
    """The elastic cases' rates: H^1 and energy, against the theorem's, with the Poisson ratio."""
    elastic = {case.name: case for case in cases if case.physics.components > 1}
    rows = rates[rates.case.isin(list(elastic))]
    return pd.DataFrame({
        "case": rows.case, "Poisson ratio": [f"{elastic[c].physics.poisson:g}" for c in rows.case], "method": rows.method,
        "expected": [bound_text(p, q) for p, q in zip(rows.expected_rate, rows.expected_log_exponent)],
        "H¹ rate": [_fmt(v, ".3f") for v in rows.fitted_rate], "energy rate": [_fmt(v, ".3f") for v in rows.fitted_rate_energy],
        "best (R_h u) rate": [_fmt(v, ".3f") for v in rows.fitted_rate_best], "verdict": rows.verdict,
    })


def regularity_view(rates: pd.DataFrame, results: pd.DataFrame) -> pd.DataFrame:
    """Per case and order: the best approximation's fitted rate against min(nu - 1, k), and each
    method's err / best on its finest level."""
    rows = []
    for (case, order), group in rates.groupby(["case", "order"], sort=False):
        first = group.iloc[0]
        if not np.isfinite(first.get("fitted_rate_best", np.nan)):
            continue            # no best approximation: a case measured against a reference
        finest = results[(results.case == case) & (results.order == order)]
        finest = finest[finest.level == finest.level.max()]
        rows.append({
            "case": case, "order": f"P{order}", "best rate": _fmt(first.fitted_rate_best, ".3f"),
            "min(ν − 1, k)": _fmt(first.best_expected_rate, ".3g"), "verdict": first.best_verdict,
            "pairwise (best)": first.pairwise_rates_best,
            "err / best, finest level": ", ".join(f"{m} {r:.3f}" for m, r in zip(finest.method, finest.err_h1_over_best)),
        })
    return pd.DataFrame(rows)


def gamma_c_view(rates: pd.DataFrame, results: pd.DataFrame, case: str) -> pd.DataFrame:
    finest = results[results.case == case].sort_values("level").groupby("method", sort=False).last()
    r = rates[rates.case == case].set_index("method")
    return pd.DataFrame([{
        "method": m,
        "trace L² (rate)": f"{_fmt(row.err_trace_l2)} ({_fmt(r.loc[m, 'fitted_rate_trace'], '.2f')})",
        "pressure L² (rate)": f"{_fmt(row.err_pressure_l2)} ({_fmt(r.loc[m, 'fitted_rate_pressure_l2'], '.2f')})",
        "pressure h^½-L² (rate)": f"{_fmt(row.err_pressure_h12)} ({_fmt(r.loc[m, 'fitted_rate_pressure_h12'], '.2f')})",
        "max penetration": _fmt(row.max_penetration, ".2e"), "max tension": _fmt(row.max_tension, ".2e"),
    } for m, row in finest.iterrows()])


def which_bound(case, rates: pd.DataFrame, results: pd.DataFrame) -> str:
    """Two sentences: which of the two bounds the P2 cones' errors follow."""
    r = rates[(rates.case == case.name) & rates.method.isin(["mean", "nodal"])]
    if r.empty:
        return ""
    fitted = ", ".join(f"{m} {p:.2f}" for m, p in zip(r.method, r.fitted_rate))
    paper = bound_text(case.expected_rate, case.expected_log_exponent)
    first = r.iloc[0]
    dh = bound_text(first.sharper_rate) if np.isfinite(first.sharper_rate) else None
    text = f"Fitted H¹ rates (last three levels, with each theory's log factor) {fitted}; the paper bounds them by {paper}"
    text += (f", Drouet & Hild by {dh}." if dh else "; Drouet & Hild say nothing for ν ≤ 3/2.")
    if not dh:
        return text + " The data follow the paper's bound."
    if not case.expected_log_exponent and np.isclose(first.sharper_rate, case.expected_rate):
        return text + " Both bounds are the same here, and the data " + \
            ("follow it." if (r.verdict == "meets").all() else "beat it (verdicts above).")
    if not case.expected_log_exponent:
        follows = "follow" if (r.verdict == "meets").all() else "reach"
        return text + (f" The data {follows} the paper's {paper} (Remark 4.9, under its finite-transition "
                       f"assumption), beyond Drouet & Hild's {dh}, whose estimate stops at the H^(5/2) "
                       f"regularity of Signorini solutions.")
    # a log factor in the paper's bound: which normalised error levels off?
    g = results[(results.case == case.name) & (results.method == "nodal")].sort_values("level")
    with_log = normalised_errors(g.h, g.err_h1, case.expected_rate, case.expected_log_exponent)[-3:]
    plain = normalised_errors(g.h, g.err_h1, case.expected_rate, 0.0)[-3:]
    drop = lambda v: 1 - v[-1] / v[-2]
    level_off = 0.02
    if abs(drop(plain)) <= level_off < abs(drop(with_log)):
        verdict_text = "e/h has levelled off and the data follow Drouet & Hild's h, without the paper's log factor."
    elif abs(drop(with_log)) <= level_off < abs(drop(plain)):
        verdict_text = f"e/({paper}) has levelled off: the data follow the paper's bound."
    elif abs(drop(plain)) < abs(drop(with_log)):
        verdict_text = ("neither has levelled off (both fall by more than 2%), e/h the less: the data are nearer "
                        "Drouet & Hild's h than the paper's bound, and still faster than both, like the best "
                        "approximation (table above).")
    else:
        verdict_text = "neither has levelled off (both fall by more than 2%)."
    return text + (f" Over the last level, nodal's e/({paper}) falls by {drop(with_log):.1%} and e/h by "
                   f"{drop(plain):.1%}: " + verdict_text)


def reference_sentence(case, results: pd.DataFrame) -> str:
    """For a case measured against references: against what, how fine, how exactly solved."""
    rows = results[(results.case == case.name) & (results.get("errors_against", "exact") == "reference")]
    if rows.empty:
        return ""
    firsts = rows.groupby("method", sort=False).first()
    levels = sorted({int(v) for v in firsts.reference_level})
    return (f"No closed-form solution: every error is measured against the method's own solution "
            f"{case.reference_levels} levels finer than its finest studied level (level {' and '.join(map(str, levels))}, "
            f"up to {int(firsts.reference_ndof.max()):,} dofs; KKT / Newton residual of the reference solves at most "
            f"{firsts.reference_kkt_residual.max():.1e}). On nested meshes u_h is exactly a function of the "
            f"reference space, so the errors are exact norms of u_R − u_h; they miss |u − u_R|, which "
            f"for an error like h^p lowers the finest studied level's error by the factor √(1 − 4^(−p·k)) "
            f"(k = {case.reference_levels}: {np.sqrt(1 - 4.0 ** (-1.0 * case.reference_levels)):.3f} for p = 1). "
            f"No best approximation (it would need u).")


def belief_finding(case, rates: pd.DataFrame) -> str:
    """What the data say about a conjectured rate (``Case.conjectured``): supported or a loss."""
    r = rates[rates.case == case.name]
    belief = bound_text(case.expected_rate, case.expected_log_exponent)
    parts = [f"{m} {p:.3f} (pairwise {pw})" for m, p, pw in zip(r.method, r.fitted_rate, r.pairwise_rates)
             if np.isfinite(case.expected_rate)]
    cones = r[r.method.isin(["mean", "nodal"])]
    if cones.empty:
        return f"The expected rate {belief} is a belief, not a theorem (Theorem {case.theorem}). Measured: " + "; ".join(parts) + "."
    low = cones.fitted_rate.min()
    if low >= case.expected_rate - TOLERANCE:
        finding = (f"The data support the authors' belief: both P2 models converge at {belief} "
                   f"(within ±{TOLERANCE}) although Γ_C has infinitely many transition points.")
    else:
        finding = (f"The data show a loss against the authors' belief {belief}: the P2 models' fitted rate is "
                   f"{low:.3f}, {case.expected_rate - low:.3f} below it.")
    best = cones.fitted_rate_best.iloc[0] if "fitted_rate_best" in cones else np.nan
    best_text = f" The best approximation converges at {best:.3f} (ν − 1 = {case.nu - 1:.3g}: the regularity is as derived)." \
        if np.isfinite(best) else ""
    return (f"Remark 4.3's question. {finding} Fitted rates (pairwise rates level by level): " + "; ".join(parts) + "."
            + best_text)


def normalised_view(case, results: pd.DataFrame) -> pd.DataFrame:
    """e/(h |log h|^q) and e/h level by level, for the P2 cones (the paper's log-factor case)."""
    out = None
    for method in ("mean", "nodal"):
        g = results[(results.case == case.name) & (results.method == method)].sort_values("level")
        if g.empty:
            continue
        frame = pd.DataFrame({"level": g.level.values,
                              f"{method}: e / h|log h|^{fraction(case.expected_log_exponent)}":
                                  [_fmt(v) for v in normalised_errors(g.h, g.err_h1, 1.0, case.expected_log_exponent)],
                              f"{method}: e / h": [_fmt(v) for v in normalised_errors(g.h, g.err_h1, 1.0, 0.0)]})
        out = frame if out is None else out.merge(frame, on="level")
    return out


INTRO = (
    "The Poisson-Signorini problem (2.1)-(2.4): -Δu = f in Ω, u = u_D on Γ_u, ∂u/∂n = g on Γ_g and "
    "u ≥ 0, ∂u/∂n ≥ 0, u ∂u/∂n = 0 on Γ_C (with a gap α and a contact load g_C where a case "
    "declares them), on uniformly refined meshes (NGSolve); h halves per level. The paper's two P2 "
    "methods have nonconforming cones: `mean` (K_h, Section 3: vertex values and edge means ≥ 0, the "
    "degrees of freedom of J_h) and `nodal` (K̃_h, Section 5: vertex and midpoint values ≥ 0, the "
    "degrees of freedom of I_h); K̃_h ⊂ K_h by Simpson's rule. The baseline `p1` (linear elements, "
    "vertex values ≥ 0) has an exact cone. Each discrete inequality is solved exactly: every row's KKT "
    "residual is listed. What users of NGSolve or FEniCS write instead impose contact weakly, by a term "
    "on Γ_C with no constraint on the space: `nitsche` (Chouly & Hild 2013; θ-variants of Chouly, Hild "
    "& Renard 2015) and `penalty` (Chouly & Hild 2013), P2 and P1 (`-p1`), ε = γ₀h; their nonlinear "
    "equations are solved by semismooth Newton to a relative residual ≤ 1e-10, listed in the same "
    "column. Max penetration is max over Γ_C of α - u_h, between nodes included: the nonconformity of "
    "the cones, and how far the weak methods let u_h through the obstacle. P1 runs one level more than "
    "P2, so that every method ends at about the same number of dofs (P1 on level l+1 has the dofs of "
    "P2 on level l)."
)
RATES_NOTE = (
    "Fitted rate: least squares of log e = log C + p log h + q log|log h| over the last three "
    "levels, q fixed to the log exponent of the method's theory, with its standard error. Verdict: "
    "meets if within 0.1 of that theory's rate; above/below otherwise. The theorems give upper "
    "bounds, so 'above' is consistent with them; 'below' would contradict them."
)
EFFICIENCY_NOTE = (
    "The paper's claim (abstract, Section 6): its quadratic methods are more accurate than linear "
    "finite elements. Measured as cost at equal accuracy: per case, the target H¹ error is the "
    "largest of the methods' finest errors (so each method reaches it within its own levels; its "
    "fraction of the coarsest error is given), and each method's dofs and seconds to reach it are "
    "read off its levels by log-log interpolation. Seconds are summed over the levels up to the "
    "target (nested iteration needs them): 'solve' the contact solves, 'total' all a user pays for "
    "u_h (mesh refinement, assembly, set-up, solve; not the error measurement). P1 / it > 1: the "
    "method is cheaper than P1."
)


SWEEP_NOTE = (
    "Penalty and Nitsche ask the user for a parameter: ε = ε₀h (penalty) or γ₀h (Nitsche) on each "
    "contact edge. Each curve is one method over that parameter at one level, every other setting "
    "fixed; the dashed line is `nodal`, which has no parameter. Hollow markers: Newton did not "
    "converge (its status is in the table below). Nitsche with θ = 1 is coercive only while "
    "γ₀ h‖∂ₙv‖² < a(v, v) on X_h, measured here as γ₀ < 0.145 for P2 on every registered case "
    "(`methods/nitsche.py`); θ = -1 is coercive for every γ₀. The penalty method is not consistent: "
    "in contact u_h sits about ε λ below the obstacle, so its error and penetration grow with ε₀."
)


def sweep_view(frame: pd.DataFrame) -> pd.DataFrame:
    """The sweep as a table: one row per value, one column pair per swept method."""
    swept = frame[frame.sweep_parameter.fillna("") != ""]
    table = swept.pivot_table(index="sweep_value", columns="sweep_method", values="err_h1", sort=False)
    status = swept.pivot_table(index="sweep_value", columns="sweep_method", values="status", aggfunc="first", sort=False)
    view = pd.DataFrame({"value": [f"{v:g}" for v in table.index]})
    for column in table.columns:
        view[f"{column}: H¹ error"] = [_fmt(e) + ("" if st == "converged" else " (not converged)")
                                       for e, st in zip(table[column], status[column])]
    return view


def efficiency_view(table: pd.DataFrame) -> pd.DataFrame:
    return pd.DataFrame({
        "case": table.case, "method": table.method, "target H¹ error": [_fmt(v) for v in table.target_err_h1],
        "of coarsest": [f"{v:.1%}" for v in table.target_fraction], "ndof": [_fmt(v, ".3g") for v in table.ndof],
        "solve s": [_fmt(v, ".3g") for v in table.solve_seconds], "total s": [_fmt(v, ".3g") for v in table.total_seconds],
        "P1 / it: dofs": [_fmt(v, ".3g") for v in table.p1_over_ndof],
        "P1 / it: seconds": [_fmt(v, ".3g") for v in table.p1_over_seconds],
        "P1 err / its err at its finest ndof": [_fmt(v, ".3g") for v in table.err_ratio_at_equal_ndof],
    })


def build_document(cases: list[Case], results: pd.DataFrame, rates: pd.DataFrame, efficiency: pd.DataFrame,
                   figs: dict, meta: dict, sweeps: dict | None = None) -> Document:
    doc = Document("The Signorini problem in P2 and P1: measured against the theorems")
    settings = meta["settings"]
    doc.paragraph(
        f"Belhachmi and Ben Belgacem, Math. Comp. 72 (2003). Harness {meta['harness_version']} "
        f"(commit {meta['git_commit'][:12]}), NGSolve {meta['ngsolve_version']}, {meta['date']}, "
        f"{meta['machine']['node']} ({meta['machine']['cpus']} cpus); profile {settings['profile']}, "
        f"{settings['levels']} P2 levels; methods {', '.join(settings['methods'])}; "
        f"study wall time {meta['wall_seconds']:.0f} s{' ' + meta['engine'] if meta.get('engine') else ''}.", css="meta")
    doc.heading("Problem and methods")
    doc.paragraph(INTRO)
    doc.table(pd.DataFrame([{"method": m.name, "order": m.order, "contact condition": m.contact,
                             "parameters": m.parameter_text, "reference": m.reference}
                            for m in methods_named(settings["methods"])]))
    doc.heading("Summary: every case x method")
    doc.paragraph(RATES_NOTE)
    doc.table(summary_table(rates), verdict_column="verdict")
    doc.figures([(figs["summary"]["png"], "Fitted against theory rates; grey band: ±0.1.")])
    if "fitted_rate_best" in rates and rates.fitted_rate_best.notna().any():
        doc.heading("Regularity check: best approximation")
        doc.paragraph(REGULARITY_NOTE)
        doc.table(regularity_view(rates, results), verdict_column="verdict")
        doc.heading("Errors on Γ_C")
        doc.paragraph(GAMMA_C_NOTE)
    claims = verdicts(efficiency, rates)
    if claims:
        doc.heading("Is P2 worth it? Cost at equal accuracy")
        doc.paragraph(EFFICIENCY_NOTE)
        for case in cases:
            if case.name in claims:
                doc.paragraph(f"{case.name}: {claims[case.name]}")
        doc.table(efficiency_view(efficiency))
    if sweeps:
        doc.heading("Penalty and Nitsche: where their parameter is safe")
        doc.paragraph(SWEEP_NOTE)
        for name, frame in sweeps.items():
            doc.figures([(figs["sweeps"][name]["png"], f"{name}: H¹ error and largest penetration against ε₀ / γ₀.")],
                        wide=True)
            doc.table(sweep_view(frame))
    if any(case.physics.components > 1 for case in cases):
        doc.heading("Unilateral contact in linear elasticity (Remark 2.3)")
        doc.paragraph(ELASTICITY_NOTE)
        doc.table(elasticity_view(cases, rates))
    if any(case.dimension == 3 for case in cases):
        doc.heading("Three dimensions (Section 6)")
        doc.paragraph(THREE_D_NOTE + f" Levels: {settings.get('levels_3d', settings['levels'])} per 3D case.")
        doc.table(three_d_view(cases, rates, results), verdict_column="verdict")
    for case in cases:
        doc.heading(f"{case.name}: P2 " + (case.theorem if case.conjectured else f"Theorem {case.theorem}"))
        if case.physics.components > 1:
            doc.paragraph(f"Physics: {case.physics.describe()}.")
        doc.paragraph(f"{case.description}. Regime {case.regime or '-'}, "
                      + (f"ν = {fraction(case.nu)}; " if np.isfinite(case.nu) else "ν not declared; ")
                      + (f"the authors believe (no theorem) the P2 H¹ error behaves like {case.expected_bound}."
                         if case.conjectured else f"the paper bounds the P2 H¹ error by C {case.expected_bound}."))
        against = reference_sentence(case, results)
        if against:
            doc.paragraph(against)
        doc.table(summary_table(rates[rates.case == case.name]), verdict_column="verdict")
        if case.conjectured:
            doc.paragraph(belief_finding(case, rates))
        sentences = "" if case.conjectured else which_bound(case, rates, results)   # no bound to follow
        if sentences:
            doc.paragraph(sentences)
        if case.expected_log_exponent:
            view = normalised_view(case, results)
            if view is not None:
                doc.table(view)
        if "err_trace_l2" in results:
            doc.paragraph("On Γ_C, finest level (the paper's Section 5 remark; the measures are defined "
                          "under 'Errors on Γ_C' above):")
            doc.table(gamma_c_view(rates, results, case.name))
        f = figs[case.name]
        doc.figures([(f["convergence"]["png"], "H¹ error against h; dashed: each theory's bound through the coarsest point."),
                     (f["contact"]["png"], "Finest level along Γ_C: u_h - α and the discrete contact pressure; shaded: exact contact zone."
                      if case.dimension == 2 else "Γ_C from below, finest level: u_h - α and the discrete pressure per triangle.")])
        doc.figures([(f["efficiency"]["png"], "H¹ error against ndof and against seconds summed over the levels; dotted: the target.")],
                    wide=True)
        if f["solution"] is not None:
            doc.figures([(f["solution"]["png"], "Deformed shape: the mesh moved by u_h (magnified), coloured by |u_h|; grey: the body at rest."
                          if case.physics.components > 1 else "u_h on Ω.")])
        for method, group in results[results.case == case.name].groupby("method", sort=False):
            doc.heading(f"method {method}", level=3)
            doc.table(level_table(group, energy=case.physics.components > 1))
    return doc


def make_report(profile: str = "default", results_dir: Path = Path("results"), report_dir: Path = Path("report"),
                case_names=None, show_progress: bool = True, levels: int | None = None, methods=("all",),
                engine=None, check_memory: bool = True) -> Path:
    """Run (or reuse) the study of a profile, its sweeps, rates and figures, and write the report;
    ``engine``: where the jobs run (``execution``; default this process). Where the time went is
    written to ``results_dir/report_profile.csv`` (``timing``)."""
    if profile not in PROFILES:
        raise ValueError(f"unknown profile {profile!r}; expected one of: {', '.join(PROFILES)}")
    known = registered_cases()
    cases = list(known.values()) if not case_names else [known[n] if n in known else _unknown(n, known) for n in case_names]
    methods = [m if isinstance(m, str) else m.name for m in methods]
    settings = {"profile": profile, "methods": [m.name for m in methods_named(methods)], **PROFILES[profile]}
    if levels is not None:
        settings["levels"] = levels
    results_dir = Path(results_dir)
    ensure_writable(report_dir / "figures")
    timings = Timings()
    start = time.perf_counter()
    sweep_cases = cases if _has_weak(settings["methods"]) else []
    results, sweeps = compute(cases, settings, results_dir, sweep_cases, show_progress, engine, check_memory, timings)
    with timings("rates"):
        rates = rate_table(results)
        efficiency = efficiency_table(results)
    with timings("writing", "results"):
        write_csv(results, results_dir / "results.csv")
        write_csv(rates, results_dir / "rates.csv")
        write_csv(efficiency, results_dir / "efficiency.csv")
    meta = provenance(settings) | {"wall_seconds": time.perf_counter() - start, "cases": [c.name for c in cases],
                                   "engine": (engine or InProcess()).describe()}
    write_atomic(results_dir / "provenance.json", json.dumps(meta, indent=2))
    with timings("figures", f"drawn in {FIGURE_WORKERS} processes"), FigurePool(settings["methods"], Path(report_dir) / "figures") as pool:
        for case in cases:
            pool.case(case, results_dir / "cases")
        pool.summary(rates)
        for name, frame in sweeps.items():
            pool.sweep(known[name], frame)
        figs, seconds = pool.collect()
    for name, spent in seconds.items():
        timings.add("figures (in workers)", name, "", spent)
    with timings("document"):
        doc = build_document(cases, results, rates, efficiency, figs, meta, sweeps)
    with timings("writing", "report"):
        write_atomic(Path(report_dir) / "report.md", doc.markdown(Path(report_dir)))
        html_path = write_atomic(Path(report_dir) / "report.html", doc.html())
    timings.add("total", "wall", "", time.perf_counter() - start)
    write_csv(timings.frame(), results_dir / "report_profile.csv")
    return html_path


def _has_weak(names) -> bool:
    from .methods import WeakContact
    return any(isinstance(m, WeakContact) for m in methods_named(names))


def _unknown(name, known):
    raise ValueError(f"unknown case {name!r}; known cases: {', '.join(known)}")
