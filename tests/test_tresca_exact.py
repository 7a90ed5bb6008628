"""The Tresca cases' exact solutions, checked symbolically with SymPy (no mesh, no NGSolve):
the Williams eigenproblem of an elastic stick-slip point (its characteristic equation, the
exponents, the signs of its modes), and for each case the PDE and every Tresca condition on both
sides of each stick-slip point -- as closed forms where SymPy reduces them, and at many sample
points of Gamma_C for the inequalities. The case modules write the same fields with NGSolve; the
last test compares them at points."""
from __future__ import annotations

import numpy as np
import pytest

sp = pytest.importorskip("sympy")

r = sp.Symbol("r", positive=True)
t = sp.Symbol("theta", real=True)
X, Y, Z = sp.symbols("x y z", real=True)
lam = sp.Symbol("lambda")
mu_, kappa_ = sp.symbols("mu kappa", positive=True)
HALF = sp.Rational(1, 2)
# samples of (0, 1]: distances to a stick-slip point along Gamma_C
DISTANCES = [sp.Rational(k, 200) for k in range(1, 201)]


# ---------------------------------------------------------------------------------------------
# polar calculus: derivatives of functions of (r, theta) along x and y
def d_x(f):
    return sp.cos(t) * sp.diff(f, r) - sp.sin(t) / r * sp.diff(f, t)


def d_y(f):
    return sp.sin(t) * sp.diff(f, r) + sp.cos(t) / r * sp.diff(f, t)


def zero(expr) -> bool:
    """expr == 0 identically in r and theta (trigonometric simplification)."""
    return sp.simplify(sp.expand_trig(sp.simplify(expr))) == 0


def lame(mu, kappa):
    """Plane strain: lambda = mu (3 - kappa) / (kappa - 1) with kappa = 3 - 4 nu."""
    return mu * (3 - kappa) / (kappa - 1)


def polar_stresses(ur, ut, mu, kappa):
    """(sigma_rr, sigma_tt, sigma_rt) of the polar displacement (u_r, u_theta), plane strain."""
    err = sp.diff(ur, r)
    ett = ur / r + sp.diff(ut, t) / r
    ert = (sp.diff(ur, t) / r + sp.diff(ut, r) - ut / r) / 2
    la = lame(mu, kappa)
    return la * (err + ett) + 2 * mu * err, la * (err + ett) + 2 * mu * ett, 2 * mu * ert


def williams(ell):
    """Williams' four-parameter ansatz r^l (u_r, u_theta) and its coefficients (A, B, C, D)."""
    A, B, C, D = sp.symbols("A B C D")
    c1, s1, cm, sm = sp.cos((ell + 1) * t), sp.sin((ell + 1) * t), sp.cos((ell - 1) * t), sp.sin((ell - 1) * t)
    ur = r**ell * (A * c1 + B * s1 + C * (kappa_ - ell) * cm - D * (kappa_ - ell) * sm)
    ut = r**ell * (-A * s1 + B * c1 + C * (kappa_ + ell) * sm + D * (kappa_ + ell) * cm)
    return ur, ut, (A, B, C, D)


def face_matrix(ell, omega):
    """The 4 x 4 system of the faces: theta = 0 roller (u_theta = sigma_rt = 0), theta = omega
    clamped (u_r = u_theta = 0), each divided by its power of r."""
    ur, ut, unknowns = williams(ell)
    _, _, srt = polar_stresses(ur, ut, mu_, kappa_)
    rows = [ut.subs(t, 0) / r**ell, srt.subs(t, 0) * r / r**ell, ur.subs(t, omega) / r**ell, ut.subs(t, omega) / r**ell]
    return sp.Matrix([[sp.diff(row, v) for v in unknowns] for row in rows]).applyfunc(sp.simplify), (ur, ut, unknowns)


# ---------------------------------------------------------------------------------------------
# the elastic stick-slip eigenproblem
def test_williams_ansatz_solves_navier():
    ur, ut, _ = williams(lam)
    srr, stt, srt = polar_stresses(ur, ut, mu_, kappa_)
    assert zero(sp.diff(srr, r) + sp.diff(srt, t) / r + (srr - stt) / r)
    assert zero(sp.diff(srt, r) + sp.diff(stt, t) / r + 2 * srt / r)


