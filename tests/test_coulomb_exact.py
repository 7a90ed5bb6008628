"""The Coulomb cases' exact solutions, checked symbolically with SymPy: the Williams eigenproblem
of a Coulomb stick-slip point (its characteristic equation, the exponent, the mode's faces), and
for elastic-coulomb-r32 and elastic-coulomb-3d Navier's equations and every Coulomb condition on
both sides of the stick-slip point -- closed forms where SymPy reduces them, sample points of
Gamma_C for the inequalities. Then the NGSolve case fields against the SymPy ones at points, and
validation of both cases."""
from __future__ import annotations

import numpy as np
import pytest

sp = pytest.importorskip("sympy")

from tests.test_tresca_exact import DISTANCES, KAPPA, MU, cartesian_stresses, d_x, d_y, lame, polar_stresses, r, t, williams, zero  # noqa: E402

ell = sp.Symbol("l", positive=True)
mu_, kappa_, friction = sp.Symbol("mu", positive=True), sp.Symbol("kappa", positive=True), sp.Symbol("mu_F", positive=True)
# the cases' data: mu_F = 1/2, kappa = 9/5 (Poisson 0.3), s = 1, c = 1; P0 = s / mu_F
MU_F, S, C_AMP = sp.Rational(1, 2), 1, 1
P0 = S / MU_F
TAN = MU_F * (KAPPA - 1) / (KAPPA + 1)                  # tan(pi delta) = 1/7
EXPONENT = sp.Rational(3, 2) + sp.atan(TAN) / sp.pi


def coulomb_face_matrix(ex):
    """Williams' 4 x 4 system: theta = 0 slipping along +x (u_theta = 0, sigma_rt + mu_F sigma_tt = 0),
    theta = pi clamped (u_r = u_theta = 0), each row divided by its power of r."""
    ur, ut, unknowns = williams(ex)
    _, stt, srt = polar_stresses(ur, ut, mu_, kappa_)
    rows = [ut.subs(t, 0) / r**ex, (srt + friction * stt).subs(t, 0) * r / r**ex,
            ur.subs(t, sp.pi) / r**ex, ut.subs(t, sp.pi) / r**ex]
    return sp.Matrix([[sp.diff(sp.simplify(row), v) for v in unknowns] for row in rows]), (ur, ut, unknowns)


def test_coulomb_stick_slip_characteristic_equation():
    """det = 4 l mu kappa sin(pi l)((kappa + 1) cos(pi l) + mu_F (kappa - 1) sin(pi l)): besides
    the integers, cot(pi l) = -mu_F (kappa - 1)/(kappa + 1), whose root in (1, 2) is
    3/2 + arctan(mu_F (kappa - 1)/(kappa + 1))/pi (3/2 at mu_F = 0, Tresca's)."""
    matrix, _ = coulomb_face_matrix(ell)
    det = matrix.det()
    expected = 4 * ell * mu_ * kappa_ * sp.sin(sp.pi * ell) * (
        (kappa_ + 1) * sp.cos(sp.pi * ell) + friction * (kappa_ - 1) * sp.sin(sp.pi * ell))
    assert sp.simplify(sp.expand_trig(sp.simplify(det - expected))) == 0
    root = sp.Rational(3, 2) + sp.atan(friction * (kappa_ - 1) / (kappa_ + 1)) / sp.pi
    assert sp.simplify(sp.expand_trig((kappa_ + 1) * sp.cos(sp.pi * root) + friction * (kappa_ - 1) * sp.sin(sp.pi * root))) == 0
    assert sp.Rational(3, 2) < EXPONENT < 2


def coulomb_mode(ex=EXPONENT):
    """functions.coulomb_stick_slip_series in Williams' polar form: B = tan A, C = A/(kappa + l),
    D = -tan A/(kappa + l), A = (kappa + l) cos(pi delta)/(2 mu (kappa + 1)); the case's data."""
    ur, ut, (A, B, C, D) = williams(ex)
    a = (KAPPA + ex) * sp.cos(sp.atan(TAN)) / (2 * MU * (KAPPA + 1))
    values = {A: a, B: TAN * a, C: a / (KAPPA + ex), D: -TAN * a / (KAPPA + ex), kappa_: KAPPA}
    ur, ut = ur.subs(values), ut.subs(values)
    return ur * sp.cos(t) - ut * sp.sin(t), ur * sp.sin(t) + ut * sp.cos(t)       # (m_x, m_y)


