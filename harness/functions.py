"""Building blocks for exact solutions in case modules (NGSolve CoefficientFunctions).

Each satisfies the Signorini conditions on a straight Gamma_C = {y = 0} with outward normal
n = -e_y, the domain lying above it; see MATH.md Section 4.
"""
from __future__ import annotations

from ngsolve import atan2, pi, sin, sqrt, x, y


def polar(x0: float = 0.0, mirrored: bool = False):
    """(r, theta) about (x0, 0), theta in [0, pi] in the upper half plane; ``mirrored``
    measures theta from the negative x-direction (x -> x0 - x)."""
    dx = (x0 - x) if mirrored else (x - x0)
    # theta = atan2(y, dx) in the upper half plane, written with its branch cut on the negative
    # y-axis, outside the domain: a point of Gamma_C with dx < 0 that NGSolve's element map puts
    # at y = -1e-17 must get theta = pi, not -pi (which flipped the sign of e^{-beta theta}-type
    # terms in oscillating-r34 by a factor e^{2 pi beta} at some load quadrature points)
    return sqrt(dx * dx + y * y), pi / 2 + atan2(-dx, y)


def transition(x0: float = 0.0, binding_side: str = "right"):
    """-r^{3/2} sin(3 theta/2) about (x0, 0) (Remark 2.2): harmonic; u = 0 with
    du/dn = (3/2) sqrt(r) on the binding side, u = r^{3/2} with du/dn = 0 on the other."""
    r, theta = polar(x0, mirrored=(binding_side == "left"))
    return -(r ** 1.5) * sin(1.5 * theta)

