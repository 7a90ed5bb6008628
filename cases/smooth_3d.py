"""3D: a smooth solution with a transition (Remark 4.9 in 3D): rate h^2.

Omega = (-1, 1)^2 x (0, 1), Gamma_C = the bottom face z = 0 (n = -e_z), and with w(y) = 1 + y^2/2,
    u = w(y) v(x, z),   v = max(0,-x)^3 - z max(0,x)^3 + z^2 cos(x + z)
(the 2D case `smooth` in the plane (x, z), times w > 0). On Gamma_C: u = w max(0,-x)^3 >= 0 and
du/dn = -du/dz = w max(0,x)^3 >= 0, one of them zero at every point: x < 0 free, x > 0 binding,
the transition along the straight line x = 0. f = -Laplace(u) = w f_2D - w'' v with
f_2D = -Laplace_(x,z) v as in `smooth`; it is only C^0 across the plane x = 0, so the box is
glued from two along it (no element is cut by the kink). Regularity: D^3 v jumps across x = 0:
u is in H^{7/2 - eps}, nu = 7/2; P2 cannot do better than h^2.
"""
from ngsolve import IfPos, cos, sin, x, y, z

from harness.problem import contact_box

name = "smooth-3d"
description = "3D: (1 + y^2/2) (max(0,-x)^3 - z max(0,x)^3 + z^2 cos(x+z)), transition along x = 0"
regime = "nu > 5/2, 3D"
theorem = "Section 6 (3D open in the paper)"
conjectured = True
nu = 3.5
expected_rate = 2.0

geometry = contact_box(split_at=0.0)
# the exact transition curve on Gamma_C, drawn on the report's pictures of it
transition_curve = [[(0.0, -1.0), (0.0, 1.0)]]
# nothing to grade toward (u in H^{7/2 - eps}: a graded P2 mesh is a uniform one)
singular_lines = []
maxh = 0.25

w = 1 + 0.5 * y * y
v = IfPos(-x, -x * x * x, 0.0) - z * IfPos(x, x * x * x, 0.0) + z * z * cos(x + z)
f_2d = IfPos(-x, 6 * x, 0.0) + IfPos(x, 6 * x * z, 0.0) + (2 * z * z - 2) * cos(x + z) + 4 * z * sin(x + z)
u = w * v
f = w * f_2d - v

# the default report runs one scalar and one elastic 3D case (transition-line-3d, elastic-transition-3d);
# this one, 15-22 s of its study, in `make report-fine` and `report --case` (make report within its 3 minutes)
report_profile = "fine"
