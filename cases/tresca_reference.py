"""Tresca friction without a closed form: a loaded membrane held by friction of a varying threshold.

The scalar Tresca problem (``harness.problem.friction``) on Omega = (-1, 1) x (0, 1): f = 1,
u = 0 on the top (Gamma_u), d_n u = 0 on the sides (Gamma_g), and on the bottom Gamma_C friction
with the threshold s(x) = 1/2 + 3x/10. Held everywhere (u = 0 on Gamma_C too) the solution would
be y (1 - y)/2, whose flux on Gamma_C is d_n u = -1/2: friction could hold it where s >= 1/2
(x >= 0) and not where s < 1/2. The left part slips (u > 0, d_n u = -s) and its slip loads the
rest, so the stick zone is smaller than x > 0: one stick-slip point, at x = 0.354 by the nodal
rows' ``qoi_stick_slip_point`` (0.3543 at 1.5e5 dofs), that nobody placed: it falls inside
contact edges, unlike the exact cases' points at mesh vertices.

Regularity. At a stick-slip point of a straight Gamma_C with smooth data the leading singular
function is r^{3/2} cos(3 theta/2) (cases/tresca_r32.py): u in H^{5/2 - eps}, nu = 5/2. The
corners of Gamma_C with the sides are right angles with a Neumann side: the stick corner's
leading term r sin(theta) is smooth, the slip corner's r^2 cos(2 theta) too. Rates: P2's
conjectured h^{3/2}, P1 h.

Errors: against the nodal P2 solution two levels finer (``reference_levels``).
"""
from ngsolve import x

from harness.problem import Tresca, contact_strip

name = "tresca-reference"
description = "Tresca friction, f = 1 held by a threshold 1/2 + 3x/10: stick-slip point off the vertices"
regime = "2 < nu <= 5/2 (stick-slip point off the mesh vertices)"
theorem = "friction analogue of 4.1 ii, 5.1 ii"
nu = 2.5
expected_rate = 1.5

friction = Tresca(threshold=0.5 + 0.3 * x)
geometry = contact_strip(breaks=[])
maxh = 0.5

f = 1
dirichlet = 0
neumann = 0
singular_points = []            # the stick-slip point is unknown; the data are smooth everywhere
reference_levels = 2
