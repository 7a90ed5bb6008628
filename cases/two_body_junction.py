"""Two bodies, non-matching meshes: corner-r12's junction, where the binding interface meets
the free (Neumann) part of the two bodies' common side (Section 6; harness.problem.bodies).

Upper body (-1, 1) x (0, 1), lower body its mirror image; they touch along Gamma_C = (0, 1) x {0}
and face each other without contact law on (-1, 0) x {0} (Gamma_g of both: a crack). Upper:
s = -r^{1/2} sin(theta/2) + the transition at x = 1/2 (corner-r12), lower u_2(x, y) = -s(x, -y).
The jump [u] = 2 s: binding on (0, 1/2) with the pressure r^{-1/2}/2 singular at the junction,
open as 2 (x - 1/2)^{3/2} beyond. u in H^{3/2 - eps} on each body: h^{1/2} (Thm 4.1 i, 5.1 i for
one body) limits every method.

Non-matching meshes: upper maxh 1/4 (Gamma_C vertices at the quarters), lower maxh 1/6 with an
extra break at x = 0.8: element sizes 2:3 on Gamma_C. The junction 0 and the transition point
1/2 are corners of both.
"""
from ngsolve import IfPos, sin, x

from harness.problem import MirrorBody, polar, polygon, transition

name = "two-body-junction"
description = "two bodies on non-matching meshes (2:3): the binding interface meets a crack (r^{1/2}), transition at x = 1/2"
regime = "1 < nu <= 3/2"
theorem = "4.1 i, 5.1 i (one body)"
nu = 1.5
expected_rate = 0.5

geometry = polygon(
    [(-1, 0), (0, 0), (0.5, 0), (1, 0), (1, 1), (-1, 1)],
    ["neumann", "contact", "contact", "neumann", "dirichlet", "neumann"],
)
maxh = 0.25
second_body = MirrorBody(
    geometry=polygon([(-1, 0), (0, 0), (0.5, 0), (0.8, 0), (1, 0), (1, 1), (-1, 1)],
                     ["neumann", "contact", "contact", "contact", "neumann", "dirichlet", "neumann"]),
    maxh=1 / 6,
)

r, theta = polar()
u = -(r ** 0.5) * sin(theta / 2) + transition(0.5, binding_side="left")
f = 0
singular_points = [(0.0, 0.0), (0.5, 0.0)]
# beyond the transition the load takes over u_s's pressure (corner-r12), on both bodies' sides
contact_load = IfPos(x - 0.5, 0.5 * x ** (-0.5), 0.0)

# Asymptotic by five P2 levels: a sixth moves no method's fitted H1 rate by more than 0.01,
# nor does P1's level past P2 move its rate by that much, so the default report stops both at
# five.
asymptotic_levels = 5
asymptotic_levels_p1 = 5
