"""The best approximation of u in X_h, with no contact involved: the Ritz projection R_h u.

(In elasticity R_h u is the best approximation in the energy norm a(e, e)^{1/2}, not in the
H^1 seminorm: a contact solution may have a smaller H^1 error than R_h u, never a smaller
energy error. The rotated frame at Gamma_C changes nothing: the flux load below is the
pressure against the contact variable's basis, as in the scalar case.)

a(u - R_h u, v_h) = 0 for every v_h in X_h vanishing on Gamma_u, R_h u = u_D,h on Gamma_u (the
methods' own Dirichlet lift). By Green's formula a(u, v) = (f, v) + int_{Gamma_g} g v +
int_{Gamma_C} d_n u v: the Galerkin solution with u's own flux on Gamma_C as Neumann data, one
linear solve with the stiffness matrix. It minimises |u - v_h|_1 over those v_h, so its error
measures the regularity of u alone (h^{min(nu - 1, k)} for P_k, uniform meshes) and the methods'
errors over it are the price of the contact discretisation (Falk's lemma's extra terms, the
paper's Remark 4.6).
"""
from __future__ import annotations

import numpy as np

from ..fem.assembly import DiscreteProblem, boundary_load_points
from ..fem.contact_laws.channels import slip_rows, tangent_frames
from ..fem.contact_quadrature import contact_quadrature, exact_pressure
from ..fem.element_quadrature import singular_vertices
from ..fem.nested import nested_start
from ..fem.p1_embedding import ContactEdges
from ..solvers.bound_constraints import Cholesky, MultigridSystem

# relative to the load, as deep as the contact solves' linear systems
TOLERANCE = 1e-11
# Gauss points per contact edge for the flux load (degree 2k + smooth pressure)
FLUX_POINTS = 8


def contact_flux_load(case, problem: DiscreteProblem) -> np.ndarray:
    """int_{Gamma_C} (d_n u - g_C) v for every basis function v: the exact contact pressure as a
    load (the load vector b already holds g_C). The pressure is singular where binding contact
    meets Gamma_g (r^{-1/2} in corner-r12): a Gauss rule there errs by O(1) relative on the
    first edge, which moves R_h u by as much as its own error (on corner-r12 enough to put R_h u
    above a method's error in |.|_1, which a best approximation cannot be); the rule is graded on
    the edges at singular points."""
    quadrature = contact_quadrature(problem, boundary_load_points(problem.order, FLUX_POINTS), graded_at=singular_vertices(case, problem.mesh))
    load = quadrature.T.T @ (quadrature.weights * exact_pressure(case, problem, quadrature))
    if case.frictional and problem.physics.rotated_frame:
        load += tangential_flux_load(case, problem, quadrature)
    return load


def tangential_flux_load(case, problem: DiscreteProblem, quadrature) -> np.ndarray:
    """int_{Gamma_C} (sigma_t(u) - g_t) . v_t for every basis function v: under Tresca friction
    the tangential traction is the friction force, not zero as in frictionless contact
    (``problem.friction``), and it loads the Ritz projection as the pressure does."""
    rows, _ = slip_rows(problem, quadrature)
    traction = case.physics.tangential_traction(case, problem.mesh, quadrature.points, quadrature.normals)
    frames = tangent_frames(quadrature.normals)
    return sum(T.T @ (quadrature.weights * np.einsum("qd,qd->q", traction, frames[:, j]))
               for j, T in enumerate(rows))


def ritz_projection(case, problem: DiscreteProblem, multilevel=None, start: np.ndarray | None = None) -> np.ndarray:
    """R_h u (all dofs), by the multigrid CG of the contact solver when the hierarchy is given and
    the order is 1 or 2, else by sparse Cholesky. (P3 and P4 reach errors whose size the CG's
    tolerance leaves in R_h u, which then reads above the methods' errors: there the best
    approximation is factorised, tests/test_rates.py.) Call it before a method takes the
    stiffness matrix. ``start``: the CG's first iterate (nested iteration: the coarser level's
    R_h u interpolated, ``nested_ritz_start``); it changes the result only below the tolerance."""
    b = problem.b + contact_flux_load(case, problem)
    pinned = ~problem.free
    scale = max(np.abs((b - problem.A @ problem.lift)[problem.free]).max(initial=0.0), np.finfo(float).tiny)
    if multilevel is not None and problem.order <= 2:
        system = MultigridSystem(problem.A_ngs, b, multilevel, ContactEdges.of(problem, model=False))
        return system.solve(pinned, problem.lift, start=start, tol=TOLERANCE * scale)
    rhs = np.where(problem.free, b - problem.A @ problem.lift, 0.0)
    return np.where(problem.free, Cholesky(problem.A_ngs, problem.free).solve(rhs), problem.lift)


def nested_ritz_start(multilevel, problem: DiscreteProblem, coarse_vertex_values: np.ndarray | None) -> np.ndarray | None:
    """The coarser level's R_h u at its vertices, interpolated onto ``problem``'s space (bubbles
    zero): the CG then starts within the coarse level's discretisation error of R_h u instead of
    at zero, as the contact solves' nested iteration does. None without a hierarchy or a coarser
    level."""
    if multilevel is None or coarse_vertex_values is None:
        return None
    return nested_start(multilevel, coarse_vertex_values, problem, ContactEdges.of(problem, model=False))
