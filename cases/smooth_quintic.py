"""A smoother solution with a contact/separation transition, for elements of degree k <= 4.

Omega = (-1, 1) x (0, 1), Gamma_C = bottom, Gamma_g = sides, Gamma_u = top, and
    u = max(0, -x)^5 - y max(0, x)^5 + y^2 cos(x + y),
``smooth`` with fifth powers in place of cubes. On Gamma_C (y = 0, n = -e_y): u = max(0,-x)^5
and du/dn = max(0,x)^5, so x < 0 is free and x > 0 binding with positive pressure; the
conditions (2.4) hold exactly, one transition at 0. Regularity: max(0, x)^5 has a jump in its
fifth derivative, so u is in H^{11/2 - eps}: nu = 11/2, enough for the optimal rate h^k of
Nitsche's method up to k = 4 (min(nu - 1, k); ``smooth``'s nu = 7/2 caps every degree at
h^{5/2}). P2's cones cannot do better than h^2 (Remark 4.9), the expected rate.
"""
from ngsolve import IfPos, cos, sin, x, y

from harness.problem import contact_strip

name = "smooth-quintic"
description = "max(0,-x)^5 - y max(0,x)^5 + y^2 cos(x+y): H^{11/2-eps}, transition at 0"
regime = "nu > 5/2"
theorem = "Remark 4.9"
nu = 5.5
expected_rate = 2.0

geometry = contact_strip(breaks=[0.0])
maxh = 0.25

x3 = x * x * x
u = IfPos(-x, -x3 * x * x, 0.0) - y * IfPos(x, x3 * x * x, 0.0) + y * y * cos(x + y)
f = IfPos(-x, 20 * x3, 0.0) + IfPos(x, 20 * x3 * y, 0.0) + (2 * y * y - 2) * cos(x + y) + 4 * y * sin(x + y)
# singular nowhere: D^5 u (and D^3 f) jumps across x = 0, a line no quadrature rule needs grading
# for, but one that crosses elements: they are subdivided, as smooth's are
singular_points = []
derivative_jumps = [((0.0, 0.0), (0.0, 1.0))]

# a case for the degree axis (P3, P4): the default report's P2 and P1 methods see nothing here
# that ``smooth`` does not show them
report_profile = "fine"
