"""Convergence rates measured against the theorem rates.

For each (case, method) the H^1 errors e_l on levels l with mesh sizes h_l give
* pairwise rates log(e_l / e_{l-1}) / log(h_l / h_{l-1});
* a least-squares fit of  log e = log C + p log h + q log|log h|  over the last k >= 3 levels
  (the asymptotic range), q fixed to the log exponent of the method's theory (1/4 for the
  paper's Thm 4.2 ii / 5.2 ii, else 0), with the standard error of p;
* the normalised errors e / (h^p |log h|^q) with the theorem's p and q, which stay bounded
  exactly when the theorem's bound is observed;
* the rate against the number of dofs N, e ~ N^-r (``fit_ndof_rate``), the measure that
  compares meshes (``mesh.strategies``): on uniform meshes in d dimensions r = p / d; on any
  2D mesh family P_k can do at best r = k / 2 (``optimal_ndof_rate``), which graded meshes
  (Remark 4.4; Apel, Sändig & Whiteman 1996) and adaptive ones reach on singular solutions.

Each (case, mesh, method) is fitted on its own.
"""
from __future__ import annotations

import numpy as np
import pandas as pd

from ..problem.regularity import capped_rate
from .exponential import exponential_fit

DEFAULT_FIT_LEVELS = 3
TOLERANCE = 0.1
# A "below" that the discrete space itself explains (``space_explains``): the method's error within
# this factor of the best approximation's on the finest level
PRE_ASYMPTOTIC_RATIO = 1.1

RATE_COLUMNS = ["case", "mesh", "method", "order", "reference", "expected_rate", "expected_log_exponent", "fitted_rate",
                "fitted_rate_se", "pairwise_rates", "verdict",
                # the second theory (Drouet & Hild 2015 for the cones), fitted with its own log exponent
                "sharper_reference", "sharper_rate", "sharper_fitted_rate", "sharper_verdict",
                # the other errors' rates, no log factor: L^2, the best approximation, on Gamma_C
                "fitted_rate_l2", "fitted_rate_best", "best_expected_rate", "best_verdict", "pairwise_rates_best",
                "fitted_rate_trace", "fitted_rate_pressure_l2", "fitted_rate_pressure_h12",
                # the energy norm a(e, e)^{1/2}: the H^1 seminorm's rate for the Laplacian; in
                # elasticity equivalent to it (Korn), so the same theorem rate
                "fitted_rate_energy",
                # against the number of dofs: fitted, the theory's on this mesh (p/d uniform), the
                # optimal k/d and its verdict; the estimator's rate and its effectivity on the finest level
                "fitted_rate_ndof", "uniform_rate_ndof", "optimal_rate_ndof", "ndof_verdict", "pairwise_rates_ndof",
                "fitted_rate_estimator", "effectivity_finest",
                # hp meshes: err ~ C exp(-b N^{1/(d+1)}) (``exponential``)
                "exponential_b", "exponential_r2", "algebraic_r2", "exponential_verdict", "finest_relative_error"]
