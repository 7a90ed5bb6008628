"""A weak contact method given by its contact law on Gamma_C: the second level of the method
protocol (``harness.methods.protocol.ContactLawMethod``), solved by the harness's semismooth
Newton method (``solvers.newton``) as the built-in penalty and Nitsche methods are.

The law. At each Gauss point of Gamma_C (``contact_quadrature``) the law sees the state
``GammaPoints`` (u_h, d_n u_h, the gap alpha, the contact load g_C, the cell size h, the point)
and returns two terms, a pressure p and a flux term f, which enter the discrete system as

    F(u) = A u - b - int_{Gamma_C} p v + int_{Gamma_C} f d_n v = 0      for all v in X_h,

i.e. F(u) = A u - b - T^T W p + N^T W f with T, N the trace and normal-derivative rows of the
basis at the points and W the weights. Penalty (Chouly & Hild, Appl. Numer. Math. 65 (2013)) is
p = (1/eps)[alpha - u]_+, f = 0; Nitsche's theta-family (Chouly, Hild & Renard, Math. Comp. 84
(2015), eq. (10); ``weak_contact``, (N)) is p = (1/eps)[P(u)]_+, f = theta ([P(u)]_+ -
eps (d_n u - g_C)) with P(u) = eps (d_n u - g_C) + alpha - u.

Semismooth Newton converges in finitely many steps, to the exact discrete solution, when F is
piecewise affine (Qi & Sun, Math. Program. 58 (1993); Hintermueller, Ito & Kunisch, SIAM J.
Optim. 13 (2002)). So a law has two branches per point, told by ``branch`` (True: "in contact"),
and on each branch its terms are affine in (u, d_n u):

    p = p0 + p_u u + p_dn d_n u,      f = f0 + f_u u + f_dn d_n u,

``derivative`` returning (p_u, p_dn, f_u, f_dn) of the given branch. The Jacobian of a branch set
S is then J_S = A - T^T W (p_u T + p_dn N) + N^T W (f_u T + f_dn N), symmetric exactly when
f_u = -p_dn; and F_S(v) = J_S v - r_S with r_S = -F_S(0). ``check_law`` verifies both
promises (affine terms, a derivative that is theirs) on every level before the solve, and
refuses a law that breaks them in one line.
"""
from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Protocol, runtime_checkable

import numpy as np
import scipy.sparse as sp

from .assembly import DiscreteProblem
from .contact_quadrature import ContactQuadrature, at_points, contact_quadrature
from .weak_contact import BoundaryTerms, boundary_jacobian, obstacle_force

# the relative mismatch of ``check_law`` beyond which a law's terms are not affine on a branch
# or its derivative is not theirs (round-off of the terms' evaluation is ~1e-15)
LAW_TOLERANCE = 1e-8


@dataclass(frozen=True)
class GammaPoints:
    """The state a contact law sees at the Gauss points of Gamma_C, each an array (q,)."""

    u: np.ndarray       # u_h
    dn: np.ndarray      # the outward normal derivative d_n u_h
    gap: np.ndarray     # alpha (u_h >= alpha is the contact condition)
    load: np.ndarray    # g_C, the contact load (lambda = d_n u - g_C; zero in the paper)
    h: np.ndarray       # the size of the point's contact edge
    x: np.ndarray       # (q, 2) the points


