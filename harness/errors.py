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
from scipy.sparse.linalg import splu

from .boundary import contact_quadrature, exact_pressure
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



# Gauss points per contact edge for the errors on Gamma_C: exact for the trace mass matrix,
# and the pressure singularities sit at edge ends, which Gauss points avoid.
CONTACT_ERROR_POINTS = 8


class ContactErrors:
    """Errors on Gamma_C of the solutions on one discrete problem.

    * trace: ||u - u_h||_{L^2(Gamma_C)};
    * pressure: the discrete pressure lambda_h is the Riesz representative, in the trace space
      W_h of X_h on Gamma_C (continuous P_k on the contact edges), of the residual:
      int lambda_h w = a(u_h, w) - L(w) for the basis functions w with a trace on Gamma_C. The
      exact pressure satisfies int lambda w = a(u, w) - L(w) (Green's formula), so this is the
      same functional for every method -- the cones' multipliers, Nitsche's and the penalty's
      contact terms all end up in it. Against lambda = d_n u - g_C in L^2(Gamma_C) and in the
      mesh-dependent norm ||h^{1/2} (lambda - lambda_h)||_{L^2(Gamma_C)};
    * tension: max over Gamma_C of -lambda_h, the flux counterpart of max_penetration (the
      exact pressure is >= 0).
    """

    def __init__(self, case, problem):
        self.problem = problem
        q = contact_quadrature(problem, CONTACT_ERROR_POINTS)
        self.weights, self.h = q.weights, q.h
        self.T = q.T[:, problem.contact_dofs].tocsc()
        self.u = evaluate(case.u, problem.mesh, q.points)
        self.pressure = exact_pressure(case, problem, q)
        self._mass = splu((self.T.T @ (self.T.multiply(self.weights[:, None]))).tocsc())
        self._full_T = q.T

    def discrete_pressure(self, u_h: np.ndarray) -> np.ndarray:
        """lambda_h at the error points."""
        return self.T @ self._mass.solve(self.problem.contact_residual(u_h))

    def __call__(self, u_h: np.ndarray) -> dict:
        w = self.weights
        trace = self._full_T @ u_h - self.u
        lam_h = self.discrete_pressure(u_h)
        difference = self.pressure - lam_h
        return {
            "err_trace_l2": float(np.sqrt(w @ trace**2)),
            "err_pressure_l2": float(np.sqrt(w @ difference**2)),
            "err_pressure_h12": float(np.sqrt((w * self.h) @ difference**2)),
            "max_tension": float(max(0.0, -lam_h.min())),
        }