# What each column of rates.csv means (the docs' table is generated from this)
COLUMN_MEANINGS = {
    "case": "the case", "mesh": "the mesh strategy", "method": "the method", "order": "its order k",
    "reference": "the theorem of the expected rate", "expected_rate": "the H¹ rate it predicts (NaN: no theory)",
    "expected_log_exponent": "the power q of |log h| in the bound C h^p |log h|^q",
    "fitted_rate": "the H¹ rate fitted by least squares over the finest levels (the log factor divided out)",
    "fitted_rate_se": "its standard error", "pairwise_rates": "the rates between successive levels",
    "verdict": "`meets` (within ±0.1), `above`, `below`, `pre-asymptotic` (below, but so is the best "
               "approximation, the error is within 1.1 of its error and the pairwise rates still climb: the levels, "
               "not the method) or `no theory`",
    "sharper_reference": "a second theory (Drouet & Hild 2015 for the cones)", "sharper_rate": "its rate",
    "sharper_fitted_rate": "the rate fitted with its log power", "sharper_verdict": "the verdict against it",
    "fitted_rate_l2": "the L² error's fitted rate", "fitted_rate_best": "the best approximation's fitted H¹ rate",
    "best_expected_rate": "min(ν − 1, k): what the best approximation's rate should be",
    "best_verdict": "`consistent`, `faster than nu` or `slower than nu`: does the case have its declared regularity",
    "pairwise_rates_best": "the best approximation's pairwise rates",
    "fitted_rate_trace": "the L²(Γ_C) error's fitted rate", "fitted_rate_pressure_l2": "the pressure's L² error's fitted rate",
    "fitted_rate_pressure_h12": "the pressure's H^{-1/2} error's fitted rate", "fitted_rate_energy": "the energy error's fitted rate",
    "fitted_rate_ndof": "the H¹ error's fitted rate in the number of dofs N (error ~ N^−r)",
    "uniform_rate_ndof": "the theory's rate in N on uniform meshes, p/d",
    "optimal_rate_ndof": "the optimal rate in N, k/d", "ndof_verdict": "`optimal` (within 0.1) or `below optimal`",
    "pairwise_rates_ndof": "the rates in N between successive levels",
    "fitted_rate_estimator": "the estimator's fitted rate in N", "effectivity_finest": "η / err_energy on the finest level",
    "exponential_b": "hp meshes: b of the fit ln(err) = ln C − b N^{1/(d+1)} over all levels",
    "exponential_r2": "its R²", "algebraic_r2": "the R² of the algebraic fit ln(err) = ln C − r ln N on the same levels",
    "exponential_verdict": "`exponential` (R² ≥ 0.98 over ≥ 5 levels, and above the algebraic fit's), `algebraic`, "
                           "`not exponential` or `too few levels`",
    "finest_relative_error": "hp meshes: err_h1 / ‖u‖₁ on the finest level",
}
# error column -> its rate column (plain fit, q = 0)
OTHER_RATES = {"err_l2": "fitted_rate_l2", "err_best_h1": "fitted_rate_best", "err_trace_l2": "fitted_rate_trace",
               "err_pressure_l2": "fitted_rate_pressure_l2", "err_pressure_h12": "fitted_rate_pressure_h12",
               "err_energy": "fitted_rate_energy"}



def pairwise_rates(h, e) -> np.ndarray:
    h, e = np.asarray(h, float), np.asarray(e, float)
    return np.log(e[1:] / e[:-1]) / np.log(h[1:] / h[:-1])


def fit_rate(h, e, log_exponent: float = 0.0, levels: int = DEFAULT_FIT_LEVELS) -> tuple[float, float]:
    """(p, standard error of p) of log e - q log|log h| = log C + p log h over the last levels."""
    if levels < 2:
        raise ValueError("a rate fit needs at least two levels")
    h, e = np.asarray(h, float)[-levels:], np.asarray(e, float)[-levels:]
    if len(h) < 2:
        return float("nan"), float("nan")
    y = np.log(e) - log_exponent * np.log(np.abs(np.log(h)))
    X = np.column_stack([np.ones_like(h), np.log(h)])
    coef, *_ = np.linalg.lstsq(X, y, rcond=None)
    dof = len(h) - 2
    if dof == 0:
        return float(coef[1]), float("nan")
    residual = y - X @ coef
    sigma2 = residual @ residual / dof
    se = np.sqrt(sigma2 * np.linalg.inv(X.T @ X)[1, 1])
    return float(coef[1]), float(se)


def fit_ndof_rate(ndof, e, levels: int = DEFAULT_FIT_LEVELS) -> float:
    """r of e = C N^-r over the last ``levels`` levels (least squares)."""
    return -fit_rate(ndof, e, 0.0, levels)[0]


def optimal_ndof_rate(order: int, dimension: int = 2) -> float:
    """The best rate in N of P_order on any mesh family in ``dimension``: k / d."""
    return order / dimension


def normalised_errors(h, e, rate: float, log_exponent: float) -> np.ndarray:
    h = np.asarray(h, float)
    return np.asarray(e, float) / (h**rate * np.abs(np.log(h)) ** log_exponent)


