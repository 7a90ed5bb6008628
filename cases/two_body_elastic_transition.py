"""Two elastic bodies, non-matching meshes: elastic-transition-r32's r^{3/2} transition on the
interface (Section 6, Remark 2.3; harness.problem.bodies).

Upper body (-1, 1) x (0, 1) in plane strain (E = 1, Poisson ratio 0.3) with elastic-transition-r32's
displacement s (the l = 3/2 roller-free mode); lower body its mirror image,
u_2(x, y) = (s_x(x, -y), -s_y(x, -y)). On Gamma_C = {y = 0}: sigma_xy = 0 on both sides
(frictionless), the normal tractions balance, the normal opening [u_y] = 2 s_y vanishes for x > 0
(binding, pressure (3/2) sqrt(x) on both) and opens as 2 s_y(x, 0) > 0 for x < 0. u in
H^{5/2 - eps} on each body: the elastic Theorems 4.1 ii / 5.1 ii (one body) give h^{3/2}.

Non-matching meshes: upper maxh 1/2 (as elastic-transition-r32), lower maxh 1/3 with an extra
break at x = -0.9: element sizes 2:3 on Gamma_C. The transition point 0 is a corner of both.
"""
from math import pi

from harness.problem import Elasticity, MirrorBody, contact_strip, roller_free_mode

name = "two-body-elastic-transition"
description = "two elastic bodies on non-matching meshes (2:3): r^{3/2} transition at the middle of the interface"
physics = "elasticity"
young, poisson = 1.0, 0.3
regime = "2 < nu <= 5/2"
theorem = "4.1 ii, 5.1 ii (one body, Remark 2.3)"
nu = 2.5
expected_rate = 1.5

geometry = contact_strip(breaks=[0.0])
maxh = 0.5
second_body = MirrorBody(geometry=contact_strip(breaks=[-0.9, 0.0]), maxh=1 / 3)

u, grad_u = roller_free_mode(1.5, pi, Elasticity(young, poisson), with_gradient=True)
f = 0
singular_points = [(0.0, 0.0)]

# Asymptotic by five P2 levels: a sixth moves no method's fitted H1 rate by more than 0.01,
# nor does P1's level past P2 move its rate by that much, so the default report stops both at
# five.
asymptotic_levels = 5
asymptotic_levels_p1 = 5
