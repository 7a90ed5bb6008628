"""An exact solution in P2: u = x y + y^2 on the unit square, binding on all of Gamma_C (the
bottom, u = 0) with pressure du/dn - g_C = 1: every P2 method reproduces it, and the residual
estimator must vanish there (tests/test_meshes.py)."""
from ngsolve import x, y

from harness.problem import polygon

name = "quadratic-binding"
description = "u = x y + y^2, binding on all of Gamma_C with pressure 1"
geometry = polygon([(0, 0), (1, 0), (1, 1), (0, 1)], ["contact", "neumann", "dirichlet", "neumann"])
maxh = 0.4
u = x * y + y * y
f = -2
# du/dn = -u_y = -x on y = 0: g_C = -x - 1 leaves the pressure du/dn - g_C = 1 > 0
contact_load = -x - 1
nu = 10.0
expected_rate = 2.0
theorem = "Remark 4.9"
singular_points = []
