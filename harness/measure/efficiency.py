"""Accuracy per dof and per second: what each method pays for a given H^1 error.

The paper's claim (abstract, Section 6) is that its quadratic methods are more accurate than
linear elements. Rates alone do not settle it where both orders share the rate (nu <= 2): the
constants do. So, per case, a target error is fixed and every method's cost to reach it is read
off its measured levels by log-log interpolation, never extrapolation:

* target: the largest of the methods' finest-level errors, so that every method reaches it
  within its measured levels; stated as a fraction of the case's coarsest error;
* dofs: log ndof interpolated linearly in log err between the two levels around the target;
* seconds: the contact solves, and everything a user pays for u_h (mesh refinement, assembly,
  set-up, solve; not the harness's error measurement), of every level up to that point, summed
  (nested iteration needs the coarser levels too), and interpolated the same way.
"""
from __future__ import annotations

import numpy as np
import pandas as pd

from ..methods import BASELINE, names_with_role

COLUMNS = ["case", "method", "order", "target_err_h1", "target_fraction", "ndof", "solve_seconds", "total_seconds",
           "p1_over_ndof", "p1_over_seconds", "err_ratio_at_equal_ndof"]

# What each column of efficiency.csv means (the docs' table is generated from this); the p1_
# prefix names the BASELINE role's method (p1 among the registered ones)
COLUMN_MEANINGS = {
    "case": "the case", "method": "the method", "order": "its order",
    "target_err_h1": "the case's target H¹ error: the largest of the methods' finest errors",
    "target_fraction": "the target over the case's coarsest error",
    "ndof": "the dofs the method needs to reach the target (interpolated in log–log between its levels)",
    "solve_seconds": "the contact solves' seconds to reach it, its coarser levels included",
    "total_seconds": "mesh, assembly, set-up and solve seconds to reach it",
    "p1_over_ndof": "the baseline's dofs over the method's (> 1: the method needs fewer)",
    "p1_over_seconds": "the baseline's total seconds over the method's",
    "err_ratio_at_equal_ndof": "the baseline's H¹ error over the method's at the largest N both reach",
}

def at_target(err: np.ndarray, cost: np.ndarray, target: float) -> float:
    """log cost interpolated linearly in log err at ``target``, between the level from which
    the error stays <= target and the one before; NaN if the levels never reach it. (From which
    it stays: an error that changes sign, as a quantity's can, is small by accident on a level
    where it crosses zero; an H^1 error falls monotonically and the two readings agree.)"""
    err, cost = np.asarray(err, float), np.asarray(cost, float)
    above = np.flatnonzero(err > target)
    k = int(above[-1]) + 1 if len(above) else 0
    if k == len(err):
        return float("nan")
    if k == 0 or err[k] == target:
        return float(cost[k])
    t = (np.log(target) - np.log(err[k - 1])) / (np.log(err[k]) - np.log(err[k - 1]))
    return float(np.exp(np.log(cost[k - 1]) + t * (np.log(cost[k]) - np.log(cost[k - 1]))))


def error_at_ndof(group: pd.DataFrame, ndof: float) -> float:
    """log err interpolated linearly in log ndof (NaN outside the measured range)."""
    g = group.sort_values("ndof")
    if not g.ndof.min() <= ndof <= g.ndof.max():
        return float("nan")
    return float(np.exp(np.interp(np.log(ndof), np.log(g.ndof), np.log(g.err_h1))))


def equal_ndof_ratio(baseline: pd.DataFrame, group: pd.DataFrame) -> float:
    """``baseline``'s H^1 error over ``group``'s at the largest ndof both reach: ``group``'s
    finest where the baseline runs to it (P1 one level past P2 has P2's finest dofs), else the
    baseline's finest (P1 stopped with P2, ``Case.asymptotic_levels_p1``), where ``group``'s
    error is interpolated between its levels."""
    ndof = min(group.ndof.max(), baseline.ndof.max())
    return error_at_ndof(baseline, ndof) / error_at_ndof(group, ndof)


