"""Errors of u_h against the exact solution, and the nonconformity of the discrete cones.

The theorems bound ||u - u_h||_{H^1}. All norms of every solution on one mesh (the methods of a
level share it) come from one integration over the elements (``quadrature``): the graded rule
on the elements touching a singular point, where an O(1) share of the error lives, and Gauss
order ``error_order`` on every other element. tests/test_errors.py checks the result against a
much more accurate reference integration, to 0.1%, on every case's finest default level.
"""

from __future__ import annotations

import ngsolve as ngs
import numpy as np

from .discrete import ContactTraceFunction
from .mesh import evaluate
from .quadrature import ElementQuadrature

def error_order(fe_order: int) -> int:
    """Gauss order on the elements away from singular points. There u - u_h for elements of
    order k is, to leading order, a polynomial of degree k + 1, so (u - u_h)^2 one of degree
    2k + 2, which this order integrates exactly: 6 for P2 (within 3e-5 of order 20 on every
    case), 4 for P1. tests/test_errors.py holds both to 1e-3 against a much finer integration."""
    return 2 * fe_order + 2
PENETRATION_SAMPLES_PER_EDGE = 33
NORMS = ("err_h1", "err_h1_semi", "err_l2")


def error_norms(case, solutions: list[ngs.GridFunction], quadrature: ElementQuadrature,
                order: int | None = None) -> list[dict]:
    """H^1, H^1-semi and L^2 errors of each of ``solutions`` (GridFunctions on one mesh): u and
    grad u are evaluated once per quadrature point for all of them, with the Gauss order the
    highest-order solution needs (``error_order``) unless ``order`` is given."""
    order = order or error_order(max(gfu.space.globalorder for gfu in solutions))
    squares = []
    for gfu in solutions:
        diff = case.u - gfu
        grad_diff = case.grad_u - ngs.grad(gfu)
        squares += [diff * diff, grad_diff * grad_diff]
    integrals = quadrature.integrate(ngs.CF(tuple(squares)), order)
    rows = []
    for l2_sq, semi_sq in integrals.reshape(-1, 2):
        l2_sq, semi_sq = max(l2_sq, 0.0), max(semi_sq, 0.0)
        rows.append({"err_h1": float(np.sqrt(l2_sq + semi_sq)), "err_h1_semi": float(np.sqrt(semi_sq)),
                     "err_l2": float(np.sqrt(l2_sq))})
    return rows


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

