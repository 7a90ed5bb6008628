"""An elastic block pressed onto a parabolic rigid obstacle: no closed form (errors against a reference).

Plane strain (E = 1, Poisson 0.3), Omega = (-1, 1) x (0, 1), Gamma_C = bottom (n = -e_y),
Gamma_g = sides (traction-free), Gamma_u = top, moved by the prescribed displacement (0, -DELTA).
The obstacle y = -x^2/2 below the body: the initial gap is alpha(x) = x^2/2, so u . n - alpha
= -u_y - x^2/2 <= 0. The body touches around x = 0, on a zone whose two transition points the
solution places (inside contact edges of every mesh): r^{3/2} there (Remark 2.3).

Regularity. The top corners (+-1, 1) are clamped-free corners of angle pi/2: the clamped top
holds u_x = 0 where the free sides would expand (Poisson), so the corner mode is excited. Its
exponent l solves Williams' clamped-free equation (plane strain, kappa = 3 - 4 nu),

    kappa sin^2(l omega) = (kappa + 1)^2 / 4 - l^2 sin^2(omega),   omega = pi/2:   l = 0.7112...

(at omega = pi it gives the clamped-free half plane's l = 1/2 +- i log(kappa)/(2 pi)), more singular
than the transitions' r^{3/2}: u in H^{1 + l - eps}, so nu = 1 + l and P2's expected
H^1 rate h^l (4.2 i, 5.2 i in their elastic form) on uniform meshes; graded meshes refine
toward the two corners (``singular_points``). The bottom corners are free (separated).
"""
from math import pi, sin

from ngsolve import CF, x
from scipy.optimize import brentq

from harness.problem import contact_strip

DELTA = 0.05
POISSON = 0.3
KAPPA = 3 - 4 * POISSON
OMEGA = pi / 2
EXPONENT = brentq(lambda s: KAPPA * sin(s * OMEGA) ** 2 - (KAPPA + 1) ** 2 / 4 + s * s * sin(OMEGA) ** 2, 0.5, 0.9)

name = "elastic-parabolic-punch"
description = "elastic block pressed on the parabolic obstacle y = -x^2/2 (plane strain, Poisson 0.3), no closed form"
physics = "elasticity"
young, poisson = 1.0, POISSON
theorem = "4.2 i, 5.2 i (Remark 2.3)"
nu = 1.0 + EXPONENT
expected_rate = EXPONENT

geometry = contact_strip(breaks=[])
maxh = 0.5

f = 0
dirichlet = CF((0.0, -DELTA))
neumann = 0
gap = x * x / 2
singular_points = [(-1.0, 1.0), (1.0, 1.0)]
reference_levels = 2
