"""A smooth 3D elastic Tresca case with stick, and slip in a direction that turns, for the Tresca
laws' tests (the disc): u = (x_+^3 (1 + z), y x_+^3 (1 + z), z^2) on (-1, 1)^2 x (0, 1), Poisson
ratio 0.3, Gamma_C the bottom (n = -e_z), bilateral u . n = -u_z = 0 there. The slip
u_t = x_+^3 (1, y): slip for x > 0 with lambda_t = -s (1, y)/sqrt(1 + y^2), stick for x < 0 with
lambda_t = -s (1 - x_-^2)(1, y)/sqrt(1 + y^2), inside the disc. The contact traction
g_C = sigma(u) n - lambda_t + n makes both exact and leaves the normal pressure 1."""
from ngsolve import CF, IfPos, sqrt, x, y, z

from harness.problem import Elasticity, Tresca, contact_box
from harness.problem.physics import gradient

name = "elastic-tresca-smooth-3d"
description = "3D elastic Tresca, u = x_+^3 (1 + z)(1, y, 0) + (0, 0, z^2): slip turning with y for x > 0, stick for x < 0"
physics = "elasticity"
poisson = 0.3
nu = 3.5
expected_rate = 2.0
theorem = "friction analogue of Remark 4.9"
s = 1.0
friction = Tresca(threshold=s)
geometry = contact_box(split_at=0.0)
maxh = 0.6

_material = Elasticity(poisson=poisson, dim=3)
x_plus, x_minus = IfPos(x, x, 0.0), IfPos(-x, -x, 0.0)
u = CF((x_plus ** 3 * (1 + z), y * x_plus ** 3 * (1 + z), z * z))
_n = CF((0.0, 0.0, -1.0))
_scale = -s * (1 - x_minus ** 2) / sqrt(1 + y * y)
contact_load = _material.stress(gradient(u, 3)) * _n - CF((_scale, _scale * y, 0.0)) + _n
singular_lines = []