def verdict(fitted: float, expected: float, tolerance: float = TOLERANCE) -> str:
    if not np.isfinite(expected):
        return "no theory"
    if not np.isfinite(fitted):
        return "undetermined"
    if fitted < expected - tolerance:
        return "below"
    if fitted > expected + tolerance:
        return "above"
    return "meets"


def best_approximation_rate(nu: float, order: int) -> float:
    """The rate of the Ritz projection's H^1 error on uniform meshes: min(nu - 1, order)
    (``problem.regularity.capped_rate``)."""
    return capped_rate(nu, float(order))


def rate_table(results: pd.DataFrame, error: str = "err_h1", levels: int = DEFAULT_FIT_LEVELS,
               tolerance: float = TOLERANCE) -> pd.DataFrame:
    """One row per (case, method) of ``results``, each against its own theories: the expected
    rates, log exponents and references that the study wrote into every row; and the fitted
    rates of the other errors, with the best approximation's set against min(nu - 1, order)
    (``best_verdict``: does the case have the regularity it declares?)."""
    rows = []
    if "mesh" not in results.columns:
        results = results.assign(mesh="uniform")
    for (case_name, mesh, method), group in results.groupby(["case", "mesh", "method"], sort=False):
        group = group.sort_values("level")
        first = group.iloc[0]
        if mesh != "uniform":
            # h (the largest element) says nothing of a graded or adaptive mesh: rates in N only,
            # judged against the optimal k/d; on hp meshes, the exponential law
            ndof = ndof_rates(group, error, levels, tolerance)
            rows.append({"case": case_name, "mesh": mesh, "method": method, "order": int(first.order),
                         "reference": first.reference, "expected_rate": first.expected_rate,
                         "expected_log_exponent": first.expected_log_exponent, "verdict": ndof["ndof_verdict"], **ndof,
                         **(hp_columns(group, error) if is_hp(mesh) else {})})
            continue
        p, se = fit_rate(group.h, group[error], _q(first.expected_log_exponent), levels)
        row = {
            "case": case_name, "mesh": mesh, "method": method, "order": int(first.order), "reference": first.reference,
            "expected_rate": first.expected_rate, "expected_log_exponent": first.expected_log_exponent,
            "fitted_rate": p, "fitted_rate_se": se,
            "pairwise_rates": " ".join(f"{r:.3f}" for r in pairwise_rates(group.h, group[error])),
            "verdict": verdict(p, first.expected_rate, tolerance),
        }
        sharper = float(first.get("sharper_rate", np.nan))
        if np.isfinite(sharper):
            p2, _ = fit_rate(group.h, group[error], _q(first.sharper_log_exponent), levels)
            row |= {"sharper_reference": first.sharper_reference, "sharper_rate": sharper, "sharper_fitted_rate": p2,
                    "sharper_verdict": verdict(p2, sharper, tolerance)}
        elif isinstance(first.get("sharper_reference"), str) and first.sharper_reference:
            row |= {"sharper_reference": first.sharper_reference, "sharper_rate": sharper, "sharper_verdict": "no theory"}
        for column, name in OTHER_RATES.items():
            if column in group and group[column].notna().all() and (group[column] > 0).all():
                row[name] = fit_rate(group.h, group[column], 0.0, levels)[0]
        if "fitted_rate_best" in row:
            row["best_expected_rate"] = best_approximation_rate(float(first.nu), int(first.order))
            gap = row["fitted_rate_best"] - row["best_expected_rate"]
            row["best_verdict"] = ("" if not np.isfinite(gap) else  # no best approximation (reference case) or no nu
                                   "consistent" if abs(gap) <= tolerance else ("faster than nu" if gap > 0 else "slower than nu"))
            row["pairwise_rates_best"] = " ".join(f"{r:.3f}" for r in pairwise_rates(group.h, group.err_best_h1))
        if "ndof" in group:             # (results of harness 0.1 may have no ndof)
            row |= ndof_rates(group, error, levels, tolerance)
        for kind, rate, fitted in (("verdict", "expected_rate", "fitted_rate"),
                                   ("sharper_verdict", "sharper_rate", "sharper_fitted_rate")):
            if row.get(kind) == "below" and space_explains(row, group, row[rate], row[fitted], tolerance):
                row[kind] = "pre-asymptotic"
        rows.append(row)
    return pd.DataFrame(rows, columns=RATE_COLUMNS)


