"""Building blocks for exact solutions in case modules (NGSolve CoefficientFunctions).

Each satisfies the Signorini conditions on a straight Gamma_C = {y = 0} with outward normal
n = -e_y, the domain lying above it; see MATH.md Section 4.
"""
from __future__ import annotations

from ngsolve import atan2, sin, sqrt, x, y


def polar(x0: float = 0.0, mirrored: bool = False):
    """(r, theta) about (x0, 0), theta in [0, pi] in the upper half plane; ``mirrored``
    measures theta from the negative x-direction (x -> x0 - x)."""
    dx = (x0 - x) if mirrored else (x - x0)
    return sqrt(dx * dx + y * y), atan2(y, dx)


def transition(x0: float = 0.0, binding_side: str = "right"):
    """-r^{3/2} sin(3 theta/2) about (x0, 0) (Remark 2.2): harmonic; u = 0 with
    du/dn = (3/2) sqrt(r) on the binding side, u = r^{3/2} with du/dn = 0 on the other."""
    r, theta = polar(x0, mirrored=(binding_side == "left"))
    return -(r ** 1.5) * sin(1.5 * theta)

