"""Refused: u = +r^{3/2} sin(3 theta/2) is -|x|^{3/2} < 0 on the free side x < 0 of Gamma_C."""
from ngsolve import atan2, sin, sqrt, x, y

from harness.problem import contact_strip

name = "bad-sign"
description = "wrong sign of the transition singularity"
theorem = "none"
nu = 2.5
expected_rate = 1.5
geometry = contact_strip(breaks=[0.0])
maxh = 0.25
u = sqrt(x * x + y * y) ** 1.5 * sin(1.5 * atan2(y, x))