def is_hp(mesh: str) -> bool:
    """Whether a ``mesh`` label is the hp strategy's (``hp``, ``hp:mu=0.5``)."""
    return mesh.split(":")[0] == "hp"


def hp_columns(group: pd.DataFrame, error: str) -> dict:
    """The exponential fit of one (case, hp mesh, method)'s levels (``exponential``), its verdict
    as the row's, and the finest relative H^1 error."""
    fit = exponential_fit(group.ndof, group[error], space_dimension(group))
    relative = float(group[error].iloc[-1] / group.norm_h1_exact.iloc[-1]) if "norm_h1_exact" in group else float("nan")
    return fit | {"verdict": fit["exponential_verdict"], "finest_relative_error": relative}


def space_explains(row: dict, group: pd.DataFrame, expected: float, fitted: float, tolerance: float = TOLERANCE) -> bool:
    """Whether a method's rate ``fitted`` below ``expected`` is the levels' and not the method's: on the
    finest level its H¹ error is within ``PRE_ASYMPTOTIC_RATIO`` of the best approximation's
    (Falk's lemma, Remark 4.6: the contact discretisation costs nothing beyond the space), the
    best approximation's own rate falls short of min(nu - 1, k) by as much (within the
    tolerance), and the last pairwise rate is above the fitted one (still climbing). Then no
    method on these meshes could do better, and the theorem's rate is not yet visible."""
    best, best_expected = row.get("fitted_rate_best", np.nan), row.get("best_expected_rate", np.nan)
    if not (np.isfinite(best) and np.isfinite(best_expected) and "err_h1_over_best" in group):
        return False
    ratio = float(group.err_h1_over_best.iloc[-1])
    pairwise = [float(r) for r in str(row.get("pairwise_rates", "")).split()]
    return (np.isfinite(ratio) and ratio <= PRE_ASYMPTOTIC_RATIO
            and best_expected - best >= expected - fitted - tolerance
            and bool(pairwise) and pairwise[-1] > fitted)


def ndof_rates(group: pd.DataFrame, error: str, levels: int, tolerance: float = TOLERANCE) -> dict:
    """The rate columns against N of one (case, mesh, method)'s levels."""
    order = int(group.order.iloc[0])
    dimension = space_dimension(group)
    r = fit_ndof_rate(group.ndof, group[error], levels)
    optimal = optimal_ndof_rate(order, dimension)
    out = {"fitted_rate_ndof": r, "optimal_rate_ndof": optimal,
           "uniform_rate_ndof": float(group.expected_rate.iloc[0]) / dimension,
           "ndof_verdict": "optimal" if r >= optimal - tolerance else ("below optimal" if np.isfinite(r) else "undetermined"),
           "pairwise_rates_ndof": " ".join(f"{-x:.3f}" for x in pairwise_rates(group.ndof, group[error]))}
    if "estimator" in group and group.estimator.notna().all() and (group.estimator > 0).all():
        out["fitted_rate_estimator"] = fit_ndof_rate(group.ndof, group.estimator, levels)
    if "effectivity" in group and np.isfinite(group.effectivity.iloc[-1]):
        out["effectivity_finest"] = float(group.effectivity.iloc[-1])
    return out


def space_dimension(group: pd.DataFrame) -> int:
    """d of the levels' meshes: the rows' ``dimension``; in a results file written before that
    column, read off N ~ h^-d on uniform meshes, and 2 on graded and adaptive ones (they were 2D
    only then)."""
    if "dimension" in group and np.isfinite(group.dimension.iloc[0]):
        return int(group.dimension.iloc[0])
    if group.mesh.iloc[0] != "uniform" or len(group) < 2:
        return 2
    return int(round(-np.polyfit(np.log(group.h.astype(float)), np.log(group.ndof.astype(float)), 1)[0]))


def _q(log_exponent) -> float:
    return float(log_exponent) if np.isfinite(log_exponent) else 0.0
