"""The built-in Coulomb laws: Nitsche's method and the penalty method for Coulomb friction
(``problem.friction.Coulomb``), as friction laws of the method protocol's second level
(``fem.contact_laws.protocol.FrictionLaw``), in 2D and 3D elasticity.

Coulomb's conditions couple the two channels of a point (``protocol.FrictionPoints``): the
normal one is the frictionless contact variable (c = -u . n >= alpha, the pressure lambda_n =
flux_n - load_n >= 0, complementarity) and the tangential one Tresca's with the threshold
s = mu_F lambda_n. As for Tresca (``tresca``'s note), both are projections, for every gamma > 0:

    lambda_n = [x_n]_+,                 x_n = lambda_n - (c - alpha) / gamma,
    lambda_t = P_{mu_F [x_n]_+}(x_t),   x_t = lambda_t - w_t / gamma,                     (*)

w_t the slip over the load step (u_t less the previous step's, ``channels.FrictionSystem``).

Nitsche (F. Chouly, P. Hild, V. Lleras & Y. Renard, Nitsche method for contact with Coulomb
friction: existence results for the static and dynamic finite element formulations, J. Comput.
Appl. Math. (2022); its statements were not available to read here, docs/theory/coulomb.md; the
form below is GetFEM's documented Nitsche friction term in the harness's channels): put (*) into the
first term of the theta-family, as for the frictionless law (``builtin.Nitsche``) and Tresca's
(``tresca.NitscheTresca``), on both channels:

    p_n = [x_n]_+,  p_t = P_{mu_F p_n}(x_t),  f = theta gamma (p - lambda),   gamma = gamma0 h / M.

Penalty: p_n = [(alpha - c)/eps]_+, p_t = P_{mu_F p_n}(-w_t / eps), f = 0 (the regularised
Coulomb law of Oden & Martins, CMAME 52 (1985), as a penalty of both channels).

The scales. gamma (eps) is gamma0 h / M_j per channel j, M_j the stiffness of the channel's flux:
lambda + 2 mu for the normal one (the frictionless law's), 2 mu for the slip ones -- the
tangential traction mu (d_n u_t + d_t u_n) carries no lambda, and the coercivity bound of theta = 1
asks gamma_t |sigma_t(v)|^2 <~ a(v, v) of it alone. One gamma0 h/(lambda + 2 mu) for both, as the
Tresca laws have, makes the slip channel (lambda + 2 mu)/(2 mu) times stiffer than it needs to be:
on the near-incompressible Cattaneo cases (nu = 0.49: 25 times) the stick slab |w_t| <~ gamma |lambda_t|
shrinks toward round-off and semismooth Newton stalled on every level; with 2 mu it converges in
7 steps per level (measured; docs/theory/coulomb.md).

The branches of a point: SEPARATED (x_n <= 0: p = 0 on both channels), and in contact STICK
(|x_t| <= mu_F x_n), SLIP (2D elasticity: x_t > mu_F x_n; 3D: |x_t| > mu_F x_n) and SLIP_BELOW
(2D: x_t < -mu_F x_n). On SLIP the threshold moves with the normal channel:
d p_t / d x_n = mu_F x_t / |x_t|, an entry of the Jacobian's tangential rows in the normal
column with nothing to balance it in the normal rows (d p_n / d x_t = 0): the Jacobian is not
symmetric for any theta (theta = 1 included) as soon as a point slips, and Newton's linear
solves go to GMRES (``solvers.newton``). In 2D every branch is affine (p_t = +-mu_F x_n on the
slip branches): semismooth Newton ends in finitely many steps once the branches settle; in 3D
the slip branch is not affine (s x_t/|x_t|) and Newton relinearises.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .builtin import THETAS, Nitsche, Penalty, _positive, degree_scale
from .protocol import FrictionPoints, LawError
from .tresca import SLIP, SLIP_BELOW, STICK, ball_branch, ball_jacobian, ball_projection

SEPARATED = 3       # the branch where the normal channel is not in contact: no force on either channel


def _check_channels(at: FrictionPoints) -> None:
    if at.u.shape[1] != at.tangential + 1:
        raise LawError("a Coulomb law needs the slip channel(s) and the normal channel (elasticity)")


def threshold(at: FrictionPoints, x_n: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(s, ds/dx_n) at the points on a contact branch (the projection and its Jacobian set both
    to zero where SEPARATED): Coulomb's mu_F x_n (``at.coefficient``; x_n > 0 in contact), or,
    without a coefficient, Tresca's given s (``at.threshold``: the frozen threshold of the fixed
    point over Tresca problems, ``solvers.coulomb_fixed_point``), whose slope is 0. Affine in
    x_n on every branch, as the law's check asks (``channels.check_friction_law``)."""
    if at.coefficient is None:
        return at.threshold, np.zeros_like(x_n)
    return at.coefficient * x_n, at.coefficient


