"""The report's section on Tresca friction (``problem.friction``): the friction cases' rates
against each method's expectation, the methods left out of them and why
(``methods.method.Method.refusal``), the friction quantities where the rows have them
(``FRICTION_QUANTITIES``: their finest value with the grid convergence index,
``measure.richardson``), and per case the stick/slip picture along Gamma_C (``stick_slip``:
each case's contact figure when it is frictional, ``report.sections.cases``). A study without a
friction case writes nothing."""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd

from ...measure.quantities import exact_column
from ...measure.rates import fit_rate
from ...measure.richardson import exact_columns, mesh_sizes, richardson
from ...methods import left_out
from ..document import Document
from ..plan import ReportPlan
from ..tables import _fmt, bound_text

FRICTION_NOTE = (
    "Tresca's law on Γ_C (docs: theory/friction): in the scalar model |∂ₙu − g_C| ≤ s, and ∂ₙu − g_C = −s u/|u| where "
    "u ≠ 0 (stick where u = 0, slip elsewhere); in elasticity u·n = 0 and the tangential traction plays its part. "
    "The cones carry the paper's two ideas over to j(v) = ∫ s|v_t|: `nodal` by the quadrature of s|v| at Γ_C's P2 "
    "nodes (Simpson's weights: a two-sided bound per node on the multiplier), `mean` by the edge means (a P0 "
    "multiplier, |λ_e| ≤ s_e), `p1` by the trapezoidal rule; each discrete problem is solved exactly, as the "
    "bound-constrained dual, by the primal-dual active set method. No theorem for P2 Tresca was read: each case "
    "declares the rate its regularity allows the best approximation (h^{min(ν−1, k)}, capped by the method's own "
    "theory where it has one), a conjecture the rows test.")

# the friction quantities (results.csv columns) the section tabulates where the rows have them:
# what each is, and whether it is an error (fitted for its rate) or a value (its GCI band)
FRICTION_QUANTITIES = {
    "qoi_slip_measure": ("the length (3D: area) of the slip zone", "value"),
    "qoi_stick_slip_point": ("where stick turns to slip along Γ_C", "value"),
    "err_friction_l2": ("‖λ − λ_h‖ on Γ_C, the friction force's L² error", "error"),
    "qoi_tangential_force": ("Coulomb: the total friction force Q on the obstacle", "value"),
    "qoi_stick_measure": ("Coulomb: the length (3D: area) of the stick zone", "value"),
}


def friction_cases(plan: ReportPlan, law: str = "tresca") -> list:
    """The report's cases with the friction law ``law`` (``problem.friction``), in its order."""
    return [case for case in plan.cases if case.friction.name == law]


def write(doc: Document, plan: ReportPlan) -> None:
    """The section, where the report has a Tresca case."""
    cases = friction_cases(plan)
    if not cases:
        return
    doc.heading("Tresca friction")
    doc.paragraph(FRICTION_NOTE)
    write_common(doc, plan, cases)


def write_common(doc: Document, plan: ReportPlan, cases: list) -> None:
    """What the Tresca and the Coulomb sections (``sections.coulomb``) both show of their
    ``cases``: the rates, the methods left out, the friction quantities, the stick/slip pictures."""
    names = [case.name for case in cases]
    bilateral = {case.name for case in cases if case.physics.elastic}
    doc.table(friction_rates_view(plan.rates[plan.rates.case.isin(names)], plan.results, bilateral), verdict_column="verdict")
    absent = left_out_view(cases, plan.methods)
    if not absent.empty:
        doc.paragraph("Methods of the report left out of the friction cases, each with its own reason (n/a in the "
                      "matrix above where the method ran on another case):")
        doc.table(absent)
    quantities = friction_quantity_view(plan.results[plan.results.case.isin(names)])
    if not quantities.empty:
        doc.paragraph("The friction quantities, finest level: a value with its band φ₁ ± GCI (observed order p; * outside "
                      "the asymptotic range) and its error where the case knows the exact value; an error with its "
                      "fitted rate over the last three levels. "
                      + "; ".join(f"`{name}`: {meaning}" for name, (meaning, _) in FRICTION_QUANTITIES.items()) + ".")
        doc.table(quantities)
    figures = [(plan.figs[case.name]["contact"]["png"], f"{case.name}: {stick_slip_caption(case)}")
               for case in cases if draws_stick_slip(case) and plan.figs.get(case.name, {}).get("contact") is not None]
    if figures:
        doc.figures(figures, wide=True)


