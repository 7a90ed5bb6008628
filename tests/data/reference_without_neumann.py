"""A reference case (no u) that forgets its Neumann data: must be refused at load time."""
from harness.problem import contact_strip

name = "reference-without-neumann"
description = "no u, no neumann"
geometry = contact_strip(breaks=[])
maxh = 0.5
f = -1.0
dirichlet = 1.0