def baseline_name(names, methods=()) -> str | None:
    """The P1 baseline among the method names ``names``: the first whose method declares the
    role BASELINE (``methods.method.Method.roles``; looked up among ``methods``, Method objects, then by name:
    ``methods.names_with_role``); None if none does."""
    return next(iter(names_with_role(BASELINE, names, methods)), None)


def efficiency_table(results: pd.DataFrame, baseline: str | None = None, methods=(), target_method: str | None = None) -> pd.DataFrame:
    """One row per (case, method): the cost of reaching the case's target error; for the other
    methods, ``baseline``'s cost over theirs (> 1: they are cheaper) and ``baseline``'s error
    over theirs at equal ndof (``equal_ndof_ratio``). ``baseline``: a method name, by default
    the method that declares the role BASELINE (``baseline_name``; ``methods``: Method objects
    to look roles up in besides the registered ones). The target is the largest of the methods'
    finest errors, or ``target_method``'s finest error where it ran (a method that does not
    reach it has no cost there)."""
    baseline = baseline or baseline_name(results.method, methods)
    tables = []
    for case, frame in results.groupby("case", sort=False):
        groups = {m: g.sort_values("level") for m, g in frame.groupby("method", sort=False)}
        target = (groups[target_method].err_h1.iloc[-1] if target_method in groups
                  else max(g.err_h1.iloc[-1] for g in groups.values()))
        coarsest = max(g.err_h1.iloc[0] for g in groups.values())
        table = pd.DataFrame([{
            "case": case, "method": method, "order": int(g.order.iloc[0]), "target_err_h1": target,
            "target_fraction": target / coarsest,
            "ndof": at_target(g.err_h1, g.ndof, target),
            "solve_seconds": at_target(g.err_h1, g.solve_seconds.cumsum(), target),
            "total_seconds": at_target(g.err_h1, g.total_seconds.cumsum(), target),
        } for method, g in groups.items()])
        if baseline in groups:
            base = table.set_index("method").loc[baseline]
            table["p1_over_ndof"] = base.ndof / table.ndof
            table["p1_over_seconds"] = base.total_seconds / table.total_seconds
            table["err_ratio_at_equal_ndof"] = [equal_ndof_ratio(groups[baseline], g) for g in groups.values()]
        tables.append(table)
    return pd.concat(tables, ignore_index=True).reindex(columns=COLUMNS)


def verdicts(table: pd.DataFrame, rates: pd.DataFrame, baseline: str | None = None, methods=()) -> dict[str, str]:
    """Per case, one sentence: does the best P2 method beat ``baseline`` (by default the method
    that declares the role BASELINE, ``baseline_name``) at the target, by how much, and what the
    rates say."""
    baseline = baseline or baseline_name(table.method, methods)
    out = {}
    for case, t in table.groupby("case", sort=False):
        if baseline not in set(t.method) or not (t.order == 2).any():
            continue
        best = t[t.order == 2].sort_values("total_seconds").iloc[0]
        base = t[t.method == baseline].iloc[0]
        r = rates[rates.case == case].set_index("method")
        p2_rate, p1_rate = r.loc[best.method, "fitted_rate"], r.loc[baseline, "fitted_rate"]
        p2_theory, p1_theory = r.loc[best.method, "expected_rate"], r.loc[baseline, "expected_rate"]
        cheaper = best.p1_over_ndof > 1 and best.p1_over_seconds > 1
        claim = "holds" if cheaper else ("holds in dofs, not in time" if best.p1_over_ndof > 1 else "does not hold")
        if not (np.isfinite(p2_theory) and np.isfinite(p1_theory)):
            why = (f"no theory gives {best.method if not np.isfinite(p2_theory) else base.method} a rate here; "
                   f"measured {p2_rate:.2f} ({best.method}) and {p1_rate:.2f} ({base.method})")
        elif np.isclose(p2_theory, p1_theory):
            why = (f"the theories give both orders the same rate ({p1_theory:.3g}; measured {p2_rate:.2f} and "
                   f"{p1_rate:.2f}), so the gain is the constant: at equal dofs {best.method}'s error is "
                   f"{_times(best.err_ratio_at_equal_ndof)} smaller than P1's")
        else:
            why = (f"P2's rate is higher ({p2_theory:.3g} against {p1_theory:.3g} in theory; measured {p2_rate:.2f} "
                   f"and {p1_rate:.2f}), so the gap widens as the target tightens")
        out[case] = (f"The claim {claim}: to reach H¹ error {best.target_err_h1:.2e} ({best.target_fraction:.1%} of the "
                     f"coarsest), {best.method} needs {_times(best.p1_over_ndof)} fewer dofs and "
                     f"{_times(best.p1_over_seconds)} less time than {base.method} "
                     f"({best.ndof:.3g} against {base.ndof:.3g} dofs, {best.total_seconds:.2g} against "
                     f"{base.total_seconds:.2g} s); {why}.")
    return out


