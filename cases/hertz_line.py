"""Hertz line contact: an elastic block pressed onto a rigid cylinder (plane strain, frictionless).

Why this case. Every other elastic case is manufactured: a singular function is made exact by
choosing the data. Hertz is the textbook contact problem an engineer checks a contact code
against, and here nobody places the transition points: they fall where the solution puts them,
inside contact edges, as in smooth-obstacle. What it is read for is not an H1 error but what
Hertz predicts: the half-width a and the peak pressure p0 at the computed force (the rows'
quantities of interest ``qoi_contact_measure`` = 2 a_h, ``qoi_peak_pressure``, ``qoi_force``).

Setup. Omega = (-L, L) x (0, H), E = 1, Poisson ratio 0.3; Gamma_C the bottom (n = -e_y), Gamma_g
the sides (traction-free), Gamma_u the top with u = (0, -delta). The cylinder (radius R = 1)
touches the bottom at x = 0; the initial gap is the parabola alpha(x) = x^2/(2R). The parabola,
not the circle R - sqrt(R^2 - x^2): Hertz's half-space solution is exact for the parabolic
profile, so every measured difference is discretisation or finite size, not profile (the circle
differs by x^4/(8R^3), 0.25 % of the gap at x = a = 0.1). In elasticity the constraint is
u.n - alpha <= 0, i.e. u_y >= -x^2/(2R). The motion, not the force, is prescribed: in plane
strain a half-space's indentation grows like log(depth) (Flamant), so delta is defined by the
body and F is read off: F = int lambda_h = qoi_force.

Hertz (Johnson, Contact Mechanics, 1985, Sect. 4.2): E* = E/(1 - nu^2),
    a = sqrt(4 F R / (pi E*)),   p0 = 2 F / (pi a),   p(x) = p0 sqrt(1 - x^2/a^2)   (``hertz``).
a = 0.1 needs F = pi a^2 E* / (4R) = 8.63e-3; delta = 0.015 gives about that force here
(L = H = 1 = 10 a). The log law: the delta that keeps a = 0.1 grows by
2 F ln 2 / (pi E*) = 0.0035 per doubling of the block (the Flamant field).

Domain size. A finite block is stiffer than the half-space (a higher, narrower pressure at
equal F), by a share of p0 that falls like (a/L)^2 as the block grows: at L = H = 10 a a
fraction of a percent (scale the block, find delta again for a = 0.1 and compare p_max / p0).
a_h is read from the contact-law argument at the pressure's Gauss points and is quantized by
them: it wanders by a few tenths of a percent from level to level.

Mesh. The contract has one maxh, but a netgen geometry carries local sizes: corners of Gamma_C at
x = +-2a (not at +-a, which the solution chooses) and maxh a/4 on [-2a, 2a] give a coarse mesh
fine where the pressure lives, which uniform red refinement keeps. (On the plain rectangle a_h
would be read off a contact zone only a few elements wide on the coarse levels.)

Regularity. At x = +-a the transition gives r^{3/2} (nu = 5/2, Remark 2.2). The top corners,
where the clamped top meets a traction-free side at 90 degrees, are worse: Williams' clamped-free
wedge equation (J. Appl. Mech. 19 (1952) 526-528) in Kolosov's kappa = 3 - 4 nu (plane strain),
    kappa^2 + 1 + 2 kappa cos(2 l omega) - 4 l^2 sin^2(omega) = 0,
has at omega = pi/2, kappa = 1.8 the least root l = 0.71117 (checked against a 4x4 determinant
built without the elimination, and at omega = pi against the known 1/2 + i ln(kappa)/(2 pi) of
a bonded edge; no complex root with 0 < Re l < 1.5). So u is in H^{1.7112 - eps} and the
whole-domain H1 error on uniform meshes falls at most like h^{0.711}, the corners', not the
transitions' h^{3/2}: the strain energy's pairwise orders (about twice the H1 order) fall
toward 2 x 0.711 = 1.42 on uniform meshes, and stay well above it with maxh 0.01 at the two top
corners. The contract's boundary labels have no roller side (u_x = 0,
sigma_xy = 0) that would make the corners regular. Declared accordingly: nu = 1.7112 (Theorems
4.2 i / 5.2 i through Remark 2.3), graded meshes grade toward the two corners.

Cost. Elastic levels cost more than the scalar ones the default profile's seven levels assume
(level 6 would have 3.1e6 dofs): ``report_levels`` stops the default report at four levels
(4.9e4 P2 dofs; the reference one level finer, 2.0e5) and the fine profile at five.
"""
from math import pi

from ngsolve import CF, x

from harness.problem import clamped_free_exponent, hertz_line, hertz_pressure, zone_rectangle

YOUNG, POISSON, RADIUS = 1.0, 0.3, 1.0
E_STAR = YOUNG / (1 - POISSON**2)


def hertz(force, radius=RADIUS, e_star=E_STAR):
    """Hertz's half-width a and peak pressure p0 for a force per unit length."""
    return hertz_line(force, radius, e_star)


prediction = "Hertz (Johnson, Contact Mechanics, 1985, Sect. 4.2)"


def predicted_quantities(force):
    """Hertz's contact zone 2a and peak pressure p0 at the computed force."""
    a, p0 = hertz(force)
    return {"qoi_contact_measure": 2 * a, "qoi_peak_pressure": p0}


def predicted_pressure(s, force):
    """Hertz's p0 sqrt(1 - x^2/a^2) on the contact zone, 0 outside it."""
    return hertz_pressure(s, *hertz(force))


def setup(half_width=1.0, height=1.0, delta=0.015, zone=0.2, zone_h=0.025, maxh=0.25, corner_h=None):
    """The module-level declarations of the case (a dict) for these parameters."""
    return {
        "geometry": zone_rectangle(half_width, height, zone, zone_h, corner_h),
        "maxh": maxh,
        "f": CF((0.0, 0.0)),
        "dirichlet": CF((0.0, -delta)),
        "neumann": CF((0.0, 0.0)),
        "gap": x * x / (2 * RADIUS),
        "singular_points": [(half_width, height), (-half_width, height)],
    }


CORNER_EXPONENT = clamped_free_exponent(pi / 2, POISSON)        # 0.711173...

name = "hertz-line"
description = "Hertz line contact: elastic block (10a x 10a) pressed on a rigid cylinder, plane strain, no closed form"
physics = "elasticity"
young, poisson = YOUNG, POISSON
regime = "3/2 < nu < 2 (clamped-free top corners, r^0.711; the transitions alone give nu = 5/2)"
theorem = "4.2 i, 5.2 i (Remark 2.3)"
nu = 1 + CORNER_EXPONENT
expected_rate = CORNER_EXPONENT

# L = H = 1 (10 a), delta = 0.015 (a close to 0.1), Gamma_C corners at +-0.2 (2 a) with local maxh
# 0.025 (a/4) there, maxh 0.25 elsewhere: level 3 has 49,410 P2 dofs, level 4 196,098
globals().update(setup())
# one level finer: a reference two levels finer than the default report's finest has 7.8e5 dofs
reference_levels = 1
report_levels = {"default": 4, "fine": 5}