def coulomb_branch(x_t: np.ndarray, x_n: np.ndarray, s: np.ndarray) -> np.ndarray:
    """(q,) the branch of (*) at the arguments x_t (q, t) and x_n (q,), threshold s (q,)."""
    return np.where(x_n > 0, ball_branch(x_t, np.maximum(s, 0.0)), SEPARATED)


def coulomb_projection(x_t: np.ndarray, x_n: np.ndarray, s: np.ndarray, branch: np.ndarray) -> np.ndarray:
    """(q, t + 1): (P_s(x_t), p_n) by the formulas of ``branch``, p_n = x_n in contact; both 0
    where SEPARATED (the threshold 0 makes P_0 = 0 on the slip formula)."""
    contact = branch != SEPARATED
    p_n = np.where(contact, x_n, 0.0)
    p_t = ball_projection(x_t, np.where(contact, s, 0.0), np.where(contact, branch, SLIP))
    return np.column_stack([p_t, p_n])


def coulomb_jacobian(x_t: np.ndarray, x_n: np.ndarray, s: np.ndarray, ds: np.ndarray, branch: np.ndarray) -> np.ndarray:
    """(q, t + 1, t + 1) the derivative of ``coulomb_projection`` with respect to (x_t, x_n) on
    ``branch``: the ball's Jacobian in the tangential block, the threshold's slope
    ds/dx_n x_t/|x_t| (1D: +-ds) in the tangential rows' normal column on a slip branch, 1 on
    the normal diagonal in contact; zero where SEPARATED."""
    q, t = x_t.shape
    contact = branch != SEPARATED
    D = np.zeros((q, t + 1, t + 1))
    D[:, :t, :t] = ball_jacobian(x_t, np.where(contact, s, 0.0), np.where(contact, branch, SLIP))
    ds = np.where(contact, ds, 0.0) * np.ones(q)
    if t == 1:
        slope = np.select([branch == SLIP, branch == SLIP_BELOW], [ds, -ds], 0.0)[:, None]
    else:
        norm = np.linalg.norm(x_t, axis=1)
        # (the disc has one slip branch: SLIP_BELOW, a 1D code, takes its formula, as in
        # ``tresca``); at x_t = 0 the direction x_t/|x_t| has no value: 0, as ``tresca.ball_jacobian``
        slip = contact & (branch != STICK) & (norm > 0)
        slope = np.where(slip[:, None], np.divide(ds, norm, out=np.zeros(q), where=slip)[:, None] * x_t, 0.0)
    D[:, :t, t] = slope
    D[:, t, t] = contact
    return D


def channel_scales(parameter: float, degree: int | None, at: FrictionPoints) -> np.ndarray:
    """(q, m) parameter h / M_j per channel j: M the slip channels' stiffness scale 2 mu
    (``FrictionPoints.slip_modulus``), then the normal channel's lambda + 2 mu (``modulus``),
    scaled by the degree on an hp mesh (``builtin.degree_scale``)."""
    base = parameter * at.h * degree_scale(degree, at)
    t = at.tangential
    return np.column_stack([np.repeat((base / at.slip_modulus)[:, None], t, axis=1), base / at.modulus])


def _blocks(D: np.ndarray, du: np.ndarray, ddn: np.ndarray, flux_scale: np.ndarray | None):
    """(p_u, p_dn, f_u, f_dn) from D = dp/dx and the arguments' slopes per channel (q, m):
    dx_k/du_k = ``du``, dx_k/d(flux_k) = ``ddn``; f_j = flux_scale_j (p_j - lambda_j) (None: f = 0)."""
    p_u, p_dn = D * du[:, None, :], D * ddn[:, None, :]
    if flux_scale is None:
        zero = np.zeros_like(D)
        return p_u, p_dn, zero, zero
    g = flux_scale[:, :, None]
    return p_u, p_dn, g * p_u, g * (p_dn - np.eye(D.shape[1]))


