"""3D elasticity: the plane-strain r^{3/2} contact/separation transition extruded along y.

Frictionless unilateral contact of a 3D body (E = 1, Poisson ratio 0.3) on a rigid foundation.
Omega = (-1, 1)^2 x (0, 1), Gamma_C = the bottom face z = 0 (n = -e_z), Gamma_u = the top,
Gamma_g = the four sides. With (rho, theta) the polar coordinates of (x, z) about the line
{x = 0, z = 0}, u = (u_x(x, z), 0, u_z(x, z)) is the displacement of elastic-transition-r32
(``roller_free_mode(3/2, pi)``, Kolosov-Muskhelishvili) written in the (x, z) plane. A
plane-strain field is a 3D one (u_y = 0 and no y-dependence: eps_yy = 0, sigma_yy = lambda div u
depends on x and z only), so f = 0 and, on Gamma_C, as in 2D along every line y = const:
  x > 0: u_z = 0 (u . n = 0, binding), sigma_xz = sigma_yz = 0 (frictionless), pressure
         -sigma_zz = (3/2) sqrt(x) > 0;
  x < 0: traction-free, u . n = -u_z < 0 (separated);
the transition is the straight line x = 0 of Gamma_C. The sides y = +-1 carry the traction
sigma_yy e_y the harness derives (Gamma_g). Regularity: D^2 u ~ rho^{-1/2} across the line,
u in H^{5/2 - eps}, nu = 5/2: the 2D rate h^{3/2} of the elastic Theorems 4.1 ii, 5.1 ii
(Remark 2.3) is the expectation; in 3D the paper proves nothing (Section 6) and Drouet & Hild
(2015) prove the optimal P2 rate of the nodal cone.
The box is two boxes glued along x = 0, so every mesh has edges along the transition line.
"""
from math import pi

from harness.problem import Elasticity, contact_box, roller_free_mode

name = "elastic-transition-3d"
description = "3D elastic r^{3/2} contact/separation transition along the line x = 0 of Gamma_C (Poisson 0.3)"
physics = "elasticity"
young, poisson = 1.0, 0.3
regime = "2 < nu <= 5/2, 3D"
theorem = "Section 6 (3D open in the paper); 4.1 ii, 5.1 ii (Remark 2.3) in 2D"
conjectured = True
nu = 2.5
expected_rate = 1.5

geometry = contact_box(split_at=0.0)
transition_curve = [[(0.0, -1.0), (0.0, 1.0)]]
# the same line in space, {x = 0, z = 0}: u ~ rho^{3/2} in the distance to it, graded meshes refine toward it
singular_lines = [((0.0, -1.0, 0.0), (0.0, 1.0, 0.0))]
# three P2 unknowns per node: a coarser start than the scalar 3D cases (maxh 0.25); level 3
# has 5.9e5 dofs
maxh = 0.4

u, grad_u = roller_free_mode(1.5, pi, Elasticity(young, poisson, dim=3), coordinates="xz", with_gradient=True)
f = 0
