"""A residual a posteriori error estimator for the scalar Signorini problem, element by element.

For u_h on a mesh T_h (any method: the cones, Nitsche, penalty), with -Laplace(u) = f, d_n u = g
on Gamma_g and the contact conditions u - alpha >= 0, lambda = d_n u - g_C >= 0,
lambda (u - alpha) = 0 on Gamma_C (docs/mathematics.md §1):

    eta_T^2 =   h_T^2 ||f + Laplace(u_h)||_T^2                          element residual
              + 1/2 sum_{E in dT, interior} h_E ||[d_n u_h]||_E^2         flux jumps (half to each side)
              + sum_{E in dT on Gamma_g} h_E ||g - d_n u_h||_E^2          Neumann residual
              + sum_{E in dT on Gamma_C} (  h_E ||lambda_h - (d_n u_h - g_C)||_E^2     flux against pressure
                                          + h_E ||(lambda_h)_-||_E^2                   tension
                                          + h_E^-1 ||(alpha - u_h)_+||_E^2              penetration
                                          + int_E (lambda_h)_+ (u_h - alpha)_+ )        complementarity

and eta^2 = sum_T eta_T^2. Every term vanishes for u_h = u (with lambda_h = lambda).

lambda_h is the discrete contact pressure of the residual, ``errors.DiscretePressure``: the
representative in the trace space of the functional a(u_h, w) - L(w) on Gamma_C -- the
construction of the "quasi-discrete contact force density" of Krause, Veeser & Walloth (Numer.
Math. 130 (2015)), the same for every method. The terms are those of the residual estimators
for Signorini's problem of Hild & Nicaise (Numer. Math. 101 (2005)), Weiss & Wohlmuth (Math.
Comp. 78 (2009)), Krause, Veeser & Walloth, and, for quadratic elements, the adaptive P2
method of arXiv 2209.04906 (element and jump residuals, the flux mismatch on Gamma_C, the
penetration, the complementarity): the penetration term is the one
the P2 cones need, as their nodal or mean constraints let u_h dip below alpha between nodes.
The texts of these papers were not reachable from this sandbox: the weights above are the
standard scalings (h for flux terms, h^-1 for the H^1/2-like penetration), not a quotation of
one paper's definition, and no constant is claimed. What the harness measures instead is the
effectivity eta / ||u - u_h||_a on the exact cases (``study.chain``).
"""
from __future__ import annotations

import ngsolve as ngs
import numpy as np

from ..fem.contact_quadrature import at_points, contact_quadrature
from ..fem.element_quadrature import singular_vertices
from .errors import CONTACT_ERROR_POINTS, DiscretePressure

# Gauss order of the volume moments: f^2 exactly for f of degree 4, as the error norms' rule
VOLUME_ORDER = 8


def facet_indicators(mesh: ngs.Mesh) -> tuple:
    """(interior, neumann, along): piecewise constants on the facets, 1 on the interior ones,
    resp. on those of Gamma_g; and the triangles with a side on Gamma_g (a BitArray)."""
    space = ngs.FacetFESpace(mesh, order=0)
    interior, neumann = ngs.GridFunction(space), ngs.GridFunction(space)
    interior.vec.FV().NumPy()[:] = 1.0
    neumann.vec[:] = 0.0
    along = ngs.BitArray(mesh.ne)
    along.Clear()
    for element in mesh.Elements(ngs.BND):
        facet = space.GetDofNrs(element)[0]
        interior.vec[facet] = 0.0
        if element.mat == "neumann":
            neumann.vec[facet] = 1.0
            along.Set(mesh[element.edges[0]].elements[0].nr)
    return interior, neumann, along


