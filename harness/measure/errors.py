"""Errors of u_h against the exact solution, and the nonconformity of the discrete cones.

The theorems bound ||u - u_h||_{H^1}. All norms of every solution on one mesh (the methods of a
level share it) come from one integration over the elements (``quadrature``): the graded rule
on the elements touching a singular point, where an O(1) share of the error lives, and Gauss
order ``error_order`` on every other element. tests/test_errors.py checks the result against a
much more accurate reference integration, to 0.1%, on every case's finest default level.
"""

from __future__ import annotations

import weakref

import ngsolve as ngs
import numpy as np
from scipy.sparse.linalg import splu

from ..fem.contact_quadrature import contact_quadrature, exact_pressure
from ..fem.element_quadrature import ElementQuadrature
from ..fem.nested import p1_values
from ..fem.rotated_frame import RotatedFrame
from ..mesh.points import evaluate
from .best_approximation import nested_ritz_start, ritz_projection


def error_order(fe_order: int) -> int:
    """Gauss order on the elements away from singular points. There u - u_h for elements of
    order k is, to leading order, a polynomial of degree k + 1, so (u - u_h)^2 one of degree
    2k + 2, which this order integrates exactly: 6 for P2 (within 3e-5 of order 20 on every
    case), 4 for P1. tests/test_errors.py holds both to 1e-3 against a much finer integration.
    For k >= 3 two more: the error is then small enough that what a degree 2k + 2 rule misses of
    a case's data shows (smooth-quintic's D^5 u jumps across x = 0, inside elements). Where a
    lower derivative jumps inside elements (``smooth``: D^3 u), no Gauss order is enough: such a
    case declares the line (``derivative_jumps``), and the elements it crosses get a split rule
    (``fem.element_quadrature.split_rule``)."""
    return 2 * fe_order + (2 if fe_order <= 2 else 4)
NORMS = ("err_h1", "err_h1_semi", "err_l2", "err_energy")


def error_norms(case, solutions: list[ngs.GridFunction], quadrature: ElementQuadrature,
                order: int | None = None) -> list[dict]:
    """H^1, H^1-semi, L^2 and energy errors of each of ``solutions`` (GridFunctions on one
    mesh): u and grad u are evaluated once per quadrature point for all of them, with the Gauss
    order the highest-order solution needs (``error_order``) unless ``order`` is given. The
    energy norm a(e, e)^{1/2} is the H^1 seminorm for the Laplacian, (int sigma(e) : eps(e))^{1/2}
    in elasticity (``physics``)."""
    order = order or error_order(max(gfu.space.globalorder for gfu in solutions))
    squares = []
    for gfu in solutions:
        diff = case.u - gfu
        grad_diff = case.grad_u - ngs.Grad(gfu)
        squares += [ngs.InnerProduct(diff, diff), ngs.InnerProduct(grad_diff, grad_diff),
                    case.physics.energy_density(grad_diff)]
    integrals = quadrature.integrate(ngs.CF(tuple(squares)), order)
    rows = []
    for squared in integrals.reshape(len(solutions), 3):
        l2_sq, semi_sq, energy_sq = (max(value, 0.0) for value in squared)
        rows.append({"err_h1": float(np.sqrt(l2_sq + semi_sq)), "err_h1_semi": float(np.sqrt(semi_sq)),
                     "err_l2": float(np.sqrt(l2_sq)), "err_energy": float(np.sqrt(energy_sq))})
    return rows





# Gauss points per contact edge for the errors on Gamma_C: exact for the trace mass matrix,
# and the pressure singularities sit at edge ends, which Gauss points avoid.
CONTACT_ERROR_POINTS = 8


def contact_error_points(order: int) -> int:
    """``CONTACT_ERROR_POINTS``, or k + 2 for the degrees of an hp space beyond 6 (the trace
    mass matrix of degree k needs k + 1 points to be regular)."""
    return max(CONTACT_ERROR_POINTS, order + 2)


class DiscretePressure:
    """The discrete contact pressure lambda_h of a solution u_h on one discrete problem: the
    Riesz representative, in the trace space W_h of X_h on Gamma_C (continuous P_k on the
    contact edges), of the residual: int lambda_h w = a(u_h, w) - L(w) for the basis functions w
    with a trace on Gamma_C. The exact pressure satisfies int lambda w = a(u, w) - L(w) (Green's
    formula), so this is the same functional for every method -- the cones' multipliers,
    Nitsche's and the penalty's contact terms all end up in it."""

    @classmethod
    def of(cls, problem) -> "DiscretePressure":
        """The pressure of ``problem``, made once (the errors on Gamma_C and the estimator
        share it: ``fem.assembly.DiscreteProblem.cache``)."""
        if cls not in problem.cache:
            problem.cache[cls] = cls(problem)
        return problem.cache[cls]

    def __init__(self, problem):
        # a weak reference: the problem's cache holds this, and a cycle would keep the level's
        # matrices alive until the cyclic collector runs
        self._problem = weakref.ref(problem)
        self.quadrature = contact_quadrature(problem, contact_error_points(problem.order))
        q = self.quadrature
        self.T = q.T[:, problem.contact_dofs].tocsc()
        self._mass = splu((self.T.T @ (self.T.multiply(q.weights[:, None]))).tocsc())

    def coefficients(self, u_h: np.ndarray) -> np.ndarray:
        """lambda_h's coefficients on the problem's contact dofs (``fem.assembly.DiscreteProblem.contact_dofs``)."""
        return self._mass.solve(self._problem().contact_residual(u_h))

    def at_points(self, coefficients: np.ndarray) -> np.ndarray:
        return self.T @ coefficients

    def max_tension(self, coefficients: np.ndarray) -> float:
        """max over Gamma_C of -lambda_h (the exact pressure is >= 0), at the error points."""
        return float(max(0.0, -self.at_points(coefficients).min()))


