"""Building blocks for exact solutions in case modules (NGSolve CoefficientFunctions).

Each satisfies the Signorini conditions on a straight Gamma_C = {y = 0} with outward normal
n = -e_y, the domain lying above it; see docs/mathematics.md §4 (and ``roller_free_mode`` for the
elastic ones, Remark 2.3).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

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


def scalar_stick_slip(s: float = 1.0, c: float = 1.0, x0: float = 0.0):
    """(u, grad u) of the scalar Tresca problem's stick-slip point at (x0, 0) (``problem.friction``):
    u = s y + c r^{3/2} cos(3 theta/2), harmonic; on Gamma_C = {y = 0} (n = -e_y) it slips on
    the right (u = c (x - x0)^{3/2} > 0, d_n u = -s) and sticks on the left (u = 0,
    d_n u = -s + (3/2) c abs(x - x0)^{1/2}, within [-s, s] while (3/2) c abs(x - x0)^{1/2} <= 2 s).
    grad u from Re z^{3/2}' = (3/2) z^{1/2}: (3/2) c r^{1/2} (cos(theta/2), -sin(theta/2)) + (0, s)."""
    r, theta = polar(x0)
    u = s * (r * sin(theta)) + c * r ** 1.5 * cos(1.5 * theta)
    return u, (1.5 * c * sqrt(r) * cos(theta / 2), s - 1.5 * c * sqrt(r) * sin(theta / 2))


def _plane(coordinates):
    """(s, d): the coordinates of a transition's plane ("xy", "xz", or a pair of functions)."""
    return {"xy": (x, y), "xz": (x, z)}[coordinates] if isinstance(coordinates, str) else coordinates



