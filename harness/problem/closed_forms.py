"""Closed-form contact theories the Hertz, Cattaneo and Mindlin cases are read against, one home.

Each function takes the resultant(s) the discrete solution computed (the force P, per unit
length in 2D, and the tangential force Q) and returns the theory's quantities at them: the
comparison is at the row's own loads, so a prescribed motion sets the loads and the theory the
rest. E* is the plane-strain (2D) or contact modulus of an elastic body against a rigid one,
E / (1 - nu^2), and of two identical bodies E / (2 (1 - nu^2)) (``identical_bodies_modulus``),
with R* = R/2 for two cylinders of radius R (``effective_radius``): then a = sqrt(4 P R* /
(pi E*)) = sqrt(4 P R (1 - nu^2) / (pi E)), the rigid indenter's a at the same P and R.

Hertz (K.L. Johnson, *Contact Mechanics*, 1985, Sect. 4.2 for the cylinder, 3.4 for the sphere;
the formulas are the standard ones quoted in the hertz-line and hertz-sphere cases):

* line:   a = sqrt(4 P R / (pi E*)),   p0 = 2 P / (pi a),   P = pi a p0 / 2;
* sphere: a = (3 P R / (4 E*))^(1/3),  p0 = 3 P / (2 pi a^2), P = 2 pi a^2 p0 / 3;

and in both p(r) = p0 sqrt(1 - r^2/a^2) on the contact zone.

Cattaneo (line) and Mindlin (sphere) (Johnson 1985, Sect. 7.1 and 7.2: not read here; the
formulas are derived in docs/theory/coulomb.md, "Cattaneo and Mindlin"): after the normal load,
a tangential load Q < mu_F P applied without sliding gives the shear traction

    q(r) = (mu_F p0 / a) (sqrt(a^2 - r^2) - sqrt(c^2 - r^2))  for r < c,
    q(r) = mu_F p(r)                                         for c <= r <= a,

the full-slip traction less a Hertz-like one on the stick zone r < c. Its resultant is
Q = mu_F P (1 - c^2/a^2) on the line (the correction integrates to mu_F p0 pi c^2 / (2 a)) and
Q = mu_F P (1 - c^3/a^3) on the sphere (2 pi mu_F p0 c^3 / (3 a)), so

    c / a = sqrt(1 - Q / (mu_F P))  (line),   c / a = (1 - Q / (mu_F P))^(1/3)  (sphere).

These hold for uncoupled bodies (Dundurs' beta = 0; ``rigid_dundurs_beta``), the line exactly,
the sphere up to Mindlin's approximation (the slip in the annulus not exactly parallel to Q).
"""
from __future__ import annotations

from math import pi

import numpy as np


def contact_modulus(young: float, poisson: float) -> float:
    """E* = E / (1 - nu^2) of an elastic body against a rigid one (plane strain in 2D)."""
    return young / (1 - poisson**2)


def identical_bodies_modulus(young: float, poisson: float) -> float:
    """E* of two identical elastic bodies in contact (plane strain in 2D): 1/E* = (1 - nu_1^2)/E_1
    + (1 - nu_2^2)/E_2 = 2 (1 - nu^2)/E, so E* = E / (2 (1 - nu^2)), half ``contact_modulus``
    (Johnson 1985, Sect. 4.2, not read; dolfinx_contact's friction-cylinders demo writes
    ``Estar = E/(2(1-nu**2))``)."""
    return young / (2 * (1 - poisson**2))


def effective_radius(r1: float, r2: float) -> float:
    """R* of two cylinders (spheres) of radii ``r1``, ``r2`` touching from either side of the
    contact line: 1/R* = 1/R_1 + 1/R_2 (the sum of the two parabolic gaps x^2/(2 R_k) is x^2/(2 R*))."""
    return 1.0 / (1.0 / r1 + 1.0 / r2)


def hertz_line(force: float, radius: float, e_star: float) -> tuple[float, float]:
    """Hertz's half-width a and peak pressure p0 of a cylinder for a force per unit length."""
    a = (4 * force * radius / (pi * e_star)) ** 0.5
    return a, 2 * force / (pi * a)


def hertz_sphere(force: float, radius: float, e_star: float) -> tuple[float, float]:
    """Hertz's contact radius a and peak pressure p0 of a sphere for a total force."""
    a = (3 * force * radius / (4 * e_star)) ** (1 / 3)
    return a, 3 * force / (2 * pi * a * a)


def hertz_pressure(r, a: float, p0: float) -> np.ndarray:
    """p0 sqrt(1 - r^2/a^2) at the distances ``r`` from the centre, 0 outside the zone."""
    return p0 * np.sqrt(np.clip(1 - (np.asarray(r, float) / a) ** 2, 0.0, None))


def stick_ratio(load_ratio: float, dimension: int) -> float:
    """c / a at Q / (mu_F P) = ``load_ratio``: Cattaneo's sqrt(1 - ratio) (line, dimension 2) or
    Mindlin's (1 - ratio)^(1/3) (sphere, dimension 3); NaN outside 0 <= ratio <= 1 (no stick
    zone of the theory: full slip or a reversed load)."""
    if not 0.0 <= load_ratio <= 1.0:
        return float("nan")
    return (1.0 - load_ratio) ** (1.0 / dimension)


def cattaneo_traction(r, a: float, p0: float, c: float, mu: float) -> np.ndarray:
    """Cattaneo's / Mindlin's shear traction q at the distances ``r`` (module docstring): mu_F p
    in the slip zone, mu_F p less (mu_F p0 / a) sqrt(c^2 - r^2) in the stick zone."""
    r = np.asarray(r, float)
    correction = mu * p0 / a * np.sqrt(np.clip(c * c - r * r, 0.0, None))
    return mu * hertz_pressure(r, a, p0) - correction


def cattaneo_line(force: float, tangential_force: float, mu: float, radius: float, e_star: float) -> dict:
    """The line contact's a, p0, c and c/a at the computed P and Q (Cattaneo)."""
    a, p0 = hertz_line(force, radius, e_star)
    ratio = stick_ratio(tangential_force / (mu * force), 2)
    return {"a": a, "p0": p0, "c": ratio * a, "c_over_a": ratio}


def mindlin_sphere(force: float, tangential_force: float, mu: float, radius: float, e_star: float) -> dict:
    """The sphere's a, p0, c and c/a at the computed P and Q (Mindlin)."""
    a, p0 = hertz_sphere(force, radius, e_star)
    ratio = stick_ratio(tangential_force / (mu * force), 3)
    return {"a": a, "p0": p0, "c": ratio * a, "c_over_a": ratio}


def rigid_dundurs_beta(poisson: float) -> float:
    """Dundurs' beta of an elastic body (Poisson ratio ``poisson``, plane strain) against a rigid
    one: (kappa - 1) / (kappa + 1) with kappa = 3 - 4 nu, i.e. (1 - 2 nu) / (2 (1 - nu)); 0 for
    nu = 1/2 (docs/theory/coulomb.md, "Conditions"; Dundurs 1969 not read)."""
    return (1 - 2 * poisson) / (2 * (1 - poisson))
