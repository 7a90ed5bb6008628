"""The built-in Tresca laws: Nitsche's method and the penalty method for Tresca friction
(``problem.friction``), as friction laws of the method protocol's second level
(``fem.contact_laws.protocol.FrictionLaw``), in every physics and dimension.

Tresca's conditions on the friction force lambda_t = flux - load of the slip u_t (scalar model:
lambda = d_n u - g_C, u_t = u; elasticity: sigma_t - g_t and u_t, 2-vectors in 3D),
|lambda_t| <= s and lambda_t = -s u_t / |u_t| where u_t != 0, are equivalent, for every
gamma > 0, to

    lambda_t = P_s(lambda_t - u_t / gamma),     P_s(x) = x if |x| <= s, s x / |x| else,      (*)

P_s the projection onto the disc (in 1D: the interval [-s, s]) of radius s (if u_t = 0:
lambda_t = P_s(lambda_t) is |lambda_t| <= s; else lambda_t - u_t/gamma = -(s + |u_t|/gamma) u_t/|u_t|
projects to -s u_t/|u_t|). Its generalised Jacobian (Clarke's, at |x| != s): I inside ("stick"),
(s / |x|)(I - x x^T / |x|^2) outside ("slip"): zero in 1D, where the slip branch splits into
x > s and x < -s and the law is piecewise affine (finite semismooth Newton); in 2D the slip branch
is not affine, and Newton relinearises at every step (``solvers.newton``).

Nitsche (F. Chouly, J. Math. Anal. Appl. 411 (2014) 329-339, for the scalar model; its statement
was not available to read here: the form below is the frictionless theta-family of
``fem.contact_laws.builtin`` with the projection onto [0, inf) replaced by P_s, as issue 74
describes it). Write v_t = theta gamma flux_t(v) - P_theta(v) and put (*) in the
first term only:

    a(u, v) - L(v) - theta int gamma lambda_t(u) . flux_t(v)
            + int P_s(lambda_t(u) - u_t / gamma) . (theta gamma flux_t(v) - v_t) = 0,           (NT)

gamma = gamma0 h / M at each point, M the physics' modulus, scaled by the degree on an hp mesh
(``builtin.degree_scale``), as the frictionless ``builtin.Nitsche``. As a law: p_t = P_s(x),
f_t = theta gamma (p_t - lambda_t), x = lambda_t - u_t/gamma. theta = 1 is symmetric, the others not.

Penalty (J. Dione, JMAA 2019, read from its abstract only: O(h^{1/2+nu} + eps^{1/2+nu}) in the
H^1 norm for P1, u in H^{3/2+nu}): lambda_t ~ P_s(-u_t / eps), the derivative of a Huber
regularisation of s |u_t|; p_t = P_s(-u_t/eps), f_t = 0, eps = epsilon0 h / M as ``builtin.Penalty``.

Bilateral normal contact in elasticity (u . n = g, here g = 0; ``problem.friction.Tresca``): the
normal channel (c = -u . n, flux -sigma_n, obstacle -g) by the same method, without a sign
condition: Nitsche's linear term p_n = lambda_n - (c - alpha)/gamma, f_n = theta gamma (p_n - lambda_n)
= -theta (c - alpha) (the frictionless (N) without its [.]_+, the same theta and gamma), or the
penalty p_n = (alpha - c)/eps, f_n = 0. Coulomb's law (next) puts s = mu_F [lambda_n]_+ and a
unilateral normal branch into the same law: its p_t then depends on the normal channel's flux,
an off-diagonal entry of ``derivative``, and the Jacobian is not symmetric for any theta
(``channels.check_friction_law`` notices, and Newton factorises).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .builtin import THETAS, Nitsche, Penalty, _positive, degree_scale
from .protocol import FrictionPoints, LawError

STICK, SLIP, SLIP_BELOW = 0, 1, 2     # branch codes: |x| <= s; |x| > s (1D: x > s); 1D: x < -s


def ball_branch(x: np.ndarray, s: np.ndarray) -> np.ndarray:
    """(q,) the branch of P_s at x (q, t): STICK inside the disc, SLIP outside (in 1D SLIP
    above s, SLIP_BELOW below -s)."""
    if x.shape[1] == 1:
        return np.where(x[:, 0] > s, SLIP, np.where(x[:, 0] < -s, SLIP_BELOW, STICK))
    return np.where(np.linalg.norm(x, axis=1) > s, SLIP, STICK)


def ball_projection(x: np.ndarray, s: np.ndarray, branch: np.ndarray) -> np.ndarray:
    """P_s(x) by the formula of ``branch`` (x itself, s x/|x|; in 1D s or -s)."""
    if x.shape[1] == 1:
        return np.select([branch == SLIP, branch == SLIP_BELOW], [s, -s], x[:, 0])[:, None]
    length = np.maximum(np.linalg.norm(x, axis=1), np.finfo(float).tiny)
    return np.where((branch == STICK)[:, None], x, (s / length)[:, None] * x)


def ball_jacobian(x: np.ndarray, s: np.ndarray, branch: np.ndarray) -> np.ndarray:
    """(q, t, t) the derivative of ``ball_projection`` on ``branch``: I on STICK,
    (s/|x|)(I - x x^T/|x|^2) on SLIP (zero in 1D)."""
    q, t = x.shape
    eye = np.broadcast_to(np.eye(t), (q, t, t))
    stick = (branch == STICK)[:, None, None]
    if t == 1:          # the interval's slip branches are the constants +-s: their derivative is 0
        return np.where(stick, eye, 0.0)
    norm = np.linalg.norm(x, axis=1)
    length = np.maximum(norm, np.finfo(float).tiny)
    unit = x / length[:, None]
    # s/|x| only off STICK and where x != 0: a stick point, or a slip branch carried to a point
    # where x = 0 (a nested prediction at the start of a load step), has no value of the slip
    # formula's derivative there; 0 is the derivative of its value s x/|x| = 0 along x = 0
    ratio = np.divide(s, length, out=np.zeros(q), where=(branch != STICK) & (norm > 0))
    slip = ratio[:, None, None] * (eye - unit[:, :, None] * unit[:, None, :])
    return np.where(stick, eye, slip)


def _blocks(q: int, m: int) -> list[np.ndarray]:
    return [np.zeros((q, m, m)) for _ in range(4)]


def _check_channels(at: FrictionPoints) -> None:
    if at.u.shape[1] not in (at.tangential, at.tangential + 1):
        raise LawError(f"a Tresca law has {at.tangential} slip channel(s) and at most one normal one, got {at.u.shape[1]}")


@dataclass(frozen=True)
class NitscheTresca:
    """Nitsche's law (NT) for Tresca friction, gamma = gamma0 h / M (``degree`` as for
    ``builtin.Nitsche``), variant theta in (1, 0, -1); in elasticity Nitsche's bilateral term
    with the same theta and gamma on the normal channel (the module's note)."""

    gamma0: float = 0.05
    theta: float = 1.0
    degree: int | None = None
    friction = "tresca"
    branches = (STICK, SLIP, SLIP_BELOW)

    def __post_init__(self):
        _positive("gamma0", self.gamma0)
        if self.theta not in THETAS:
            raise ValueError(f"theta must be 1, 0 or -1, got {self.theta}")

    @classmethod
    def of(cls, law: Nitsche) -> "NitscheTresca":
        """The Tresca law of the frictionless ``law``: its gamma0, theta and degree."""
        return cls(law.gamma0, law.theta, law.degree)

    def gamma(self, at: FrictionPoints) -> np.ndarray:
        return self.gamma0 * at.h / at.modulus * degree_scale(self.degree, at)

    def argument(self, at: FrictionPoints) -> tuple[np.ndarray, np.ndarray]:
        """(x, gamma): x = lambda_t - u_t / gamma, the argument of P_s."""
        gamma = self.gamma(at)
        return at.friction_force - at.slip / gamma[:, None], gamma

    def branch(self, at: FrictionPoints) -> np.ndarray:
        return ball_branch(self.argument(at)[0], at.threshold)

    def term(self, at: FrictionPoints, branch: np.ndarray):
        _check_channels(at)
        x, gamma = self.argument(at)
        p_t = ball_projection(x, at.threshold, branch)
        p, f = [p_t], [self.theta * gamma[:, None] * (p_t - at.friction_force)]
        normal = at.normal
        if normal is not None:       # Nitsche's bilateral term: lambda_n - (c - alpha)/gamma
            p.append((normal.dn - normal.load - (normal.u - normal.gap) / gamma)[:, None])
            f.append((-self.theta * (normal.u - normal.gap))[:, None])
        return np.concatenate(p, axis=1), np.concatenate(f, axis=1)

    def derivative(self, at: FrictionPoints, branch: np.ndarray):
        x, gamma = self.argument(at)
        t, (q, m) = at.tangential, at.u.shape
        D = ball_jacobian(x, at.threshold, branch)
        g = gamma[:, None, None]
        p_u, p_dn, f_u, f_dn = _blocks(q, m)
        # dx/du_t = -1/gamma, dx/ddn_t = 1: p_t' = D (., .), f_t = theta gamma (p_t - lambda_t)
        p_u[:, :t, :t], p_dn[:, :t, :t] = -D / g, D
        f_u[:, :t, :t], f_dn[:, :t, :t] = -self.theta * D, self.theta * g * (D - np.eye(t))
        if m > t:
            p_u[:, t, t], p_dn[:, t, t], f_u[:, t, t] = -1.0 / gamma, 1.0, -self.theta
        return p_u, p_dn, f_u, f_dn


@dataclass(frozen=True)
class PenaltyTresca:
    """The penalty law for Tresca friction, p_t = P_s(-u_t / eps), eps = epsilon0 h / M
    (``degree`` as for ``builtin.Penalty``); in elasticity the penalty (alpha - c)/eps on the
    normal channel (bilateral)."""

    epsilon0: float = 0.05
    degree: int | None = None
    friction = "tresca"
    branches = (STICK, SLIP, SLIP_BELOW)

    def __post_init__(self):
        _positive("epsilon0", self.epsilon0)

    @classmethod
    def of(cls, law: Penalty) -> "PenaltyTresca":
        """The Tresca law of the frictionless ``law``: its epsilon0 and degree."""
        return cls(law.epsilon0, law.degree)

    def eps(self, at: FrictionPoints) -> np.ndarray:
        return self.epsilon0 * at.h / at.modulus * degree_scale(self.degree, at)

    def branch(self, at: FrictionPoints) -> np.ndarray:
        return ball_branch(-at.slip / self.eps(at)[:, None], at.threshold)

    def term(self, at: FrictionPoints, branch: np.ndarray):
        _check_channels(at)
        eps = self.eps(at)
        p = [ball_projection(-at.slip / eps[:, None], at.threshold, branch)]
        normal = at.normal
        if normal is not None:
            p.append(((normal.gap - normal.u) / eps)[:, None])
        p = np.concatenate(p, axis=1)
        return p, np.zeros_like(p)

    def derivative(self, at: FrictionPoints, branch: np.ndarray):
        eps = self.eps(at)
        t, (q, m) = at.tangential, at.u.shape
        p_u, p_dn, f_u, f_dn = _blocks(q, m)
        p_u[:, :t, :t] = -ball_jacobian(-at.slip / eps[:, None], at.threshold, branch) / eps[:, None, None]
        if m > t:
            p_u[:, t, t] = -1.0 / eps
        return p_u, p_dn, f_u, f_dn
