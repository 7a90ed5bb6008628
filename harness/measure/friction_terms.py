"""The Gamma_C terms of the residual estimator (``estimator.ResidualEstimator``) on a Tresca case
(``problem.friction``): the friction law replaces the Signorini conditions, so the tension,
penetration and contact complementarity give way to the friction ones, per point of Gamma_C
(integrated over the contact cells by the estimator):

scalar (Stadler's simplified friction: |lambda| <= s, lambda = -s u/|u| where u != 0,
lambda = d_n u - g_C):

    h_E (lambda_h - lambda(u_h))^2          flux against the discrete friction force
  + h_E (|lambda_h| - s)_+^2                 excess over the threshold
  + (s |u_h| + lambda_h u_h)_+               complementarity of the friction law

elasticity with bilateral normal contact (u . n = 0; |sigma_t| <= s, sigma_t = -s u_t/|u_t|
where u_t != 0, sigma_t the tangential traction less g_t, a vector), with lambda_t,h the
discrete friction force (``FrictionTerms`` says how it is made):

    h_E (lambda_h - p(u_h))^2 + h_E |lambda_t,h - sigma_t(u_h)|^2   fluxes against the discrete forces
  + h_E^-1 (c(u_h) - obstacle)^2             the bilateral condition's residual, both signs
  + h_E (|lambda_t,h| - s)_+^2               excess over the threshold
  + (s |u_h,t| + lambda_t,h . u_h,t)_+       complementarity of the friction law

Coulomb (``problem.friction.Coulomb``): the elastic terms with s = mu_F [lambda_h]_+ and, for
the unilateral normal condition, the Signorini estimator's penetration, tension and
complementarity in place of the bilateral residual. On a load history the complementarity
takes the last step's slip, u_h,t less the step before's (the law of that step).

Every term vanishes at the exact solution: |lambda| <= s makes s|u| + lambda u >= 0 with
equality exactly where lambda = -s sign(u) or u = 0, so its positive part is zero there, and the
others are residuals of equations u satisfies. The complementarity takes the discrete force,
not the flux of u_h: with sigma_t(u_h) in it, it is linear in the traction's error on the slip
zone (where |u_t| is of order one), and on elastic-tresca-r32 the effectivity drifted from 3.4
to 6.1 over five P1 levels; with lambda_t,h it stays at 3.4-3.6 (tests/test_tresca_meshes.py).

These are not a quotation of a published residual estimator for Tresca friction: none was
found whose text could be read here. The a posteriori analyses seen (abstracts only) are
equilibrated-stress or constitutive-relation ones: Fontana & Di Pietro, arXiv 2401.02944
(Tresca and Coulomb, unilateral contact); Coorevits, Hild & Hjiaj (Coulomb, error in the
constitutive relation). The terms above follow the pattern of the Signorini estimator's
(``estimator``'s docstring): residuals of the equations, h-weighted for forces, h^-1 for the
displacement constraint, and the complementarity unsquared (it is linear in the error as the
Signorini one is). As there, P_k with k >= 3 leave the complementarity out (``gap_density``
of the estimator says why). No reliability constant is claimed; the harness measures the
effectivity on the exact cases.
"""
from __future__ import annotations

import ngsolve as ngs
import numpy as np
from scipy.sparse.linalg import splu

from ..mesh.points import evaluate


def scalar_density(lam_h, force, u_h, s, h, complementarity: bool = True) -> dict:
    """The scalar terms at points (arrays of one shape): ``lam_h`` the discrete friction force,
    ``force`` lambda(u_h) = d_n u_h - g_C, ``u_h`` the trace, ``s`` the threshold, ``h`` the
    cell size. A dict term name -> density."""
    terms = {"flux": h * (lam_h - force) ** 2, "excess": h * np.maximum(np.abs(lam_h) - s, 0.0) ** 2}
    terms["complementarity"] = np.maximum(s * np.abs(u_h) + lam_h * u_h, 0.0) if complementarity else 0.0 * h
    return terms


def elastic_density(lam_h, pressure, normal_residual, force_t, traction_t, u_t, s, h,
                    complementarity: bool = True, unilateral: bool = False) -> dict:
    """The elastic terms at q points: ``lam_h`` the discrete normal reaction, ``pressure``
    p(u_h), ``normal_residual`` c(u_h) - obstacle (q,); ``force_t`` the discrete friction force,
    ``traction_t`` sigma_t(u_h) - g_t and ``u_t`` the tangential trace (q, dim); ``s``, ``h`` (q,).
    ``unilateral`` (Coulomb): the normal condition's terms are the Signorini estimator's --
    penetration, tension of lambda_h and their complementarity -- not the bilateral residual."""
    flux = (lam_h - pressure) ** 2 + ((force_t - traction_t) ** 2).sum(axis=-1)
    excess = np.maximum(np.linalg.norm(force_t, axis=-1) - s, 0.0)
    normal = normal_residual**2 / h
    if unilateral:
        normal = np.maximum(-normal_residual, 0.0) ** 2 / h + h * np.minimum(lam_h, 0.0) ** 2
        if complementarity:
            normal = normal + np.maximum(lam_h, 0.0) * np.maximum(normal_residual, 0.0)
    terms = {"flux": h * flux, "normal": normal, "excess": h * excess**2}
    work = s * np.linalg.norm(u_t, axis=-1) + (force_t * u_t).sum(axis=-1)
    terms["complementarity"] = np.maximum(work, 0.0) if complementarity else 0.0 * h
    return terms


