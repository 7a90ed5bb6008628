"""3D elastic Coulomb friction with a stick-slip line, exact from u itself (no contact load):
elastic-coulomb-r32's plane-strain field in the (x, z) plane, its amplitude varying along the line.

Unilateral contact with Coulomb friction (``harness.problem.friction``, static) of a 3D body
(E = 1, Poisson ratio 0.3): Omega = (-1, 1)^2 x (0, 1), Gamma_C = the bottom face z = 0
(n = -e_z, p = -sigma_zz), Gamma_u = the top, Gamma_g = the four sides; mu_F = 1/2. The friction
force sigma_t = -(sigma_xz, sigma_yz) lies in the disc of radius mu_F p and equals
-mu_F p u_t/|u_t| where u_t = (u_x, u_y) does not vanish. Stick on x < 0, slip on x > 0;
(rho, theta) the polar coordinates of (x, z) about the line {x = 0, z = 0}.

U = (s z / mu, 0, -b z) + c (m_x, 0, m_z)(x, z) is elastic-coulomb-r32's field in the (x, z)
plane (its docstring derives it: the Coulomb stick-slip mode m of exponent l = 3/2 + delta,
delta = arctan(mu_F (kappa - 1)/(kappa + 1))/pi = 0.04516, ``harness.problem.functions.coulomb_stick_slip_series``);
a plane-strain field is a 3D one (u_y = 0, nothing depends on y). Here

    u = w(y) U(x, z),   w = 1 + y^2 / 2 in [1, 3/2],   s = 1, b = 2/(lambda + 2 mu), c = 1.

Why this is exact for Coulomb: u_y = 0 and div u = w div U, so on z = 0 sigma_zz(u) = w sigma_zz(U),
sigma_xz(u) = w sigma_xz(U), and sigma_yz(u) = mu (d_z u_y + d_y u_z) = mu w' U_z = 0 (U_z = 0 on
Gamma_C on both sides): every stress on Gamma_C is U's times w > 0, and Coulomb's conditions are
positively homogeneous in (p, sigma_t). On Gamma_C (u_z = 0 on both sides: contact everywhere):
  x > 0: u_t = w c kappa cos(pi delta)/(mu (kappa + 1)) x^l e_x,
         p = w (P0 + c l (kappa - 1) cos(pi delta)/(kappa + 1) x^{l-1}) in [2, 3.66] (P0 = 2),
         (sigma_xz, sigma_yz) = (mu_F p, 0): sigma_t = -mu_F p u_t/|u_t|              -- slip;
  x < 0: u = 0, p = w P0 in [2, 3], (sigma_xz, sigma_yz) = w (s - c l |x|^{l-1}, 0), inside the
         disc of radius mu_F p = w s for c <= 2 s / l                                   -- stick.
The y-dependence costs a volume load, bounded and explicit: with D = d_x U_x + d_z U_z and
Navier's equations of U in the plane, div sigma(w U) = mu w'' U + (lambda + mu) w' D e_y, so
    f = -(mu U_x, (lambda + mu) y D, mu U_z)        (w' = y, w'' = 1).
The slip direction is e_x all along the line: a slip direction that turns along it (as in
elastic-tresca-3d) is not exact for Coulomb without a contact load -- the antiplane stick-slip
field's exponent stays 3/2 (its slip face condition does not involve the pressure) while the
in-plane one's is 3/2 + delta, so u_t/|u_t| would turn with x too and the force could not follow it.
Regularity: D^2 u ~ rho^{l-2} across the line, nu = 5/2 + delta; no theorem (Coulomb, 3D); the
expected rate h^{nu - 1} is the best approximation's (conjectured). tests/test_coulomb_exact.py
checks every Coulomb condition and the load with SymPy; the box is two boxes glued along x = 0,
so every mesh has edges along the stick-slip line.
"""
from ngsolve import CF, y, z

from harness.problem import Coulomb, Elasticity, contact_box, coulomb_stick_slip_exponent, stick_slip_mode

name = "elastic-coulomb-3d"
description = "3D elastic Coulomb friction: stick-slip along the line x = 0 of Gamma_C, amplitude varying along it"
physics = "elasticity"
young, poisson = 1.0, 0.3
regime = "5/2 < nu < 3 (delta = 0.045 above Tresca's 5/2), 3D"
theorem = "none (Coulomb; Section 6: 3D open in the paper)"
conjectured = True

s, mu_F, c = 1.0, 0.5, 1.0
friction = Coulomb(coefficient=mu_F)

material = Elasticity(young, poisson, dim=3)
EXPONENT = coulomb_stick_slip_exponent(material, mu_F)
nu = 1 + EXPONENT
expected_rate = EXPONENT

geometry = contact_box(split_at=0.0)
transition_curve = [[(0.0, -1.0), (0.0, 1.0)]]
singular_lines = [((0.0, -1.0, 0.0), (0.0, 1.0, 0.0))]
# three P2 unknowns per node: a coarser start than the scalar 3D cases, as elastic-tresca-3d
maxh = 0.4

mu, lam = material.mu, material.lam
b = s / mu_F / (lam + 2 * mu)      # the pressure P0 = s / mu_F at w = 1
mode, mode_gradient = stick_slip_mode(material, coordinates="xz", with_gradient=True, coefficient=mu_F)
U = CF((s / mu * z, 0.0, -b * z)) + c * mode
grad_U = CF((0.0, 0.0, s / mu, 0.0, 0.0, 0.0, 0.0, 0.0, -b), dims=(3, 3)) + c * mode_gradient
w = 1 + y * y / 2
u = w * U
# grad(w U) = w grad U + U (x) grad w, grad w = (0, y, 0)
grad_u = w * grad_U + CF((0.0, y * U[0], 0.0, 0.0, 0.0, 0.0, 0.0, y * U[2], 0.0), dims=(3, 3))
D = grad_U[0, 0] + grad_U[2, 2]
f = CF((-mu * U[0], -(lam + mu) * y * D, -mu * U[2]))

# only the contact laws (Nitsche, penalty) solve the 3D disc, and the default report runs no
# weak method on 3D cases (``harness.study.chain.run.PROFILES``, "weak_3d"): the fine profile's case
report_profile = "fine"
