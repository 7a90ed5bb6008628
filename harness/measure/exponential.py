"""Exponential convergence: the fit of hp meshes' errors, err ~ C exp(-b N^{1/(d+1)}).

On geometric meshes with linearly increasing degrees, a solution analytic but for point
singularities has ||u - u_hp||_1 <= C exp(-b N^{1/(d+1)}): N^{1/3} in 2D, N^{1/4} in 3D about
points (``mesh.hp`` has the references). So
ln(err) is affine in N^{1/(d+1)}: a least-squares line gives b (the slope, negated) and its
coefficient of determination R^2, the measure of how straight it is. The verdict is
"exponential" when R^2 >= ``R2_EXPONENTIAL`` over at least ``MIN_LEVELS`` levels with b > 0, and
the same line in ln N (an algebraic rate N^-r) fits worse; else it says which law fits better.
"""
from __future__ import annotations

import numpy as np

R2_EXPONENTIAL = 0.98
MIN_LEVELS = 5


def r_squared(x: np.ndarray, y: np.ndarray) -> tuple[float, float]:
    """(slope, R^2) of the least-squares line of y on x."""
    slope, intercept = np.polyfit(x, y, 1)
    residual = y - (slope * x + intercept)
    total = ((y - y.mean()) ** 2).sum()
    return float(slope), float(1.0 - (residual ** 2).sum() / total) if total > 0 else float("nan")


def exponential_fit(ndof, errors, dimension: int = 2) -> dict:
    """b, R^2 and the verdict of ln(err) = ln C - b N^{1/(d+1)} over all the levels given
    (``errors`` relative or absolute: b does not depend on it), with the algebraic fit's R^2 beside."""
    N, e = np.asarray(ndof, float), np.asarray(errors, float)
    keep = np.isfinite(e) & (e > 0)
    N, e = N[keep], e[keep]
    if len(e) < 3:
        return {"exponential_b": float("nan"), "exponential_r2": float("nan"), "algebraic_r2": float("nan"),
                "exponential_verdict": "too few levels"}
    slope, r2 = r_squared(N ** (1.0 / (dimension + 1)), np.log(e))
    _, algebraic = r_squared(np.log(N), np.log(e))
    if len(e) < MIN_LEVELS:
        verdict = "too few levels"
    elif slope < 0 and r2 >= R2_EXPONENTIAL and r2 >= algebraic:
        verdict = "exponential"
    elif algebraic > r2:
        verdict = "algebraic"
    else:
        verdict = "not exponential"
    return {"exponential_b": -slope, "exponential_r2": r2, "algebraic_r2": algebraic, "exponential_verdict": verdict}
