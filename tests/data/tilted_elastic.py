"""elastic-transition-r32 turned by 0.3 rad about the origin: Gamma_C no longer horizontal, so
the rotated frame at its nodes (``fem.rotated_frame.RotatedFrame``) is not the identity."""
from math import cos, pi, sin

from harness.problem import Elasticity, polygon, roller_free_mode

ANGLE = 0.3
name = "tilted-elastic"
description = "the elastic r^{3/2} transition on a tilted strip"
physics = "elasticity"
poisson = 0.3
theorem = "4.1 ii, 5.1 ii (Remark 2.3)"
nu, expected_rate = 2.5, 1.5


def _turned(px, py):
    return cos(ANGLE) * px - sin(ANGLE) * py, sin(ANGLE) * px + cos(ANGLE) * py


geometry = polygon([_turned(*p) for p in [(-1, 0), (0, 0), (1, 0), (1, 1), (-1, 1)]],
                   ["contact", "contact", "neumann", "dirichlet", "neumann"])
maxh = 0.5
u, grad_u = roller_free_mode(1.5, pi, Elasticity(poisson=poisson), angle=ANGLE, with_gradient=True)
f = 0
singular_points = [(0.0, 0.0)]