def friction_rates_view(rates: pd.DataFrame, results: pd.DataFrame, bilateral=()) -> pd.DataFrame:
    """Per friction case and method: the expected H¹ rate and whose it is, the fitted one, the
    pairwise rates, the L² and Γ_C trace rates, the finest KKT residual and the verdict. The
    trace rate is the contact variable's: for the ``bilateral`` (elastic) cases u_h . n, which
    vanishes (exactly for the cones): no rate, "—"."""
    rows = []
    for rate in rates.itertuples():
        finest = results[(results.case == rate.case) & (results.method == rate.method)].sort_values("level").iloc[-1]
        rows.append({"case": rate.case, "method": rate.method, "expected": bound_text(rate.expected_rate, rate.expected_log_exponent),
                     "theory": rate.reference, "H¹ rate": f"{rate.fitted_rate:.3f} ± {rate.fitted_rate_se:.3f}",
                     "pairwise H¹ rates": " ".join(str(rate.pairwise_rates).split()[-4:]),
                     "L² rate": _fmt(rate.fitted_rate_l2, ".2f"), "trace rate": "—" if rate.case in bilateral else _fmt(getattr(rate, "fitted_rate_trace", np.nan), ".2f"),
                     "finest ndof": _fmt(finest.ndof, ".3g"), "KKT": _fmt(finest.kkt_residual, ".1e"), "verdict": rate.verdict})
    return pd.DataFrame(rows)


def left_out_view(cases, methods) -> pd.DataFrame:
    """(method, cases, why) of each of ``methods`` that does not discretise some friction case
    (``methods.left_out``), one row per method and reason."""
    found: dict[tuple[str, str], list[str]] = {}
    for case in cases:
        for name, why in left_out(case, methods):
            found.setdefault((name, why), []).append(case.name)
    return pd.DataFrame([{"method": name, "cases": ", ".join(names), "why": why} for (name, why), names in found.items()],
                        columns=["method", "cases", "why"])


def friction_quantity_view(results: pd.DataFrame) -> pd.DataFrame:
    """One row per (case, method), one column per friction quantity the rows have
    (``FRICTION_QUANTITIES``); empty when they have none."""
    present = [column for column in FRICTION_QUANTITIES if column in results and results[column].notna().any()]
    rows = []
    for (case, method), group in results.groupby(["case", "method"], sort=False) if present else ():
        group = group.sort_values("level")
        row = {"case": case, "method": method}
        for column in present:
            row[column] = quantity_text(group, column, FRICTION_QUANTITIES[column][1])
        rows.append(row)
    return pd.DataFrame(rows)


def quantity_text(group: pd.DataFrame, column: str, kind: str) -> str:
    """One chain's friction quantity: an error as "e (rate r)", a value as "φ₁ ± GCI (p)" with
    its error against the exact value where the rows have one (``measure.richardson``)."""
    values = group[column].to_numpy(float)
    if not np.isfinite(values).all() or len(values) < 3:
        return _fmt(values[-1]) if len(values) else ""
    h = mesh_sizes(group.assign(mesh=group.get("mesh", "uniform")))
    if kind == "error":
        return f"{values[-1]:.3e} (rate {fit_rate(h, values)[0]:.2f})" if (values > 0).all() else _fmt(values[-1])
    band = richardson(values, h)
    exact = exact_columns(group, column, h, values) if exact_column(column) in group else {"error": np.nan}
    if band["convergence"] == "settled":
        text = f"{values[-1]:.6g} (settled)"
    elif not np.isfinite(band["gci"]):
        text = f"{values[-1]:.6g} ({band['convergence']})"
    else:
        text = f"{values[-1]:.6g} ± {band['gci']:.1e} (p {band['observed_order']:.2f}){'' if band['asymptotic'] else '*'}"
    return text + (f"; error {exact['error']:.1e}" if np.isfinite(exact["error"]) else "")


