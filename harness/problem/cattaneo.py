"""The set-ups of the Cattaneo and Mindlin cases: hertz-line's block (hertz-sphere's box in 3D)
pressed by a rigid cylinder (sphere), then sheared, with Coulomb friction on Gamma_C; and two
identical blocks pressed together, then sheared (``cattaneo_two_body_case``).

The history (``friction.LoadHistory``) has two steps: the normal step prescribes the top's
motion u = (0, -delta) (3D: (0, 0, -delta)), the tangential step (the case's own data)
u = (xi, -delta) (3D: (xi, 0, -delta)): the press, then the shear with the depth held, as
Cattaneo's and Mindlin's problems are posed. xi is data: the rows' Q and P are computed, and the
theory is read at the computed ratio Q / (mu_F P) (``closed_forms``), never tuned to it.

The predictions declared (the case contract's ``predicted_quantities``, ``predicted_friction``,
``predicted_traction``): Hertz's contact zone and peak pressure at the computed P, Cattaneo's
(Mindlin's) stick zone 2c (pi c^2) and shear traction q at the computed P and Q.
"""
from __future__ import annotations

from math import pi

import numpy as np
from ngsolve import CF, x, y

from . import closed_forms
from .bodies import MirrorBody
from .friction import Coulomb, LoadHistory, LoadStep
from .functions import clamped_free_exponent
from .geometry import zone_box, zone_rectangle

RADIUS = 1.0


def cattaneo_line_case(poisson: float, mu: float, xi: float, delta: float = 0.015, young: float = 1.0) -> dict:
    """The declarations of a Cattaneo line case (hertz-line's block 10a x 10a, Gamma_C corners at
    +-2a with local size a/4, maxh 0.25) for this Poisson ratio, mu_F, shear xi and depth delta."""
    exponent = clamped_free_exponent(pi / 2, poisson)
    return line_predictions(RADIUS, closed_forms.contact_modulus(young, poisson), mu) | {
        "physics": "elasticity", "young": young, "poisson": poisson,
        "geometry": zone_rectangle(1.0, 1.0, 0.2, 0.025), "maxh": 0.25,
        "f": CF((0.0, 0.0)), "dirichlet": CF((xi, -delta)), "neumann": CF((0.0, 0.0)),
        "gap": x * x / (2 * RADIUS), "singular_points": [(1.0, 1.0), (-1.0, 1.0)],
        "friction": Coulomb(mu),
        "history": LoadHistory((LoadStep("normal", dirichlet=CF((0.0, -delta))), LoadStep("tangential"))),
        # no rate theorem for Coulomb (docs/theory/coulomb.md): the regime only, no nu or rate
        "regime": f"u at most H^{1 + exponent:.3f} (clamped-free top corners, r^{exponent:.3f}); Coulomb, two load steps",
        "prediction": "Hertz and Cattaneo (Johnson, Contact Mechanics, 1985, Sect. 4.2, 7.1)",
        "reference_levels": 1, "report_profile": "fine",
    }


def cattaneo_two_body_case(poisson: float, mu: float, xi: float, delta: float = 0.015, young: float = 1.0,
                           size: float = 1.0) -> dict:
    """The declarations of a two-body Cattaneo case: two identical elastic blocks, each with the
    gap x^2/(2R) of a cylinder of radius R (R* = R/2), pressed together, then sheared. The upper
    block is hertz-line's (zone at a/4), the lower one (``bodies.MirrorBody``, in its mirrored
    frame) the same outline with the zone at a/6, so the meshes on Gamma_C stand 3:2 and stay
    non-matching under uniform refinement. The upper top moves (0, -delta), then (xi, -delta);
    the lower top (its own Dirichlet data) holds (0, -delta) at both steps. The predictions are
    the line contact's with the two bodies' E* and R* (``closed_forms.identical_bodies_modulus``,
    ``closed_forms.effective_radius``): for identical bodies Dundurs' beta = 0, so Cattaneo's
    uncoupled solution holds up to the finite blocks, each (-size, size) x (0, size) (1: 10 a; a
    larger block measures the finite-size effect, delta raised to keep a, as hertz-line's)."""
    exponent = clamped_free_exponent(pi / 2, poisson)
    predictions = line_predictions(closed_forms.effective_radius(RADIUS, RADIUS),
                                   closed_forms.identical_bodies_modulus(young, poisson), mu)
    return predictions | {
        "physics": "elasticity", "young": young, "poisson": poisson,
        "geometry": zone_rectangle(size, size, 0.2, 0.025), "maxh": 0.25,
        "second_body": MirrorBody(zone_rectangle(size, size, 0.2, 1 / 60), 0.25, dirichlet=CF((0.0, -delta))),
        "f": CF((0.0, 0.0)), "dirichlet": CF((xi, -delta)), "neumann": CF((0.0, 0.0)),
        "gap": x * x / (2 * RADIUS), "singular_points": [(size, size), (-size, size)],
        "friction": Coulomb(mu),
        "history": LoadHistory((LoadStep("normal", dirichlet=CF((0.0, -delta))), LoadStep("tangential"))),
        "regime": f"u at most H^{1 + exponent:.3f} (clamped-free top corners, r^{exponent:.3f}); Coulomb between two "
                  f"bodies, two load steps",
        "prediction": "Hertz and Cattaneo for two identical bodies (Johnson, Contact Mechanics, 1985, Sect. 4.2, 7.1)",
        "reference_levels": 1, "report_profile": "fine",
    }


