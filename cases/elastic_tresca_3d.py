"""3D elastic Tresca friction with a stick-slip line and a slip direction that turns along it.

Bilateral contact with Tresca friction (``harness.problem.friction``) of a 3D body (E = 1,
Poisson ratio 0.3): Omega = (-1, 1)^2 x (0, 1), Gamma_C = the bottom face z = 0 (n = -e_z),
Gamma_u = the top, Gamma_g = the four sides. On Gamma_C: u_z = 0, and the friction force
sigma_t = -(sigma_xz, sigma_yz) lies in the disc of radius s = 1 and equals -s u_t/|u_t| where
the tangential slip u_t = (u_x, u_y) does not vanish -- a 2-vector, so the slip direction can
turn. Stick on x < 0, slip on x > 0; (rho, theta) the polar coordinates of (x, z) about the line
{x = 0, z = 0}. Three exact pieces:

* m = (m_x, 0, m_z)(x, z): elastic-tresca-r32's plane-strain stick-slip mode in the (x, z) plane
  (``harness.problem.functions.stick_slip_mode``: roller on theta = 0, clamped on theta = pi, the
  exponent 3/2 of the characteristic equation kappa sin(2 pi l) = 0, admissible as shown there),
  a plane-strain field is a 3D one (nothing depends on y, u_y = 0): div sigma(m) = 0. On
  z = 0: m_z = 0; m_x = P x^{3/2} (x > 0, P = kappa / (mu (kappa + 1))), sigma_xz(m) = 0 there,
  m = 0 and sigma_xz(m) = -(3/2) |x|^{1/2} on x < 0; sigma_yz(m) = 0.
* v = rho^{3/2} cos(3 theta/2), the antiplane (mode III) stick-slip field: u = (0, v, 0) has
  div sigma = mu Laplace(v) e_y = 0; its exponents are the scalar ones (v = 0 on theta = pi,
  d_z v = 0 on theta = 0: l = 1/2, 3/2, ..., 3/2 the first the friction inequality admits,
  tresca-r32). On z = 0: v = x^{3/2} (x > 0), sigma_yz = mu d_z v = -(3/2) mu |x|^{1/2} (x < 0).
* (s z / mu) e(y): u = 0 on Gamma_C, tangential shear (sigma_xz, sigma_yz) = s e(y) there.

    u = (s z / mu) e(y) + a m + b y (0, v, 0),   e(y) = (a P, b y) / |(a P, b y)|,   a = 1, b = 2.

On Gamma_C (u_z = a m_z = 0 on both sides: bilateral):
  x > 0: u_t = (a P, b y) x^{3/2}, direction e(y) (turning from -50 to +50 degrees along the
         line), and (sigma_xz, sigma_yz) = s e(y): sigma_t = -s u_t/|u_t|            -- slip;
  x < 0: u_t = 0 and (sigma_xz, sigma_yz) = s e(y) - (3/2) |x|^{1/2} (a, mu b y): not parallel
         to e(y); inside the disc iff (3/2)|x|^{1/2} |q|^2 <= 2 s e . q, q = (a, mu b y),
         which holds for |x| <= 1, |y| <= 1 (tightest at x = -1, y = +-1:
         (3/2) |q|^2 = 2.39 <= 2 s e . q = 2.46)                                        -- stick.
The y-dependence costs a volume load, bounded and explicit: with lambda, mu the Lame constants,
N = |(a P, b y)|, e_x = a P / N, e_y = b y / N,
    f = -(s z e_x'' + (lambda + mu) b v_x,  (lambda + 2 mu) s z e_y'' / mu,
          (lambda + mu) (s e_y' / mu + b v_z)),
e_x' = -a P b^2 y / N^3, e_x'' = a P b^2 (2 b^2 y^2 - a^2 P^2) / N^5, e_y' = a^2 P^2 b / N^3,
e_y'' = -3 a^2 P^2 b^3 y / N^5. Regularity: D^2 u ~ rho^{-1/2} across the line, u in
H^{5/2 - eps}, nu = 5/2; the 2D rate h^{3/2} is the expectation (3D: no theorem, Section 6).
tests/test_tresca_exact.py checks every Tresca condition with SymPy; the box is two boxes glued
along x = 0, so every mesh has edges along the stick-slip line.
"""
from ngsolve import CF, cos, sin, sqrt, y, z

from harness.problem import Elasticity, Tresca, contact_box, polar, stick_slip_mode

name = "elastic-tresca-3d"
description = "3D elastic Tresca friction: stick-slip along the line x = 0 of Gamma_C, slip direction turning along it"
physics = "elasticity"
young, poisson = 1.0, 0.3
regime = "2 < nu <= 5/2, 3D"
theorem = "friction analogue of 4.1 ii, 5.1 ii (Remark 2.3); Section 6 (3D open in the paper)"
conjectured = True
nu = 2.5
expected_rate = 1.5

s, a, b = 1.0, 1.0, 2.0
friction = Tresca(threshold=s)

geometry = contact_box(split_at=0.0)
transition_curve = [[(0.0, -1.0), (0.0, 1.0)]]
singular_lines = [((0.0, -1.0, 0.0), (0.0, 1.0, 0.0))]
# three P2 unknowns per node: a coarser start than the scalar 3D cases, as elastic-transition-3d
maxh = 0.4

material = Elasticity(young, poisson, dim=3)
mu, lam = material.mu, material.lam
P = material.kappa / (mu * (material.kappa + 1))
mode, mode_gradient = stick_slip_mode(material, coordinates="xz", with_gradient=True)
rho, theta = polar(0.0, py=z)
v = rho ** 1.5 * cos(1.5 * theta)
v_x, v_z = 1.5 * sqrt(rho) * cos(theta / 2), -1.5 * sqrt(rho) * sin(theta / 2)

N = sqrt((a * P) ** 2 + (b * y) ** 2)
e_x, e_y = a * P / N, b * y / N
de_x, de_y = -a * P * b * b * y / N ** 3, a * a * P * P * b / N ** 3
dde_x, dde_y = a * P * b * b * (2 * b * b * y * y - (a * P) ** 2) / N ** 5, -3 * (a * P) ** 2 * b ** 3 * y / N ** 5

u = CF((s / mu * z * e_x, s / mu * z * e_y + b * y * v, 0.0)) + a * mode
grad_u = CF((0.0, s / mu * z * de_x, s / mu * e_x,
             b * y * v_x, s / mu * z * de_y + b * v, s / mu * e_y + b * y * v_z,
             0.0, 0.0, 0.0), dims=(3, 3)) + a * mode_gradient
f = CF((-(s * z * dde_x + (lam + mu) * b * v_x),
        -(lam + 2 * mu) * s * z * dde_y / mu,
        -(lam + mu) * (s * de_y / mu + b * v_z)))

# only the contact laws (Nitsche, penalty) solve the 3D disc, and the default report runs no
# weak method on 3D cases (``study.chain.run.PROFILES``, "weak_3d"): the fine profile's case
report_profile = "fine"
