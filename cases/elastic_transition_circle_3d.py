"""3D elasticity: a circular contact zone, the r^{3/2} transition along a *curved* line.

Frictionless unilateral contact of a 3D body (E = 1, Poisson ratio 0.3) on a rigid foundation.
Omega = (-1, 1)^2 x (0, 1), Gamma_C = the bottom face z = 0 (n = -e_z), Gamma_u the top,
Gamma_g the sides; the transition curve is the circle x^2 + y^2 = R^2 of Gamma_C, R = 1/2, in
the local coordinates of transition-circle-3d: the level set s = (R^2 - x^2 - y^2) / (2R)
(positive inside, grad s = -(x, y)/R, of unit length on the circle) and z. With (U_s, U_z)
the plane-strain field of elastic-transition-r32 (``roller_free_mode(3/2, pi)``) evaluated at
(s, z), the displacement is

    u = U_s(s, z) grad s + U_z(s, z) e_z,

a polynomial frame times the plane field: smooth at the disc's centre, and the 2D field to
first order at the circle. On Gamma_C (z = 0), by hand:
  * sigma_xz = mu (d_z u_x + d_x u_z) = mu s_x (d_z U_s + d_s U_z) = s_x sigma_sz^{2D} = 0, and
    sigma_yz likewise: frictionless on both sides, exactly;
  * inside (s > 0, theta = 0): u_z = U_z = 0 (binding); outside (theta = pi): u . n = -U_z < 0
    (separated);
  * sigma_zz = sigma_zz^{2D} + lambda (d_s U_s (|grad s|^2 - 1) + U_s Laplace(s))
             = sigma_zz^{2D} - (2 lambda / R) (s d_s U_s + U_s),
    where sigma_zz^{2D} = -(3/2) sqrt(s) inside and 0 outside: the curvature leaves a normal
    traction O(rho^{3/2}) on both sides. The contact load g_C = -(sigma_zz(u) + p) e_z, with
    p = (3/2) sqrt(s) inside and 0 outside, takes it (sigma(u) n - g_C = -p n): the pressure is
    the plane one, p >= 0, zero where u separates.
f = -div sigma(u), by the plane Navier equations mu Laplace U + (lambda + mu) d_s div2 = 0
(and for W = U_z) and div u = div2 + E, E = -(2/R)(s d_s U + U) (both functions of s, z):
    f = (2/R) ( (lambda + 2 mu)(s U_ss + 2 U_s) grad s,
                mu (s W_ss + W_s) + (lambda + mu)(s U_sz + U_z) ),
bounded (second derivatives rho^{-1/2} times s), declared in closed form below with grad u
(validation checks both against the ones it derives from u; the derived load, through the
level set, costs many times this one in the load vector). g_C is derived from u.
Regularity: as for the straight line, u is in H^{5/2 - eps} near the circle: nu = 5/2, h^{3/2}
the 2D expectation (elastic Theorems 4.1 ii, 5.1 ii, Remark 2.3); in 3D the paper proves
nothing (Section 6). Mesh: ``disc_box`` glues the cylinder of the circle into the box, so the
circle is a curve of the geometry (the discrete transition curve a polygon inscribed in it).
"""
from math import cos, pi, sin

from ngsolve import CF, IfPos, sqrt, x, y, z

from harness.problem import Elasticity, disc_box, polar, roller_free_series

name = "elastic-transition-circle-3d"
description = "3D elastic: circular contact zone, r^{3/2} transition along the circle x^2 + y^2 = 1/4 of Gamma_C (Poisson 0.3)"
physics = "elasticity"
young, poisson = 1.0, 0.3
regime = "2 < nu <= 5/2, 3D"
theorem = "Section 6 (3D open in the paper); 4.1 ii, 5.1 ii (Remark 2.3) in 2D"
conjectured = True
nu = 2.5
expected_rate = 1.5

radius = 0.5
geometry = disc_box(radius)
# three P2 unknowns per node: a coarser start than the scalar circle case (maxh 0.25)
maxh = 0.4

_material = Elasticity(young, poisson, dim=3)
_lam, _mu = _material.lam, _material.mu
level_set = (radius * radius - x * x - y * y) / (2 * radius)
grad_s = (-x / radius, -y / radius, 0.0)
# the plane-strain field U + i W of elastic-transition-r32 and its derivatives in closed form
# (``PolarSeries``), at (s, z)
_series = roller_free_series(1.5, pi, Elasticity(young, poisson))
_polar = polar(px=level_set, py=z)
_at = {}
for _name, _path in {"U": "", "U_s": "x", "U_z": "y", "U_ss": "xx", "U_sz": "xy"}.items():
    _derivative = _series
    for _axis in _path:
        _derivative = _derivative.diff(_axis)
    _at[_name], _at["W" + _name[1:]] = _derivative.real_imag(*_polar)
u = CF((_at["U"] * grad_s[0], _at["U"] * grad_s[1], _at["W"]))
# J = grad s (U_s grad s + U_z e_z)^T - (U/R) I_h + e_z (W_s grad s + W_z e_z)^T (row i = grad u_i)
_dU, _dW = [_at["U_s"] * g for g in grad_s[:2]] + [_at["U_z"]], [_at["W_s"] * g for g in grad_s[:2]] + [_at["W_z"]]
grad_u = CF(tuple(grad_s[i] * _dU[j] - (_at["U"] / radius if i == j else 0.0) for i in range(2) for j in range(3))
            + tuple(_dW), dims=(3, 3))
_horizontal = (2 / radius) * (_lam + 2 * _mu) * (level_set * _at["U_ss"] + 2 * _at["U_s"])
f = CF((_horizontal * grad_s[0], _horizontal * grad_s[1],
        (2 / radius) * (_mu * (level_set * _at["W_ss"] + _at["W_s"]) + (_lam + _mu) * (level_set * _at["U_sz"] + _at["U_z"]))))
# the plane pressure (3/2) sqrt(s) inside the circle; g_C takes sigma_zz(u)'s rest (docstring)
_pressure = IfPos(level_set, 1.5 * sqrt(IfPos(level_set, level_set, 0.0)), 0.0)
contact_load = CF((0.0, 0.0, -(_material.stress(grad_u)[2, 2] + _pressure)))
# the exact transition curve on Gamma_C, drawn on the report's pictures of it
transition_curve = [[(radius * cos(2 * pi * k / 128), radius * sin(2 * pi * k / 128)) for k in range(129)]]
# graded meshes (Remark 4.4, Apel & Nicaise in 3D) refine toward the transition circle, given as
# 128 chords: a chord lies within R (1 - cos(pi / 128)) = 1.5e-4 of the circle, far below the
# sizes of the tetrahedra the grading makes at the levels a study reaches
singular_lines = [((radius * cos(2 * pi * k / 128), radius * sin(2 * pi * k / 128), 0.0),
                   (radius * cos(2 * pi * (k + 1) / 128), radius * sin(2 * pi * (k + 1) / 128), 0.0)) for k in range(128)]

# Its study is the dearest of the 3D cases (three P2 methods at 1.7e5 dofs and P1 on 3.3e5
# tetrahedra, a curved refinement): more than the five minutes of `make report` leave. `make report-fine` and `report --case` run it.
report_profile = "fine"
