"""Elastic Tresca friction (plane strain) with a stick-slip point: u = (s y / mu, 0) + c U_{3/2}.

The problem (``harness.problem.friction``): -div sigma(u) = 0 in Omega = (-1, 1) x (0, 1),
E = 1, Poisson ratio 0.3; Gamma_C = bottom (n = -e_y), Gamma_g = sides, Gamma_u = top. On
Gamma_C bilateral contact u_y = 0 and Tresca friction with the threshold s = 1: the friction
force sigma_t = sigma(u) n - sigma_n n = -sigma_xy e_x obeys |sigma_xy| <= s, and
sigma_xy = s sign(u_x) where u_x != 0. We want a stick zone x < 0 (u = 0) meeting a slip zone
x > 0 (u_x > 0, sigma_xy = s) at 0, polar coordinates (r, theta) about 0, theta in [0, pi].

Why a singular field, and which. The smooth shear field u_0 = (s y / mu, 0) (sigma_xy = s
everywhere, u_0 = 0 on Gamma_C) carries the slip side's shear. What remains must satisfy, near
0, the homogeneous conditions of a half plane:
  theta = 0 (slip):  u_y = 0, sigma_xy = 0        -- roller;
  theta = pi (stick): u_x = u_y = 0                -- clamped (stick with bilateral contact).
Williams' ansatz u = r^l (u_r(theta), u_theta(theta)) in Navier's equations gives, with
kappa = 3 - 4 nu (plane strain), the four-parameter family
  u_r     = r^l (A cos((l+1) t) + B sin((l+1) t) + C (kappa - l) cos((l-1) t) - D (kappa - l) sin((l-1) t)),
  u_theta = r^l (-A sin((l+1) t) + B cos((l+1) t) + C (kappa + l) sin((l-1) t) + D (kappa + l) cos((l-1) t))
(the Kolosov-Muskhelishvili potentials phi = a z^l, psi = b z^l written in polar components).
The four face conditions (u_theta = sigma_r theta = 0 at t = 0, u_r = u_theta = 0 at t = omega)
are a 4 x 4 system whose determinant SymPy factors as
    2 l mu (kappa + 1) (kappa sin(2 l omega) - l sin(2 omega)) = 0,
at omega = pi:  kappa sin(2 pi l) = 0,   l = 1/2, 1, 3/2, 2, ...
-- the clamped/roller ("anticrack") equation: real, simple roots, and the same for every
Poisson ratio (kappa in (1, 3] only scales it; no oscillating complex exponents, unlike the
clamped/free interface wedge). The integer roots are polynomials (l = 1: u = (0, y), l = 2: a
quadratic): smooth. For half-integer l the null vector is B = D = 0, C = A / (kappa + l); the
scale A = (kappa + l) / (2 mu (kappa + 1)) gives (``harness.problem.functions.stick_slip_series``)
    u_x(theta = 0) = kappa / (mu (kappa + 1)) r^l > 0,   sigma_xy(theta = pi) = (-1)^(l - 1/2) l r^(l-1).
Which exponents the friction inequalities admit (as r^{1/2} and r^{5/2} in the scalar case):
  l = 1/2: sigma_xy ~ r^{-1/2} on the stick side, unbounded for either sign of c: it breaks
      |sigma_xy| <= s. Excluded.
  l = 3/2: slip u_x = c kappa / (mu (kappa + 1)) x^{3/2}, positive for c > 0, so the slip side
      needs sigma_xy = +s (the smooth field's), and the stick side then has
      sigma_xy = s - (3/2) c |x|^{1/2}: inside [-s, s] for 0 < c <= 4 s / 3 (|x| <= 1). Admitted:
      slip and stick-side shear have opposite signs.
  l = 5/2 (as the only singular term): the stick-side shear s + (5/2) c |x|^{3/2} leaves the
      disc. Excluded, as r^{5/2} in the scalar case (the signs alternate with l).
So the leading stick-slip singularity is r^{3/2} for every Poisson ratio, the same exponent as a
frictionless contact/separation point (elastic-transition-r32), but a different mode (clamped,
not traction-free, on the stick side). Here s = 1, c = 1: on Gamma_C
  x > 0: u_y = 0, u_x = c kappa / (mu (kappa + 1)) x^{3/2} > 0, sigma_xy = s   -- slip;
  x < 0: u = 0, sigma_xy = s - (3/2) c |x|^{1/2} in [-1/2, 1]                  -- stick.
f = 0 (a linear field and a Kolosov-Muskhelishvili field). Regularity: D^2 u ~ r^{-1/2}, u in
H^{5/2 - eps}, nu = 5/2; the friction analogue of the P2 rate h^{min(nu - 1, 3/2)} = h^{3/2}
(Chouly 2014 for Nitsche-Tresca; the nodal and mean analogues read from the paper's Theorems
4.1 ii and 5.1 ii). tests/test_tresca_exact.py checks the determinant, the modes' signs and this
field (Navier, every Tresca condition on both sides) with SymPy.
"""
from ngsolve import CF, y

from harness.problem import Elasticity, Tresca, contact_strip, stick_slip_mode

name = "elastic-tresca-r32"
description = "elastic Tresca friction, s y/mu e_x + r^{3/2} stick-slip mode: stick-slip point at the middle of Gamma_C"
physics = "elasticity"
young, poisson = 1.0, 0.3
regime = "2 < nu <= 5/2"
theorem = "friction analogue of 4.1 ii, 5.1 ii (Remark 2.3)"
nu = 2.5
expected_rate = 1.5

s, c = 1.0, 1.0
friction = Tresca(threshold=s)

# the stick-slip point (0, 0) is a polygon corner, hence a vertex of every mesh
geometry = contact_strip(breaks=[0.0])
maxh = 0.25

material = Elasticity(young, poisson)
mode, mode_gradient = stick_slip_mode(material, with_gradient=True)
u = CF((s / material.mu * y, 0.0)) + c * mode
grad_u = CF((0.0, s / material.mu, 0.0, 0.0), dims=(2, 2)) + c * mode_gradient
f = 0
singular_points = [(0.0, 0.0)]
