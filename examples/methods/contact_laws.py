"""Weak methods of your own, given by their contact law on Γ_C (the method protocol's second
level, ``harness.methods.ContactLawMethod``): at each Gauss point the law returns a pressure p
and a flux term f, affine in (u_h, ∂ₙu_h) on each of its two branches, and their slopes; the
harness assembles F(u) = A u − b − ∫ p v + ∫ f ∂ₙv and solves F(u_h) = 0 exactly with its
semismooth Newton method (multigrid CG when the Jacobian is symmetric), residual recorded.

- ``nitsche-law``: Nitsche's method (θ = 1, ε = γ₀h), written as a law. It is the built-in
  ``nitsche`` (Chouly, Hild & Renard, Math. Comp. 84 (2015), eq. (10)) and gives its rows to
  round-off: the check that the protocol adds nothing of its own.
- ``penalty-h2``: the penalty method with ε = ε₀h² instead of ε₀h. The penalty method is not
  consistent: in contact u_h sits about ελ below the obstacle. With ε ∝ h that error is O(h) in
  H¹ whatever the degree (Gustafsson & Stenberg 2025); with ε ∝ h² it is O(h^{3/2}) or better,
  at the price of a stiffer system. No theorem states its rate: it declares none ("no theory",
  grey in the verdict matrix) and the study measures it.

Run them::

    python -m harness run --case transition-r32 --method examples/methods/contact_laws.py --method nitsche --levels 4
    python -m harness run --case transition-r32 --method "examples/methods/contact_laws.py:penalty_h2" --levels 4
"""
from dataclasses import dataclass

import numpy as np

from harness.methods import ContactLawMethod, Expectation


@dataclass(frozen=True)
class Nitsche:
    """p = (1/ε)[P]₊, f = θ([P]₊ − ε(∂ₙu − g_C)), P = ε(∂ₙu − g_C) + α − u, ε = γ₀h."""

    gamma0: float = 0.05
    theta: float = 1.0

    def bracket(self, at):
        eps = self.gamma0 * at.h
        return eps * (at.dn - at.load) + at.gap - at.u, eps

    def branch(self, at):
        return self.bracket(at)[0] > 0

    def term(self, at, branch):
        P, eps = self.bracket(at)
        positive = np.where(branch, P, 0.0)
        return positive / eps, self.theta * (positive - eps * (at.dn - at.load))

    def derivative(self, at, branch):
        eps = self.gamma0 * at.h
        # (p_u, p_dn, f_u, f_dn): on the contact branch p_u = -1/eps, p_dn = 1, f_u = -theta,
        # f_dn = theta eps - theta eps = 0; off it only the consistency term -theta eps d_n u
        return (np.where(branch, -1.0 / eps, 0.0), np.where(branch, 1.0, 0.0),
                np.where(branch, -self.theta, 0.0), np.where(branch, 0.0, -self.theta * eps))


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
    # Chouly, Hild & Renard 2015, Theorem 3.8: h^{nu - 1} up to h^2 for nu > 3/2; nothing below
    if case.nu <= 1.5:
        return Expectation(float("nan"), 0.0, "CHR 2015 Thm 3.8: no result for nu <= 3/2")
    return Expectation(min(case.nu - 1.0, 2.0), 0.0, "Chouly, Hild & Renard 2015, Thm 3.8")


nitsche_law = ContactLawMethod(
    name="nitsche-law", order=2, contact="Nitsche (θ = 1, ε = γ₀h) as a contact law",
    reference="examples/methods/contact_laws.py", expected=nitsche_theorem, law=Nitsche())

penalty_h2 = ContactLawMethod(
    name="penalty-h2", order=2, contact="penalty (1/ε)[α − u]₊, ε = ε₀h²",
    reference="examples/methods/contact_laws.py", expected=None, law=PenaltyH2())

methods = [nitsche_law, penalty_h2]
