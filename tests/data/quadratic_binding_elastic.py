"""An elastic exact solution in P2: u = (x y + y^2, x y + y^2) on the unit square (plane strain,
Poisson ratio 0.3), binding on all of Gamma_C (the bottom: u . n = -u_y = 0 = the gap) with
pressure p = -(sigma_n(u) - g_n) = 1 and the frictionless condition sigma_t(u) = g_t made exact
by the contact traction g_C: every P2 method reproduces it, and the residual estimator, with its
tangential term, must vanish there (tests/test_meshes.py)."""
from ngsolve import CF, x, y

from harness.problem import Elasticity, polygon

name = "quadratic-binding-elastic"
description = "u = (x y + y^2, x y + y^2), binding on all of Gamma_C with pressure 1"
physics = "elasticity"
poisson = 0.3
geometry = polygon([(0, 0), (1, 0), (1, 1), (0, 1)], ["contact", "neumann", "dirichlet", "neumann"])
maxh = 0.4
u = CF((x * y + y * y, x * y + y * y))
_material = Elasticity(poisson=poisson)
_mu, _lam = _material.mu, _material.lam
# on y = 0 with n = (0, -1): sigma n = (-mu x, -(2 mu + lam) x); g_C = sigma n + n . 1 leaves
# p = 1 and sigma_t - g_t = 0
contact_load = CF((-_mu * x, -(2 * _mu + _lam) * x - 1))
nu = 10.0
expected_rate = 2.0
theorem = "Remark 4.9"
singular_points = []
