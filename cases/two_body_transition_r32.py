"""Two bodies, non-matching meshes: transition-r32's r^{3/2} contact/separation transition on
the interface (Section 6; harness.problem.bodies).

Upper body (-1, 1) x (0, 1), lower body its mirror image (-1, 1) x (-1, 0), Gamma_C = {y = 0}
between them, Gamma_u the outer horizontal sides, Gamma_g the vertical ones. Upper:
s = -r^{3/2} sin(3 theta/2) (transition-r32); lower: u_2(x, y) = -s(x, -y). The jump
[u] = 2 s vanishes for x > 0 (binding, pressure (3/2) sqrt(x) on both sides) and opens as
2 |x|^{3/2} for x < 0 (free): u in H^{5/2 - eps} on each body, the one-body theorems' h^{3/2}
(4.1 ii, 5.1 ii) is the rate the mortar methods should reach.

Non-matching meshes: the upper body is meshed with maxh 1/4 (Gamma_C vertices at the quarters),
the lower with maxh 1/6 and an extra break at x = -0.9 (its vertices at sixths of
(-0.9, 0) and (0, 1), elsewhere near them): element sizes in ratio 2:3 on Gamma_C that
uniform refinement keeps apart. The transition point 0 is a corner of both.
"""
from harness.problem import MirrorBody, contact_strip, transition, transition_gradient

name = "two-body-transition-r32"
description = "two bodies on non-matching meshes (2:3 on Gamma_C): r^{3/2} transition at the middle of the interface"
regime = "2 < nu <= 5/2"
theorem = "4.1 ii, 5.1 ii (one body)"
nu = 2.5
expected_rate = 1.5

geometry = contact_strip(breaks=[0.0])
maxh = 0.25
second_body = MirrorBody(geometry=contact_strip(breaks=[-0.9, 0.0]), maxh=1 / 6)

# (``transition`` puts the branch cut of theta outside the body: the lower body's mesh maps some
# points of Gamma_C with x < 0 to y = -1e-17, where atan2(y, x) = -pi flipped the sign of u)
u = transition(0.0)
grad_u = transition_gradient(0.0)
f = 0
singular_points = [(0.0, 0.0)]

# Asymptotic by five P2 levels: a sixth moves no method's fitted H1 rate by more than 0.01,
# nor does P1's level past P2 move its rate by that much, so the default report stops both at
# five.
asymptotic_levels = 5
asymptotic_levels_p1 = 5
