"""Contact/separation transition: u = -r^{3/2} sin(3 theta/2) (Remark 2.2).

Omega = (-1, 1) x (0, 1), Gamma_C = bottom side, Gamma_u = top, Gamma_g = the two sides;
polar coordinates about the transition point 0, theta = atan2(y, x) in [0, pi], n = -e_y.
u is harmonic (f = 0). On Gamma_C:
  x > 0 (theta = 0): u = 0 and du/dn = -du/dy = (3/2) sqrt(x) >= 0   -- binding;
  x < 0 (theta = pi): u = |x|^{3/2} > 0 and du/dn = 0               -- free.
Regularity: D^2 u ~ r^{-1/2} is in H^s for s < 1/2 only, so u is in H^{5/2 - eps} and in no
H^{5/2}: nu = 5/2 (from below). Theorems 4.1 ii and 5.1 ii give ||u - u_h||_1 <= C h^{3/2}.
"""
from harness.problem import contact_strip, transition, transition_gradient

name = "transition-r32"
description = "r^{3/2} sin(3 theta/2) contact/separation transition at the middle of Gamma_C"
regime = "2 < nu <= 5/2"
theorem = "4.1 ii, 5.1 ii"
groups = ["paper"]            # one scalar case per regime of the paper's theorems (--case paper)
nu = 2.5
expected_rate = 1.5
expected_log_exponent = 0.0

# The transition point (0, 0) is a polygon corner, hence a vertex of every mesh.
geometry = contact_strip(breaks=[0.0])
maxh = 0.25

# u = -r^{3/2} sin(3 theta/2) with theta's branch cut outside the body (``harness.problem.functions.transition``):
# written with atan2(y, x), a Gamma_C point with x < 0 that NGSolve's map of a bisected triangle
# puts at y = -1e-17 would get theta = -pi, and u there the wrong sign (graded and adaptive
# meshes make such points; uniform ones do not)
u = transition(0.0)
grad_u = transition_gradient(0.0)   # in closed form: cheaper per point than the derived one
f = 0                         # u is harmonic
singular_points = [(0.0, 0.0)]  # the transition point

# Asymptotic by six P2 levels: a seventh moves no method's fitted H1 rate by more than 0.01
# (the rule of asymptotic_levels) nor any verdict, so the default report stops at six.
asymptotic_levels = 6

# P1 runs one level past P2 by default (to P2's finest number of dofs); that level moves no P1
# method's fitted H1 rate by more than 0.01 nor any verdict, so the default report stops P1
# with P2.
asymptotic_levels_p1 = 6
