"""The contact law of a weak contact method: the method protocol's second level
(``harness.methods.ContactLawMethod``), solved by the harness's semismooth Newton method on its
system (``fem.contact_laws.system``). The built-in penalty and Nitsche methods are such laws
(``fem.contact_laws.builtin``).

The law. At each Gauss point of Gamma_C (``fem.contact_quadrature``: edges in 2D, triangles in 3D)
the law sees the state ``GammaPoints`` -- the contact variable c(u_h) and its flux, the obstacle
alpha, the contact load g_C, the cell size h, the point -- and returns two terms, a pressure p
and a flux term f, which enter the discrete system as

    F(u) = A u - b - int_{Gamma_C} p c(v) + int_{Gamma_C} f flux(v) = 0      for all v in X_h,

i.e. F(u) = A u - b - T^T W p + N^T W f with T, N the rows of c and of its flux at the points
and W the weights. One law serves every physics, because each is written on its contact
variable (``problem.physics``): c = u, flux = d_n u for the scalar problem (u >= alpha,
lambda = d_n u - g_C >= 0); c = -u . n, flux = -sigma_n(u) for frictionless elasticity (u . n <=
g reads c >= alpha = -g, and the pressure -sigma_n(u) + g_n = flux - g_C with g_C = -g_n),
where -int p c(v) = int p v_n and sigma_t = 0 stays natural.

A law has two branches per point, told by ``branch`` (True: "in contact"), and on each branch
its terms are affine in (c, flux) (``fem.contact_laws.system`` says why):

    p = p0 + p_u c + p_dn flux,      f = f0 + f_u c + f_dn flux,

``derivative`` returning (p_u, p_dn, f_u, f_dn) of the given branch.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Protocol, runtime_checkable

import numpy as np


@dataclass(frozen=True)
class GammaPoints:
    """The state a contact law sees at the Gauss points of Gamma_C, each an array (q,), on the
    contact variable of the case's physics (the module's note): the contact condition is
    ``u >= gap``, the pressure ``dn - load >= 0``, their product zero. Scalar problem: u_h,
    d_n u_h, alpha, g_C. Elasticity: -u_h . n, -sigma_n(u_h), -g, -g_n; the views
    ``normal_displacement``, ``normal_stress``, ``initial_gap`` and ``normal_load`` give u_h . n,
    sigma_n(u_h), g and g_n for a law written in elasticity's own terms (its derivative is still taken with
    respect to ``u`` and ``dn``: d/du = -d/du_n, d/ddn = -d/dsigma_n)."""

    u: np.ndarray       # the contact variable c(u_h): u_h, or -u_h . n
    dn: np.ndarray      # its flux: d_n u_h, or -sigma_n(u_h) (n the outward normal)
    gap: np.ndarray     # its obstacle: alpha, or -g (u_h . n <= g)
    load: np.ndarray    # g_C, the contact load (the pressure is dn - load; zero in the paper), or -g_n
    h: np.ndarray       # the size of the point's contact cell (edge in 2D, triangle in 3D)
    x: np.ndarray       # (q, dim) the points
    physics: str = "scalar"     # ``problem.physics.Scalar.name``: "scalar" or "elasticity"
    # the stiffness scale of the flux: 1 for the scalar problem, lambda + 2 mu in elasticity
    # (``physics.modulus``); a weak method's eps ~ h / modulus keeps its parameter's range
    # independent of the material (``fem.contact_laws.builtin``)
    modulus: float = 1.0
    # (q,) the polynomial degree of each point's cell: k of P_k, or its element's on an hp mesh
    # (``mesh.hp``), where a law's eps scales like h / k^2 (``fem.contact_laws.builtin.Nitsche``); None: not known
    degree: np.ndarray | None = None

    @property
    def normal_displacement(self) -> np.ndarray:
        """u_h . n (elasticity)."""
        return -self.u

    @property
    def normal_stress(self) -> np.ndarray:
        """sigma_n(u_h) = n . sigma(u_h) n (elasticity; compression negative)."""
        return -self.dn

    @property
    def initial_gap(self) -> np.ndarray:
        """g of u_h . n <= g (elasticity)."""
        return -self.gap

    @property
    def normal_load(self) -> np.ndarray:
        """g_n = g_C . n, the normal part of a manufactured contact traction (elasticity; zero
        in a physical problem): the contact pressure is -(sigma_n(u_h) - g_n)."""
        return -self.load


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


# Friction laws: the same protocol on more than one variable per point


@dataclass(frozen=True)
class FrictionPoints:
    """The state a friction law sees at the Gauss points of Gamma_C (``problem.friction``): m
    *channels* per point, each a variable c_j(u_h) with its flux, its load and so its force
    lambda_j = flux_j - load_j, written as the frictionless contact variable is (``GammaPoints``),
    so that Green's formula reads a(u, v) - L(v) = sum_j int_{Gamma_C} lambda_j(u) c_j(v). The
    first ``tangential`` channels are the slip and the friction force:

    * scalar model: the slip u_h itself and lambda = d_n u_h - g_C (one channel, no normal one);
    * 2D elasticity: u_h . tau and sigma_t(u_h) = tau . sigma(u_h) n - tau . g_C, tau = (-n_y, n_x),
      then the normal channel of ``GammaPoints`` (-u_h . n, -sigma_n(u_h), obstacle -g, load -g_n);
    * 3D elasticity: the 2-vector (u_h . tau_1, u_h . tau_2) and its traction on an orthonormal
      tangent frame of each point (``fem.contact_laws.channels.tangent_frames``), then the normal
      channel.

    Tresca's conditions on the friction force lambda_t (a vector of the ``tangential`` first
    channels): |lambda_t| <= s, lambda_t = -s u_t / |u_t| where u_t != 0; Coulomb's put
    s = mu_F lambda_n (``coefficient``) and the unilateral conditions on the normal channel. Over
    a load step (``problem.friction.LoadHistory``) the slip channels hold the slip of the step,
    u_t less the previous step's (``fem.contact_laws.channels.FrictionSystem``)."""

    u: np.ndarray           # (q, m) the channels' variables
    dn: np.ndarray          # (q, m) their fluxes
    gap: np.ndarray         # (q,) the normal channel's obstacle (-g; zeros without a normal channel)
    load: np.ndarray        # (q, m) the channels' loads
    threshold: np.ndarray   # (q,) Tresca's s (zeros for Coulomb's, whose threshold is mu_F times the pressure)
    h: np.ndarray           # (q,) the size of the point's contact cell
    x: np.ndarray           # (q, dim) the points
    tangential: int = 1     # the slip's components (1, or 2 in 3D elasticity)
    physics: str = "scalar"
    modulus: float = 1.0    # the flux's stiffness scale (``GammaPoints.modulus``)
    degree: np.ndarray | None = None    # (q,) the degree of each point's cell, or None
    # (q,) Coulomb's friction coefficient mu_F (``problem.friction.Coulomb``); None for Tresca
    coefficient: np.ndarray | None = None
    # the stiffness scale of the slip channels' flux: 2 mu in elasticity (sigma_t = mu (d_n u_t +
    # d_t u_n) carries no lambda), ``modulus`` where not given
    shear_modulus: float | None = None

    @property
    def slip_modulus(self) -> float:
        """The slip channels' stiffness scale: ``shear_modulus``, else ``modulus``."""
        return self.modulus if self.shear_modulus is None else self.shear_modulus

    @property
    def slip(self) -> np.ndarray:
        """(q, tangential) u_t: the slip (the scalar model's u_h)."""
        return self.u[:, :self.tangential]

    @property
    def friction_force(self) -> np.ndarray:
        """(q, tangential) lambda_t = flux - load of the slip channels (d_n u - g_C; sigma_t - g_t)."""
        return self.dn[:, :self.tangential] - self.load[:, :self.tangential]

    @property
    def normal(self) -> GammaPoints | None:
        """The normal channel as a frictionless law sees it (``GammaPoints``), or None (scalar
        model): what a normal condition -- bilateral here, unilateral with Coulomb's threshold
        mu_F [-sigma_n]_+ next -- is written on."""
        if self.u.shape[1] == self.tangential:
            return None
        return GammaPoints(self.u[:, -1], self.dn[:, -1], self.gap, self.load[:, -1], self.h, self.x, self.physics,
                           self.modulus, self.degree)


@runtime_checkable
class FrictionLaw(Protocol):
    """A friction law (``FrictionPoints``): any number of branches per point, each an integer
    code of ``branches`` (0: the stiff one, "stick", by convention), and on each branch a
    pressure p and a flux term f per channel, entering F(u) = A u - b - sum_j int p_j c_j(v) +
    sum_j int f_j flux_j(v). Its terms need not be affine on a branch (the projection onto the
    disc is not); ``derivative`` is their derivative at the state, with respect to every channel.
    ``friction`` names the law of ``problem.friction`` it discretises ("tresca")."""

    friction: str
    branches: tuple

    def branch(self, at: FrictionPoints) -> np.ndarray:
        """(q,) int: the branch code of the state ``at`` at each point."""

    def term(self, at: FrictionPoints, branch: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(p, f), each (q, m): the formula of ``branch`` evaluated at ``at`` (whether or not
        ``at`` lies in it)."""

    def derivative(self, at: FrictionPoints, branch: np.ndarray) -> tuple:
        """(p_u, p_dn, f_u, f_dn), each (q, m, m): d p_j / d u_k and so on, of ``branch`` at ``at``."""
