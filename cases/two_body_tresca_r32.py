"""Two bodies with Tresca friction between them, non-matching meshes: tresca-r32's stick-slip
point on the interface (``harness.problem.bodies``, ``harness.problem.friction``).

Upper body (-1, 1) x (0, 1), lower body its mirror image, Gamma_C = {y = 0} between them,
Gamma_u the outer horizontal sides, Gamma_g the vertical ones. Upper: u = s y + c r^{3/2}
cos(3 theta/2) (cases/tresca_r32.py, s = c = 1); lower: its mirror image, whose scalar variable
is -u_2 (``harness.problem.bodies``). Friction acts on the jump [u] = u_1 - u_2 = 2 u on Gamma_C:
j(v) = int s |[v]|. The jump vanishes for x < 0 (stick, |d_n u| <= s on both sides) and is
2 x^{3/2} > 0 for x > 0 (slip, d_n u = -s on both): each body's flux is tresca-r32's, and the
friction force balances across Gamma_C. u in H^{5/2 - eps} on each body: the one-body rate
h^{3/2} is what the dual mortar methods should reach (a conjecture, as for one body).

Non-matching meshes as two-body-transition-r32: maxh 1/4 above, 1/6 below with a break at
x = -0.9 (element sizes 2:3 on Gamma_C); the stick-slip point 0 is a corner of both.
"""
from harness.problem import MirrorBody, Tresca, contact_strip, scalar_stick_slip

name = "two-body-tresca-r32"
description = "two bodies, Tresca friction on the jump, non-matching meshes (2:3): stick-slip point at 0"
regime = "2 < nu <= 5/2"
theorem = "friction analogue of 4.1 ii, 5.1 ii (one body)"
nu = 2.5
expected_rate = 1.5

s, c = 1.0, 1.0
friction = Tresca(threshold=s)
geometry = contact_strip(breaks=[0.0])
maxh = 0.25
second_body = MirrorBody(geometry=contact_strip(breaks=[-0.9, 0.0]), maxh=1 / 6)

u, grad_u = scalar_stick_slip(s, c)   # grad u in closed form: cheaper per point than the derived one
f = 0
singular_points = [(0.0, 0.0)]

# the default report holds one scalar and one elastic Tresca case (tresca-r32,
# elastic-tresca-r32) within its time goal; this one is the fine profile's (``report --case``
# runs it alone)
report_profile = "fine"
