"""Errors of u_h against the exact solution, and the nonconformity of the discrete cones.

The theorems bound ||u - u_h||_{H^1}; the integrals use a quadrature order well above the
polynomial degree because u is singular (tests/test_errors.py shows that raising the order
further changes the finest-level error of a singular case by far less than 1%).
"""
from __future__ import annotations

import ngsolve as ngs
import numpy as np

from .discrete import ContactTraceFunction
from .mesh import evaluate

ERROR_QUADRATURE_ORDER = 12
PENETRATION_SAMPLES_PER_EDGE = 33


def error_norms(case, gfu: ngs.GridFunction, order: int = ERROR_QUADRATURE_ORDER) -> dict:
    mesh = gfu.space.mesh
    diff = case.u - gfu
    grad_diff = case.grad_u - ngs.grad(gfu)
    l2_sq = ngs.Integrate(diff * diff, mesh, order=order)
    semi_sq = ngs.Integrate(grad_diff * grad_diff, mesh, order=order)
    return {
        "err_h1": float(np.sqrt(l2_sq + semi_sq)),
        "err_h1_semi": float(np.sqrt(semi_sq)),
        "err_l2": float(np.sqrt(l2_sq)),
    }


def max_penetration(case, mesh: ngs.Mesh, trace_u: ContactTraceFunction) -> float:
    """max over Gamma_C of (gap - u_h): positive where u_h dips below the obstacle.

    Sampled densely on every contact edge and at the stationary point of its quadratic, so
    the value between nodes is seen (K_h and K~_h only constrain nodes and edge means).
    """
    dense = np.linspace(0.0, 1.0, PENETRATION_SAMPLES_PER_EDGE)
    t_star = trace_u.minimum_parameters()
    values = np.concatenate([trace_u.at(dense), trace_u.value(np.arange(len(t_star)), t_star)[:, None]], axis=1)
    params = np.concatenate([np.broadcast_to(dense, (len(t_star), len(dense))), t_star[:, None]], axis=1)
    points = trace_u.a[:, None, :] + params[..., None] * (trace_u.b - trace_u.a)[:, None, :]
    gap = evaluate(case.gap_or_zero, mesh, points) if case.gap is not None else 0.0
    return float((gap - values).max())

