"""The elastic r^{3/2} transition of elastic-transition-r32, nearly incompressible (Poisson 0.49).

The same geometry and the same construction (see that case): the exponent 3/2 of the roller /
traction-free half plane does not depend on the Poisson ratio, so nu = 5/2 and the bound
h^{3/2} stay; only the constants grow with lambda / mu = 2 nu / (1 - 2 nu) = 49. Plain P1
locks as lambda / mu grows (its error constant grows with it); P2 locks less. The case shows
how much at this Poisson ratio.
"""
from math import pi

from harness.problem import Elasticity, contact_strip, roller_free_mode

name = "elastic-transition-incompressible"
description = "elastic r^{3/2} transition, nearly incompressible (plane strain, Poisson 0.49)"
physics = "elasticity"
young, poisson = 1.0, 0.49
regime = "2 < nu <= 5/2"
theorem = "4.1 ii, 5.1 ii (Remark 2.3)"
nu = 2.5
expected_rate = 1.5

geometry = contact_strip(breaks=[0.0])
maxh = 0.5

u, grad_u = roller_free_mode(1.5, pi, Elasticity(young, poisson), with_gradient=True)
f = 0
singular_points = [(0.0, 0.0)]
# The default report stops at six levels (the fine profile runs eight): the seventh P2 level and
# P1's eighth cost a large share of the report's five minutes and change no verdict.
report_levels = {"default": 6}
