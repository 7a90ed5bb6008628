"""Building blocks for exact solutions in case modules (NGSolve CoefficientFunctions).

Each satisfies the Signorini conditions on a straight Gamma_C = {y = 0} with outward normal
n = -e_y, the domain lying above it; see docs/mathematics.md §4 (and ``roller_free_mode`` for the
elastic ones, Remark 2.3).
"""
from __future__ import annotations

from ngsolve import atan2, cos, pi, sin, sqrt, x, y, z


def polar(x0: float = 0.0, mirrored: bool = False, px=x, py=y):
    """(r, theta) about (x0, 0), theta in [0, pi] in the upper half plane; ``mirrored``
    measures theta from the negative x-direction (x -> x0 - x). ``px``, ``py``: the coordinates
    (default x, y; rotated ones for a tilted picture)."""
    x, y = px, py
    dx = (x0 - x) if mirrored else (x - x0)
    # theta = atan2(y, dx) in the upper half plane, written with its branch cut on the negative
    # y-axis, outside the domain: a point of Gamma_C with dx < 0 that NGSolve's element map puts
    # at y = -1e-17 must get theta = pi, not -pi (which flipped the sign of e^{-beta theta}-type
    # terms in oscillating-r34 by a factor e^{2 pi beta} at some load quadrature points)
    return sqrt(dx * dx + y * y), pi / 2 + atan2(-dx, y)


def transition(x0: float = 0.0, binding_side: str = "right", coordinates="xy"):
    """-r^{3/2} sin(3 theta/2) about (x0, 0) (Remark 2.2): harmonic; u = 0 with
    du/dn = (3/2) sqrt(r) on the binding side, u = r^{3/2} with du/dn = 0 on the other.
    ``coordinates``: the plane it lives in, "xy", or "xz" (3D, Gamma_C = {z = 0}), or a pair of
    CoefficientFunctions (s, d): a coordinate along Gamma_C across the transition curve and the
    distance to Gamma_C (a curved transition line in 3D)."""
    r, theta = polar(x0, mirrored=(binding_side == "left"), px=_plane(coordinates)[0], py=_plane(coordinates)[1])
    return -(r ** 1.5) * sin(1.5 * theta)


def transition_gradient(x0: float = 0.0, binding_side: str = "right", coordinates="xy"):
    """The partial derivatives (along, across) of ``transition`` with the same arguments, in its
    plane's two coordinates (a case composes them into grad u, ``grad_u``: the derived gradient
    of r^{3/2} sin(3 theta/2) costs three times u at each quadrature point). With
    w = (s - x0) + i d and g = -Im w^{3/2}, Cauchy-Riemann gives
    (g_s, g_d) = -(3/2) r^{1/2} (sin(theta/2), cos(theta/2)); mirrored (theta from the negative
    s-direction, s - x0 -> x0 - s) g_s changes sign."""
    mirrored = binding_side == "left"
    r, theta = polar(x0, mirrored=mirrored, px=_plane(coordinates)[0], py=_plane(coordinates)[1])
    along, across = -1.5 * sqrt(r) * sin(theta / 2), -1.5 * sqrt(r) * cos(theta / 2)
    return (-along if mirrored else along), across


def _plane(coordinates):
    """(s, d): the coordinates of a transition's plane ("xy", "xz", or a pair of functions)."""
    return {"xy": (x, y), "xz": (x, z)}[coordinates] if isinstance(coordinates, str) else coordinates



