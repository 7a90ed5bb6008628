"""3D: a circular contact zone, the r^{3/2} transition along a *curved* line (Section 6).

Omega = (-1, 1)^2 x (0, 1), Gamma_C = the bottom face z = 0 (n = -e_z). The transition curve
is the circle x^2 + y^2 = R^2 of Gamma_C, R = 1/2. Its local coordinates: the level set
    s = (R^2 - x^2 - y^2) / (2R),
a polynomial whose zero set is the circle and whose gradient has unit length on it (a smooth
signed distance to the circle to first order, positive inside), and z, the distance to Gamma_C.
With (rho, theta) the polar coordinates of (s, z) (theta in [0, pi]),
    u = -rho^{3/2} sin(3 theta / 2).
Signorini conditions on Gamma_C (z = 0, d_n = -d_z, and d_z u at fixed x, y is the 2D
function's d_y at x = s):
  inside the circle (s > 0, theta = 0): u = 0, du/dn = (3/2) sqrt(s) >= 0  -- binding;
  outside (s < 0, theta = pi): u = |s|^{3/2} > 0, du/dn = 0               -- free.
f = -Laplace(u): g(s, z) = -rho^{3/2} sin(3 theta/2) is harmonic in (s, z), so
    Laplace(u) = g_ss (|grad s|^2 - 1) + g_s Laplace(s),
with |grad s|^2 - 1 = -2 s / R = O(rho) against g_ss = O(rho^{-1/2}), and g_s = O(rho^{1/2}):
f is bounded, in L^2 (the level set, smooth through the disc's centre, keeps it so; the
Euclidean distance to the circle would be singular at the centre). With w = s + i z,
g = -Im w^{3/2}, so g_s = -(3/2) rho^{1/2} sin(theta/2), g_ss = (3/4) rho^{-1/2} sin(theta/2),
and Laplace(s) = -2/R:
    f = (2/R) (s g_ss + g_s) = (2/R) ((3/4) s rho^{-1/2} - (3/2) rho^{1/2}) sin(theta/2),
declared below (validation checks it against the derived -Laplace(u)): cheaper to evaluate
than the derived expression, whose load vector would be a large share of this case's study.
Regularity: as for the straight line, u is in H^{5/2 - eps} near the circle: nu = 5/2.
Mesh: the cylinder x^2 + y^2 < R^2 is glued into the box, so the circle is a curve of the
geometry: the coarse mesh has vertices on it, and netgen's refinement moves every new vertex
of the circle onto it. The edges of Gamma_C along the circle are chords, so the discrete
transition curve is a polygon inscribed in it (the exact one is between the vertices, off by
O(h^2)), and the hierarchy is not nested there (see the report).
"""
from math import cos, pi, sin

import ngsolve
from ngsolve import x, y, z

from harness.problem import disc_box, polar, transition, transition_gradient

name = "transition-circle-3d"
description = "3D: circular contact zone, r^{3/2} transition along the circle x^2 + y^2 = 1/4 of Gamma_C"
regime = "2 < nu <= 5/2, 3D"
theorem = "Section 6 (3D open in the paper)"
conjectured = True
nu = 2.5
expected_rate = 1.5

radius = 0.5
geometry = disc_box(radius)
maxh = 0.25

level_set = (radius * radius - x * x - y * y) / (2 * radius)
u = transition(0.0, binding_side="right", coordinates=(level_set, z))
_rho, _theta = polar(px=level_set, py=z)
f = (2 / radius) * (0.75 * level_set * _rho**-0.5 - 1.5 * _rho**0.5) * ngsolve.sin(_theta / 2)
# grad u = g_s grad s + g_z e_z, grad s = -(x, y, 0)/R, in closed form (the derived one of this
# composition costs several times u per point)
_g_s, _g_z = transition_gradient(0.0, binding_side="right", coordinates=(level_set, z))
grad_u = (-_g_s * x / radius, -_g_s * y / radius, _g_z)
# the exact transition curve on Gamma_C, drawn on the report's pictures of it
transition_curve = [[(radius * cos(2 * pi * k / 128), radius * sin(2 * pi * k / 128)) for k in range(129)]]
# graded meshes (Remark 4.4, Apel & Nicaise in 3D) refine toward the transition circle, given as
# 128 chords: a chord lies within R (1 - cos(pi / 128)) = 1.5e-4 of the circle, far below the
# sizes of the tetrahedra the grading makes at the levels a study reaches
singular_lines = [((radius * cos(2 * pi * k / 128), radius * sin(2 * pi * k / 128), 0.0),
                   (radius * cos(2 * pi * (k + 1) / 128), radius * sin(2 * pi * (k + 1) / 128), 0.0)) for k in range(128)]

# the default report runs one scalar and one elastic 3D case (transition-line-3d, elastic-transition-3d);
# this one, 15-22 s of its study, in `make report-fine` and `report --case` (make report within its 3 minutes)
report_profile = "fine"
