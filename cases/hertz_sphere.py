"""Hertz point contact: an elastic block pressed onto a rigid sphere (3D, frictionless).

Why this case. The 3D counterpart of hertz-line and of smooth-obstacle: no closed form, the
contact zone a disc whose edge crosses the triangles of Gamma_C wherever the solution puts it.
It is read for what Hertz predicts: the contact area pi a^2 and the peak pressure p0 at the
computed force (the rows' ``qoi_contact_measure``, ``qoi_peak_pressure``, ``qoi_force``).

Setup. Omega = (-L, L)^2 x (0, H), E = 1, Poisson ratio 0.3; Gamma_C the bottom (n = -e_z),
Gamma_g the four sides (traction-free), Gamma_u the top with u = (0, 0, -delta). The sphere
(radius R = 1) touches the bottom at the origin; the initial gap is the paraboloid
alpha = (x^2 + y^2)/(2R), for which Hertz's half-space solution is exact (the sphere differs by
r^4/(8R^3)). The constraint is u.n - alpha <= 0, i.e. u_z >= -alpha. In 3D the half-space's
indentation under a point load is finite (Boussinesq), so the force or the motion could be
prescribed: the motion is, as in hertz-line, and F is read off: F = int lambda_h = qoi_force.

Hertz (Johnson, Contact Mechanics, 1985, Sect. 3.4 and 4.2; rigid indenter, E* = E/(1 - nu^2)):
    a = (3 F R / (4 E*))^{1/3},   p0 = 3 F / (2 pi a^2),   p(r) = p0 sqrt(1 - r^2/a^2),
    approach delta_H = a^2 / R   (``hertz``).

Mesh. The coarse mesh is fine (``zone_h``) on the square (-zone, zone)^2 of Gamma_C around the
contact disc (a glued box, ``harness.problem.geometry.zone_box``: flat faces, so the refined meshes nest), coarse
(``maxh``) elsewhere. Uniform refinement multiplies 3D dofs by 8 per level: the fine profile
studies two levels (h = a/4 on the zone) with the reference one level finer.

The zone is meshed at a/2 (a_h = sqrt(area / pi), read with p_max at the computed force): at
a, the deviations of a_h and p_max from Hertz's a and p0 stay several times larger on the same
levels.

Domain size. As in hertz-line, a finite block is stiffer than the half-space (a higher peak
pressure at equal F), but a point load's field decays like 1/r, a line load's like log r, so
the block's share of p_max / p0 - 1 falls faster as the block grows: at L = H = 10 a the
discretisation, not the size, decides the deviations (scale the block, find delta again and
compare p_max / p0). a_h / a is quantized by the Gauss points of Gamma_C, as in hertz-line.

Regularity. As in hertz-line, the clamped top meets the traction-free sides at right angles:
along those edges the plane-strain clamped-free exponent 0.7112 (Williams; the antiplane part's
exponent is 1), so u is in H^{1.7112 - eps} and the whole-domain H1 error falls at most like
h^{0.711} on uniform meshes; the contact disc's edge alone gives r^{3/2} (nu = 5/2). The paper
has no 3D theorem (Section 6): the rate is a conjecture through Remark 2.3.
"""
from math import pi

import numpy as np
from ngsolve import CF, x, y

from harness.problem import zone_box

YOUNG, POISSON, RADIUS = 1.0, 0.3, 1.0
E_STAR = YOUNG / (1 - POISSON**2)
# the clamped-free edge exponent of hertz-line (plane strain, 90 degrees, Poisson ratio 0.3)
EDGE_EXPONENT = 0.711173


def hertz(force, radius=RADIUS, e_star=E_STAR):
    """Hertz's contact radius a and peak pressure p0 for a total force."""
    a = (3 * force * radius / (4 * e_star)) ** (1 / 3)
    return a, 3 * force / (2 * pi * a * a)


prediction = "Hertz (Johnson, Contact Mechanics, 1985, Sect. 3.4)"


def predicted_quantities(force):
    """Hertz's contact area pi a^2 and peak pressure p0 at the computed force."""
    a, p0 = hertz(force)
    return {"qoi_contact_measure": pi * a * a, "qoi_peak_pressure": p0}


def predicted_pressure(r, force):
    """Hertz's p0 sqrt(1 - r^2/a^2) at the distances r from the axis, 0 outside the disc."""
    a, p0 = hertz(force)
    return p0 * np.sqrt(np.clip(1 - (np.asarray(r) / a) ** 2, 0.0, None))


def setup(half_width=1.0, height=1.0, delta=0.01, zone=0.2, zone_h=0.05, maxh=0.5):
    """The module-level declarations of the case (a dict) for these parameters."""
    L, H = half_width, height
    top_edges = [((-L, -L, H), (L, -L, H)), ((L, -L, H), (L, L, H)), ((L, L, H), (-L, L, H)), ((-L, L, H), (-L, -L, H))]
    return {
        "geometry": zone_box(half_width, height, zone, zone_h),
        "maxh": maxh,
        "f": CF((0.0, 0.0, 0.0)),
        "dirichlet": CF((0.0, 0.0, -delta)),
        "neumann": CF((0.0, 0.0, 0.0)),
        "gap": (x * x + y * y) / (2 * RADIUS),
        "singular_lines": top_edges,
    }


name = "hertz-sphere"
description = "Hertz point contact: elastic block (10a x 10a x 10a) pressed on a rigid sphere, 3D, no closed form"
physics = "elasticity"
young, poisson = YOUNG, POISSON
regime = "3/2 < nu < 2 (clamped-free top edges, r^0.711; the contact disc's edge alone gives nu = 5/2), 3D"
theorem = "Section 6 (3D open in the paper); 4.2 i, 5.2 i (Remark 2.3) in 2D"
conjectured = True
nu = 1 + EDGE_EXPONENT
expected_rate = EDGE_EXPONENT

globals().update(setup())
reference_levels = 1
# 3D elastic P2 levels cost 8 times the dofs each: the fine profile only (``report_profile``)
report_profile = "fine"
# L = H = 1 (10 a), delta = 0.01 (a close to 0.1), the zone (-0.2, 0.2)^2 (2 a) at maxh 0.05 (a/2),
# maxh 0.5 elsewhere: level 0 has 2.4e4 P2 dofs, level 1 1.8e5, level 2 1.4e6. The fine profile studies two levels, the reference one level finer: a
# third studied level would need a reference of 1.1e7 dofs
report_levels = {"fine": 2}