def _times(ratio: float) -> str:
    return f"{ratio:.0f}x" if ratio >= 10 else f"{ratio:.2g}x"


# quantity_efficiency.csv: the cost at equal error in each quantity of interest
QUANTITY_EFFICIENCY_COLUMNS = ["case", "quantity", "method", "order", "target_error", "ndof", "total_seconds",
                               "p1_over_ndof", "p1_over_seconds"]
QUANTITY_EFFICIENCY_MEANINGS = {
    "case": "the case (with u, uniform meshes)", "quantity": "the quantity of interest",
    "method": "the method", "order": "its order",
    "target_error": "the case's target error in the quantity: the largest of the methods' finest errors",
    "ndof": "the dofs the method needs to reach it (interpolated in log–log between its levels)",
    "total_seconds": "mesh, assembly, set-up and solve seconds to reach it",
    "p1_over_ndof": "the baseline's dofs over the method's (> 1: the method needs fewer)",
    "p1_over_seconds": "the baseline's total seconds over the method's",
}


def quantity_efficiency_table(results: pd.DataFrame, columns: dict, baseline: str | None = None, methods=()) -> pd.DataFrame:
    """What each method pays for a given error in each quantity of interest (``columns``: name
    -> results column, whose exact value is the column ``<column>_exact``): the cost at equal
    accuracy of the module docstring with |Q_h - Q| for the H^1 error, on the uniform chains of
    the cases with u. An engineer's "is P2 worth it?" is asked of the force, not of a norm."""
    if "mesh" in results:
        results = results[results.mesh == "uniform"]
    baseline = baseline or baseline_name(results.method, methods)
    rows = []
    for quantity, column in columns.items():
        exact = f"{column}_exact"
        if column not in results or (exact not in results and quantity != "penetration"):
            continue
        for case, group in results.groupby("case", sort=False):
            # the exact value of the finest row (its rule is the finest; ``measure.quantities``)
            value = group.loc[group.ndof.idxmax(), exact] if exact in group else 0.0
            group = group.assign(error=(group[column] - value).abs())
            groups = {m: g.sort_values("level") for m, g in group.groupby("method", sort=False)
                      if np.isfinite(g.error).all() and (g.error > 0).all() and len(g) >= 2}
            if not groups:
                continue
            target = max(g.error.iloc[-1] for g in groups.values())
            rows += [{"case": case, "quantity": quantity, "method": method, "order": int(g.order.iloc[0]),
                      "target_error": target, "ndof": at_target(g.error, g.ndof, target),
                      "total_seconds": at_target(g.error, g.total_seconds.cumsum(), target)} for method, g in groups.items()]
    table = pd.DataFrame(rows, columns=QUANTITY_EFFICIENCY_COLUMNS)
    for _, index in table.groupby(["case", "quantity"], sort=False).groups.items():
        part = table.loc[index]
        base = part[part.method == baseline]
        if len(base):
            table.loc[index, "p1_over_ndof"] = base.ndof.iloc[0] / part.ndof
            table.loc[index, "p1_over_seconds"] = base.total_seconds.iloc[0] / part.total_seconds
    return table
