"""transition-r32 lifted by a smooth gap: u = alpha - r^{3/2} sin(3 theta/2).

alpha = 0.1 (1 + x^2 + y) has d(alpha)/dn = -0.1 on Gamma_C (n = -e_y), so with the contact
load g_C = -0.1 the Signorini conditions of u - alpha are those of transition-r32."""
from ngsolve import atan2, sin, sqrt, x, y

from harness.problem import contact_strip

name = "gap-transition"
description = "transition-r32 with a gap and a contact-boundary load"
theorem = "4.1 ii, 5.1 ii"
nu = 2.5
expected_rate = 1.5
geometry = contact_strip(breaks=[0.0])
maxh = 0.25
gap = 0.1 * (1 + x * x + y)
contact_load = -0.1
u = gap - sqrt(x * x + y * y) ** 1.5 * sin(1.5 * atan2(y, x))
