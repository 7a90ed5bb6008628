"""3D: the r^{3/2} transition extruded along a straight line of Gamma_C (Section 6).

Omega = (-1, 1)^2 x (0, 1), Gamma_C = the bottom face z = 0 (n = -e_z), Gamma_u = the top,
Gamma_g = the four sides. With (rho, theta) the polar coordinates of (x, z) about the line
{x = 0, z = 0} (theta in [0, pi]) and w(y) = 1 + y^2/2 > 0,
    u = w(y) v(x, z),   v = -rho^{3/2} sin(3 theta / 2)   (``harness.problem.functions.transition``).
v is harmonic in (x, z), so f = -Laplace(u) = -w''(y) v = -v.
Signorini conditions on Gamma_C (z = 0, d_n = -d_z), as in 2D times w > 0:
  x > 0 (theta = 0): u = 0 and du/dn = (3/2) w(y) sqrt(x) >= 0   -- binding;
  x < 0 (theta = pi): u = w(y) |x|^{3/2} > 0 and du/dn = 0        -- free;
so u - 0 >= 0, du/dn >= 0 and their product vanishes: (2.4) holds exactly, the transition is
the whole line x = 0 of Gamma_C. Regularity: D^2 u ~ rho^{-1/2} in the plane normal to the
line, which is in H^s for s < 1/2 only: u is in H^{5/2 - eps}, nu = 5/2, and the 2D rate
h^{3/2} of Theorems 4.1 ii, 5.1 ii is the expectation. In 3D the paper proves nothing (its
Section 6 names 3D as open); Drouet & Hild (SINUM 2015) prove the optimal P2 rate for the
nodal (Lagrange) cone in 3D; for `mean` there is no theorem.
The box is two boxes glued along x = 0, so every mesh has edges along the transition line.
"""
from ngsolve import y

from harness.problem import contact_box, transition, transition_gradient

name = "transition-line-3d"
description = "3D: (1 + y^2/2) r^{3/2} sin(3 theta/2), transition along the straight line x = 0 of Gamma_C"
regime = "2 < nu <= 5/2, 3D"
theorem = "Section 6 (3D open in the paper)"
conjectured = True
nu = 2.5
expected_rate = 1.5

geometry = contact_box(split_at=0.0)
# the exact transition curve on Gamma_C, drawn on the report's pictures of it
transition_curve = [[(0.0, -1.0), (0.0, 1.0)]]
# the same line in space, {x = 0, z = 0}: u ~ rho^{3/2} in the distance to it, graded meshes refine toward it
singular_lines = [((0.0, -1.0, 0.0), (0.0, 1.0, 0.0))]
maxh = 0.25

v = transition(0.0, binding_side="right", coordinates="xz")
u = (1 + 0.5 * y * y) * v
f = -v
# grad u = (w v_x, w' v, w v_z) in closed form (cheaper per point than the derived one)
v_x, v_z = transition_gradient(0.0, binding_side="right", coordinates="xz")
grad_u = ((1 + 0.5 * y * y) * v_x, y * v, (1 + 0.5 * y * y) * v_z)
