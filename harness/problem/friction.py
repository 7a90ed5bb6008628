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

* ``Coulomb(coefficient)`` -- Coulomb friction with the coefficient mu_F > 0 (elasticity only): the
  unilateral contact conditions of the frictionless problem (Remark 2.3; the contact pressure
  p = -(sigma_n(u) - g_n) >= 0, u . n <= g, p (u . n - g) = 0) together with Tresca's
  conditions whose threshold is the pressure itself, s = mu_F p:

      |sigma_t| <= mu_F p,   sigma_t = -mu_F p w_t / |w_t| where w_t != 0,

  w_t the slip: u_t itself in a static problem, the increment u_t - u_t^{previous} over a load
  step of a load history (``LoadHistory``; quasi-static Coulomb friction discretised in time,
  L.-E. Andersson, Appl. Math. Optim. 42 (2000) (statement not read here); P. Wriggers,
  Computational Contact Mechanics, 2006, Sect. 5.2). No convexity: the discrete problem has a
  solution for every mu_F and a unique one only for mu_F small (H. B. Khenous, J. Pommier &
  Y. Renard, Appl. Numer. Math. 56 (2006) 163-192, read from its abstract only), and
  no theorem gives a rate: the harness reports the measured rates beside Tresca's.

A case declares ``friction = Tresca(threshold=...)`` or ``Coulomb(coefficient=...)``
(``harness.problem.Tresca``, ``harness.problem.Coulomb``) and, optionally, a
``history = LoadHistory(...)``; a method
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


@dataclass(frozen=True)
class Coulomb:
    """Coulomb friction with the coefficient ``coefficient`` (mu_F > 0, a number) on top of
    unilateral contact (the module's note); elasticity only (the scalar model has no normal
    stress to take the threshold from)."""

    coefficient: float = 0.3
    name = "coulomb"
    normal = "unilateral"

    def __post_init__(self):
        mu = self.coefficient
        if isinstance(mu, bool) or not (isinstance(mu, (int, float)) and math.isfinite(mu) and mu > 0):
            raise ValueError(f"Coulomb coefficient must be a number > 0, got {mu!r}")

    def describe(self) -> str:
        return f"Coulomb friction, mu_F = {self.coefficient:g}"


@dataclass(frozen=True, eq=False)
class LoadStep:
    """One step of a ``LoadHistory``: the data that change at it, each None where the case's own
    (its last step's) holds -- ``dirichlet`` (u_D on Gamma_u), ``neumann`` (the traction on
    Gamma_g), ``f``, CoefficientFunctions or numbers -- and its label ("normal", "tangential")."""

    label: str = ""
    dirichlet: object = None
    neumann: object = None
    f: object = None

    def overrides(self) -> dict:
        """The case fields this step replaces (``dataclasses.replace`` on a ``case.Case``)."""
        return {key: value for key, value in (("dirichlet", self.dirichlet), ("neumann", self.neumann),
                                              ("declared_f", self.f)) if value is not None}


@dataclass(frozen=True, eq=False)
class LoadHistory:
    """A quasi-static load history: the steps in order, the state carried from one to the next
    (Coulomb's slip is the increment over a step, ``Coulomb``); the last step's data are the
    case's own (its u, dirichlet, neumann, f), so that its errors and quantities are measured on
    the final state. ``LoadHistory((LoadStep("normal", dirichlet=...), LoadStep("tangential")))``:
    press first, then shear -- Cattaneo's history."""

    steps: tuple = (LoadStep(),)

    def __post_init__(self):
        steps = tuple(self.steps)
        if not steps or not all(isinstance(step, LoadStep) for step in steps):
            raise ValueError("a load history is a non-empty sequence of harness.problem.LoadStep")
        if steps[-1].overrides():
            raise ValueError("a load history's last step carries the case's own data (give it no dirichlet, neumann or f)")
        object.__setattr__(self, "steps", steps)

    def __len__(self) -> int:
        return len(self.steps)

    def labels(self) -> list[str]:
        return [step.label or f"step {k + 1}" for k, step in enumerate(self.steps)]


# one step: the case's data at once (a static problem)
STATIC = LoadHistory()

# the normal conditions an elastic Tresca case may declare (unilateral contact with Tresca
# friction is the next step: the contact and friction rows of one active set)
NORMAL_CONDITIONS = ("bilateral",)
FRICTIONLESS = Frictionless()
# the friction laws, by name (``harness.methods.method.Method.friction`` names them)
FRICTION_LAWS = ("frictionless", "tresca", "coulomb")