def draws_stick_slip(case) -> bool:
    """Whether the case's contact figure is the stick/slip picture (``stick_slip``): a 2D case,
    one body (scalar, or elastic, whose snapshots then hold the slip and the friction force:
    ``study.chain.snapshots.friction_snapshot``) or two elastic ones (the slip their tangential
    jump: ``study.chain.snapshots.two_body_friction_snapshot``). A 3D case's snapshots hold
    faces, two scalar bodies' the opening: each keeps its contact figure."""
    return case.frictional and case.dimension == 2 and (case.bodies == 1 or case.physics.elastic)


def stick_slip_caption(case) -> str:
    """What ``stick_slip`` shows of ``case`` (with or without a closed-form solution; one body or
    two, whose slip is the jump between them)."""
    exact, elastic = case.u is not None, case.physics.elastic
    coulomb, two = case.friction.name == "coulomb", case.bodies == 2
    step = " of the last load step" if len(case.history) > 1 else ""
    if two:
        slip = ("the slip [u_h·τ] = t₁ − t₂" + step + ", the tangential jump between the bodies (upper less lower, "
                "sampled on the intersection of the two trace meshes; none exact: a mirror pair has no jump")
        exact = False
    else:
        slip = "the slip u_h·τ" + step if elastic else "the slip u_h (the friction variable's trace"
    force = "the friction force σ_t,h − g_t along τ (the Riesz representative, per edge's mean" if elastic else \
        "the friction force λ_h = ∂ₙu_h − g_C (the discrete multiplier per edge"
    force = force.replace("the friction force", "the upper (slave) body's friction force") if two else force
    bound = "±μ_F p_h (dotted, p_h the discrete pressure" + (" per slave edge)" if two else ")") if coulomb else "±s (dotted)"
    if getattr(case, "predicted_traction", None) is not None:
        bound += "; dashed: the closed form's force at the first method's P_h, Q_h (" + case.prediction + ")"
    return ("finest level of each method along Γ_C. Top: " + slip + (")" if two or not elastic else "") + ("; the exact one dashed" if exact else "")
            + "; bottom: " + force + ("; the exact one dashed" if exact else "") + ") between the threshold " + bound
            + ". Shaded: " + ("the exact stick zone (no slip)" if exact else "the first method's stick zone, where "
            + (f"its {'jump' if two else 'slip'} moves less than 10⁻³ of its largest and p_h > 0" if elastic else "|λ_h| < the threshold")
            + " (no closed-form solution)")
            + ". Right: zoomed on the first stick-slip point.")


