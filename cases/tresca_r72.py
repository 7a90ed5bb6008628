"""Tresca friction (scalar), a smoother stick-slip point: u = s y - beta x_-^3 y + x_+^3.

The scalar Tresca problem (``harness.problem.friction``) on Omega = (-1, 1) x (0, 1),
Gamma_C = bottom (n = -e_y), Gamma_g = sides, Gamma_u = top, with x_+ = max(x, 0),
x_- = max(-x, 0), s = 1, beta = 1 (any 0 < beta < 2 s works) and
f = -Laplace(u) = -6 x_+ + 6 beta x_- y. On Gamma_C:
  x > 0: u = x^3 > 0 and d_n u = -s                            -- slip;
  x < 0: u = 0 and d_n u = -s + beta |x|^3 in [-s, s]           -- stick.
The third derivative of x_+^3 jumps across x = 0: u in H^{7/2 - eps}, nu = 7/2 (MATH.md §11):
P2 can reach h^2, P3 h^{5/2}.
"""
from ngsolve import IfPos, x, y

from harness.problem import Tresca, contact_strip

name = "tresca-r72"
description = "Tresca friction, s y - x_-^3 y + x_+^3: H^{7/2-eps} stick-slip point at 0"
regime = "nu > 5/2"
theorem = "friction analogue of Remark 4.9"
nu = 3.5
expected_rate = 2.0
# the sixth and seventh levels move no fitted H^1 rate (nodal, mean, p1) by more than 0.003
asymptotic_levels = 5

s, beta = 1.0, 1.0
friction = Tresca(threshold=s)

geometry = contact_strip(breaks=[0.0])
maxh = 0.25

x_plus, x_minus = IfPos(x, x, 0.0), IfPos(-x, -x, 0.0)
u = s * y - beta * x_minus ** 3 * y + x_plus ** 3
grad_u = (3 * beta * x_minus ** 2 * y + 3 * x_plus ** 2, s - beta * x_minus ** 3)
f = -6 * x_plus + 6 * beta * x_minus * y
singular_points = []
# D^3 u and D f jump across x = 0, a line inside the elements of no mesh: they are subdivided
derivative_jumps = [((0.0, 0.0), (0.0, 1.0))]