def test_stick_slip_characteristic_equation():
    """det = 2 l mu (kappa + 1)(kappa sin(2 l omega) - l sin(2 omega)); at omega = pi it is
    2 l mu kappa (kappa + 1) sin(2 pi l): the roots l = 1/2, 1, 3/2, ... are real and do not
    depend on kappa (Poisson's ratio), which is only a nonzero factor (kappa in (1, 3])."""
    omega = sp.Symbol("omega", positive=True)
    matrix, _ = face_matrix(lam, omega)
    det = sp.simplify(sp.expand_trig(matrix.det()))
    expected = 2 * lam * mu_ * (kappa_ + 1) * (kappa_ * sp.sin(2 * lam * omega) - lam * sp.sin(2 * omega))
    assert sp.simplify(sp.expand_trig(det - expected)) == 0
    at_pi = sp.simplify(det.subs(omega, sp.pi))
    assert sp.simplify(at_pi - 2 * lam * mu_ * kappa_ * (kappa_ + 1) * sp.sin(2 * sp.pi * lam)) == 0
    # sin(2 pi l) = 0 has only the real roots l = k/2 (sin w = 0 iff w = k pi, also for complex w)
    w = sp.Symbol("w")
    assert sp.solveset(sp.sin(w), w, sp.S.Complexes) == sp.ImageSet(sp.Lambda(sp.Symbol("n"), sp.pi * sp.Symbol("n")), sp.S.Integers) \
        or set(sp.solveset(sp.sin(w), w, sp.Interval(-10, 10))) == {k * sp.pi for k in range(-3, 4)}


@pytest.mark.parametrize("k", [0, 1, 2, 3])
def test_stick_slip_modes_alternate_in_sign(k):
    """Half-integer l = k + 1/2: a one-dimensional null space (B = D = 0, C = A / (kappa + l));
    u_x(theta = 0) = 2 kappa / (kappa + l) A r^l and sigma_xy(theta = pi) =
    (-1)^k 2 mu (kappa + 1) l / (kappa + l) A r^{l-1}: slip and stick-side shear of opposite
    signs (admissible as the leading term) exactly for k odd, l = 3/2, 7/2."""
    ell = k + HALF
    matrix, (ur, ut, unknowns) = face_matrix(ell, sp.pi)
    null = matrix.nullspace()
    assert len(null) == 1
    v = null[0] / null[0][0]
    A, B, C, D = unknowns
    assert [sp.simplify(e) for e in v] == [1, 0, sp.simplify(1 / (kappa_ + ell)), 0]
    sub = dict(zip(unknowns, v))
    ur, ut = ur.subs(sub), ut.subs(sub)
    _, stt, srt = polar_stresses(ur, ut, mu_, kappa_)
    slip = sp.simplify(ur.subs(t, 0) / r**ell)                          # u_x on theta = 0
    shear = sp.simplify(srt.subs(t, sp.pi) / r**(ell - 1))              # sigma_xy on theta = pi
    assert sp.simplify(slip - 2 * kappa_ / (kappa_ + ell)) == 0
    assert sp.simplify(shear - (-1) ** k * 2 * mu_ * (kappa_ + 1) * ell / (kappa_ + ell)) == 0
    # the face conditions themselves
    assert sp.simplify(ut.subs(t, 0)) == 0 and sp.simplify(srt.subs(t, 0)) == 0
    assert sp.simplify(ur.subs(t, sp.pi)) == 0 and sp.simplify(ut.subs(t, sp.pi)) == 0
    assert (sp.sign(sp.simplify(slip * shear)) == -1) == (k % 2 == 1)


# ---------------------------------------------------------------------------------------------
# the cases' fields, in polar form about their stick-slip point
NU = sp.Rational(3, 10)
MU = 1 / (2 * (1 + NU))                 # E = 1
KAPPA = 3 - 4 * NU


def stick_slip_mode_xy():
    """functions.stick_slip_series (l = 3/2): u_x + i u_y = r^l (A e^{-i l t} + C kappa e^{i l t}
    - C l e^{i (2 - l) t}), A = (kappa + l) / (2 mu (kappa + 1)), C = A / (kappa + l)."""
    ell = sp.Rational(3, 2)
    A = (KAPPA + ell) / (2 * MU * (KAPPA + 1))
    C = A / (KAPPA + ell)
    U = r**ell * (A * sp.exp(-sp.I * ell * t) + C * KAPPA * sp.exp(sp.I * ell * t) - C * ell * sp.exp(sp.I * (2 - ell) * t))
    U = sp.expand_complex(U)
    return sp.re(U), sp.im(U)


def cartesian_stresses(ux, uy, mu, kappa):
    exx, eyy, exy = d_x(ux), d_y(uy), (d_y(ux) + d_x(uy)) / 2
    la = lame(mu, kappa)
    return la * (exx + eyy) + 2 * mu * exx, la * (exx + eyy) + 2 * mu * eyy, 2 * mu * exy


def elastic_r32_field():
    s, c = 1, 1
    mx, my = stick_slip_mode_xy()
    y = r * sp.sin(t)
    return s * y / MU + c * mx, c * my, s, c


