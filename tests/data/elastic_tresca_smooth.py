"""A smooth elastic Tresca case (plane strain) with stick and slip, for the Tresca laws' tests:
u = (x_+^3 (1 + y), y^2) on (-1, 1) x (0, 1), Poisson ratio 0.3, Gamma_C the bottom (n = -e_y,
tau = e_x), bilateral u . n = -u_y = 0 there. The slip u_t = u_x = x_+^3: slip for x > 0 with the
friction force lambda_t = -s, stick for x < 0 with lambda_t = -s (1 - x_-^2), inside [-s, s].
The contact traction g_C = sigma(u) n - lambda_t tau + n makes both exact (sigma_t - g_t =
lambda_t) and leaves the normal pressure -(sigma_n - g_n) = 1. u in H^{7/2 - eps} (x_+^3)."""
from ngsolve import CF, IfPos, x, y

from harness.problem import Elasticity, Tresca, contact_strip
from harness.problem.physics import gradient

name = "elastic-tresca-smooth"
description = "elastic Tresca, u = (x_+^3 (1 + y), y^2): slip for x > 0, stick for x < 0"
physics = "elasticity"
poisson = 0.3
nu = 3.5
expected_rate = 2.0
theorem = "friction analogue of Remark 4.9"
s = 1.0
friction = Tresca(threshold=s)
geometry = contact_strip(breaks=[0.0])
maxh = 0.25

_material = Elasticity(poisson=poisson)
x_plus, x_minus = IfPos(x, x, 0.0), IfPos(-x, -x, 0.0)
u = CF((x_plus ** 3 * (1 + y), y * y))
_n = CF((0.0, -1.0))
_friction_force = -s * (1 - x_minus ** 2)
contact_load = _material.stress(gradient(u, 2)) * _n - CF((_friction_force, 0.0)) + _n
derivative_jumps = [((0.0, 0.0), (0.0, 1.0))]
