"""A smooth obstacle under a membrane: no closed-form u; transitions where the solution puts them.

Omega = (-1, 1) x (0, 1), Gamma_C = bottom, Gamma_g = sides, Gamma_u = top. All data smooth:
f = 0, u = 0 on the top, du/dn = 0 on the sides, and the constraint u >= alpha on the bottom
with the obstacle
    alpha(x) = cos(pi x) + 0.3 sin(pi x / 2) - 0.2,
positive around x = 0 and negative near the sides. The obstacle lifts the bottom: u = alpha with
a positive pressure du/dn on a contact zone, u > alpha and du/dn = 0 outside: one interval
around x = 0 (the report's pictures of Gamma_C show it). Nobody placed its ends, the two
transition points: they fall inside contact edges of every mesh, unlike the exact cases'
transitions at vertices.

Regularity. The sides are no corners for the solution: alpha'(+-1) = 0, and the even reflection
x -> 2 - x (and x -> -2 - x) of the data is smooth (cos(pi x) and sin(pi x/2) are even about
x = +-1), so by uniqueness u is the restriction of the solution on a strip twice as wide, smooth
at (+-1, 0) (free there: alpha(+-1) < 0 < u) and at (+-1, 1) (Dirichlet on a straight line).
At a transition point of a straight Gamma_C with smooth data the leading singular function is
r^{3/2} sin(3 theta/2) (Remark 2.2): u in H^{5/2 - eps}, nu = 5/2, and Theorems 4.1 ii / 5.1 ii
give h^{3/2} for P2 with no assumption on the transitions.

Errors: against the nodal P2 solution two levels finer (``reference_levels``).
"""
from ngsolve import cos, pi, sin, x

from harness.problem import contact_strip

name = "smooth-obstacle"
description = "smooth obstacle cos(pi x) + 0.3 sin(pi x/2) - 0.2 under a membrane, no closed form"
regime = "2 < nu <= 5/2 (transitions off the mesh vertices)"
theorem = "4.1 ii, 5.1 ii"
groups = ["paper"]            # one scalar case per regime of the paper's theorems (--case paper)
nu = 2.5
expected_rate = 1.5

geometry = contact_strip(breaks=[])
maxh = 0.5             # the default report (7 levels) then has its references at 2.3e6 dofs

f = 0
dirichlet = 0
neumann = 0
gap = cos(pi * x) + 0.3 * sin(pi * x / 2) - 0.2
singular_points = []            # the transitions are unknown; the data are smooth everywhere
reference_levels = 2

# P1 runs one level past P2 by default (to P2's finest number of dofs); that level moves no P1
# method's fitted H1 rate by more than 0.01 nor any verdict, so the default report stops P1
# with P2.
asymptotic_levels_p1 = 7
# The default report stops P2 at six levels (P1 at seven, asymptotic_levels_p1; the fine profile
# runs eight): the seventh P2 level's reference, 1.8e6 dofs, costs a large share of the report's
# five minutes, and the seventh level changes no verdict.
report_levels = {"default": 6}