def test_elastic_tresca_r32():
    ux, uy, s, c = elastic_r32_field()
    sxx, syy, sxy = cartesian_stresses(ux, uy, MU, KAPPA)
    # Navier: div sigma = 0 (f = 0)
    assert zero(d_x(sxx) + d_y(sxy)) and zero(d_x(sxy) + d_y(syy))
    # Gamma_C, n = -e_y: bilateral u_y = 0 on both sides; friction force sigma_t = -sigma_xy e_x
    assert zero(uy.subs(t, 0)) and zero(uy.subs(t, sp.pi))
    # slip side x > 0 (theta = 0): u_x = c kappa / (mu (kappa + 1)) x^{3/2} > 0 and sigma_xy = s,
    # i.e. sigma_t = -s u_t/|u_t|
    assert sp.simplify(ux.subs(t, 0) - c * KAPPA / (MU * (KAPPA + 1)) * r ** sp.Rational(3, 2)) == 0
    assert zero(sxy.subs(t, 0) - s)
    # stick side x < 0 (theta = pi): u = 0 and sigma_xy = s - (3/2) c |x|^{1/2}, |.| <= s
    assert zero(ux.subs(t, sp.pi))
    stick_shear = sp.simplify(sxy.subs(t, sp.pi))
    assert sp.simplify(stick_shear - (s - sp.Rational(3, 2) * c * sp.sqrt(r))) == 0
    assert all(abs(stick_shear.subs(r, d)) <= s for d in DISTANCES)
    assert all(ux.subs(t, 0).subs(r, d) > 0 for d in DISTANCES)


# 3D elastic: the plane-strain stick-slip mode in the (x, z) plane and an antiplane one
ELASTIC_3D = (1, 1, 2)      # s, a, b of cases/elastic_tresca_3d.py


def test_elastic_tresca_3d():
    """u = (s z / mu) e(y) + a (m_x, 0, m_z)(x, z) + b y (0, v, 0)(x, z), e(y) = (a P, b y)/|.|:
    (theta measured in the (x, z) plane). The (x, z) mode and the antiplane v are exact; the
    y-dependence leaves a bounded load f (checked in closed form by validation). Gamma_C = {z = 0},
    n = -e_z, friction force -(sigma_xz, sigma_yz) in the disc of radius s."""
    s, a, b = ELASTIC_3D
    mx, mz = stick_slip_mode_xy()                        # (x, z) plays (x, y)
    v = r ** sp.Rational(3, 2) * sp.cos(sp.Rational(3, 2) * t)     # antiplane, harmonic
    assert zero(d_x(d_x(v)) + d_y(d_y(v)))
    P = KAPPA / (MU * (KAPPA + 1))
    ex, ey, yv = sp.symbols("e_x e_y y_0", real=True)         # e(y) and y on a line y = const
    # on z = 0: sigma_xz = mu (d_z u_x + d_x u_z), sigma_yz = mu (d_z u_y + d_y u_z), d_y u_z = a d_y m_z = 0
    sxz = s * ex + a * MU * (d_y(mx) + d_x(mz))
    syz = s * ey + b * yv * MU * d_y(v)
    # bilateral: u_z = a m_z = 0 on both sides
    assert zero(mz.subs(t, 0)) and zero(mz.subs(t, sp.pi))
    # slip side x > 0: u_t = (a m_x, b y v) = (a P, b y) x^{3/2}, force -(sigma_xz, sigma_yz) = -s e(y)
    assert zero(a * mx.subs(t, 0) - a * P * r ** sp.Rational(3, 2))
    assert zero(b * yv * v.subs(t, 0) - b * yv * r ** sp.Rational(3, 2))
    assert zero(sxz.subs(t, 0) - s * ex) and zero(syz.subs(t, 0) - s * ey)
    # stick side x < 0: u = 0 and |(sigma_xz, sigma_yz)| <= s
    assert zero(mx.subs(t, sp.pi)) and zero(v.subs(t, sp.pi))
    fx, fy = sp.simplify(sxz.subs(t, sp.pi)), sp.simplify(syz.subs(t, sp.pi))
    assert zero(fx - (s * ex - sp.Rational(3, 2) * a * sp.sqrt(r)))
    assert zero(fy - (s * ey - sp.Rational(3, 2) * MU * b * yv * sp.sqrt(r)))
    distances = np.array([float(d) for d in DISTANCES])
    for y0 in np.linspace(-1.0, 1.0, 41):
        direction = np.array([float(a * P), b * y0]) / np.hypot(float(a * P), b * y0)
        force = s * direction[:, None] - 1.5 * np.sqrt(distances) * np.array([a, float(MU) * b * y0])[:, None]
        assert (np.hypot(*force) <= s * (1 + 1e-14)).all()
    assert float(a * P) > 0


