"""Weak methods of your own, given by their contact law on Γ_C (the method protocol's second
level, ``harness.methods.ContactLawMethod``): at each Gauss point the law returns a pressure p
and a flux term f, affine in the contact variable and its flux on each of its two branches, and
their slopes; the harness assembles F(u) = A u − b − ∫ p c(v) + ∫ f flux(v) and solves F(u_h) = 0
exactly with its semismooth Newton method (multigrid CG when the Jacobian is symmetric),
residual recorded. A law runs on the scalar problem (c = u, flux = ∂ₙu) and on elasticity
(c = −u·n, flux = −σₙ(u)), in 2D and 3D: ``at`` gives both readings.

- ``nitsche-law``: Nitsche's method for frictionless elastic contact (θ = 1, γ = γ₀h/(λ + 2μ)), written
  in elasticity's own terms as Chouly, Hild & Renard, Math. Comp. 84 (2015), eq. (10) state it:
  the bracket [u_n − g − γ(σ_n(u) − g_n)]₊. It is the built-in ``nitsche`` and gives its rows to
  round-off on elastic and scalar cases alike: the check that the protocol adds nothing of its own.
- ``penalty-h2``: the penalty method with ε = ε₀h² instead of ε₀h. The penalty method is not
  consistent: in contact u_h sits about ελ below the obstacle. With ε ∝ h that error is O(h) in
  H¹ whatever the degree (Gustafsson & Stenberg 2025); with ε ∝ h² it is O(h^{3/2}) or better,
  at the price of a stiffer system. No theorem states its rate: it declares none ("no theory",
  grey in the verdict matrix) and the study measures it.

Run them::

    python -m harness run --case elastic-transition-r32 --method examples/methods/contact_laws.py --method nitsche --levels 4
    python -m harness run --case transition-r32 --method "examples/methods/contact_laws.py:penalty_h2" --levels 4
"""
from dataclasses import dataclass

import numpy as np

from harness.methods import ContactLawMethod


@dataclass(frozen=True)
class ElasticNitsche:
    """p = [P]₊/γ, f = θ([P]₊ + γ(σ_n − g_n)), P = u_n − g − γ(σ_n − g_n), γ = γ₀h/M
    (M = λ + 2μ, ``at.modulus``; 1 for the scalar problem)."""

    gamma0: float = 0.05
    theta: float = 1.0

    def bracket(self, at):
        gamma = self.gamma0 * at.h / at.modulus
        return at.normal_displacement - at.initial_gap - gamma * (at.normal_stress - at.normal_load), gamma

    def branch(self, at):
        return self.bracket(at)[0] > 0

    def term(self, at, branch):
        P, gamma = self.bracket(at)
        positive = np.where(branch, P, 0.0)
        return positive / gamma, self.theta * (positive + gamma * (at.normal_stress - at.normal_load))

    def derivative(self, at, branch):
        # slopes in (at.u, at.dn) = (-u_n, -sigma_n): dP/du = -1, dP/ddn = gamma, so in contact
        # p_u = -1/gamma, p_dn = 1, f_u = -theta, f_dn = theta gamma - theta gamma = 0; separated,
        # f = -theta gamma dn alone
        gamma = self.bracket(at)[1]
        return (np.where(branch, -1.0 / gamma, 0.0), np.where(branch, 1.0, 0.0),
                np.where(branch, -self.theta, 0.0), np.where(branch, 0.0, -self.theta * gamma))


@dataclass(frozen=True)
class PenaltyH2:
    """p = (1/ε)[α − u]₊, f = 0, ε = ε₀h²."""

    epsilon0: float = 0.05

    def branch(self, at):
        return at.gap - at.u > 0

    def term(self, at, branch):
        return np.where(branch, (at.gap - at.u) / (self.epsilon0 * at.h**2), 0.0), 0.0

    def derivative(self, at, branch):
        return np.where(branch, -1.0 / (self.epsilon0 * at.h**2), 0.0), 0.0, 0.0, 0.0


def nitsche_theorem(case):
    from harness.methods import METHODS
    return METHODS["nitsche"].expected(case)            # the built-in Nitsche's theory


nitsche_law = ContactLawMethod(
    name="nitsche-law", order=2, contact="Nitsche (θ = 1, γ = γ₀h/M), CHR 2015 eq. (10) as a contact law",
    reference="examples/methods/contact_laws.py", expected=nitsche_theorem, law=ElasticNitsche())

penalty_h2 = ContactLawMethod(
    name="penalty-h2", order=2, contact="penalty (1/ε)[α − u]₊, ε = ε₀h²",
    reference="examples/methods/contact_laws.py", expected=None, law=PenaltyH2())

methods = [nitsche_law, penalty_h2]