class DiscreteTraction:
    """The discrete friction force of u_h on one problem (a Tresca case, ``problem.friction``),
    beside its slip, at the pressure's Gauss points (``DiscretePressure.quadrature``):

    * scalar model: the friction force is the flux itself, lambda_h of ``DiscretePressure`` (the
      same numbers, not a second computation), and the slip is u_h;
    * elasticity: sigma_t,h, the Riesz representative in W_h^{d-1} of the residual's tangential
      part, built as ``DiscretePressure`` builds the normal one: int sigma_t,h . tau_j w =
      a(u_h, w tau_j) - L(w tau_j) for the basis functions w tau_j of the rotated frame's
      tangential dofs on Gamma_C (``fem.rotated_frame.RotatedFrame``). Green's formula gives
      int (sigma(u) n - g_C) . w tau_j for the exact u, i.e. sigma_t(u) - g_t, so it is the same
      functional for every method. On a flat piece of Gamma_C w tau_j's tangential trace is w,
      so the trace mass matrix is the pressure's own (one factorisation). The slip is u_h . tau_j.

    Both come as (q, d - 1) arrays: component j along tau_j (2D: tau = (-n_y, n_x))."""

    @classmethod
    def of(cls, problem) -> "DiscreteTraction":
        if cls not in problem.cache:
            problem.cache[cls] = cls(problem)
        return problem.cache[cls]

    def __init__(self, problem):
        self._problem = weakref.ref(problem)
        self.pressure = DiscretePressure.of(problem)
        self.quadrature = self.pressure.quadrature
        self.elastic = problem.physics.rotated_frame
        if self.elastic and problem.tangential_rows is None:
            raise ValueError("the problem keeps no tangential rows of A: it was not discretised for a friction case")

    def at_points(self, u_h: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(friction force, slip) of ``u_h`` at the points, each (q, d - 1)."""
        own = self.pressure
        if not self.elastic:
            force = own.at_points(own.coefficients(u_h))
            return force[:, None], (self.quadrature.T @ u_h)[:, None]
        problem = self._problem()
        dofs = problem.tangential_dofs
        residual = (problem.tangential_rows @ u_h - problem.b[dofs.ravel()]).reshape(dofs.shape)
        force = np.column_stack([own.at_points(own._mass.solve(r)) for r in residual])
        slip = np.column_stack([own.T @ u_h[d] for d in dofs])
        return force, slip


def point_tangents(normals: np.ndarray) -> np.ndarray:
    """(q, d - 1, d) the rotated frame's tangents at points with outward ``normals``."""
    return RotatedFrame(np.zeros((len(normals), 1), np.int64), normals).tangents()


def exact_friction(case, problem, q) -> tuple[np.ndarray, np.ndarray]:
    """(friction force, slip) of the exact u at the points of the rule ``q``, each (q, d - 1) as
    ``DiscreteTraction.at_points``: lambda = d_n u - g_C and u (scalar); (sigma_t(u) - g_t) . tau_j and
    u . tau_j (elasticity)."""
    physics, mesh = case.physics, problem.mesh
    if not physics.rotated_frame:
        return (physics.pressure(case, mesh, q.points, q.normals)[:, None],
                physics.contact_value(case, mesh, q.points, q.normals)[:, None])
    tangents = point_tangents(q.normals)
    traction = physics.tangential_traction(case, mesh, q.points, q.normals)
    displacement = evaluate(case.u, mesh, q.points)
    return np.einsum("qjd,qd->qj", tangents, traction), np.einsum("qjd,qd->qj", tangents, displacement)


class ContactErrors:
    """Errors on Gamma_C of the solutions on one discrete problem, against the exact u:

    * trace: ||u - u_h||_{L^2(Gamma_C)};
    * pressure: lambda_h (``DiscretePressure``) against lambda = d_n u - g_C in L^2(Gamma_C) and
      in the mesh-dependent norm ||h^{1/2} (lambda - lambda_h)||_{L^2(Gamma_C)};
    * tension: max over Gamma_C of -lambda_h, the flux counterpart of max_penetration;
    * friction (Tresca cases): the friction force of ``DiscreteTraction`` against the exact one in
      L^2(Gamma_C), ``err_friction_l2``: in the scalar model the pressure's error itself (its
      lambda is the friction force), in elasticity |sigma_t(u) - sigma_t,h|.
    """

    def __init__(self, case, problem):
        self.own = DiscretePressure.of(problem)
        q = self.own.quadrature
        self.weights, self.h = q.weights, q.h
        self.u = case.physics.contact_value(case, problem.mesh, q.points, q.normals)
        self.pressure = exact_pressure(case, problem, q)
        self._full_T = q.T
        self.friction = None
        if case.frictional and problem.physics.rotated_frame:
            self.friction = (DiscreteTraction.of(problem), exact_friction(case, problem, q)[0])
        self.frictional = case.frictional

    def __call__(self, u_h: np.ndarray) -> dict:
        w = self.weights
        trace = self._full_T @ u_h - self.u
        coefficients = self.own.coefficients(u_h)
        difference = self.pressure - self.own.at_points(coefficients)
        errors = {
            "err_trace_l2": float(np.sqrt(w @ trace**2)),
            "err_pressure_l2": float(np.sqrt(w @ difference**2)),
            "err_pressure_h12": float(np.sqrt((w * self.h) @ difference**2)),
            "max_tension": self.own.max_tension(coefficients),
        }
        if self.friction is not None:
            traction, exact = self.friction
            errors["err_friction_l2"] = float(np.sqrt(w @ ((exact - traction.at_points(u_h)[0]) ** 2).sum(axis=1)))
        elif self.frictional:
            errors["err_friction_l2"] = errors["err_pressure_l2"]       # the scalar model's lambda is the friction force
        return errors


class ExactErrors:
    """The error columns of a study of a case with an exact u, level by level: the contact
    errors after each solve, the volume norms of every solution and of the best approximation
    R_h u (``best``) in one integration at the end of the level. R_h u of each order starts its
    CG from the coarser level's (nested iteration: what a chain carries, ``state_of``, so that
    a resumed chain computes the same numbers)."""

    def __init__(self, case, phases, orders: dict[str, int] | None = None):
        self.case, self.phases, self.orders = case, phases, orders or {}
        self.vertex_values: dict[tuple[int, int], np.ndarray] = {}     # (order, level): R_h u at the vertices

    def begin_level(self, level: int, mesh, problems: dict, quadrature: ElementQuadrature, multilevel) -> None:
        self.quadrature, self.pending = quadrature, []
        self.best, self.contact = {}, {}
        with self.phases("best"):
            for order, problem in problems.items():
                start = nested_ritz_start(multilevel, problem, self.vertex_values.get((order, level - 1)))
                best = ritz_projection(self.case, problem, multilevel, start)
                self.vertex_values = {key: v for key, v in self.vertex_values.items() if key[1] >= level - 1}
                self.vertex_values[(order, level)] = p1_values(problem, best)
                self.best[order] = problem.gridfunction(best)
                self.contact[order] = ContactErrors(self.case, problem)

    def solved(self, method, level: int, problem, u: np.ndarray, row: dict | None) -> dict:
        self.pending.append((row, method.order, problem.gridfunction(u)))
        return self.contact[method.order](u)

    def end_level(self) -> None:
        """The volume norms, order by order: each order's solutions and its R_h u in one
        integration with that order's Gauss rule (``error_order``), so that a method's errors do
        not depend on which other methods share the level (a study split into jobs per method
        gives the same numbers, bit for bit). Each pass also integrates u's own energy a(u, u),
        as the energy "error" of the zero function: its rows' exact strain energy
        (``quantities``), for a few more components of a pass made anyway, and the same number
        however the study is split."""
        for order in self.best:
            mine = [(row, gfu) for row, own_order, gfu in self.pending if own_order == order]
            zero = ngs.GridFunction(self.best[order].space)
            *norms, best, of_u = error_norms(self.case, [gfu for _, gfu in mine] + [self.best[order], zero], self.quadrature)
            for (row, _), own in zip(mine, norms):
                row |= own | {"err_best_h1": best["err_h1"], "err_best_h1_semi": best["err_h1_semi"],
                              "err_best_energy": best["err_energy"],
                              "err_h1_over_best": own["err_h1"] / best["err_h1"],
                              "qoi_energy_exact": 0.5 * of_u["err_energy"] ** 2, "norm_h1_exact": of_u["err_h1"]}

    def skip_level(self, level: int, mesh) -> None:
        pass

    def state_of(self, method_name: str) -> list:
        """What a method's chain carries to its next level (``study.chain.walk.ChainState``): its order's
        R_h u at the vertices of its last level, the next level's CG start."""
        mine = sorted(key for key in self.vertex_values if key[0] == self.orders.get(method_name))
        return [(key, self.vertex_values[key]) for key in mine[-1:]]

    def restore(self, method_name: str, state: list, rows: list[dict]) -> None:
        """A resumed chain: the R_h u it carried (``state_of``)."""
        for key, values in state:
            self.vertex_values[tuple(key)] = values
