"""Convergence rates measured against the theorem rates.

For each (case, method) the H^1 errors e_l on levels l with mesh sizes h_l give
* pairwise rates log(e_l / e_{l-1}) / log(h_l / h_{l-1});
* a least-squares fit of  log e = log C + p log h + q log|log h|  over the last k >= 3 levels
  (the asymptotic range), q fixed to the log exponent of the method's theory (1/4 for the
  paper's Thm 4.2 ii / 5.2 ii, else 0), with the standard error of p;
* the normalised errors e / (h^p |log h|^q) with the theorem's p and q, which stay bounded
  exactly when the theorem's bound is observed.
"""
from __future__ import annotations

import numpy as np
import pandas as pd

DEFAULT_FIT_LEVELS = 3
TOLERANCE = 0.1

RATE_COLUMNS = ["case", "method", "order", "reference", "expected_rate", "expected_log_exponent", "fitted_rate",
                "fitted_rate_se", "pairwise_rates", "verdict"]



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


def rate_table(results: pd.DataFrame, error: str = "err_h1", levels: int = DEFAULT_FIT_LEVELS,
               tolerance: float = TOLERANCE) -> pd.DataFrame:
    """One row per (case, method) of ``results``, each against its own theory: the expected
    rate, log exponent and reference that the study wrote into every row."""
    rows = []
    for (case_name, method), group in results.groupby(["case", "method"], sort=False):
        group = group.sort_values("level")
        first = group.iloc[0]
        q = float(first.expected_log_exponent) if np.isfinite(first.expected_log_exponent) else 0.0
        p, se = fit_rate(group.h, group[error], q, levels)
        rows.append({
            "case": case_name, "method": method, "order": int(first.order), "reference": first.reference,
            "expected_rate": first.expected_rate, "expected_log_exponent": first.expected_log_exponent,
            "fitted_rate": p, "fitted_rate_se": se,
            "pairwise_rates": " ".join(f"{r:.3f}" for r in pairwise_rates(group.h, group[error])),
            "verdict": verdict(p, first.expected_rate, tolerance),
        })
    return pd.DataFrame(rows, columns=RATE_COLUMNS)
