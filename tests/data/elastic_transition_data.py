"""elastic-transition-r32 declared by its data, without u: a reference case whose exact solution
is known, to check the errors against a reference with the exact ones (tests/test_elastic_reference.py).
The Dirichlet data are u on the top, the Neumann data the traction sigma(u) n on the sides
x = +-1 (n = (+-1, 0)), f = -div sigma(u) = 0; no gap, no contact load."""
from math import pi

from ngsolve import CF, IfPos, x

from harness.problem import Elasticity, contact_strip, roller_free_mode

name = "elastic-transition-r32-data"
description = "elastic-transition-r32 declared by its data (no u)"
physics = "elasticity"
young, poisson = 1.0, 0.3
geometry = contact_strip(breaks=[0.0])
maxh = 0.5

_material = Elasticity(young, poisson)
_u, _grad_u = roller_free_mode(1.5, pi, _material, with_gradient=True)
_stress = _material.stress(_grad_u)
_outward_x = IfPos(x, 1.0, -1.0)            # n = (+-1, 0) on the sides

f = 0
dirichlet = _u
neumann = CF((_outward_x * _stress[0, 0], _outward_x * _stress[1, 0]))
singular_points = [(0.0, 0.0)]
reference_levels = 2
