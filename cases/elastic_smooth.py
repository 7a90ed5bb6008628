"""A smooth elastic solution with a contact/separation transition (Remark 2.3, 4.9): rate h^2.

Plane strain (E = 1, Poisson 0.3), Omega = (-1, 1) x (0, 1), Gamma_C = bottom (n = -e_y),
Gamma_g = sides, Gamma_u = top (cut by the interior line x = 0, which every mesh follows);
with m(t) = max(0, t),

    u_x = 4 y m(-x)^3 + y^2 sin(x + y),     u_y = m(-x)^4 - y m(x)^3 + y^2 cos(x + y).

By hand, on y = 0: u . n = -u_y = -m(-x)^4 <= 0 (gap alpha = 0). d_y u_x = 4 m(-x)^3 and
d_x u_y = -4 m(-x)^3 cancel: sigma_xy = 0, frictionless without any tangential load.
d_x u_x = 0 and d_y u_y = -m(x)^3 give sigma_yy = -(lambda + 2 mu) m(x)^3: p = (lambda + 2 mu)
m(x)^3 >= 0. So x < 0 is free (u . n < 0, p = 0), x > 0 binding (u . n = 0, p >= 0): one
transition at 0, no contact load. f = -div sigma(u) is derived by the harness.
Regularity: m(-x)^3 has a jump in its third derivative, so u is in H^{7/2 - eps}: nu = 7/2;
P2 cannot do better than h^2 (Remark 4.9 with finitely many transitions), the expected rate.
"""
from ngsolve import CF, IfPos, cos, sin, x, y

from harness.problem import split_strip

name = "elastic-smooth"
description = "smooth elastic displacement (H^{7/2-eps}) with one transition at 0 (plane strain, Poisson 0.3)"
physics = "elasticity"
young, poisson = 1.0, 0.3
regime = "nu > 5/2"
theorem = "Remark 4.9 (Remark 2.3)"
nu = 3.5
expected_rate = 2.0

# D^2 u has kinks across the whole line x = 0 (f = -div sigma(u) is only continuous there): the
# mesh follows that line, so that no element has a kink inside (on a mesh cut across by it, the
# load's Gauss rule is not exact on the elements the line cuts, and moves the H^1 error)
geometry = split_strip(0.0)
maxh = 0.5

left, right = IfPos(-x, -x, 0.0), IfPos(x, x, 0.0)
u = CF((4 * y * left**3 + y * y * sin(x + y), left**4 - y * right**3 + y * y * cos(x + y)))
# singular nowhere: D^3 u jumps across x = 0, a line no quadrature rule needs grading for
singular_points = []

# Asymptotic by six P2 levels: a seventh moves no method's fitted H1 rate by more than 0.01
# (the rule of asymptotic_levels) nor any verdict, so the default report stops at six.
asymptotic_levels = 6

# P1 runs one level past P2 by default (to P2's finest number of dofs); that level moves no P1
# method's fitted H1 rate by more than 0.01 nor any verdict, so the default report stops P1
# with P2.
asymptotic_levels_p1 = 6