class FrictionTerms:
    """The friction terms of one discrete problem at the estimator's contact points ``q``
    (``fem.contact_quadrature``): ``density(lam_h, u, gfu)`` per point, summed over the terms;
    ``terms(...)`` gives them apart.

    The discrete friction force of 2D elasticity is made as the scalar one (``errors.DiscretePressure``):
    the representative in the trace space of a(u_h, w tau) - L(w tau), the residual's rows of
    the tangential dofs of the rotated frame (``fem.rotated_frame``: the component before the
    contact one, tau = (-n_y, n_x)), kept here before a solve takes the stiffness matrix. In 3D
    (and without a rotated frame) the pointwise traction sigma_t(u_h) stands in for it, and the
    complementarity is then linear in the traction's error on the slip zone."""

    def __init__(self, case, problem, q, load, obstacle):
        self.case, self.problem, self.q, self.load = case, problem, q, load
        self.obstacle = 0.0 if obstacle is None else obstacle
        # Coulomb's threshold is mu_F times the discrete pressure, known at ``terms`` only
        self.coulomb = case.friction.name == "coulomb"
        self.s = None if self.coulomb else evaluate(case.friction.threshold_function, problem.mesh, q.points)
        # the complementarity is left out for P_k, k >= 3, as in the Signorini terms
        self.complementarity = problem.order <= 2
        self.tangential = None
        if problem.physics.rotated_frame and problem.mesh.dim == 2:
            rows = problem.contact_dofs - problem.ndof // problem.physics.components
            T = q.T[:, problem.contact_dofs].tocsc()     # the scalar trace basis on Gamma_C
            mass = splu((T.T @ T.multiply(q.weights[:, None])).tocsc())
            self.tangential = (problem.A[rows].copy(), problem.b[rows], T.tocsr(), mass)

    def friction_force(self, u: np.ndarray, traction_t: np.ndarray) -> np.ndarray:
        """The discrete friction force (q, dim) of an elastic u (``traction_t`` without one)."""
        if self.tangential is None:
            return traction_t
        rows, b, T, mass = self.tangential
        normals = self.q.normals
        return (T @ mass.solve(rows @ u - b))[:, None] * np.stack([-normals[:, 1], normals[:, 0]], axis=-1)

    def terms(self, lam_h: np.ndarray, u: np.ndarray, gfu, before=None) -> dict:
        """The densities of ``scalar_density`` or ``elastic_density`` at the contact points, of
        the solution u (its GridFunction ``gfu``) and its discrete force ``lam_h`` there;
        ``before``: the GridFunction of the load step before on a history, whose tangential
        displacement the step's slip is measured from (Coulomb's law is a law of slip rates)."""
        q, physics, mesh = self.q, self.case.physics, self.problem.mesh
        gradients = evaluate(ngs.grad(gfu), mesh, q.points).reshape(len(q.h), physics.components, -1)
        flux = physics.flux_array(gradients)
        force, tangential = physics.contact_forces(flux, q.normals, self.load)
        if tangential is None:          # the physics has no tangential force: the scalar model
            return scalar_density(lam_h, force, q.T @ u, self.s, q.h, self.complementarity)
        traction = np.einsum("qij,qj->qi", flux, q.normals) - self.load
        traction_t = traction - (traction * q.normals).sum(axis=-1)[:, None] * q.normals
        values = evaluate(gfu, mesh, q.points).reshape(q.normals.shape)
        if before is not None:
            values = values - evaluate(before, mesh, q.points).reshape(q.normals.shape)
        u_t = values - (values * q.normals).sum(axis=-1)[:, None] * q.normals
        s = self.case.friction.coefficient * np.maximum(lam_h, 0.0) if self.coulomb else self.s
        return elastic_density(lam_h, force, q.T @ u - self.obstacle, self.friction_force(u, traction_t), traction_t,
                               u_t, s, q.h, self.complementarity, unilateral=self.coulomb)

    def density(self, lam_h: np.ndarray, u: np.ndarray, gfu, before=None) -> np.ndarray:
        return sum(self.terms(lam_h, u, gfu, before).values())