@runtime_checkable
class ContactLaw(Protocol):
    """A contact law: two branches per Gauss point, affine terms on each (see the module)."""

    def branch(self, at: GammaPoints) -> np.ndarray:
        """(q,) bool: the branch of the state ``at`` (True: the contact term is active)."""

    def term(self, at: GammaPoints, branch: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(p, f): the pressure and the flux term of ``branch`` at ``at``."""

    def derivative(self, at: GammaPoints, branch: np.ndarray) -> tuple:
        """(p_u, p_dn, f_u, f_dn) of ``branch`` (arrays (q,) or numbers)."""


class LawError(ValueError):
    """A contact law that breaks its protocol, in one line."""


@dataclass
class LawSystem(BoundaryTerms):
    """F(u) and J of a contact law on one level: the interface ``solvers.newton`` solves."""

    problem: DiscreteProblem
    quadrature: ContactQuadrature
    law: object
    gap: np.ndarray
    load: np.ndarray
    rhs: np.ndarray             # b: the part of -F independent of u and of the law
    J: sp.csr_matrix
    J_ngs: object
    delta: sp.csr_matrix        # J - A: the boundary terms, on their own (sorted) pattern
    positions: np.ndarray
    obstacle_force: float
    symmetric: bool

    def at(self, u: np.ndarray) -> GammaPoints:
        q = self.quadrature
        return GammaPoints(q.T @ u, q.N @ u, self.gap, self.load, q.h, q.points)

    def zero(self) -> GammaPoints:
        """The state u_h = 0: where an affine term takes its constant part."""
        return self.at(np.zeros(self.problem.ndof))

    def bracket(self, u: np.ndarray) -> np.ndarray:
        """Positive where the law's branch is "in contact" (what ``newton`` reads as active)."""
        return np.where(self.branch(u), 1.0, -1.0)

    def branch(self, u: np.ndarray) -> np.ndarray:
        return np.asarray(self.law.branch(self.at(u)), bool)

    def terms(self, state: GammaPoints, branch: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        p, f = self.law.term(state, branch)
        return np.broadcast_to(p, branch.shape), np.broadcast_to(f, branch.shape)

    def pressure(self, u: np.ndarray) -> np.ndarray:
        """The law's own contact pressure p at the Gauss points."""
        return self.terms(self.at(u), self.branch(u))[0]

    def residual(self, u: np.ndarray) -> np.ndarray:
        """F(u) on the free dofs (zero on Gamma_u)."""
        return np.where(self.problem.free, self._F(u, self.branch(u)), 0.0)

    def _F(self, u: np.ndarray, branch: np.ndarray) -> np.ndarray:
        W, T, N = self.quadrature.weights, self.quadrature.T, self.quadrature.N
        p, f = self.terms(self.at(u), branch)
        return self.J @ u - self.delta @ u - self.rhs - T.T @ (W * p) + N.T @ (W * f)      # A u = J u - delta u

    def affine_rhs(self, active: np.ndarray) -> np.ndarray:
        """r_S = -F_S(0): F_S(v) = J_S v - r_S on the branch set ``active``."""
        return -self._F(np.zeros(self.problem.ndof), active)

    def set_jacobian(self, active: np.ndarray) -> None:
        """J_S = A - T^T W (p_u T + p_dn N) + N^T W (f_u T + f_dn N), into J's memory."""
        W, T, N = self.quadrature.weights, self.quadrature.T, self.quadrature.N
        p_u, p_dn, f_u, f_dn = self.derivatives(active)
        self.write_terms(-(T.T @ sp.diags(W * p_u) @ T) - T.T @ sp.diags(W * p_dn) @ N
                         + N.T @ sp.diags(W * f_u) @ T + N.T @ sp.diags(W * f_dn) @ N)

    def derivatives(self, active: np.ndarray) -> list[np.ndarray]:
        return [np.broadcast_to(np.asarray(d, float), active.shape) for d in self.law.derivative(self.zero(), active)]


def law_system(case, problem: DiscreteProblem, law, take_stiffness: bool = False) -> LawSystem:
    """The system of ``law`` on ``problem`` (2D scalar: d_n u_h needs ``ContactQuadrature.N``),
    its law checked (``check_law``), its Jacobian set for no active point."""
    quadrature = contact_quadrature(problem)
    if quadrature.N is None:
        raise LawError("a contact law needs d_n u_h on Gamma_C: 2D scalar cases only")
    gap, load = at_points(case.gap, problem.mesh, quadrature), at_points(case.contact_load, problem.mesh, quadrature)
    T, N = quadrature.T, quadrature.N
    both = (abs(T) + abs(N)).tocsr()
    J, J_ngs, delta, positions = boundary_jacobian(problem, both.T @ both, take_stiffness)
    system = LawSystem(problem, quadrature, law, gap, load, problem.b.copy(), J, J_ngs, delta, positions,
                       obstacle_force(case, problem, J), symmetric=True)
    system.symmetric = check_law(system)
    system.set_jacobian(np.zeros(len(gap), bool))
    return system


def check_law(system: LawSystem, seed: int = 0) -> bool:
    """Whether the law's Jacobian is symmetric, after checking on both branches, at two random
    states, that its terms are affine and ``derivative`` is theirs; LawError naming the broken
    promise else (a wrong derivative would make Newton's "exact" solve silently inexact)."""
    rng = np.random.default_rng(seed)
    q = len(system.gap)
    for name, branch in (("in contact", np.ones(q, bool)), ("separated", np.zeros(q, bool))):
        states = [replace(system.zero(), u=rng.standard_normal(q), dn=rng.standard_normal(q)) for _ in range(2)]
        (p0, f0), (p1, f1) = (system.terms(s, branch) for s in states)
        p_u, p_dn, f_u, f_dn = system.derivatives(branch)
        du, ddn = states[1].u - states[0].u, states[1].dn - states[0].dn
        for label, change, predicted in (("pressure", p1 - p0, p_u * du + p_dn * ddn), ("flux term", f1 - f0, f_u * du + f_dn * ddn)):
            scale = max(np.abs(change).max(initial=0.0), np.abs(predicted).max(initial=0.0), np.finfo(float).tiny)
            if not np.all(np.isfinite(change)) or np.abs(change - predicted).max(initial=0.0) > LAW_TOLERANCE * scale:
                raise LawError(f"contact law {type(system.law).__name__}: its {label} on the branch '{name}' is not affine "
                               f"in (u, d_n u) with the slopes its derivative gives")
    # J_S is symmetric for every set S when the cross slopes cancel on both branches
    return all(np.allclose(d[2], -d[1], rtol=1e-12, atol=0.0) for d in (system.derivatives(np.full(q, b)) for b in (True, False)))