class ResidualEstimator:
    """eta_T^2 of solutions on one discrete problem (2D, scalar): ``indicators(u)``."""

    def __init__(self, case, problem):
        if case.dimension != 2 or case.physics.elastic:
            raise ValueError("the residual estimator is for 2D scalar problems")
        self.case, self.problem, mesh = case, problem, problem.mesh
        self.interior, self.neumann, self.along_neumann = facet_indicators(mesh)
        self.pressure = DiscretePressure(problem)
        q = contact_quadrature(problem, CONTACT_ERROR_POINTS, graded_at=singular_vertices(case, mesh))
        self.q = q
        self.T_contact = q.T[:, problem.contact_dofs].tocsr()
        self.obstacle = at_points(case.gap, mesh, q)
        self.load = at_points(case.contact_load, mesh, q)
        self.element_of_edge = problem.trace.volumes
        # Laplace(u_h) is constant on each element (P2; zero for P1), so with f_T the mean of f
        #   h_T^2 ||f + Laplace(u_h)||_T^2 = h_T^2 ||f - f_T||_T^2 + h_T^2 |T| (f_T + Laplace_T)^2,
        # the first term (the data's oscillation) made once per mesh for all methods, the second
        # per solution from one number per element, without cancellation
        h = ngs.specialcf.mesh_size

        def moment(cf, order=VOLUME_ORDER):
            return np.array(ngs.Integrate(cf, mesh, ngs.VOL, order=order, element_wise=True).NumPy())
        self.area = moment(ngs.CF(1.0), 0)
        self.h2 = moment(h * h, 0)
        self.mean_f = np.zeros(mesh.ne) if case.f_vanishes else moment(case.f) / self.area
        self.oscillation = np.zeros(mesh.ne)
        if not case.f_vanishes:
            mean = ngs.GridFunction(ngs.L2(mesh, order=0))
            mean.vec.FV().NumPy()[:] = self.mean_f
            self.oscillation = moment(h * h * (case.f - mean) ** 2)

    def indicators(self, u: np.ndarray) -> np.ndarray:
        """eta_T^2 for every element of the mesh."""
        mesh, case = self.problem.mesh, self.case
        gfu = self.problem.gridfunction(u)
        h = ngs.specialcf.mesh_size
        n = ngs.specialcf.normal(mesh.dim)
        laplace = 0.0
        if self.problem.order > 1:
            hesse = gfu.Operator("hesse")
            laplace = ngs.Integrate((hesse[0] + hesse[3]) * ngs.dx(bonus_intorder=-3), mesh, element_wise=True).NumPy() / self.area
        eta2 = self.oscillation + self.h2 * (self.mean_f + laplace) ** 2
        flux = ngs.grad(gfu) * n
        jump = flux - ngs.grad(gfu).Other() * n
        jumps = (0.5 * h * self.interior * jump**2).Compile() * ngs.dx(element_boundary=True)
        eta2 += ngs.Integrate(jumps, mesh, element_wise=True).NumPy()
        # on the triangles along Gamma_g only (on a boundary element NGSolve's grad is the
        # tangential one: the normal derivative needs the triangle's side)
        neumann = h * self.neumann * (case.neumann_data(n) - flux) ** 2 * \
            ngs.dx(element_boundary=True, bonus_intorder=2, definedonelements=self.along_neumann)
        eta2 += ngs.Integrate(neumann, mesh, element_wise=True).NumPy()
        np.add.at(eta2, self.element_of_edge, self.contact_terms(u))
        return np.maximum(eta2, 0.0)

    def contact_terms(self, u: np.ndarray) -> np.ndarray:
        """The Gamma_C terms of each contact edge (``problem.trace``'s order)."""
        q = self.q
        lam_h = self.T_contact @ self.pressure.coefficients(u)
        flux = q.N @ u - self.load
        gap = q.T @ u - self.obstacle
        density = (q.h * ((lam_h - flux) ** 2 + np.minimum(lam_h, 0.0) ** 2)
                   + np.maximum(-gap, 0.0) ** 2 / q.h
                   + np.maximum(lam_h, 0.0) * np.maximum(gap, 0.0))
        return np.bincount(q.edge, weights=q.weights * density, minlength=len(self.problem.trace.edges))


def estimate(indicators: np.ndarray) -> float:
    """eta = (sum_T eta_T^2)^(1/2)."""
    return float(np.sqrt(np.sum(indicators)))
