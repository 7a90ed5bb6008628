"""Two bodies on *matching* meshes: two-body-transition-r32 with the lower body meshed as the
upper one (Section 6; harness.problem.bodies).

The control of two-body-transition-r32: the same solution (transition-r32's r^{3/2} transition
on the upper body, its mirror image below), both bodies with maxh 1/4 and the same breaks, so
every vertex of Gamma_C is a vertex of both meshes. There the dual mortar condition is the
one-body cone on the jump (`mortar-nodal` is `nodal`, `mortar-mean` `mean`, `mortar-p1` `p1`;
tests/test_two_body.py checks every error to 1e-8), and the non-matching case's rows are measured
against these.
"""
from harness.problem import MirrorBody, contact_strip, transition, transition_gradient

name = "two-body-transition-r32-matching"
description = "two bodies on matching meshes (the control): r^{3/2} transition at the middle of the interface"
regime = "2 < nu <= 5/2"
theorem = "4.1 ii, 5.1 ii (one body)"
nu = 2.5
expected_rate = 1.5

geometry = contact_strip(breaks=[0.0])
maxh = 0.25
second_body = MirrorBody(geometry=contact_strip(breaks=[0.0]), maxh=0.25)

u = transition(0.0)
grad_u = transition_gradient(0.0)
f = 0
singular_points = [(0.0, 0.0)]

# Asymptotic by five P2 levels: a sixth moves no method's fitted H1 rate by more than 0.01,
# nor does P1's level past P2 move its rate by that much, so the default report stops both at
# five.
asymptotic_levels = 5
asymptotic_levels_p1 = 5
