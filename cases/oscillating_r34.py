"""Infinitely many contact/separation transitions accumulating at 0, nu = 7/4 (Remark 4.3).

Theorems 4.2 i and 5.2 i prove h^{nu - 1} for 3/2 < nu < 2 only when Gamma_C has finitely many
transition points; Remark 4.3 states the authors' belief that the rate stays optimal without
that assumption. This case has infinitely many.

Omega = (-1, 1) x (0, 1), Gamma_C = bottom, Gamma_g = sides, Gamma_u = top, n = -e_y, polar
coordinates about 0 with theta in [0, pi]. With gamma = a + i beta, a = 3/4, beta = 3,

    v = Re z^gamma = r^a e^{-beta theta} cos(a theta + beta log r),   u = v(x, y) + v(-x, y),

harmonic (f = 0) and even in x. On Gamma_C (theta = 0 or pi) u = |x|^a s(x) with
    s(x) = cos(beta log|x|) + e^{-beta pi} cos(a pi + beta log|x|) = A cos(beta log|x| + psi),
which changes sign at |x_n| = exp((pi/2 - psi + n pi)/beta): infinitely many points
accumulating at 0, a factor e^{pi/beta} = 2.85 apart.

Signorini conditions. A gap alpha and a contact load g_C (docs/mathematics.md §1) make u exact:
    alpha = u - |x|^a [s]_+^{3/2},        g_C = du/dn - |x|^{a-1} [-s]_+^{1/2},
so that on Gamma_C
    u - alpha = |x|^a [s]_+^{3/2} >= 0,   du/dn - g_C = |x|^{a-1} [-s]_+^{1/2} >= 0,
and their product is 0: binding (u = alpha, positive pressure) where s < 0, free where s > 0.
Near each x_n, s ~ s'(x_n)(x - x_n), so u - alpha ~ d^{3/2} on the free side and the pressure
~ d^{1/2} on the binding side, as at the genuine transition r^{3/2} sin(3 theta/2) (Remark 2.2).
u itself is analytic away from 0: the transitions are carried by alpha and g_C, whose own
regularity is that of the trace and of the flux of u (scaling |x|^a and |x|^{a-1}). A solution
of the problem without gap and load with infinitely many transitions has no closed form.

Regularity. |D^m u| ~ |gamma|^m r^{a-m}, and the oscillation e^{i beta log r} does not change
the modulus, so as for r^a sin(a theta): u in H^s near 0 iff int r^{2(a-s)} r dr < infinity,
s < 1 + a. nu = 1 + a = 7/4, 3/2 < nu < 2. Away from 0, u is analytic, and the data at the
corners of Omega are derived from u, so they create no singularity: 0 is the only singular
point; it is a polygon corner.

What an off-vertex transition changes. The cases with finitely many transitions put each at a
polygon corner, so every mesh has a vertex there. Here only the accumulation point 0 can be a
vertex: every x_n lies inside a contact edge, at a place no refinement reaches, so on every
mesh the discrete contact set switches inside edges, where neither K_h nor K~_h sees the
switch; the edges that contain a transition -- which the proofs of Theorems 4.2 i / 5.2 i count
and which the finite-transition assumption keeps bounded -- number about (beta/pi) log2(1/h)
+ C per side, growing without bound; the first edge at 0 holds infinitely many. The Gauss rules
of the loads meet the d^{1/2} of g_C inside edges (the graded rules only grade at 0).

Expected rate: the authors' belief h^{nu - 1} = h^{3/4}, not a theorem of the paper. (Drouet &
Hild 2015 claim optimal bounds without any assumption on the contact set: our reading of their
abstract gives the same h^{3/4}, the second verdict.) Whatever the study measures is reported.
"""
from ngsolve import CF, IfPos, cos, exp, log, pi, sin, sqrt, x, y

from harness.problem import contact_strip, polar

name = "oscillating-r34"
description = "infinitely many transitions accumulating at 0 (r^{3/4} cos(3 log r) on Gamma_C), Remark 4.3"
regime = "3/2 < nu < 2, infinitely many transitions"
theorem = "Remark 4.3 (belief; 4.2 i, 5.2 i need finitely many transitions)"
groups = ["paper"]            # one scalar case per regime of the paper's theorems (--case paper)
A_EXPONENT, BETA = 0.75, 3.0
nu = 1.0 + A_EXPONENT
expected_rate = nu - 1.0
conjectured = True

geometry = contact_strip(breaks=[0.0])
maxh = 0.25

r, theta = polar()
# guarded at the accumulation point itself, a vertex: the limit there is 0
_positive = r - 1e-300


def _v(angle):
    return r**A_EXPONENT * exp(-BETA * angle) * cos(A_EXPONENT * angle + BETA * log(r))


u = IfPos(_positive, _v(theta) + _v(pi - theta), 0.0)
f = 0                                        # u is harmonic


def _dv(angle, sign_x):
    # v = Re z^gamma is analytic: dv/dx = Re(gamma z^(gamma-1)), dv/dy = -Im(gamma z^(gamma-1)),
    # z^(gamma-1) = r^(a-1) e^(-beta angle) e^(i((a-1) angle + beta log r)); the mirror
    # v(-x, y) (angle pi - theta) has the x-derivative of the opposite sign
    modulus = r ** (A_EXPONENT - 1.0) * exp(-BETA * angle)
    phase = (A_EXPONENT - 1.0) * angle + BETA * log(r)
    re, im = modulus * cos(phase), modulus * sin(phase)
    return CF((sign_x * (A_EXPONENT * re - BETA * im), -(A_EXPONENT * im + BETA * re)))


# in closed form: cheaper than the derived one in the error norms (validation compares them)
grad_u = IfPos(_positive, _dv(theta, 1.0) + _dv(pi - theta, -1.0), CF((0.0, 0.0)))

# on Gamma_C (y = 0): |x| and s(x)
_abs_x = sqrt(x * x)
_s = cos(BETA * log(_abs_x)) + exp(-BETA * pi) * cos(A_EXPONENT * pi + BETA * log(_abs_x))
_free_part = _abs_x**A_EXPONENT * sqrt(IfPos(_s, _s, 0.0)) ** 3
_pressure = _abs_x ** (A_EXPONENT - 1.0) * sqrt(IfPos(_s, 0.0, -_s))
gap = IfPos(_abs_x - 1e-300, u - _free_part, 0.0)
contact_load = IfPos(_abs_x - 1e-300, -u.Diff(y) - _pressure, 0.0)     # du/dn = -du/dy
singular_points = [(0.0, 0.0)]
# The default report stops at six levels (the fine profile runs eight): the seventh P2 level and
# P1's eighth cost a large share of the report's five minutes and change no verdict.
report_levels = {"default": 6}
