"""3D elasticity: binding contact meeting Gamma_g along a straight junction line, u ~ r^{1/2}.

Frictionless unilateral contact of a 3D body (E = 1, Poisson ratio 0.3) on a rigid foundation:
the elastic, 3D counterpart of corner-r12. Omega = (-1, 1)^2 x (0, 1); the bottom face z = 0
is Gamma_g for x < 0 and Gamma_C for x > 0 (n = -e_z), the top Gamma_u, the sides Gamma_g.
In the (x, z) plane, (rho, theta) the polar coordinates about the line {x = 0, z = 0}:

  * the junction: ``roller_free_mode(1/2, pi)``, a root of sin(2 l omega) + l sin(2 omega) at
    omega = pi (the crack-tip mode I field of elastic-transition-r32's docstring, which the
    sign conditions exclude at a transition point, is admissible where Gamma_C meets Gamma_g:
    no sign condition holds on Gamma_g). On theta = 0: u_z = 0 (binding), sigma_xz = 0,
    pressure -sigma_zz = (1/2) x^{-1/2} > 0; theta = pi is traction-free;
  * a transition at x = 1/2 (``roller_free_mode(3/2, pi, x0=1/2, mirrored=True)``: binding to
    its left, separated to its right), so that Gamma_C has a free part, as in corner-r12.
    There the junction field still presses with (1/2) x^{-1/2}: the contact load
    g_C = (1/2) x^{-1/2} (-n) for x > 1/2 takes it (sigma(u) n - g_C = 0: p = 0, u . n < 0),
    the elastic form of corner-r12's g_C.
Both are plane-strain fields in the (x, z) plane with u_y = 0, so exact 3D fields with f = 0
(elastic-transition-3d's docstring); the sides y = +-1 and the bottom x < 0 carry the traction
sigma(u) n the harness derives (Gamma_g). On (0, 1/2) the pressure is
(1/2) x^{-1/2} + (3/2) (1/2 - x)^{1/2} > 0.
Regularity: Du ~ rho^{-1/2} along the junction line, u in H^{3/2 - eps}: nu = 3/2, h^{1/2} (the
elastic Theorems 4.1 i, 5.1 i in 2D, Remark 2.3; for P1 too: the singular function limits every
method). In 3D the paper proves nothing (Section 6).
The box is three boxes glued along x = 0 and x = 1/2, so every mesh has edges along the junction
and the transition line.
"""
from math import pi

from ngsolve import CF, IfPos, x

from harness.problem import Elasticity, contact_box, roller_free_mode

name = "elastic-junction-3d"
description = "3D elastic: binding contact meets Gamma_g along the line x = 0 (r^{1/2}), transition along x = 1/2 (Poisson 0.3)"
physics = "elasticity"
young, poisson = 1.0, 0.3
regime = "1 < nu <= 3/2, 3D"
theorem = "Section 6 (3D open in the paper); 4.1 i, 5.1 i (Remark 2.3) in 2D"
conjectured = True
nu = 1.5
expected_rate = 0.5

geometry = contact_box(split_at=[0.0, 0.5], bottom=["neumann", "contact", "contact"])
# three P2 unknowns per node: the coarse start of elastic-transition-3d
maxh = 0.4

_material = Elasticity(young, poisson, dim=3)
_junction = roller_free_mode(0.5, pi, _material, coordinates="xz", with_gradient=True)
_transition = roller_free_mode(1.5, pi, _material, x0=0.5, mirrored=True, coordinates="xz", with_gradient=True)
u, grad_u = _junction[0] + _transition[0], _junction[1] + _transition[1]
f = 0
# n = -e_z: g_C = (1/2) x^{-1/2} e_z on the free part x > 1/2 (docstring)
contact_load = CF((0.0, 0.0, IfPos(x - 0.5, 0.5 * IfPos(x - 0.5, x, 1.0) ** -0.5, 0.0)))
# the junction line (where Gamma_C meets Gamma_g) and the transition line, drawn on Gamma_C's pictures
transition_curve = [[(0.0, -1.0), (0.0, 1.0)], [(0.5, -1.0), (0.5, 1.0)]]
# the same lines in space (z = 0), graded meshes refine toward both (with nu's exponent 1/2, the junction's)
singular_lines = [((0.0, -1.0, 0.0), (0.0, 1.0, 0.0)), ((0.5, -1.0, 0.0), (0.5, 1.0, 0.0))]

# P1 runs one level past P2 by default (to P2's finest number of dofs); that level moves P1's
# fitted H1 rate by less than the contract's 0.01 (`run --levels 4` shows it), so the default
# report stops P1 with P2.
asymptotic_levels_p1 = 3

# the default report runs one scalar and one elastic 3D case (transition-line-3d, elastic-transition-3d);
# this one, 15-22 s of its study, in `make report-fine` and `report --case` (make report within its 3 minutes)
report_profile = "fine"
