"""Two bodies in contact along Gamma_C (the paper's Section 6): the second body, the
mirror image of the first across Gamma_C, meshed on its own.

A case declares ``second_body = MirrorBody(geometry=..., maxh=...)`` beside the one-body
contract: its u, f, data and geometry are the *upper* body's (y > 0, Gamma_C on y = 0 with
outward normal -e_y). The lower body (y < 0) carries the mirror solution of
docs/mathematics.md §8:

* scalar: u_2(x, y) = -s(x, -y) with f_2(x, y) = -f(x, -y). Then d_y u_2 = d_y s on y = 0 (the
  fluxes balance), the jump [u] = u_1 - u_2 = 2 s >= 2 alpha, the pressure is the same lambda,
  and lambda ([u] - 2 alpha) = 0.
* elasticity: u_2(x, y) = (s_x(x, -y), -s_y(x, -y)): normal tractions balance, tangential ones
  stay zero (frictionless), the normal opening is twice the one-body gap.

In the lower body's own frame (x, y') = (x, -y), the scalar variable w = -u_2 and the mirrored
displacement (u_x, -u_y) both equal s: the lower body solves the *upper body's* problem -- the
same u, f, Dirichlet, Neumann and contact-load data -- on its own geometry and mesh, and its
contact variable (w, or -u . n in its frame) adds to the upper one's to the opening of the
interface. So a two-body case is two one-body problems on independent meshes coupled by the
mortar condition on c_1 + c_2 >= 2 obstacle (``fem.mortar``); ``lower_body`` is the one-body
case of the lower body, in its frame.

The lower body's geometry must have the upper one's outline (the same domain, with Gamma_C on
y = 0) but may place other points on its boundary (breaks that move its mesh's vertices) and
has its own ``maxh``: the two meshes do not match on Gamma_C, and uniform refinement keeps them
apart. Every singular point of u must be a corner of both (each body's errors are graded there).
"""
from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import ngsolve as ngs

from .friction import LoadHistory


@dataclass(frozen=True)
class MirrorBody:
    """The lower body of a two-body case: the mirror image of the upper one across Gamma_C,
    with its own ``geometry`` (the upper one's outline, in the lower body's mirrored frame)
    and coarse mesh size ``maxh``; ``dirichlet``, if given, its own u_D on Gamma_u (in its
    frame, a CoefficientFunction or a number), held at every load step: the data that let one
    body shear against the other (a mirror pair with equal data never slips, docs/theory/coulomb.md).
    A case loaded from a file declares it on a reference case only (``problem.contract``)."""

    geometry: object
    maxh: float
    dirichlet: object = None

    def __post_init__(self):
        if not hasattr(self.geometry, "GenerateMesh"):
            raise ValueError(f"second_body: geometry must be a netgen geometry, got {type(self.geometry).__name__}")
        if isinstance(self.maxh, bool) or not isinstance(self.maxh, (int, float)) or not (math.isfinite(self.maxh) and self.maxh > 0):
            raise ValueError(f"second_body: maxh must be a finite number > 0, got {self.maxh!r}")
        if self.dirichlet is not None and (isinstance(self.dirichlet, bool) or
                                           not isinstance(self.dirichlet, (int, float, ngs.CoefficientFunction))):
            raise ValueError(f"second_body: dirichlet must be a CoefficientFunction or a number, got {self.dirichlet!r}")


LOWER_SUFFIX = " (second_body: the lower body)"


def lower_body(case):
    """The one-body case the lower body solves in its own frame: ``case`` with the second body's
    geometry and maxh (module docstring), and its own Dirichlet data if it declares them
    (``MirrorBody.dirichlet``: at every step of the load history, whose Dirichlet values are the
    upper body's)."""
    body = case.second_body
    if body is None:
        raise ValueError(f"case {case.name} has one body")
    lower = dataclasses.replace(case, name=case.name + LOWER_SUFFIX, geometry=body.geometry, maxh=float(body.maxh),
                                second_body=None)
    if body.dirichlet is None:
        return lower
    data = case.physics.constant(body.dirichlet) if isinstance(body.dirichlet, (int, float)) else body.dirichlet
    steps = tuple(dataclasses.replace(step, dirichlet=None) for step in case.history.steps)
    return dataclasses.replace(lower, dirichlet=data, history=LoadHistory(steps))
