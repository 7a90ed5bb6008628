"""The built-in contact laws: Nitsche's method and the penalty method, as laws of the method
protocol's second level (``fem.contact_laws``), in every physics and dimension. The built-in and a
user's weak methods are the same kind of object, solved by the same semismooth Newton method.

The law is written on the contact variable c and its flux (``contact_laws.protocol.GammaPoints``): the
scalar problem's u and d_n u, elasticity's -u . n and -sigma_n(u). With lambda = flux - g_C the
contact pressure, the Signorini conditions c - alpha >= 0, lambda >= 0, lambda (c - alpha) = 0
are equivalent, for any eps > 0, to

    lambda = (1/eps) [P(u)]_+,      P(u) = eps lambda - (c(u) - alpha)                    (*)

(if c > alpha: lambda = 0 = [-(c - alpha)/eps]_+; if c = alpha: lambda = [lambda]_+ >= 0).
Green's formula gives a(u, v) - int_{Gamma_C} lambda c(v) = L(v) for every v in X (L includes
the contact load; in elasticity sigma_t = 0 is natural, frictionless).

Nitsche (Chouly & Hild, SIAM J. Numer. Anal. 51 (2013) for theta = 1; the theta-family of
Chouly, Hild & Renard, Math. Comp. 84 (2015), eq. (10), for elasticity in 2D and 3D): write
c(v) = theta eps flux(v) - P_theta(v), P_theta(v) = theta eps flux(v) - c(v), so that
-int lambda c(v) = int lambda P_theta(v) - theta int eps lambda flux(v), and put (*) in the
first term only:

    a(u, v) - theta int eps (flux(u) - g_C) flux(v) + int (1/eps) [P(u)]_+ P_theta(v) = L(v). (N)

In elasticity, with flux = -sigma_n, c = -u_n, alpha = -g and g_C = 0, P(u) = u_n - g -
eps sigma_n(u) and (N) is CHR's eq. (10) term by term, their gamma = eps = gamma0 h_T. The exact
solution satisfies (N) (consistency); theta = 1 is symmetric (the derivative of an energy,
coercive for gamma0 small enough), theta = 0 incomplete, theta = -1 skew-symmetric (coercive for
every gamma0 > 0).

Penalty (Chouly & Hild, Appl. Numer. Math. 65 (2013)): (*) without the flux, lambda ~ (1/eps)
[alpha - c]_+, the derivative of 1/2 a(v,v) - L(v) + (1/2 eps) int [alpha - c(v)]_+^2:

    a(u, v) - int (1/eps) [alpha - c(u)]_+ c(v) = L(v).                                    (P)

Not consistent: where the body is in contact, c(u_h) sits about eps lambda below the obstacle.

As laws (pressure p, flux term f: F(u) = A u - b - int p c(v) + int f flux(v)): Nitsche is
p = (1/eps)[P]_+, f = theta ([P]_+ - eps (flux - g_C)); penalty p = (1/eps)[alpha - c]_+, f = 0.

The scale of eps. eps = gamma0 h / M with M the stiffness scale of the flux (``GammaPoints.
modulus``: 1 for the scalar problem, lambda + 2 mu in elasticity). theta = 1 is coercive when
eps ||flux(v)||^2_{Gamma_C} stays below a(v, v) on X_h; with the discrete trace inequality
h ||grad v||^2_{dT} <= C_I ||grad v||^2_T and sigma_n(v) = 2 mu eps_nn(v) + lambda div v,
gamma0 h ||sigma_n(v)||^2 <= 2 C_I gamma0 max(2 mu, lambda) a(v, v): dividing by M makes the
admissible gamma0 independent of the material, also as lambda/mu grows (with eps = gamma0 h
the admissible gamma0 shrinks like 1/lambda: a gamma0 fit for a compressible material leaves J
indefinite on elastic-transition-incompressible, lambda/mu = 49, and P1 Nitsche stalls). CHR
2015 write gamma = gamma0 h_T with E = 1; dolfinx_contact divides by E, which is not robust near
incompressibility.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

# theta: the three members of the family of Chouly, Hild & Renard, Math. Comp. 84 (2015), eq. (10)
# (symmetric, incomplete, skew-symmetric); its analysis covers no other value
THETAS = (1.0, 0.0, -1.0)


def _positive(name: str, value) -> None:
    if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
        raise ValueError(f"{name} must be a finite positive number, got {value}")


def degree_scale(degree: int | None, at) -> np.ndarray | float:
    """(k / p)^2 at each point of degree p (``contact_laws.protocol.GammaPoints``) for a law calibrated on P_k:
    the discrete trace-inverse constant grows like p^2 (``methods.nitsche.gamma0_for``), so on an
    hp mesh eps ~ h / p^2 keeps the margin of P_k's parameter in every element. Exactly 1 where
    p = k, or where either is not known."""
    if degree is None or at.degree is None:
        return 1.0
    return (degree / np.asarray(at.degree, float)) ** 2


@dataclass(frozen=True)
class Nitsche:
    """Nitsche's law (N), eps = gamma0 h / M at each Gauss point (h its cell's size, M the
    physics' modulus), variant theta; ``degree``: the k of P_k that gamma0 is chosen for, so that
    on an hp mesh eps = gamma0 (k / p)^2 h / M at a point of degree p (``degree_scale``)."""

    gamma0: float = 0.05
    theta: float = 1.0
    degree: int | None = None

    def __post_init__(self):
        _positive("gamma0", self.gamma0)
        if self.theta not in THETAS:
            raise ValueError(f"theta must be 1, 0 or -1 (Chouly, Hild & Renard 2015), got {self.theta}")

    def bracket(self, at) -> tuple[np.ndarray, np.ndarray]:
        """(P(u), eps) at the points: P = eps (flux - g_C) + alpha - c."""
        eps = self.gamma0 * at.h / at.modulus * degree_scale(self.degree, at)
        return eps * (at.dn - at.load) + at.gap - at.u, eps

    def branch(self, at) -> np.ndarray:
        return self.bracket(at)[0] > 0

    def term(self, at, branch):
        P, eps = self.bracket(at)
        positive = np.where(branch, P, 0.0)
        return positive / eps, self.theta * (positive - eps * (at.dn - at.load))

    def derivative(self, at, branch):
        eps = self.bracket(at)[1]
        # in contact: p_u = -1/eps, p_dn = 1, f_u = -theta, f_dn = theta eps - theta eps = 0;
        # separated: only the consistency term -theta eps flux(u), f_dn = -theta eps
        return (np.where(branch, -1.0 / eps, 0.0), np.where(branch, 1.0, 0.0),
                np.where(branch, -self.theta, 0.0), np.where(branch, 0.0, -self.theta * eps))


@dataclass(frozen=True)
class Penalty:
    """The penalty law (P), eps = epsilon0 h / M at each Gauss point (M the physics' modulus);
    ``degree`` as for ``Nitsche``."""

    epsilon0: float = 0.05
    degree: int | None = None

    def __post_init__(self):
        _positive("epsilon0", self.epsilon0)

    def eps(self, at) -> np.ndarray:
        return self.epsilon0 * at.h / at.modulus * degree_scale(self.degree, at)

    def branch(self, at) -> np.ndarray:
        return at.gap - at.u > 0

    def term(self, at, branch):
        return np.where(branch, (at.gap - at.u) / self.eps(at), 0.0), 0.0

    def derivative(self, at, branch):
        return np.where(branch, -1.0 / self.eps(at), 0.0), 0.0, 0.0, 0.0