def stick_slip(case, snapshots: dict, folder: Path) -> dict[str, Path] | None:
    """The stick/slip picture of a friction case from its contact snapshots
    (``study.chain.snapshots.contact_snapshot``, finest level of each method): the slip and the
    friction force along Gamma_C against the threshold, exact ones dashed, the exact stick zone
    shaded; left all of Gamma_C, right zoomed on the first exact stick-slip point. None where the
    snapshots do not hold the slip: an elastic case's store the normal displacement and reaction
    (``slip``/``friction_force`` fields would be drawn), and a 3D case's are faces."""
    from ..figures import plt, save, style
    first = next(iter(snapshots.values()))
    fields = slip_fields(case, first)
    if fields is None:
        return None
    fig, axes = plt.subplots(2, 2, figsize=(11, 5.6), sharex="col", gridspec_kw={"width_ratios": (1.6, 1)})
    exact = bool(np.isfinite(first[fields["exact_slip"]]).all())       # a reference case has no exact u
    threshold = coulomb_threshold(case, first) if case.friction.name == "coulomb" else threshold_along(case, first["s"])
    stick = stick_zone(first, fields, exact, threshold)
    slip = "[u_h]" if case.bodies == 2 else "u_h"      # two bodies: the tangential jump between them
    for column, window in enumerate((None, zoom_window(first["s"], stick, first["edge_lengths"]))):
        top, bottom = axes[:, column]
        if exact:       # the exact ones on top (zorder): the finest levels lie on them
            top.plot(first["s"], first[fields["exact_slip"]], "k--", lw=1.0, label="exact u", zorder=5)
            bottom.plot(first["s"], fields["sign"] * first[fields["exact_force"]], "k--", lw=1.0, label="exact λ", zorder=5)
        for method, snap in snapshots.items():
            colour = style(method)["color"]
            top.plot(snap["s"], snap[fields["slip"]], color=colour, lw=1.1, label=f"{method}: ${slip}$")
            bottom.step(snap["edge_s"], snap[fields["force"]], where="mid", color=colour, lw=1.1, label=f"{method}: $\\lambda_h$")
        for bound in (threshold, -threshold) if threshold is not None else ():
            bottom.plot(first["s"], bound, color="0.5", lw=1.2, ls=":")
        closed = predicted_force(case, first)
        if closed is not None:
            bottom.plot(first["s"], closed, "k--", lw=1.0, label="closed form at $P_h$, $Q_h$", zorder=5)
        for ax in (top, bottom):
            ax.fill_between(first["s"], 0, 1, where=stick, transform=ax.get_xaxis_transform(), color="0.85", alpha=0.6, lw=0)
            ax.grid(True, alpha=0.25)
            if window is not None:
                ax.set_xlim(*window)
        if window is not None:
            inside = (first["s"] >= window[0]) & (first["s"] <= window[1])
            _fit_limits(top, [snap[fields["slip"]][(snap["s"] >= window[0]) & (snap["s"] <= window[1])]
                              for snap in snapshots.values()] + [first[fields["exact_slip"]][inside]])
            _fit_limits(bottom, [snap[fields["force"]][(snap["edge_s"] >= window[0]) & (snap["edge_s"] <= window[1])]
                                 for snap in snapshots.values()] + ([fields["sign"] * first[fields["exact_force"]][inside]] if exact else []))
    axes[0, 0].set_ylabel(f"slip ${slip}$ on $\\Gamma_C$")
    axes[1, 0].set_ylabel("friction force $\\lambda_h$")
    axes[0, 0].legend(fontsize=7, loc="best")
    axes[1, 0].legend(fontsize=7, loc="best")
    axes[1, 0].set_xlabel("coordinate along $\\Gamma_C$; shaded: " + ("exact" if exact else f"{next(iter(snapshots))}'s")
                          + " stick zone; dotted: " + ("±μ_F p_h" if case.friction.name == "coulomb" else "±s"))
    axes[1, 1].set_xlabel("zoom on the stick-slip point")
    axes[0, 0].set_title(f"{case.name}: stick and slip, finest level of each method", fontsize=10)
    return save(fig, folder, f"{case.name}_stick_slip")


def stick_zone(snapshot: dict, fields: dict, exact: bool, threshold: np.ndarray | None) -> np.ndarray:
    """Where along Gamma_C (at the snapshot's points) it sticks: the exact solution's zeros, or
    without one the edges of the snapshot's method whose friction force is inside the threshold
    (a mean-analogue u_h is not pointwise 0 where it sticks: only its vertex values and edge
    means are)."""
    if exact or threshold is None:
        slip = snapshot[fields["exact_slip"] if exact else fields["slip"]]
        return np.abs(slip) <= 1e-12 * max(1.0, np.abs(slip).max())
    if fields["slip"] == "slip":
        # an elastic body's own slip (Nitsche's vanishes where it sticks; the per-edge means of the
        # friction force touch the threshold only approximately), where it presses (threshold > 0)
        slip = np.abs(snapshot["slip"])
        return (slip <= 1e-3 * slip.max(initial=0.0)) & (threshold > 0)
    bound = np.interp(snapshot["edge_s"], snapshot["s"], threshold)
    inside = np.abs(snapshot[fields["force"]]) < (1 - 1e-8) * bound
    return np.interp(snapshot["s"], snapshot["edge_s"], inside.astype(float)) > 0.5


def predicted_force(case, snapshot: dict) -> np.ndarray | None:
    """The friction force a closed form predicts along Gamma_C (``Case.predicted_traction``:
    Cattaneo's shear q on the body, drawn as the force sigma_t = -q), read at the snapshot's own
    P = int p_h and Q = -int sigma_t,h (the per-edge means times the edge lengths); None where the
    case declares none."""
    if getattr(case, "predicted_traction", None) is None or "friction_force" not in snapshot:
        return None
    lengths = snapshot["edge_lengths"]
    force, tangential = float(snapshot["pressure"] @ lengths), float(-snapshot["friction_force"] @ lengths)
    return -np.asarray(case.predicted_traction(snapshot["s"], force, tangential), float)


