"""Binding contact meeting Gamma_g at interior angle 3 pi/4: u ~ r^{2/3} (Thm 4.2 i, 5.2 i).

Omega is the pentagon (0,0), (1/2,0), (1,0), (1,1), (-1,1); Gamma_C = [0, 1] x {0}, Gamma_g
the right side and the ray from (0,0) to (-1,1) (angle omega = 3 pi/4 with Gamma_C), Gamma_u
the top. At 0 the binding contact (u = 0) meets the Neumann ray: a mixed Dirichlet-Neumann
corner with leading exponent pi/(2 omega) = 2/3 (docs/mathematics.md §4):
    u_s = -r^{2/3} sin(2 theta/3):  harmonic, u_s = 0, du_s/dn = (2/3) r^{-1/3} > 0 on
    Gamma_C, du_s/dn = 0 on the ray theta = 3 pi/4 (cos(pi/2) = 0).
A transition singularity at x = 1/2 (binding left, free right) adds one transition point, so
Theorems 4.2 i / 5.2 i apply; on the free part a contact load g_C = (2/3) r^{-1/3} balances
the flux of u_s, as in corner-r12. D u_s ~ r^{-1/3}: u in H^{1 + 2/3 - eps}, nu = 5/3, rate 2/3.
"""
from ngsolve import IfPos, sin, x

from harness.problem import polar, polygon, transition

name = "wedge-r23"
description = "binding contact meets Gamma_g at angle 3pi/4 (r^{2/3}), transition at x = 1/2"
regime = "3/2 < nu < 2"
theorem = "4.2 i, 5.2 i"
groups = ["paper"]            # one scalar case per regime of the paper's theorems (--case paper)
nu = 5 / 3
expected_rate = 2 / 3

geometry = polygon(
    [(0, 0), (0.5, 0), (1, 0), (1, 1), (-1, 1)],
    ["contact", "contact", "neumann", "dirichlet", "neumann"],
)
maxh = 0.25

r, theta = polar()
u = -(r ** (2 / 3)) * sin(2 * theta / 3) + transition(0.5, binding_side="left")
f = 0                                     # both terms are harmonic
singular_points = [(0.0, 0.0), (0.5, 0.0)]  # the junction, the transition point
# On the free part x > 1/2 the load g_C takes over the pressure (2/3) r^{-1/3} of u_s, so that
# du/dn - g_C = 0 there: the contact-load generalisation of (2.4) (docs/mathematics.md §1).
contact_load = IfPos(x - 0.5, (2 / 3) * x ** (-1 / 3), 0.0)

# Asymptotic by six P2 levels: a seventh moves no method's fitted H1 rate by more than 0.01
# (the rule of asymptotic_levels) nor any verdict, so the default report stops at six.
asymptotic_levels = 6
