"""A smooth solution with a contact/separation transition (Remark 4.9): rate h^2.

Omega = (-1, 1) x (0, 1), Gamma_C = bottom, Gamma_g = sides, Gamma_u = top, and
    u = max(0, -x)^3 - y max(0, x)^3 + y^2 cos(x + y).
On Gamma_C (y = 0, n = -e_y): u = max(0,-x)^3 and du/dn = max(0,x)^3, so x < 0 is free and
x > 0 binding with positive pressure; the conditions (2.4) hold exactly, one transition at 0.
Regularity: max(0, x)^3 has a jump in its third derivative, so u is in H^{7/2 - eps}:
nu = 7/2 > 5/2. Remark 4.9 proves h^{7/4} without and h^2 with finitely many transitions;
P2 cannot do better than h^2, the expected rate.
"""
from ngsolve import IfPos, cos, sin, x, y

from harness.problem import contact_strip

name = "smooth"
description = "max(0,-x)^3 - y max(0,x)^3 + y^2 cos(x+y): H^{7/2-eps}, transition at 0"
regime = "nu > 5/2"
theorem = "Remark 4.9"
groups = ["paper"]            # one scalar case per regime of the paper's theorems (--case paper)
nu = 3.5
expected_rate = 2.0

geometry = contact_strip(breaks=[0.0])
maxh = 0.25

u = IfPos(-x, -x * x * x, 0.0) - y * IfPos(x, x * x * x, 0.0) + y * y * cos(x + y)
f = IfPos(-x, 6 * x, 0.0) + IfPos(x, 6 * x * y, 0.0) + (2 * y * y - 2) * cos(x + y) + 4 * y * sin(x + y)
# singular nowhere: D^3 u (and D f) jumps across x = 0, a line no quadrature rule needs grading
# for, but one that crosses elements, where no Gauss rule integrates the P3/P4 errors and the load
# as accurately as they need: those elements are subdivided (``derivative_jumps``)
singular_points = []
derivative_jumps = [((0.0, 0.0), (0.0, 1.0))]

# P1 runs one level past P2 by default (to P2's finest number of dofs); that level moves no P1
# method's fitted H1 rate by more than 0.01 nor any verdict, so the default report stops P1
# with P2.
asymptotic_levels_p1 = 7
# The default report stops P2 at six levels (P1 at seven, asymptotic_levels_p1; the fine profile
# runs eight): the seventh P2 level costs a large share of the report's five minutes and changes
# no verdict.
report_levels = {"default": 6}
