"""The report's tables: pandas frames of formatted cells, one function per table (levels of a
method, rates against the theorems, the Gamma_C errors, elasticity, 3D, sweeps, efficiency)."""
from __future__ import annotations

import numpy as np
import pandas as pd

from ..measure.rates import normalised_errors, pairwise_rates
from ..methods import PAPER, names_with_role
from ..problem.case import bound_text, fraction


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
    elastic = {case.name: case for case in cases if case.physics.elastic}
    rows = rates[rates.case.isin(list(elastic))]
    return pd.DataFrame({
        "case": rows.case, "Poisson ratio": [f"{elastic[c].physics.poisson:g}" for c in rows.case], "method": rows.method,
        "expected": [bound_text(p, q) for p, q in zip(rows.expected_rate, rows.expected_log_exponent)],
        "H¹ rate": [_fmt(v, ".3f") for v in rows.fitted_rate], "energy rate": [_fmt(v, ".3f") for v in rows.fitted_rate_energy],
        "best (R_h u) rate": [_fmt(v, ".3f") for v in rows.fitted_rate_best], "verdict": rows.verdict,
    })


def two_body_view(cases, rates: pd.DataFrame, results: pd.DataFrame) -> pd.DataFrame:
    """The two-body cases: per case x method the ratio of the bodies' coarse mesh sizes (1.00: the
    matching control), the fitted H^1 rate over both bodies against the one-body rate, and on the
    finest level the dofs, err / best, the largest interpenetration between the slave's nodes and
    the largest KKT residual over the levels."""
    two = {case.name: case for case in cases if case.bodies == 2}
    rows = []
    for _, rate in rates[rates.case.isin(list(two))].iterrows():
        mine = results[(results.case == rate.case) & (results.method == rate.method)]
        finest = mine[mine.level == mine.level.max()].iloc[0]
        case = two[rate.case]
        rows.append({"case": rate.case, "lower / upper maxh": f"{case.second_body.maxh / case.maxh:.2f}", "method": rate.method,
                     "expected": bound_text(rate.expected_rate, rate.expected_log_exponent),
                     "H¹ rate": _fmt(rate.fitted_rate, ".3f"), "finest ndof": f"{int(finest.ndof):,}",
                     "err / best": _fmt(finest.err_h1_over_best, ".3f"),
                     "max [u_h] below 2α": _fmt(finest.max_penetration, ".1e"),
                     "max KKT residual": _fmt(mine.kkt_residual.max(), ".1e"), "verdict": rate.verdict})
    return pd.DataFrame(rows)


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


def normalised_view(case, results: pd.DataFrame, methods=()) -> pd.DataFrame:
    """e/(h |log h|^q) and e/h level by level, for the paper's P2 cones (the paper's log-factor
    case): the methods that declare the role PAPER (``methods``: Method objects to look roles up
    in besides the registered ones)."""
    out = None
    for method in names_with_role(PAPER, results.method[results.case == case.name], methods):
        g = results[(results.case == case.name) & (results.method == method)].sort_values("level")
        if g.empty:
            continue
        frame = pd.DataFrame({"level": g.level.values,
                              f"{method}: e / h|log h|^{fraction(case.expected_log_exponent)}":
                                  [_fmt(v) for v in normalised_errors(g.h, g.err_h1, 1.0, case.expected_log_exponent)],
                              f"{method}: e / h": [_fmt(v) for v in normalised_errors(g.h, g.err_h1, 1.0, 0.0)]})
        out = frame if out is None else out.merge(frame, on="level")
    return out


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
        "P1 err / its err at equal ndof": [_fmt(v, ".3g") for v in table.err_ratio_at_equal_ndof],
    })