# ---------------------------------------------------------------------------------------------
# scalar cases (n = -e_y on Gamma_C: d_n u = -d_y u)
def test_tresca_line_3d():
    """u = s z + w(y) c rho^{3/2} cos(3 theta/2), (rho, theta) polar in (x, z), w = 1 + y^2/2:
    -Laplace u = -w'' v = -c rho^{3/2} cos(3 theta/2) (w'' = 1)."""
    s, c = 1, sp.Rational(4, 5)
    w = sp.Symbol("w", positive=True)           # w(y) on a line y = const
    v = c * r ** sp.Rational(3, 2) * sp.cos(sp.Rational(3, 2) * t)
    assert zero(d_x(d_x(v)) + d_y(d_y(v)))       # so Laplace(w(y) v) = w'' v
    u = s * r * sp.sin(t) + w * v
    flux = -d_y(u)
    # slip x > 0: u = w c x^{3/2} > 0, d_n u = -s
    assert zero(u.subs(t, 0) - w * c * r ** sp.Rational(3, 2)) and zero(flux.subs(t, 0) + s)
    # stick x < 0: u = 0, d_n u = -s + (3/2) c w |x|^{1/2} in [-s, s] for w in [1, 3/2]
    assert zero(u.subs(t, sp.pi))
    stick = sp.simplify(flux.subs(t, sp.pi))
    assert zero(stick - (-s + sp.Rational(3, 2) * c * w * sp.sqrt(r)))
    values = sp.lambdify((w, r), stick, "numpy")
    ws, ds = np.meshgrid(1 + np.linspace(-1.0, 1.0, 41) ** 2 / 2, np.array([float(d) for d in DISTANCES]))
    assert (np.abs(values(ws, ds)) <= s * (1 + 1e-14)).all()


def test_tresca_corner_r12():
    """u = s y - rho0^{1/2} sin(theta0/2) + c rho1^{3/2} cos(3 theta1/2) about 0 and 1/2,
    theta1 measured from the positive x-direction (stick on 0 < x < 1/2, slip on x > 1/2);
    Gamma_C = (0, 1) x {0} with the load g_C = x^{-1/2}/2; Gamma_g = (-1, 0) x {0}."""
    s, c = 1, 1
    # each term is harmonic (Im w^{1/2}, Re w^{3/2}; mirroring and shifting keep it so)
    assert zero(d_x(d_x(sp.sqrt(r) * sp.sin(t / 2))) + d_y(d_y(sp.sqrt(r) * sp.sin(t / 2))))
    v = r ** sp.Rational(3, 2) * sp.cos(sp.Rational(3, 2) * t)
    assert zero(d_x(d_x(v)) + d_y(d_y(v)))
    rho0, th0 = sp.sqrt(X**2 + Y**2), sp.atan2(Y, X)
    rho1, th1 = sp.sqrt((X - HALF) ** 2 + Y**2), sp.atan2(Y, X - HALF)
    u = s * Y - sp.sqrt(rho0) * sp.sin(th0 / 2) + c * rho1 ** sp.Rational(3, 2) * sp.cos(sp.Rational(3, 2) * th1)
    flux = -sp.diff(u, Y)                      # d_n u, n = -e_y
    for px in [sp.Rational(k, 80) for k in range(1, 80) if k != 40]:
        value = sp.simplify(u.subs({X: px, Y: 0}))
        friction = sp.simplify(flux.subs({X: px, Y: 0}) - 1 / (2 * sp.sqrt(px)))      # d_n u - g_C
        if px < HALF:           # stick: u = 0, d_n u - g_C = -s + (3/2) c (1/2 - x)^{1/2} in [-s, s]
            assert value == 0
            assert sp.simplify(friction - (-s + sp.Rational(3, 2) * c * sp.sqrt(HALF - px))) == 0
            assert abs(float(friction)) <= s
        else:                   # slip: u = c (x - 1/2)^{3/2} > 0, d_n u - g_C = -s
            assert sp.simplify(value - c * (px - HALF) ** sp.Rational(3, 2)) == 0 and value > 0
            assert friction == -s
    # Gamma_g (x < 0): its Neumann datum d_n u is derived by the harness; there the r^{1/2} term
    # has d_n = 0 (theta0 = pi is its Neumann face)
    for px in [sp.Rational(-k, 10) for k in range(1, 10)]:
        assert sp.simplify(sp.diff(-sp.sqrt(rho0) * sp.sin(th0 / 2), Y).subs({X: px, Y: 0})) == 0
