"""Elastic binding contact meeting a traction-free face at angle 3 pi/4: u ~ r^{0.5445}.

Plane strain (E = 1, Poisson 0.3). Omega is the quadrilateral (0,0), (1,0), (1,1), (-1,1);
Gamma_C = [0, 1] x {0} (n = -e_y), Gamma_g the right side and the ray from (0,0) to (-1,1)
(interior angle omega = 3 pi/4 with Gamma_C), Gamma_u the top.

The exponent. Binding frictionless contact is the roller condition u . n = 0, sigma_t = 0; the
ray is traction-free. Reflecting across Gamma_C (u_n odd, u_t even) turns the roller face into
the bisector of a traction-free wedge of angle 2 omega, and the fields into its symmetric ones:
Williams' characteristic equation of a free-free wedge (``harness.problem.functions.roller_free_mode``)

    sin(2 l omega) + l sin(2 omega) = 0,   here   sin(3 pi l / 2) = l,

whose least positive root is l = 0.544484... Neither the equation nor the root depends on the
Poisson ratio: a traction-free face and a roller face carry no elastic constant, so the
Poisson ratio enters the singular *function* (through kappa = 3 - 4 nu), not its exponent.
(An exponent that depends on the Poisson ratio needs a clamped face -- contact meeting
Gamma_u, which the paper's Section 2 excludes -- or friction.) A dependence might be expected;
the mathematics gives none, and the case says so.

By hand (f = 0): on theta = 0, u_y = 0 (u . n = 0, binding) and sigma_xy = 0 (frictionless),
sigma_yy = -l r^{l-1} < 0: pressure p = l r^{l - 1} > 0 on all of Gamma_C, singular at the
corner; the ray is traction-free. Du ~ r^{l - 1}: u in H^{1 + l - eps}, nu = 1.5445 in
(3/2, 2): the elastic Theorems 4.2 i / 5.2 i give h^{nu - 1} = h^{0.5445}. (The scalar
wedge-r23, same geometry, has r^{2/3}: elasticity is more singular here.)
"""
from math import pi, sin

from harness.problem import Elasticity, bracketed_root, polygon, roller_free_mode

OMEGA = 3 * pi / 4
EXPONENT = bracketed_root(lambda s: sin(2 * s * OMEGA) + s * sin(2 * OMEGA), 0.3, 0.9, xtol=1e-15)

name = "elastic-wedge"
description = f"elastic binding contact meets a traction-free face at 3pi/4: r^{{{EXPONENT:.4f}}} (plane strain, Poisson 0.3)"
physics = "elasticity"
young, poisson = 1.0, 0.3
regime = "3/2 < nu < 2"
theorem = "4.2 i, 5.2 i (Remark 2.3)"
nu = 1 + EXPONENT
expected_rate = EXPONENT

geometry = polygon([(0, 0), (1, 0), (1, 1), (-1, 1)], ["contact", "neumann", "dirichlet", "neumann"])
maxh = 0.5

u, grad_u = roller_free_mode(EXPONENT, OMEGA, Elasticity(young, poisson), with_gradient=True)
f = 0
singular_points = [(0.0, 0.0)]

# Asymptotic by six P2 levels: a seventh moves no method's fitted H1 rate by more than 0.01
# (the rule of asymptotic_levels) nor any verdict, so the default report stops at six.
asymptotic_levels = 6

# P1 runs one level past P2 by default (to P2's finest number of dofs); that level moves no P1
# method's fitted H1 rate by more than 0.01 nor any verdict, so the default report stops P1
# with P2.
asymptotic_levels_p1 = 6
