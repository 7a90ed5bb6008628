"""Tresca friction (scalar) with a stick-slip point: u = s y + c r^{3/2} cos(3 theta/2).

The scalar Tresca problem (``harness.problem.friction``; Stadler, SIAM J. Optim. 15 (2004)):
-Laplace(u) = 0 in Omega = (-1, 1) x (0, 1), Gamma_C = bottom, Gamma_g = sides, Gamma_u = top,
and on Gamma_C (n = -e_y) |d_n u| <= s, d_n u = -s u/|u| where u != 0. Polar (r, theta) about
0, theta in [0, pi]; s = 1, c = 1 (any 0 < c <= 4 s/3 works). On Gamma_C:
  x > 0 (theta = 0):  u = c x^{3/2} > 0 and d_n u = -s                           -- slip;
  x < 0 (theta = pi): u = 0 and d_n u = -s + (3/2) c |x|^{1/2} in [-s, s] (|x| <= 1) -- stick.
The stick-slip point carries r^{3/2} as a contact/separation point does: the r^{1/2} term would
break |d_n u| <= s, the r^{5/2} one the sign (MATH.md §11). D^2 u ~ r^{-1/2}: u in
H^{5/2 - eps}, nu = 5/2. The contact theorems' rate h^{min(nu - 1, k - 1/2)}... for P2 h^{3/2}
(Chouly 2014 for Nitsche; the nodal and mean analogues as the paper's models, Theorems 4.1 ii
and 5.1 ii read for friction), P1 h.
"""
from harness.problem import Tresca, contact_strip, scalar_stick_slip

name = "tresca-r32"
description = "Tresca friction, s y + r^{3/2} cos(3 theta/2): stick-slip point at the middle of Gamma_C"
regime = "2 < nu <= 5/2"
theorem = "friction analogue of 4.1 ii, 5.1 ii"
nu = 2.5
expected_rate = 1.5
# Asymptotic by five P2 levels: the sixth and seventh move no fitted H^1 rate by more than 0.003
# (nodal, mean, p1, nitsche, nitsche-p1, penalty-p1), except the P2 penalty's, which falls
# towards 1 from above (1.047, 1.025, 1.012 at five, six, seven levels; its verdict the same)
asymptotic_levels = 5
asymptotic_levels_p1 = 5

s, c = 1.0, 1.0
friction = Tresca(threshold=s)

# the stick-slip point (0, 0) is a polygon corner, hence a vertex of every mesh
geometry = contact_strip(breaks=[0.0])
maxh = 0.25

u, grad_u = scalar_stick_slip(s, c)   # grad u in closed form: cheaper per point than the derived one
f = 0
singular_points = [(0.0, 0.0)]