def coulomb_threshold(case, snapshot: dict) -> np.ndarray:
    """Coulomb's threshold mu_F p_h at the snapshot's coordinates: its per-edge pressure, held
    over each edge (the per-edge friction force is drawn the same way)."""
    edge = np.clip(np.searchsorted(snapshot["edge_s"] + 0.5 * snapshot["edge_lengths"], snapshot["s"]), 0, len(snapshot["edge_s"]) - 1)
    return case.friction.coefficient * np.maximum(snapshot["pressure"][edge], 0.0)


def threshold_along(case, s: np.ndarray) -> np.ndarray | None:
    """The threshold s at the snapshot's coordinates along Gamma_C: a constant as it is; a
    function evaluated on Gamma_C's edges of the case's coarse mesh, matched by their coordinate
    along Gamma_C (``study.chain.snapshots.contact_snapshot``'s: along the direction from its first
    to its last vertex); None where that fails."""
    if case.friction.constant:
        return np.full(len(s), float(case.friction.threshold))
    from ...mesh.levels import coarse_mesh
    from ...mesh.points import evaluate
    from ...mesh.trace import CONTACT
    mesh = coarse_mesh(case)
    ends = np.array([[mesh.vertices[v.nr].point for v in el.vertices] for el in mesh.Boundaries(CONTACT).Elements()])
    if ends.shape[-1] != 2:
        return None
    start, end = ends.reshape(-1, 2).min(axis=0), ends.reshape(-1, 2).max(axis=0)
    direction = (end - start) / np.linalg.norm(end - start)
    along = ends @ direction                                          # (edges, 2)
    lo, hi = along.min(axis=1), along.max(axis=1)
    edge = np.argmax((s[:, None] >= lo - 1e-12) & (s[:, None] <= hi + 1e-12), axis=1)     # the edge holding each s
    k = ((s - along[edge, 0]) / (along[edge, 1] - along[edge, 0]))[:, None]
    points = ends[edge, 0] * (1 - k) + ends[edge, 1] * k
    return evaluate(case.friction.threshold_function, mesh, points)


def _fit_limits(ax, values: list) -> None:
    """``ax``'s y-range to the values shown in its window, padded by 5%."""
    shown = np.concatenate(values)
    shown = shown[np.isfinite(shown)]            # a reference case's exact values are NaN
    if not len(shown):
        return
    pad = 0.05 * np.ptp(shown) + 1e-12
    ax.set_ylim(shown.min() - pad, shown.max() + pad)


def slip_fields(case, snapshot: dict) -> dict | None:
    """Which snapshot fields hold the slip and the friction force (and their exact values), and
    the sign that turns the exact one into the discrete one's convention (both the flux
    λ = ∂ₙu − g_C, ``problem.friction``); None where the snapshot has neither (see ``stick_slip``)."""
    if "faces" in snapshot:
        return None
    if "slip" in snapshot and "friction_force" in snapshot:
        return {"slip": "slip", "force": "friction_force", "exact_slip": "exact_slip",
                "exact_force": "exact_friction_force", "sign": 1.0}
    if case.physics.elastic:
        return None
    # scalar: the contact variable is the slip, the discrete "pressure" the friction force, as
    # the exact "pressure" ∂ₙu − g_C
    return {"slip": "u_h", "force": "pressure", "exact_slip": "u", "exact_force": "exact_pressure", "sign": 1.0}


def zoom_window(s: np.ndarray, stick: np.ndarray, edge_lengths: np.ndarray) -> tuple[float, float] | None:
    """A window about the first point where the exact stick zone begins or ends inside Gamma_C:
    12 of the first snapshot's edges wide (so that its edges show), at most a tenth of Gamma_C;
    None without one."""
    changes = np.flatnonzero(np.diff(stick.astype(int)))
    if not len(changes):
        return None
    point = 0.5 * (s[changes[0]] + s[changes[0] + 1])
    half = min(6 * float(np.max(edge_lengths)), 0.05 * float(np.ptp(s)))
    return point - half, point + half
