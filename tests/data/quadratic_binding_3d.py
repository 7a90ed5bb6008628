"""A 3D exact solution in P2: u = x z + z^2 on the box (-1, 1)^2 x (0, 1), binding on all of
Gamma_C (the bottom z = 0, n = -e_z: u = 0) with pressure du/dn - g_C = 1: every P2 method
reproduces it, and the 3D residual estimator must vanish there (tests/test_adaptive_3d.py)."""
from ngsolve import x, z

from harness.problem import contact_box

name = "quadratic-binding-3d"
description = "3D: u = x z + z^2, binding on all of Gamma_C with pressure 1"
geometry = contact_box()
maxh = 0.6
u = x * z + z * z
f = -2
# du/dn = -u_z = -x on z = 0: g_C = -x - 1 leaves the pressure du/dn - g_C = 1 > 0
contact_load = -x - 1
nu = 10.0
expected_rate = 2.0
theorem = "Remark 4.9"
singular_lines = []