def test_the_coulomb_mode_is_the_null_vector_and_its_faces_are_the_docstrings():
    ex = EXPONENT
    mx, my = coulomb_mode(ex)
    sxx, syy, sxy = cartesian_stresses(mx, my, MU, KAPPA)
    cos_d = sp.cos(sp.atan(TAN))
    # theta = 0: m_y = 0, m_x = kappa cos(pi delta)/(mu (kappa + 1)) x^l, sigma_xy + mu_F sigma_yy = 0
    assert zero(my.subs(t, 0))
    assert zero(mx.subs(t, 0) - KAPPA * cos_d / (MU * (KAPPA + 1)) * r**ex)
    assert zero(syy.subs(t, 0) + ex * (KAPPA - 1) * cos_d / (KAPPA + 1) * r ** (ex - 1))
    assert zero((sxy + MU_F * syy).subs(t, 0))
    # theta = pi: clamped, sigma_yy = 0, sigma_xy = -l |x|^{l-1}
    assert zero(mx.subs(t, sp.pi)) and zero(my.subs(t, sp.pi))
    assert zero(syy.subs(t, sp.pi)) and zero(sxy.subs(t, sp.pi) + ex * r ** (ex - 1))


def elastic_coulomb_field():
    """cases/elastic_coulomb_r32.py: u = (s y/mu, -b y) + c m, b = P0/(lambda + 2 mu)."""
    mx, my = coulomb_mode()
    b = P0 / (lame(MU, KAPPA) + 2 * MU)
    y = r * sp.sin(t)
    return S * y / MU + C_AMP * mx, -b * y + C_AMP * my


@pytest.mark.slow
def test_elastic_coulomb_r32():
    ex = EXPONENT
    ux, uy = elastic_coulomb_field()
    sxx, syy, sxy = cartesian_stresses(ux, uy, MU, KAPPA)
    # Navier: div sigma = 0 (f = 0)
    assert zero(d_x(sxx) + d_y(sxy)) and zero(d_x(sxy) + d_y(syy))
    p = -syy                                    # n = -e_y, g_C = 0: p = -sigma_n(u)
    # Gamma_C: u . n = -u_y = 0 on both sides (gap 0), p > 0: contact everywhere
    assert zero(uy.subs(t, 0)) and zero(uy.subs(t, sp.pi))
    cos_d = sp.cos(sp.atan(TAN))
    slip_p, stick_p = sp.simplify(p.subs(t, 0)), sp.simplify(p.subs(t, sp.pi))
    assert zero(slip_p - (P0 + C_AMP * ex * (KAPPA - 1) * cos_d / (KAPPA + 1) * r ** (ex - 1)))
    assert zero(stick_p - P0)
    # slip x > 0: u_x > 0 and sigma_t = -sigma_xy e_x = -mu_F p e_x, i.e. sigma_xy = mu_F p
    assert zero(sxy.subs(t, 0) - MU_F * slip_p)
    # stick x < 0: u = 0, sigma_xy = s - c l |x|^{l-1}, |sigma_xy| <= mu_F p
    assert zero(ux.subs(t, sp.pi))
    stick_shear = sp.simplify(sxy.subs(t, sp.pi))
    assert zero(stick_shear - (S - C_AMP * ex * r ** (ex - 1)))
    for d in DISTANCES:
        assert float(ux.subs(t, 0).subs(r, d)) > 0 and float(slip_p.subs(r, d)) > 0
        assert abs(float(stick_shear.subs(r, d))) <= float(MU_F * P0) * (1 + 1e-14)


