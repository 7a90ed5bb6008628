"""A residual a posteriori error estimator for two bodies in contact on non-matching meshes
(``fem.two_body``), element by element over both bodies: the indicators that drive two-body
adaptive meshes (``mesh.two_body_levels.AdaptivePair``) and the ``estimator`` column of their rows.

Each body k, in its own frame (``problem.bodies``: the lower body solves the upper body's
problem), with contact variable c_k, flux F(u_k) (grad u or sigma(u)) and discrete pressure
lambda_h,k -- the representative on its own trace of its residual a_k(u_k,h, w) - L_k(w)
(``errors.DiscretePressure``; by the mortar condition that residual is B_k^T mu, the mortar
multiplier's action on body k's trace):

    eta_T^2 =   h_T^2 ||f + div F(u_h)||_T^2 + 1/2 sum h_E ||[F(u_h) n]||_E^2 + sum_{Gamma_g} h_E ||g - F(u_h) n||_E^2
                                                            (the one-body terms, ``estimator.MeshTerms``)
              + sum_{E in dT on Gamma_C} (  h_E ||lambda_h,k - lambda(u_k,h)||_E^2        each side's flux against its pressure
                                          + h_E ||(lambda_h,k)_-||_E^2                    tension
                                          + h_E ||sigma_t(u_k,h) - g_t||_E^2 )            elasticity: frictionless

and on the interface, per segment S of the intersection of the two trace meshes (``fem.mortar``),
with the opening [c_h] = c_1,h + c_2,h and the gap 2 alpha, half to the element of each side
that holds S (E_k its trace edge there):

              + 1/2 h_{E_k}^-1 ||(2 alpha - [c_h])_+||_S^2                    penetration of the opening
              + 1/2 int_S (lambda_h,k)_+ ([c_h] - 2 alpha)_+                  complementarity

The penetration and the complementarity are the one-body estimator's (``estimator``), with the
opening of the interface in place of the one body's contact variable: on non-matching meshes
the mortar condition holds weakly, so [c_h] may dip below 2 alpha between the slave's nodes,
and the flux terms of both sides measure the one pressure from each side. These are the
standard terms of the residual estimators for two-body contact with mortar multipliers --
Wohlmuth's estimators for contact on non-matching meshes (mortar multipliers, element and edge
residuals, the multiplier against each side's normal flux) and the two-body setting of Krause,
Veeser & Walloth (Numer. Math. 130 (2015)), whose discrete contact force lambda_h the harness
uses (docs/theory/references.md says what was read): the weights are the one-body estimator's standard scalings,
not a quotation, and no reliability or efficiency constant is claimed. What the harness
measures is the effectivity eta / ||u - u_h||_a on the exact two-body cases.

Every term vanishes for u_h = u, lambda_h,k = lambda (the fluxes balance, [u] >= 2 alpha and
lambda ([u] - 2 alpha) = 0).
"""
from __future__ import annotations

import numpy as np

from ..fem.contact_quadrature import gauss
from ..fem.mortar import POINTS, TraceElements, hierarchical_basis, intersection
from ..fem.two_body import TwoBodyProblem
from ..mesh.points import evaluate
from .estimator import ResidualEstimator


class OneSide(ResidualEstimator):
    """One body's indicators (``estimator.ResidualEstimator``) with the Gamma_C terms of its flux
    only: the flux against its pressure lambda_h,k, the tension and (elasticity) the tangential
    traction. Its penetration and complementarity belong to the opening of the interface
    (``Interface``), which no single body sees."""

    def gap_density(self, lam_h: np.ndarray, u: np.ndarray) -> float:
        return 0.0


class Interface:
    """The interface terms of one level's two-body problem on the segments of the intersection
    of the two trace meshes, a Gauss rule of ``fem.mortar.POINTS`` points on each (exact on the
    polynomial pieces; the few segments where (.)_+ switches are integrated approximately, as
    in the one-body estimator)."""

    def __init__(self, case, problem: TwoBodyProblem):
        self.problem = problem
        self.sides = [TraceElements.of(body) for body in problem.bodies]
        segments = intersection(*self.sides)
        t, w = gauss(POINTS)
        self.x = segments[:, :1] + t[None, :] * (segments[:, 1:] - segments[:, :1])          # (s, q)
        self.weights = (segments[:, 1] - segments[:, 0])[:, None] * w[None, :]
        middle = 0.5 * (segments[:, 0] + segments[:, 1])
        self.located = []           # per side: (its trace element of each segment, the basis at the points)
        for body, side in zip(problem.bodies, self.sides):
            e = side.locate(middle)
            basis = hierarchical_basis(side.parameters(self.x, e).ravel(), body.order).reshape(*self.x.shape, -1)
            self.located.append((e, basis))
        if case.obstacle is None:
            self.gap = np.zeros_like(self.x)
        else:
            points = np.stack([self.x, np.zeros_like(self.x)], axis=-1)
            self.gap = 2.0 * evaluate(case.obstacle, problem.upper.mesh, points)

    def trace_values(self, k: int, vector: np.ndarray) -> np.ndarray:
        """Side k's trace function with dof vector ``vector`` at the points, (segments, points)."""
        e, basis = self.located[k]
        return np.einsum("sqj,sj->sq", basis, vector[self.sides[k].dofs[e]])

    def opening(self, z: np.ndarray) -> np.ndarray:
        """[c_h] = c_1,h + c_2,h at the points."""
        return sum(self.trace_values(k, u) for k, u in enumerate(self.problem.split(z)))

    def indicators(self, z: np.ndarray, pressures: list[np.ndarray]) -> list[np.ndarray]:
        """Per side, the interface terms of each of its elements (half of every segment's):
        penetration of the opening and complementarity against its own lambda_h,k (``pressures``:
        coefficients on ``contact_dofs``)."""
        distance = self.opening(z) - self.gap
        out = []
        for k, (body, side, coefficients) in enumerate(zip(self.problem.bodies, self.sides, pressures)):
            e, _ = self.located[k]
            h = (side.right - side.left)[e][:, None]
            full = np.zeros(body.ndof)
            full[body.contact_dofs] = coefficients
            lam_h = self.trace_values(k, full)
            density = np.maximum(-distance, 0.0) ** 2 / h + np.maximum(lam_h, 0.0) * np.maximum(distance, 0.0)
            per_segment = 0.5 * (self.weights * density).sum(axis=1)
            elements = body.trace.volumes[side.edge_index[e]]
            out.append(np.bincount(elements, weights=per_segment, minlength=body.mesh.ne))
        return out


class TwoBodyEstimator:
    """eta_T^2 of two-body solutions on one ``TwoBodyProblem``, the upper body's elements then
    the lower body's (one array: Dörfler's marking ranks both bodies' elements together)."""

    def __init__(self, bodies: tuple, problem: TwoBodyProblem):
        self.problem = problem
        self.sides = [OneSide(body, side) for body, side in zip(bodies, problem.bodies)]
        self.interface = Interface(bodies[0], problem)

    def indicators(self, z: np.ndarray, previous: np.ndarray | None = None) -> np.ndarray:
        """eta_T^2 per element; NaN after a load history (``previous``, the step before's u_h):
        the terms above are frictionless, and those of the slip between the bodies over a step
        are not written."""
        if previous is not None:
            return np.full(sum(body.mesh.ne for body in self.problem.bodies), np.nan)
        parts = [side.indicators(u) for side, u in zip(self.sides, self.problem.split(z))]
        extra = self.interface.indicators(z, [side.pressure_coefficients for side in self.sides])
        return np.concatenate([part + more for part, more in zip(parts, extra)])
