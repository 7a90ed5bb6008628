"""The friction axis: which friction law holds on Gamma_C (a case's ``friction``).

* ``FRICTIONLESS`` -- the paper's problem: the Signorini conditions (2.4) on Gamma_C (in
  elasticity with sigma_t(u) = g_t).
* ``Tresca(threshold)`` -- friction with a given threshold s > 0 (a number or a
  CoefficientFunction on Gamma_C), the convex first step of frictional contact:

  - scalar physics, the "simplified friction" problem (Glowinski, Lions & Tremolieres 1981;
    G. Stadler, SIAM J. Optim. 15 (2004) 39-62, problem (P)): minimise
    1/2 a(v, v) - L(v) + j(v), j(v) = int_{Gamma_C} s |v|, over v = u_D on Gamma_u. On Gamma_C,
    with the flux lambda = d_n u - g_C (g_C the case's ``contact_load``),

        |lambda| <= s,   lambda = -s u / |u| where u != 0       (stick: u = 0; slip: u != 0);

    no unilateral condition: the friction law replaces the contact law.
  - elasticity, bilateral normal contact: u . n = 0 on Gamma_C (no gap) and, with the
    tangential traction sigma_t = sigma(u) n - sigma_n n - g_t (a vector in 3D),

        |sigma_t| <= s,   sigma_t = -s u_t / |u_t| where u_t != 0;

    in 3D u_t is a 2-vector and the admissible set of sigma_t a disc of radius s, not a box.

A case declares ``friction = Tresca(threshold=...)`` (``harness.problem.Tresca``); a method
declares the friction laws it discretises (``harness.methods.method.Method.friction``) and a study
leaves it out of the cases of the others, saying why.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import ngsolve as ngs


@dataclass(frozen=True)
class Frictionless:
    """No friction: the Signorini conditions of the case's physics on Gamma_C."""

    name = "frictionless"

    def describe(self) -> str:
        return "frictionless"


@dataclass(frozen=True, eq=False)
class Tresca:
    """Tresca friction with the threshold ``threshold`` (s > 0: a number, or a
    CoefficientFunction positive on Gamma_C); ``normal``: the normal condition of an elastic
    body, "bilateral" (u . n = 0 on Gamma_C). A scalar case has no normal condition."""

    threshold: object = 1.0
    normal: str = "bilateral"
    name = "tresca"

    def __post_init__(self):
        s = self.threshold
        if isinstance(s, bool) or not (isinstance(s, ngs.CoefficientFunction)
                                       or (isinstance(s, (int, float)) and math.isfinite(s) and s > 0)):
            raise ValueError(f"Tresca threshold must be a number > 0 or an NGSolve CoefficientFunction, got {s!r}")
        if self.normal not in NORMAL_CONDITIONS:
            raise ValueError(f"Tresca normal condition must be one of {', '.join(NORMAL_CONDITIONS)}, got {self.normal!r}")

    @property
    def threshold_function(self) -> ngs.CoefficientFunction:
        """s as a CoefficientFunction (a constant for a number)."""
        return ngs.CF(float(self.threshold)) if isinstance(self.threshold, (int, float)) else self.threshold

    @property
    def constant(self) -> bool:
        return isinstance(self.threshold, (int, float))

    def describe(self) -> str:
        s = f"s = {self.threshold:g}" if self.constant else "s(x) given"
        return f"Tresca friction, {s}"


# the normal conditions an elastic Tresca case may declare (unilateral contact with Tresca
# friction is the next step: the contact and friction rows of one active set)
NORMAL_CONDITIONS = ("bilateral",)
FRICTIONLESS = Frictionless()
# the friction laws, by name (``harness.methods.method.Method.friction`` names them)
FRICTION_LAWS = ("frictionless", "tresca")