@pytest.mark.slow
def test_elastic_coulomb_3d():
    """u = w(y) U(x, z), w = 1 + y^2/2, U elastic-coulomb-r32's field in (x, z): the load
    f = -(mu U_x, (lambda + mu) w' div U, mu U_z), and on z = 0 every stress is U's times w
    (sigma_yz = mu w' U_z = 0): checked in Cartesian coordinates with w symbolic."""
    X, Yc, Zc = sp.symbols("x y z", real=True)
    ux2, uz2 = elastic_coulomb_field()
    polar_xz = {r: sp.sqrt(X**2 + Zc**2), t: sp.atan2(Zc, X)}
    Ux, Uz = ux2.subs(polar_xz), uz2.subs(polar_xz)
    w = 1 + Yc**2 / 2
    u = [w * Ux, 0, w * Uz]
    xs = (X, Yc, Zc)
    la = lame(MU, KAPPA)
    grad = [[sp.diff(u[i], xs[j]) for j in range(3)] for i in range(3)]
    div = sum(grad[i][i] for i in range(3))
    sigma = [[la * div * int(i == j) + MU * (grad[i][j] + grad[j][i]) for j in range(3)] for i in range(3)]
    f_declared = [-MU * Ux, -(la + MU) * Yc * (sp.diff(Ux, X) + sp.diff(Uz, Zc)), -MU * Uz]
    points = [(sp.Rational(3, 10), sp.Rational(-1, 2), sp.Rational(1, 5)), (sp.Rational(-7, 10), sp.Rational(9, 10), sp.Rational(1, 2))]
    for i in range(3):
        residual = sum(sp.diff(sigma[i][j], xs[j]) for j in range(3)) + f_declared[i]
        assert all(abs(float(residual.subs(dict(zip(xs, pt))))) < 1e-12 for pt in points)
    # on Gamma_C (z = 0) at samples: u_z = 0, p = -sigma_zz > 0, (sigma_xz, sigma_yz) as Coulomb asks
    on_gamma = sp.lambdify((X, Yc), [e.subs(Zc, 0) for e in (u[0], u[2], -sigma[2][2], sigma[0][2], sigma[1][2])], "numpy")
    xg, yg = np.meshgrid([k / 20 for k in range(-20, 21) if k], np.linspace(-1.0, 1.0, 9))
    ux, uz, p, sxz, syz = (np.broadcast_to(v, xg.shape) for v in on_gamma(xg, yg))
    assert np.abs(uz).max() < 1e-14 and (p > 0).all() and np.abs(syz).max() < 1e-14
    slip, stick = xg > 0, xg < 0
    assert (ux[slip] > 0).all() and np.allclose(sxz[slip], float(MU_F) * p[slip], rtol=1e-13, atol=0)
    assert np.abs(ux[stick]).max() < 1e-14 and (np.abs(sxz[stick]) <= float(MU_F) * p[stick] * (1 + 1e-14)).all()


# ---------------------------------------------------------------------------------------------
# the NGSolve case fields against the SymPy ones, and validation
def _sympy_field_2d():
    ux, uy = elastic_coulomb_field()
    return sp.lambdify((r, t), [ux, uy], "numpy")


@pytest.mark.parametrize("case_name", ["elastic_coulomb_r32", "elastic_coulomb_3d"])
def test_the_case_modules_are_the_sympy_fields(case_name):
    from pathlib import Path

    from harness.mesh.levels import coarse_mesh
    from harness.mesh.points import evaluate
    from harness.problem import load_case
    case = load_case(str(Path(__file__).parents[1] / "cases" / f"{case_name}.py"))
    assert abs(case.nu - 1 - float(EXPONENT)) < 1e-14
    mesh = coarse_mesh(case)
    field = _sympy_field_2d()
    rng = np.random.default_rng(7)
    three = mesh.dim == 3
    points = np.column_stack([rng.uniform(-0.99, 0.99, 40), rng.uniform(-0.99, 0.99, 40), rng.uniform(0.01, 0.99, 40)]) \
        if three else np.column_stack([rng.uniform(-0.99, 0.99, 40), rng.uniform(0.01, 0.99, 40)])
    values = evaluate(case.u, mesh, points).reshape(len(points), -1)
    x, height = points[:, 0], points[:, -1]
    ux, un = field(np.hypot(x, height), np.arctan2(height, x))
    w = 1 + points[:, 1] ** 2 / 2 if three else 1.0
    expected = np.column_stack([w * ux, 0 * x, w * un] if three else [ux, un])
    assert np.allclose(values, expected, rtol=1e-12, atol=1e-13)


@pytest.mark.parametrize("case_name", ["elastic_coulomb_r32", pytest.param("elastic_coulomb_3d", marks=pytest.mark.slow)])     # 3D: 2.7 s
def test_the_coulomb_cases_validate(case_name):
    from pathlib import Path

    from harness.problem import load_case
    from harness.problem.validate import validate_case
    case = load_case(str(Path(__file__).parents[1] / "cases" / f"{case_name}.py"))
    validate_case(case)
    assert case.friction.name == "coulomb" and case.conjectured