def roller_free_mode(exponent: float, omega: float, material, x0: float = 0.0, mirrored: bool = False,
                     angle: float = 0.0, coordinates: str = "xy", with_gradient: bool = False):
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
    ``with_gradient``: return (u, grad u), the Jacobian (row i = grad u_i) in closed form from
    the series' derivatives (a case's ``grad_u``: NGSolve's derived one costs several times u).
    """
    import math

    from ngsolve import CF
    from ngsolve import x as X
    from ngsolve import y as Y

    series = roller_free_series(exponent, omega, material)
    ca, sa = math.cos(angle), math.sin(angle)
    # the local frame's coordinates (x0 + R(angle) local = global)
    if coordinates not in ("xy", "xz") or (angle and coordinates != "xy"):
        raise ValueError(f"coordinates must be 'xy' (any angle) or 'xz' (angle 0), got {coordinates!r}, angle {angle}")
    if coordinates == "xz":
        Y = z
    local = (x0 + ca * (X - x0) + sa * Y, -sa * (X - x0) + ca * Y) if angle else (X, Y)
    at = polar(x0, mirrored, *local)
    # mirrored (x -> x0 - x): the x-component changes sign, and so does each d/dx
    flip = -1.0 if mirrored else 1.0
    ux, uy = series.real_imag(*at)
    u = _in_frame((flip * ux, uy), angle, coordinates)
    if not with_gradient:
        return u
    (dx_ux, dx_uy), (dy_ux, dy_uy) = series.diff("x").real_imag(*at), series.diff("y").real_imag(*at)
    local_jacobian = ((dx_ux, flip * dy_ux), (flip * dx_uy, dy_uy))      # row i = grad of component i
    # rotated: J = R J_local R^T
    rotation = ((ca, -sa), (sa, ca))
    jacobian = [[sum(rotation[i][k] * local_jacobian[k][m] * rotation[j][m] for k in range(2) for m in range(2))
                 for j in range(2)] for i in range(2)] if angle else local_jacobian
    if coordinates == "xz":
        (a, b), (c, d) = jacobian
        return u, CF((a, 0.0, b, 0.0, 0.0, 0.0, c, 0.0, d), dims=(3, 3))
    return u, CF(tuple(jacobian[0]) + tuple(jacobian[1]), dims=(2, 2))


def _in_frame(local, angle: float, coordinates: str):
    """The plane vector ``local`` as the case's displacement: turned by ``angle`` in the (x, y)
    plane, or (u_x, 0, u_z) in the (x, z) plane."""
    import math

    from ngsolve import CF
    ux, uy = local
    if coordinates == "xz":
        return CF((ux, 0.0, uy))
    ca, sa = math.cos(angle), math.sin(angle)
    return CF((ca * ux - sa * uy, sa * ux + ca * uy)) if angle else CF((ux, uy))


def roller_free_series(exponent: float, omega: float, material) -> "PolarSeries":
    """u_x + i u_y of ``roller_free_mode`` (unrotated, about 0) as a ``PolarSeries``: with
    phi = a z^l, psi = b z^l, 2 mu (u_x + i u_y) = kappa a z^l - a l z conj(z)^{l-1} - b conj(z)^l
    = r^l (kappa a e^{i l theta} - a l e^{i (2 - l) theta} - b e^{-i l theta})."""
    import math

    l = float(exponent)
    residual = math.sin(2 * l * omega) + l * math.sin(2 * omega)
    if abs(residual) > 1e-10 * max(1.0, l):
        raise ValueError(f"{l} is not a root of sin(2 l omega) + l sin(2 omega) for omega = {omega}: residual {residual:.2e}")
    # b from whichever face equation is better conditioned, for a = 1
    c, s = math.cos((l + 1) * omega), math.sin((l + 1) * omega)
    b_unit = -(l + 1) * math.cos((l - 1) * omega) / c if abs(c) >= abs(s) else -(l - 1) * math.sin((l - 1) * omega) / s
    a = -1.0 / ((l + 1) + b_unit)       # sigma_tt(0) = l r^{l-1} (a (l + 1) + b) = -l r^{l-1}
    b = a * b_unit
    two_mu = 2 * material.mu
    return PolarSeries(((material.kappa * a / two_mu, l, l), (-a * l / two_mu, l, 2 - l), (-b / two_mu, l, -l)))


def stick_slip_series(material, exponent: float = 1.5) -> "PolarSeries":
    """u_x + i u_y of the plane-strain Williams mode at a Tresca stick-slip point, about 0 on the
    half plane theta in [0, pi]: roller (u_y = 0, sigma_xy = 0) on theta = 0 (the slip side, its
    constant shear carried by a smooth field) and clamped (u = 0, stick with bilateral contact) on
    theta = pi. In polar components u = r^l (A cos((l+1) theta) + C (kappa - l) cos((l-1) theta),
    -A sin((l+1) theta) + C (kappa + l) sin((l-1) theta)), i.e.

        u_x + i u_y = r^l (A e^{-i l theta} + C kappa e^{i l theta} - C l e^{i (2 - l) theta}),

    a Kolosov-Muskhelishvili field (phi = 2 mu C z^l, psi = -2 mu A z^l). The four face conditions
    have the determinant 2 l mu (kappa + 1)(kappa sin(2 l omega) - l sin(2 omega)) on the wedge
    of angle omega, at omega = pi 2 l mu kappa (kappa + 1) sin(2 pi l), whose roots are
    l = 1/2, 1, 3/2, ... for every Poisson ratio
    (tests/test_tresca_exact.py). A half-integer l has the null vector C = A / (kappa + l); with
    A = (kappa + l) / (2 mu (kappa + 1)),

        u_x = kappa / (mu (kappa + 1)) r^l on theta = 0,   sigma_xy = (-1)^(l - 1/2) l r^(l-1) on theta = pi:

    the slip and the stick-side shear have opposite signs for l = 3/2, 7/2, ... (admissible as the
    leading term of a Tresca solution) and equal signs for l = 1/2, 5/2, ... (elastic-tresca-r32).
    """
    l = float(exponent)
    if abs(l - round(l - 0.5) - 0.5) > 1e-12 or l <= 0:
        raise ValueError(f"stick_slip_series: the exponent must be a positive half-integer, got {exponent}")
    mu, kappa = material.mu, material.kappa
    A = (kappa + l) / (2 * mu * (kappa + 1))
    C = A / (kappa + l)
    return PolarSeries(((C * kappa, l, l), (-C * l, l, 2 - l), (A, l, -l)))


def coulomb_stick_slip_exponent(material, coefficient: float) -> float:
    """The leading exponent l of a Coulomb stick-slip point (``coulomb_stick_slip_series``):
    l = 3/2 + arctan(mu_F (kappa - 1)/(kappa + 1)) / pi, in (3/2, 2); 3/2 at mu_F = 0 (Tresca)."""
    import math
    kappa = material.kappa
    return 1.5 + math.atan(coefficient * (kappa - 1) / (kappa + 1)) / math.pi


def coulomb_stick_slip_series(material, coefficient: float) -> "PolarSeries":
    """u_x + i u_y of the plane-strain Williams mode at a Coulomb stick-slip point, about 0 on the
    half plane theta in [0, pi]: on theta = 0 (slip, u_x > 0) u_y = 0 and
    sigma_xy + mu_F sigma_yy = 0 (the slip condition sigma_xy = mu_F p less a smooth part's),
    on theta = pi clamped (stick). Williams' ansatz (``stick_slip_series``) gives the determinant
    4 l mu kappa sin(pi l) ((kappa + 1) cos(pi l) + mu_F (kappa - 1) sin(pi l)): besides the
    integers, cot(pi l) = -mu_F (kappa - 1)/(kappa + 1), the first admissible root
    l = ``coulomb_stick_slip_exponent`` (tests/test_coulomb_exact.py). With t = mu_F (kappa - 1)/(kappa + 1)
    the null vector is B = t A, C = A/(kappa + l), D = -t A/(kappa + l), i.e.

        u_x + i u_y = r^l ((A + i B) e^{-i l theta} + (C + i D) kappa e^{i l theta} - (C - i D) l e^{i (2 - l) theta}),

    scaled by A = (kappa + l) cos(pi delta) / (2 mu (kappa + 1)), delta = l - 3/2, so that on
    theta = pi sigma_xy = -l r^{l-1}, sigma_yy = 0, and on theta = 0
    u_x = kappa cos(pi delta) / (mu (kappa + 1)) r^l, sigma_yy = -l t cos(pi delta) / mu_F r^{l-1}
    (= -l (kappa - 1) cos(pi delta)/(kappa + 1) r^{l-1}), sigma_xy = -mu_F sigma_yy.
    mu_F = 0 gives ``stick_slip_series``'s l = 3/2 mode."""
    import math
    l = coulomb_stick_slip_exponent(material, coefficient)
    mu, kappa = material.mu, material.kappa
    t = coefficient * (kappa - 1) / (kappa + 1)
    A = (kappa + l) * math.cos(math.pi * (l - 1.5)) / (2 * mu * (kappa + 1))
    B, C, D = t * A, A / (kappa + l), -t * A / (kappa + l)
    return PolarSeries((((A + 1j * B), l, -l), ((C + 1j * D) * kappa, l, l), (-(C - 1j * D) * l, l, 2 - l)))


def stick_slip_mode(material, coordinates: str = "xy", with_gradient: bool = False, coefficient: float = 0.0):
    """The plane-strain displacement of ``stick_slip_series`` (l = 3/2) about 0: u_y = 0 and
    sigma_xy = 0 on x > 0 (y = 0), u = 0 on x < 0; sigma_xy = -(3/2) abs(x)^{1/2} on x < 0 and
    u_x = kappa / (mu (kappa + 1)) x^{3/2} on x > 0. ``coordinates``: "xy", or "xz" for the 3D
    field (u_x, 0, u_z) of the same displacement in the (x, z) plane (``roller_free_mode``).
    ``with_gradient``: (u, grad u), the Jacobian (row i = grad u_i) in closed form.
    ``coefficient`` mu_F > 0: the Coulomb mode of ``coulomb_stick_slip_series`` instead."""
    from ngsolve import CF
    from ngsolve import x as X
    from ngsolve import y as Y

    if coordinates not in ("xy", "xz"):
        raise ValueError(f"coordinates must be 'xy' or 'xz', got {coordinates!r}")
    series = coulomb_stick_slip_series(material, coefficient) if coefficient else stick_slip_series(material)
    at = polar(0.0, False, X, z if coordinates == "xz" else Y)
    u = _in_frame(series.real_imag(*at), 0.0, coordinates)
    if not with_gradient:
        return u
    (a, c), (b, d) = series.diff("x").real_imag(*at), series.diff("y").real_imag(*at)
    if coordinates == "xz":
        return u, CF((a, 0.0, b, 0.0, 0.0, 0.0, c, 0.0, d), dims=(3, 3))
    return u, CF((a, b, c, d), dims=(2, 2))


@dataclass(frozen=True)
class PolarSeries:
    """A complex function sum_k c_k r^{m_k} e^{i q_k theta} of the plane (z = r e^{i theta}),
    closed under d/dx and d/dy: each term is c z^A conj(z)^B with A = (m + q)/2, B = (m - q)/2,
    and d/dx = d/dz + d/dconj(z), d/dy = i (d/dz - d/dconj(z)), so

        d/dx c r^m e^{i q theta} = c A r^{m-1} e^{i (q-1) theta} + c B r^{m-1} e^{i (q+1) theta},
        d/dy c r^m e^{i q theta} = i c A r^{m-1} e^{i (q-1) theta} - i c B r^{m-1} e^{i (q+1) theta}.

    The derivatives of a Kolosov-Muskhelishvili displacement in closed form: NGSolve's Diff of
    r^l sin(l theta) through sqrt and atan2 builds deeper trees, which cost more per point."""

    terms: tuple            # (c, m, q): complex coefficient, power of r, frequency in theta

    def diff(self, axis: str) -> "PolarSeries":
        """d/dx (``axis`` 'x') or d/dy ('y') of the series."""
        unit = {"x": (1, 1), "y": (1j, -1j)}[axis]
        merged: dict = {}
        for c, m, q in self.terms:
            for factor, power, shift in ((unit[0] * (m + q) / 2, m - 1, q - 1), (unit[1] * (m - q) / 2, m - 1, q + 1)):
                if factor:
                    merged[(power, shift)] = merged.get((power, shift), 0) + c * factor
        largest = max((abs(c) for c in merged.values()), default=0.0)
        return PolarSeries(tuple((c, m, q) for (m, q), c in merged.items() if abs(c) > 1e-15 * largest))

    def real_imag(self, r, theta):
        """(Re, Im) of the series at polar coordinates (r, theta) (CoefficientFunctions). Terms
        with the same power and opposite frequencies share one cos and one sin:
        A e^{i q theta} + B e^{-i q theta} = (A + B) cos(q theta) + i (A - B) sin(q theta)."""
        pairs: dict = {}
        for c, m, q in self.terms:
            plus, minus = pairs.get((m, abs(q)), (0j, 0j))
            pairs[(m, abs(q))] = (plus + c, minus) if q >= 0 else (plus, minus + c)
        re = im = 0.0
        powers = {m: r**m for m, _ in pairs if m}
        for (m, q), (plus, minus) in pairs.items():
            even, odd = plus + minus, (plus - minus) * 1j        # the cos and sin coefficients
            scale = powers.get(m, 1.0)
            cos_q, sin_q = (cos(q * theta), sin(q * theta)) if q else (1.0, 0.0)
            re = re + scale * (even.real * cos_q + odd.real * sin_q)
            im = im + scale * (even.imag * cos_q + odd.imag * sin_q)
        return re, im



def bracketed_root(f, a: float, b: float, xtol: float = 1e-15) -> float:
    """The root of f in [a, b], where f changes sign, by bisection to ``xtol``: the cases'
    singular exponents (Williams' wedge equations) are roots of a scalar function, found at
    import time; SciPy's brentq would add SciPy's import to every case listing."""
    fa = f(a)
    if fa * f(b) > 0:
        raise ValueError(f"f does not change sign on [{a}, {b}]")
    while b - a > xtol:
        m = 0.5 * (a + b)
        fm = f(m)
        if fm == 0.0:
            return m
        if (fm < 0) == (fa < 0):
            a, fa = m, fm
        else:
            b = m
    return 0.5 * (a + b)


def clamped_free_exponent(omega: float, poisson: float) -> float:
    """The least root l in (0.5, 0.99) of Williams' clamped-free wedge equation in plane strain
    (J. Appl. Mech. 19 (1952) 526-528; cases/hertz_line.py checks it), kappa = 3 - 4 nu:
    kappa^2 + 1 + 2 kappa cos(2 l omega) - 4 l^2 sin^2(omega) = 0."""
    kappa = 3 - 4 * poisson
    return bracketed_root(lambda s: kappa**2 + 1 + 2 * kappa * math.cos(2 * s * omega) - 4 * s**2 * math.sin(omega) ** 2,
                          0.5, 0.99, xtol=1e-14)
