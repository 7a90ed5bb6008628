"""Tresca friction (scalar): a stick zone running into Gamma_g at a straight junction, u ~ r^{1/2}.

The friction analogue of corner-r12. The scalar Tresca problem (``harness.problem.friction``)
on Omega = (-1, 1) x (0, 1); bottom: Gamma_g on (-1, 0), Gamma_C on (0, 1) (n = -e_y); sides
Gamma_g, top Gamma_u; threshold s = 1 and a contact load g_C, so that on Gamma_C
|d_n u - g_C| <= s and d_n u - g_C = -s u/|u| where u != 0. Polar coordinates (r0, theta0)
about 0 and (r1, theta1) about 1/2, both theta in [0, pi] from the positive x-direction:
    u = s y + u_s + c r1^{3/2} cos(3 theta1/2),   u_s = -r0^{1/2} sin(theta0/2),   c = 1.
At the junction 0 the stick zone (u = 0: Dirichlet-like) meets the Neumann bottom: a mixed
Dirichlet-Neumann point of angle pi, leading exponent 1/2 (docs/mathematics.md §4). u_s is
harmonic, u_s = 0 on Gamma_C, d_n u_s = r0^{-1/2}/2 there (unbounded: the friction bound needs
g_C to carry it) and d_n u_s = 0 on theta0 = pi (the Neumann bottom). So
    g_C = x^{-1/2}/2 on all of Gamma_C,
and d_n u - g_C = -s + d_n(c r1^{3/2} cos(3 theta1/2)) is tresca-r32's friction force about 1/2:
  1/2 < x < 1 (theta1 = 0):  u = c (x - 1/2)^{3/2} > 0, d_n u - g_C = -s                     -- slip;
  0 < x < 1/2 (theta1 = pi): u = 0, d_n u - g_C = -s + (3/2) c (1/2 - x)^{1/2} in [-1, 0.061] -- stick
(any 0 < c <= 4 s / (3 (1/2)^{1/2}) works). f = 0 (every term harmonic or linear); the
Neumann data on Gamma_g are derived (the r^{3/2} term's flux on (-1, 0) is smooth there).
Regularity: D u_s ~ r0^{-1/2}, u in H^{3/2 - eps}: nu = 3/2, the friction analogue of
Theorems 4.1 i, 5.1 i, ||u - u_h||_1 <= C h^{1/2}. tests/test_tresca_exact.py checks the
conditions with SymPy on both sides of 1/2.
"""
from ngsolve import IfPos, cos, sin, sqrt, x

from harness.problem import Tresca, polar, polygon

name = "tresca-corner-r12"
description = "Tresca friction: stick zone meets Gamma_g at a straight junction (r^{1/2}), stick-slip point at x = 1/2"
regime = "1 < nu <= 3/2"
theorem = "friction analogue of 4.1 i, 5.1 i"
nu = 1.5
expected_rate = 0.5

s, c = 1.0, 1.0
friction = Tresca(threshold=s)

geometry = polygon(
    [(-1, 0), (0, 0), (0.5, 0), (1, 0), (1, 1), (-1, 1)],
    ["neumann", "contact", "contact", "neumann", "dirichlet", "neumann"],
)
maxh = 0.25

r0, theta0 = polar(0.0)
r1, theta1 = polar(0.5)
u = s * (r0 * sin(theta0)) - sqrt(r0) * sin(theta0 / 2) + c * r1 ** 1.5 * cos(1.5 * theta1)
# grad(-Im w^{1/2}) = (1/2) r^{-1/2} (sin(theta/2), -cos(theta/2)); grad Re w^{3/2} = (3/2) r^{1/2} (cos, -sin)(theta/2)
grad_u = (0.5 / sqrt(r0) * sin(theta0 / 2) + 1.5 * c * sqrt(r1) * cos(theta1 / 2),
          s - 0.5 / sqrt(r0) * cos(theta0 / 2) - 1.5 * c * sqrt(r1) * sin(theta1 / 2))
f = 0
singular_points = [(0.0, 0.0), (0.5, 0.0)]   # the junction, the stick-slip point
# g_C takes the flux r0^{-1/2}/2 of u_s on all of Gamma_C (x > 0 there)
contact_load = IfPos(x, 0.5 * x ** (-0.5), 0.0)
