"""Elastic contact/separation transition in the middle of Gamma_C (Remark 2.3): u ~ r^{3/2}.

Frictionless unilateral contact of a plane-strain body (E = 1, Poisson ratio 0.3) on a rigid
foundation. Omega = (-1, 1) x (0, 1), Gamma_C = bottom (n = -e_y), Gamma_g = sides, Gamma_u =
top; polar coordinates about 0, theta in [0, pi].

The exponent. Near a transition point the body sees, on a half plane, the roller conditions
u_y = 0, sigma_xy = 0 on the binding side (theta = 0) and a traction-free side (theta = pi).
Reflecting across theta = 0 (u_x even, u_y odd in y) gives a plane with a traction-free crack
along theta = +-pi and the symmetric (mode I) crack fields: the exponents l solve
sin(2 l pi) = 0, l = 1/2, 1, 3/2, ... (``harness.problem.functions.roller_free_mode``: the
determinant sin(2 l omega) + l sin(2 omega) at omega = pi), for every Poisson ratio. l = 1/2
is excluded by the sign conditions: its crack-tip field opens the free side (u_y > 0) only
with a tensile sigma_yy ~ r^{-1/2} ahead of it, and the binding side needs compression -- as
r^{1/2} sin(theta/2) in the scalar case (Remark 2.2). l = 1 is a linear (smooth) field. The
leading singular function is therefore l = 3/2, the elastic counterpart of r^{3/2} sin(3 theta/2):
    phi = a z^{3/2}, psi = -(a/2) z^{3/2} (Kolosov-Muskhelishvili), a = -1/2, kappa = 3 - 4 nu:
    2 mu u_x = a r^{3/2} ((kappa + 1/2) cos(3 theta/2) - (3/2) cos(theta/2)),
    2 mu u_y = a r^{3/2} ((kappa - 1/2) sin(3 theta/2) - (3/2) sin(theta/2)).
By hand, on Gamma_C (f = 0: the potentials make div sigma = 0):
  x > 0 (theta = 0): u_y = 0, so u . n = 0 (binding); sigma_xy = 0 (frictionless);
      sigma_yy = -(3/2) sqrt(x) < 0: pressure p = -sigma_n = (3/2) sqrt(x) >= 0;
  x < 0 (theta = pi): sigma = 0 on the face (traction-free, p = 0), and
      u_y = (kappa + 1) |x|^{3/2} / (4 mu) > 0: u . n = -u_y < 0 (separated).
Regularity: D^2 u ~ r^{-1/2}, u in H^{5/2 - eps}: nu = 5/2, rate h^{3/2} for both P2 models
(the elastic Theorems 4.1 ii / 5.1 ii, Remark 2.3), whatever the Poisson ratio.
"""
from math import pi

from harness.problem import Elasticity, contact_strip, roller_free_mode

name = "elastic-transition-r32"
description = "elastic r^{3/2} contact/separation transition at the middle of Gamma_C (plane strain, Poisson 0.3)"
physics = "elasticity"
young, poisson = 1.0, 0.3
regime = "2 < nu <= 5/2"
theorem = "4.1 ii, 5.1 ii (Remark 2.3)"
nu = 2.5
expected_rate = 1.5

geometry = contact_strip(breaks=[0.0])
# two P2 unknowns per node: a coarser start than the scalar cases keeps the levels comparable in dofs
maxh = 0.5

u, grad_u = roller_free_mode(1.5, pi, Elasticity(young, poisson), with_gradient=True)
f = 0
singular_points = [(0.0, 0.0)]

# Asymptotic by six P2 levels: a seventh moves no method's fitted H1 rate by more than 0.01
# (the rule of asymptotic_levels) nor any verdict, so the default report stops at six.
asymptotic_levels = 6

# P1 runs one level past P2 by default (to P2's finest number of dofs); that level moves no P1
# method's fitted H1 rate by more than 0.01 nor any verdict, so the default report stops P1
# with P2.
asymptotic_levels_p1 = 6