def line_predictions(radius: float, e_star: float, mu: float) -> dict:
    """A line contact's predictions at the computed P and Q (the case contract's
    ``predicted_quantities``, ``predicted_friction``, ``predicted_pressure``,
    ``predicted_traction``): Hertz's a and p0 and Cattaneo's c and q for the effective radius
    and contact modulus of the pair."""

    def predicted_quantities(force):
        a, p0 = closed_forms.hertz_line(force, radius, e_star)
        return {"qoi_contact_measure": 2 * a, "qoi_peak_pressure": p0}

    def predicted_friction(force, tangential_force):
        return {"qoi_stick_measure": 2 * closed_forms.cattaneo_line(force, tangential_force, mu, radius, e_star)["c"]}

    def predicted_pressure(s, force):
        return closed_forms.hertz_pressure(s, *closed_forms.hertz_line(force, radius, e_star))

    def predicted_traction(s, force, tangential_force):
        theory = closed_forms.cattaneo_line(force, tangential_force, mu, radius, e_star)
        c = theory["c"] if np.isfinite(theory["c"]) else 0.0
        return closed_forms.cattaneo_traction(s, theory["a"], theory["p0"], c, mu)

    return {"predicted_quantities": predicted_quantities, "predicted_friction": predicted_friction,
            "predicted_pressure": predicted_pressure, "predicted_traction": predicted_traction}


def mindlin_sphere_case(poisson: float, mu: float, xi: float, delta: float = 0.01, young: float = 1.0) -> dict:
    """The declarations of a Mindlin sphere case (hertz-sphere's box 10a x 10a x 10a, the zone
    (-2a, 2a)^2 at maxh a/2, maxh 0.5) for this Poisson ratio, mu_F, shear xi (along x) and depth."""
    e_star = closed_forms.contact_modulus(young, poisson)
    top = [((-1, -1, 1), (1, -1, 1)), ((1, -1, 1), (1, 1, 1)), ((1, 1, 1), (-1, 1, 1)), ((-1, 1, 1), (-1, -1, 1))]

    def predicted_quantities(force):
        a, p0 = closed_forms.hertz_sphere(force, RADIUS, e_star)
        return {"qoi_contact_measure": pi * a * a, "qoi_peak_pressure": p0}

    def predicted_friction(force, tangential_force):
        c = closed_forms.mindlin_sphere(force, tangential_force, mu, RADIUS, e_star)["c"]
        return {"qoi_stick_measure": pi * c * c}

    def predicted_pressure(r, force):
        return closed_forms.hertz_pressure(r, *closed_forms.hertz_sphere(force, RADIUS, e_star))

    def predicted_traction(points, force, tangential_force):
        theory = closed_forms.mindlin_sphere(force, tangential_force, mu, RADIUS, e_star)
        c = theory["c"] if np.isfinite(theory["c"]) else 0.0
        r = np.hypot(np.asarray(points)[:, 0], np.asarray(points)[:, 1])
        return closed_forms.cattaneo_traction(r, theory["a"], theory["p0"], c, mu)

    return {
        "physics": "elasticity", "young": young, "poisson": poisson,
        "geometry": zone_box(1.0, 1.0, 0.2, 0.05), "maxh": 0.5,
        "f": CF((0.0, 0.0, 0.0)), "dirichlet": CF((xi, 0.0, -delta)), "neumann": CF((0.0, 0.0, 0.0)),
        "gap": (x * x + y * y) / (2 * RADIUS), "singular_lines": top,
        "friction": Coulomb(mu),
        "history": LoadHistory((LoadStep("normal", dirichlet=CF((0.0, 0.0, -delta))), LoadStep("tangential"))),
        "prediction": "Hertz and Mindlin (Johnson, Contact Mechanics, 1985, Sect. 3.4, 7.2)",
        "predicted_quantities": predicted_quantities, "predicted_friction": predicted_friction,
        "predicted_pressure": predicted_pressure, "predicted_traction": predicted_traction,
        "reference_levels": 1, "report_profile": "fine",
    }
