"""u in H^2 and in no H^{2+delta}, one transition point (Thm 4.2 ii, 5.2 ii): h |log h|^{1/4}.

Omega = (-1, 1) x (0, 1), Gamma_C = bottom, Gamma_g = sides, Gamma_u = top, polar
coordinates about 0. With L(r) = |log(r/2)|^{-beta}, beta = 0.6 > 1/2,
    u_b = r sin^2(theta/2) L(r) = (r - x)/2 L(r)
is homogeneous of degree one up to the slowly varying L, and sin^2 + (sin^2)'' = 1/2 != 0,
so D^2 u_b ~ r^{-1} L(r): |D^2 u_b|^2 r ~ r^{-1} |log r|^{-2 beta} is integrable (beta > 1/2)
with nothing to spare, and no fractional derivative of order delta > 0 of D^2 u_b is: u_b is
in H^2 and in no H^{2+delta} (docs/mathematics.md §4). f = -Laplace(u) ~ r^{-1} L is in L^2.
On Gamma_C: u_b = 0 for x > 0, u_b = |x| L > 0 for x < 0, du_b/dn = 0 on both sides.
Adding the transition -r^{3/2} sin(3 theta/2) (in H^{5/2-eps}) gives the binding side a
positive pressure (3/2) sqrt(x), so 0 is a genuine contact/separation transition point.
Best approximation behaves like h |log h|^{1/2 - beta}, so the bound h |log h|^{1/4} of the
theorems is not expected to be sharp; the study shows which factor the errors follow.
"""
from ngsolve import log, x, y

from harness.problem import contact_strip, polar, transition, transition_gradient

name = "borderline-h2"
description = "(r - x)/2 |log(r/2)|^{-0.6} (exactly H^2) plus an r^{3/2} transition at 0"
regime = "nu = 2"
theorem = "4.2 ii, 5.2 ii"
groups = ["paper"]            # one scalar case per regime of the paper's theorems (--case paper)
nu = 2.0
expected_rate = 1.0
expected_log_exponent = 0.25

BETA = 0.6
geometry = contact_strip(breaks=[0.0])
maxh = 0.25

# A small transition part lets the singularity that sets nu dominate the error from
# coarse levels on (with weight 1 the r^{3/2} error masks it for three levels).
TRANSITION_WEIGHT = 0.1
r, _ = polar()
u = 0.5 * (r - x) * (-log(r / 2)) ** (-BETA) + TRANSITION_WEIGHT * transition(0.0)
# f = -Laplace(u) in closed form (the transition part is harmonic): with s = log(2/r) and
# L = s^-beta, Laplace((r - x)/2 L) = L/(2r) + (3/2)(1 - x/r) L' + (r - x)/2 L'',
# L' = beta s^(-beta-1)/r, L'' = beta r^-2 ((beta+1) s^(-beta-2) - s^(-beta-1)).
s = -log(r / 2)
f = -(0.5 * s ** (-BETA) + BETA * (r - x) / r * s ** (-BETA - 1)
      + 0.5 * BETA * (BETA + 1) * (r - x) / r * s ** (-BETA - 2)) / r
singular_points = [(0.0, 0.0)]  # f ~ r^{-1} |log r|^{-beta} there too
# grad u in closed form (the derived one costs several times u per point): with grad s = -(x, y)/r^2,
# grad((r - x)/2 L) = ((x/r - 1)/2, y/(2r)) L + (r - x)/2 beta s^(-beta-1) (x, y)/r^2
_t_x, _t_y = transition_gradient(0.0)
_dL = 0.5 * (r - x) * BETA * s ** (-BETA - 1) / (r * r)
grad_u = (0.5 * (x / r - 1) * s ** (-BETA) + _dL * x + TRANSITION_WEIGHT * _t_x,
          0.5 * y / r * s ** (-BETA) + _dL * y + TRANSITION_WEIGHT * _t_y)

# P1 runs one level past P2 by default (to P2's finest number of dofs); that level moves no P1
# method's fitted H1 rate by more than 0.01 nor any verdict, so the default report stops P1
# with P2.
asymptotic_levels_p1 = 7
