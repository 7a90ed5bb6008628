"""A reference case whose P1 solve stalled at the round-off floor (issue 30): the unit square,
f = -2 pi sin(2 pi x), contact on the bottom, u = 0 on the top, natural conditions on the sides."""
from ngsolve import pi, sin, x

from harness.problem import polygon

name = "square-sine"
description = "unit square, f = -2 pi sin(2 pi x), contact at the bottom"
geometry = polygon([(0, 0), (1, 0), (1, 1), (0, 1)], ["contact", "neumann", "dirichlet", "neumann"])
maxh = 0.3
f = -2 * pi * sin(2 * pi * x)
dirichlet = 0
neumann = 0
singular_points = []
