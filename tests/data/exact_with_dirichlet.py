"""A case with u that also declares Dirichlet data: ambiguous, must be refused at load time."""
from ngsolve import x

from harness.problem import contact_strip

name = "exact-with-dirichlet"
description = "u and dirichlet"
geometry = contact_strip(breaks=[])
maxh = 0.5
u = x * x
nu = 10.0
expected_rate = 2.0
theorem = "none"
dirichlet = 0.0
