"""3D scalar Tresca friction with a straight stick-slip line: tresca-r32 extruded along y.

The scalar Tresca problem (``harness.problem.friction``) on Omega = (-1, 1)^2 x (0, 1),
Gamma_C = the bottom face z = 0 (n = -e_z), Gamma_u = the top, Gamma_g = the four sides. With
(rho, theta) the polar coordinates of (x, z) about the line {x = 0, z = 0} (theta in [0, pi]),
w(y) = 1 + y^2/2 in [1, 3/2], s = 1, c = 4/5:
    u = s z + w(y) v,   v = c rho^{3/2} cos(3 theta / 2)    (tresca-r32's singular term in (x, z)).
v is harmonic in (x, z), so f = -Laplace(u) = -w''(y) v = -v. On Gamma_C (d_n = -d_z):
  x > 0 (theta = 0):  u = w c x^{3/2} > 0 and d_n u = -s                                  -- slip;
  x < 0 (theta = pi): u = 0 and d_n u = -s + (3/2) c w(y) |x|^{1/2} in [-s, s]            -- stick,
since (3/2) c w |x|^{1/2} <= (3/2)(4/5)(3/2) = 9/5 <= 2 s (any 0 < c <= 8 s / 9 works). The
stick-slip set is the whole line x = 0 of Gamma_C. As in 2D the r^{1/2} term would break
|d_n u| <= s and r^{5/2} the sign: D^2 u ~ rho^{-1/2} across the line, u in H^{5/2 - eps},
nu = 5/2, and the 2D rate h^{3/2} is the expectation (3D: no theorem; Section 6).
tests/test_tresca_exact.py checks the field with SymPy.
The box is two boxes glued along x = 0, so every mesh has edges along the stick-slip line.
"""
from ngsolve import cos, sin, sqrt, y, z

from harness.problem import Tresca, contact_box, polar

name = "tresca-line-3d"
description = "3D Tresca friction, s z + (1 + y^2/2) r^{3/2} cos(3 theta/2): stick-slip along the line x = 0 of Gamma_C"
regime = "2 < nu <= 5/2, 3D"
theorem = "friction analogue of 4.1 ii, 5.1 ii; Section 6 (3D open in the paper)"
conjectured = True
nu = 2.5
expected_rate = 1.5

s, c = 1.0, 0.8
friction = Tresca(threshold=s)

geometry = contact_box(split_at=0.0)
# the exact stick-slip line on Gamma_C, drawn on the report's pictures of it
transition_curve = [[(0.0, -1.0), (0.0, 1.0)]]
# the same line in space, {x = 0, z = 0}: u ~ rho^{3/2} in the distance to it, graded meshes refine toward it
singular_lines = [((0.0, -1.0, 0.0), (0.0, 1.0, 0.0))]
maxh = 0.25

rho, theta = polar(0.0, py=z)
w = 1 + 0.5 * y * y
v = c * rho ** 1.5 * cos(1.5 * theta)
u = s * z + w * v
f = -v
# grad v = (3/2) c rho^{1/2} (cos(theta/2), -sin(theta/2)) in (x, z) (Re of (3/2) c w^{1/2})
v_x, v_z = 1.5 * c * sqrt(rho) * cos(theta / 2), -1.5 * c * sqrt(rho) * sin(theta / 2)
grad_u = (w * v_x, y * v, s + w * v_z)