def roller_free_mode(exponent: float, omega: float, material, x0: float = 0.0, mirrored: bool = False,
                     angle: float = 0.0, coordinates: str = "xy"):
    """The plane-strain displacement r^l Phi(theta) (l = ``exponent``) on the wedge
    0 <= theta <= omega about (x0, 0) with the frictionless-contact ("roller") conditions
    u_y = 0, sigma_xy = 0 on theta = 0 and a traction-free face theta = omega: the elastic
    counterpart of ``transition`` (omega = pi) and of a binding Gamma_C meeting Gamma_g.

    Kolosov-Muskhelishvili potentials phi = a z^l, psi = b z^l with a, b real (real on the
    ray theta = 0, which gives u_y = sigma_xy = 0 there), 2 mu (u_x + i u_y) = kappa phi
    - z conj(phi') - conj(psi), kappa = 3 - 4 nu (plane strain). With
    sigma_tt + i sigma_rt = Phi + conj(Phi) + e^{2 i theta}(conj(z) Phi' + Psi), Phi = phi',
    Psi = psi', the face theta = omega is traction-free iff

        a (l + 1) cos((l - 1) omega) + b cos((l + 1) omega) = 0,
        a (l - 1) sin((l - 1) omega) + b sin((l + 1) omega) = 0,

    whose determinant is sin(2 l omega) + l sin(2 omega): the exponents are its roots, the
    symmetric (mode I) exponents of a traction-free wedge of angle 2 omega (reflect across
    theta = 0), and do not depend on Poisson's ratio. ``exponent`` must be one. The scale
    makes sigma_n = sigma_tt(theta = 0) = -l r^{l-1}: the contact pressure on theta = 0 is
    l r^{l-1} > 0. ``mirrored``: theta from the negative x-direction (the wedge to the left).
    ``angle``: the whole picture rotated by that angle about (x0, 0) (a tilted Gamma_C).
    ``coordinates``: "xy", or "xz" for the 3D field (u_x, 0, u_z) of the same plane-strain
    displacement in the (x, z) plane, Gamma_C = {z = 0}: plane strain is the 3D body with
    u_y = 0 and nothing depending on y (eps_yy = 0, and sigma_yy = lambda div u depends on x, z
    only, so div sigma keeps no y-component): an exact 3D elastic field.
    """
    import math

    from ngsolve import CF, cos
    from ngsolve import x as X
    from ngsolve import y as Y

    l = float(exponent)
    residual = math.sin(2 * l * omega) + l * math.sin(2 * omega)
    if abs(residual) > 1e-10 * max(1.0, l):
        raise ValueError(f"{l} is not a root of sin(2 l omega) + l sin(2 omega) for omega = {omega}: residual {residual:.2e}")
    # b from whichever face equation is better conditioned, for a = 1
    c, s = math.cos((l + 1) * omega), math.sin((l + 1) * omega)
    b_unit = -(l + 1) * math.cos((l - 1) * omega) / c if abs(c) >= abs(s) else -(l - 1) * math.sin((l - 1) * omega) / s
    a = -1.0 / ((l + 1) + b_unit)       # sigma_tt(0) = l r^{l-1} (a (l + 1) + b) = -l r^{l-1}
    b = a * b_unit
    ca, sa = math.cos(angle), math.sin(angle)
    # the local frame's coordinates (x0 + R(angle) local = global)
    if coordinates not in ("xy", "xz") or (angle and coordinates != "xy"):
        raise ValueError(f"coordinates must be 'xy' (any angle) or 'xz' (angle 0), got {coordinates!r}, angle {angle}")
    if coordinates == "xz":
        Y = z
    local = (x0 + ca * (X - x0) + sa * Y, -sa * (X - x0) + ca * Y) if angle else (X, Y)
    r, theta = polar(x0, mirrored, *local)
    kappa, two_mu = material.kappa, 2 * material.mu
    ux = r**l * ((kappa * a - b) * cos(l * theta) - a * l * cos((2 - l) * theta)) / two_mu
    uy = r**l * ((kappa * a + b) * sin(l * theta) - a * l * sin((2 - l) * theta)) / two_mu
    # mirrored (x -> x0 - x): the x-component changes sign
    ux = -ux if mirrored else ux
    if coordinates == "xz":
        return CF((ux, 0.0, uy))
    return CF((ca * ux - sa * uy, sa * ux + ca * uy)) if angle else CF((ux, uy))
