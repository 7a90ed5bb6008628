"""Binding contact running into Gamma_g at a straight junction: u ~ r^{1/2} (Thm 4.1 i, 5.1 i).

Omega = (-1, 1) x (0, 1). Bottom: Gamma_g on (-1, 0), Gamma_C on (0, 1); sides Gamma_g,
top Gamma_u. At the junction 0 the contact is binding (u = 0, Dirichlet-like) and the
bottom turns Neumann: a mixed Dirichlet-Neumann point of interior angle omega = pi, leading
exponent pi/(2 omega) = 1/2 (docs/mathematics.md §4):
    u_s = -r^{1/2} sin(theta/2):  harmonic, u_s = 0 and du_s/dn = r^{-1/2}/2 > 0 on Gamma_C,
    du_s/dn = 0 on the Neumann bottom (theta = pi).
A transition singularity at x = 1/2 (binding on its left, free on its right) gives Gamma_C a
free part, where u = (x - 1/2)^{3/2} > 0 and a contact load g_C = r^{-1/2}/2 balances the
flux of u_s, so du/dn - g_C = 0 there. One transition point; f = 0.
Regularity: D u_s ~ r^{-1/2} is in H^s for s < 1/2 only, so u in H^{3/2 - eps}: nu = 3/2 and
the theorems give ||u - u_h||_1 <= C h^{1/2}; g = du/dn is smooth on Gamma_g.
"""
from ngsolve import IfPos, sin, x

from harness.problem import polar, polygon, transition

name = "corner-r12"
description = "binding contact meets Gamma_g at a straight junction (r^{1/2}), transition at x = 1/2"
regime = "1 < nu <= 3/2"
theorem = "4.1 i, 5.1 i"
groups = ["paper"]            # one scalar case per regime of the paper's theorems (--case paper)
nu = 1.5
expected_rate = 0.5

geometry = polygon(
    [(-1, 0), (0, 0), (0.5, 0), (1, 0), (1, 1), (-1, 1)],
    ["neumann", "contact", "contact", "neumann", "dirichlet", "neumann"],
)
maxh = 0.25

r, theta = polar()
u = -(r ** 0.5) * sin(theta / 2) + transition(0.5, binding_side="left")
f = 0                                     # both terms are harmonic
singular_points = [(0.0, 0.0), (0.5, 0.0)]  # the junction, the transition point
# On the free part x > 1/2 the load g_C takes over the pressure r^{-1/2}/2 of u_s, so that
# du/dn - g_C = 0 there: the contact-load generalisation of (2.4) (docs/mathematics.md §1).
contact_load = IfPos(x - 0.5, 0.5 * x ** (-0.5), 0.0)

# Asymptotic by six P2 levels: a seventh moves no method's fitted H1 rate by more than 0.01
# (the rule of asymptotic_levels) nor any verdict, so the default report stops at six.
asymptotic_levels = 6

# P1 runs one level past P2 by default (to P2's finest number of dofs); that level moves no P1
# method's fitted H1 rate by more than 0.01 nor any verdict, so the default report stops P1
# with P2.
asymptotic_levels_p1 = 6
