"""Lacks the 'dirichlet' label."""
from ngsolve import x

from harness.problem import polygon

name = "no-dirichlet"
description = "geometry without Gamma_u"
theorem = "none"
nu = 3
expected_rate = 2
geometry = polygon([(0, 0), (1, 0), (1, 1), (0, 1)], ["contact", "neumann", "neumann", "neumann"])
maxh = 0.5
u = x * 0