class _CoulombProjection:
    """What the Coulomb laws share: the branch and the projection (*) at their ``arguments``."""

    friction = "coulomb"
    branches = (STICK, SLIP, SLIP_BELOW, SEPARATED)

    def branch(self, at: FrictionPoints) -> np.ndarray:
        _check_channels(at)
        x_t, x_n, _ = self.arguments(at)
        return coulomb_branch(x_t, x_n, threshold(at, x_n)[0])

    def projected(self, at: FrictionPoints, branch: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(p, the channels' scales): the projection (*) on ``branch``."""
        _check_channels(at)
        x_t, x_n, scale = self.arguments(at)
        return coulomb_projection(x_t, x_n, threshold(at, x_n)[0], branch), scale

    def jacobian(self, at: FrictionPoints, branch: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(dp/dx, the channels' scales) on ``branch``."""
        x_t, x_n, scale = self.arguments(at)
        return coulomb_jacobian(x_t, x_n, *threshold(at, x_n), branch), scale


@dataclass(frozen=True)
class NitscheCoulomb(_CoulombProjection):
    """Nitsche's law for Coulomb friction (the module's note), gamma = gamma0 h / M (``degree``
    as for ``builtin.Nitsche``), variant theta in (1, 0, -1)."""

    gamma0: float = 0.05
    theta: float = 1.0
    degree: int | None = None

    def __post_init__(self):
        _positive("gamma0", self.gamma0)
        if self.theta not in THETAS:
            raise ValueError(f"theta must be 1, 0 or -1, got {self.theta}")

    @classmethod
    def of(cls, law: Nitsche) -> "NitscheCoulomb":
        """The Coulomb law of the frictionless ``law``: its gamma0, theta and degree."""
        return cls(law.gamma0, law.theta, law.degree)

    def gammas(self, at: FrictionPoints) -> np.ndarray:
        """(q, m) gamma of each channel: gamma0 h / M_j, M_j the channel's stiffness scale (the
        module's note on the scales)."""
        return channel_scales(self.gamma0, self.degree, at)

    def arguments(self, at: FrictionPoints) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(x_t, x_n, gamma (q, m)) of (*)."""
        gamma = self.gammas(at)
        x = (at.dn - at.load) - (at.u - np.column_stack([np.zeros((len(at.h), at.tangential)), at.gap])) / gamma
        return x[:, :at.tangential], x[:, at.tangential], gamma

    def term(self, at: FrictionPoints, branch: np.ndarray):
        p, gamma = self.projected(at, branch)
        return p, self.theta * gamma * (p - (at.dn - at.load))

    def derivative(self, at: FrictionPoints, branch: np.ndarray):
        D, gamma = self.jacobian(at, branch)
        # dx_j/du_j = -1/gamma_j, dx_j/d(flux_j) = 1; f = theta gamma (p - lambda), channel by channel
        return _blocks(D, -1.0 / gamma, np.ones_like(gamma), self.theta * gamma)


@dataclass(frozen=True)
class PenaltyCoulomb(_CoulombProjection):
    """The penalty law for Coulomb friction (the module's note), eps = epsilon0 h / M
    (``degree`` as for ``builtin.Penalty``)."""

    epsilon0: float = 0.05
    degree: int | None = None

    def __post_init__(self):
        _positive("epsilon0", self.epsilon0)

    @classmethod
    def of(cls, law: Penalty) -> "PenaltyCoulomb":
        """The Coulomb law of the frictionless ``law``: its epsilon0 and degree."""
        return cls(law.epsilon0, law.degree)

    def arguments(self, at: FrictionPoints) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(x_t, x_n, eps (q, m)): -w_t/eps_t and (alpha - c)/eps_n, eps_j = epsilon0 h / M_j."""
        eps = channel_scales(self.epsilon0, self.degree, at)
        x = -(at.u - np.column_stack([np.zeros((len(at.h), at.tangential)), at.gap])) / eps
        return x[:, :at.tangential], x[:, at.tangential], eps

    def term(self, at: FrictionPoints, branch: np.ndarray):
        p, _ = self.projected(at, branch)
        return p, np.zeros_like(p)

    def derivative(self, at: FrictionPoints, branch: np.ndarray):
        D, eps = self.jacobian(at, branch)
        return _blocks(D, -1.0 / eps, np.zeros_like(eps), None)
