"""Elastic Coulomb friction (plane strain) with a stick-slip point, exact from u itself (no
contact load): u = (s y / mu, -b y) + c m_l, m_l the Coulomb stick-slip mode, l = 3/2 + delta.

The problem (``harness.problem.friction``, static): -div sigma(u) = 0 in Omega = (-1, 1) x (0, 1),
E = 1, Poisson ratio 0.3 (kappa = 3 - 4 nu = 1.8); Gamma_C = bottom (n = -e_y), Gamma_g = sides,
Gamma_u = top. On Gamma_C unilateral contact with the pressure p = -sigma_yy (u . n = -u_y <= 0,
p >= 0, p u_y = 0) and Coulomb friction with mu_F = 1/2: the friction force
sigma_t = -sigma_xy e_x obeys |sigma_xy| <= mu_F p, and sigma_xy = mu_F p sign(u_x) where
u_x != 0. Wanted: contact everywhere (p > 0: strict complementarity), a stick zone x < 0 (u = 0)
meeting a slip zone x > 0 (u_x > 0, sigma_xy = mu_F p) at 0; (r, theta) polar about 0.

Construction. The smooth part u_0 = (s y / mu, -b y) vanishes on Gamma_C and has the constant
stresses sigma_xy = s, sigma_yy = -(lambda + 2 mu) b: the pressure P0 = (lambda + 2 mu) b, and
s = mu_F P0 makes it slip at the Coulomb threshold. What remains, c m, must satisfy near 0 the
homogeneous conditions: clamped on theta = pi (stick), and on theta = 0 u_y = 0 with
sigma_xy(m) = mu_F p(m) = -mu_F sigma_yy(m) -- the slip condition is linear in u once the slip
direction is known. Tresca's l = 3/2 mode (elastic-tresca-r32,
``harness.problem.functions.stick_slip_mode``) does not: it has sigma_xy = 0 but a normal
stress sigma_yy = -(3/2)(kappa - 1)/(kappa + 1) x^{1/2} of its own on the slip side (zero on the
stick side), so u_0 + c (Tresca mode) gives p = P0 + O(x^{1/2}) and a slip-side shear s: not
mu_F p. Exact Coulomb with no contact load therefore needs the Coulomb local problem: Williams'
ansatz with the face conditions (u_theta = 0, sigma_rtheta + mu_F sigma_thetatheta = 0) at
theta = 0, (u_r = u_theta = 0) at theta = pi has the determinant (SymPy)

    4 l mu kappa sin(pi l) ((kappa + 1) cos(pi l) + mu_F (kappa - 1) sin(pi l)),

whose non-integer roots are cot(pi l) = -mu_F (kappa - 1)/(kappa + 1): real, simple, and for
mu_F > 0 (slip along +x; the other slip direction is -mu_F) shifted upwards from Tresca's 3/2:
    l = 3/2 + delta,  delta = arctan(mu_F (kappa - 1)/(kappa + 1)) / pi = arctan(1/7)/pi = 0.04516
here (mu_F (kappa - 1)/(kappa + 1) = 1/7). l = 1/2 + delta is excluded as l = 1/2 is for Tresca
(unbounded stick-side shear). The mode (``harness.problem.functions.coulomb_stick_slip_series``),
scaled so that its stick-side shear is -l |x|^{l-1}, has on Gamma_C
  theta = 0:  m_y = 0, m_x = kappa cos(pi delta)/(mu (kappa + 1)) x^l,
              sigma_yy(m) = -l (kappa - 1) cos(pi delta)/(kappa + 1) x^{l-1}, sigma_xy(m) = -mu_F sigma_yy(m);
  theta = pi: m = 0, sigma_yy(m) = 0, sigma_xy(m) = -l |x|^{l-1}.
Here s = 1, mu_F = 1/2 (P0 = 2, b = 2/(lambda + 2 mu)), c = 1. On Gamma_C (u_y = 0 on both sides:
contact everywhere):
  x > 0: u_x = c kappa cos(pi delta)/(mu (kappa + 1)) x^l > 0,
         p = P0 + c l (kappa - 1) cos(pi delta)/(kappa + 1) x^{l-1} in [2, 2.437],
         sigma_xy = s + mu_F (p - P0) = mu_F p                                    -- slip;
  x < 0: u = 0, p = P0 = 2, sigma_xy = s - c l |x|^{l-1} in [1 - l, 1] = [-0.545, 1]: inside
         [-mu_F p, mu_F p] = [-1, 1] for c <= 2 s / l (|x| <= 1)                   -- stick.
f = 0 (a linear field and a Kolosov-Muskhelishvili field), g_C = 0: p and the threshold mu_F p
are u's own, so the field is exact for Coulomb without any manufactured contact load.
Regularity: D^2 u ~ r^{l-2}, u in H^{l + 1 - eps}, nu = 5/2 + delta = 2.545 -- the same local
structure as Tresca's r^{3/2} (clamped against a slipping face), its exponent shifted by the
pressure's coupling. No theorem gives a Coulomb rate; the expected P2 rate h^{min(nu - 1, 2)} =
h^{1.545} is the best approximation's (conjectured; the Tresca analogue at nu = 5/2 is h^{3/2}).
tests/test_coulomb_exact.py checks the determinant, the mode and this field (Navier, every
Coulomb condition on both sides) with SymPy.
"""
from ngsolve import CF, y

from harness.problem import Coulomb, Elasticity, contact_strip, coulomb_stick_slip_exponent, stick_slip_mode

name = "elastic-coulomb-r32"
description = "elastic Coulomb friction, s y/mu e_x - b y e_y + r^{3/2+delta} stick-slip mode: stick-slip point at the middle of Gamma_C"
physics = "elasticity"
young, poisson = 1.0, 0.3
regime = "5/2 < nu < 3 (delta = 0.045 above Tresca's 5/2)"
theorem = "none for Coulomb; friction analogue of 4.1 ii, 5.1 ii (Remark 2.3) for Tresca"
conjectured = True

s, mu_F, c = 1.0, 0.5, 1.0
friction = Coulomb(coefficient=mu_F)

material = Elasticity(young, poisson)
EXPONENT = coulomb_stick_slip_exponent(material, mu_F)
nu = 1 + EXPONENT
expected_rate = EXPONENT

# the stick-slip point (0, 0) is a polygon corner, hence a vertex of every mesh
geometry = contact_strip(breaks=[0.0])
maxh = 0.25

b = s / mu_F / (material.lam + 2 * material.mu)      # the pressure P0 = s / mu_F
mode, mode_gradient = stick_slip_mode(material, with_gradient=True, coefficient=mu_F)
u = CF((s / material.mu * y, -b * y)) + c * mode
grad_u = CF((0.0, s / material.mu, 0.0, -b), dims=(2, 2)) + c * mode_gradient
f = 0
singular_points = [(0.0, 0.0)]
report_profile = "default"

# Asymptotic by five P2 levels: over levels 0-5 the pairwise H^1 rates of nitsche (theta = 1, 0,
# -1) are 1.541, 1.544, 1.545, 1.545, 1.545 and nitsche-p1's 1.002 ... 1.000: the sixth level
# (2.9e5 P2 dofs) moves no fitted rate by more than 0.001
asymptotic_levels = 5
asymptotic_levels_p1 = 5
