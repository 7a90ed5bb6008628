"""A 3D elastic exact solution in P2: u = (x z + z^2, y z + x y, x z + z^2) on the box
(-1, 1)^2 x (0, 1) (Poisson ratio 0.3), binding on all of Gamma_C (the bottom z = 0, n = -e_z:
u . n = -u_z = 0 = the gap) with pressure p = -(sigma_n(u) - g_n) = 1 and the frictionless
condition sigma_t(u) = g_t made exact by the contact traction g_C = sigma(u) n + n: every P2
method reproduces it, and the 3D residual estimator, with its tangential term, must vanish there
(tests/test_adaptive_3d.py)."""
from ngsolve import CF, x, y, z

from harness.problem import Elasticity, contact_box

name = "quadratic-binding-elastic-3d"
description = "3D elastic: u = (x z + z^2, y z + x y, x z + z^2), binding on all of Gamma_C with pressure 1"
physics = "elasticity"
poisson = 0.3
geometry = contact_box()
maxh = 0.6
u = CF((x * z + z * z, y * z + x * y, x * z + z * z))
_material = Elasticity(poisson=poisson, dim=3)
_mu, _lam = _material.mu, _material.lam
# on z = 0: grad u = [[z, 0, x + 2z], [y, x + z, y], [z, 0, x + 2z]] -> [[0, 0, x], [y, x, y], [0, 0, x]],
# div u = z + x + z + x + 2z -> 2x; sigma n = -sigma e_z = -(mu (x + 0), mu (y + 0), 2 mu x + lam 2x);
# g_C = sigma n + n leaves p = 1 and sigma_t - g_t = 0
contact_load = CF((-_mu * x, -_mu * y, -(2 * _mu + 2 * _lam) * x - 1))
nu = 10.0
expected_rate = 2.0
theorem = "Remark 4.9"
singular_lines = []
