"""A residual a posteriori error estimator for the Signorini problem, scalar and elastic, 2D and
3D (``estimator_3d``: the same terms on tetrahedra, faces for edges), element by element.

For u_h on a mesh T_h (any method: the cones, Nitsche, penalty), with -div F(u) = f, F(u) n = g
on Gamma_g, where F(u) = grad u (scalar) or sigma(u) (elasticity, Remark 2.3), and the contact
conditions on the contact variable c(u) - obstacle >= 0, pressure lambda >= 0, their product
zero (docs/mathematics.md §1; c = u, lambda = d_n u - g_C; elastic c = -u . n,
lambda = -(sigma_n(u) - g_n)):

    eta_T^2 =   h_T^2 ||f + div F(u_h)||_T^2                              element residual
              + 1/2 sum_{E in dT, interior} h_E ||[F(u_h) n]||_E^2        flux jumps (half to each side)
              + sum_{E in dT on Gamma_g} h_E ||g - F(u_h) n||_E^2         Neumann residual
              + sum_{E in dT on Gamma_C} (  h_E ||lambda_h - lambda(u_h)||_E^2          flux against pressure
                                          + h_E ||(lambda_h)_-||_E^2                   tension
                                          + h_E^-1 ||(obstacle - c(u_h))_+||_E^2        penetration
                                          + int_E (lambda_h)_+ (c(u_h) - obstacle)_+    complementarity (P1, P2)
                                          + h_E ||sigma_t(u_h) - g_t||_E^2 )            elasticity: friction-free

and eta^2 = sum_T eta_T^2. Every term vanishes for u_h = u (with lambda_h = lambda). On a
Tresca case (``problem.friction``) the friction law replaces the contact conditions, and the
Gamma_C terms are those of ``friction_terms``: the flux against the discrete friction force,
its excess over the threshold s and the friction law's complementarity (elasticity: the
tangential traction's, and the bilateral condition's residual u_h . n). The
elastic terms are those of Hild & Nicaise's residual estimator for contact problems in
elasticity (2007; volume and pages not verified here) (frictionless unilateral contact: the element
residual, the traction jumps, the Neumann residual, and on Gamma_C the normal terms and the
tangential traction; the text was not reachable here, the terms are the standard ones), in the
same weights as the scalar ones below.

lambda_h is the discrete contact pressure of the residual, ``errors.DiscretePressure``: the
representative in the trace space of the functional a(u_h, w) - L(w) on Gamma_C -- the
construction of the "quasi-discrete contact force density" of Krause, Veeser & Walloth (Numer.
Math. 130 (2015)), the same for every method. The terms are those of the residual estimators
for Signorini's problem of Hild & Nicaise (Numer. Math. 101 (2005)), Weiss & Wohlmuth (Math.
Comp. 78 (2009)), Krause, Veeser & Walloth, and, for quadratic elements, the adaptive P2
method of arXiv 2209.04906 (element and jump residuals, the flux mismatch on Gamma_C, the
penetration, the complementarity): the penetration term is the one
the P2 cones need, as their nodal or mean constraints let u_h dip below alpha between nodes.
The weights above (docs/theory/references.md says what of these papers was read) are the
standard scalings (h for flux terms, h^-1 for the H^1/2-like penetration), not a quotation of
one paper's definition, and no constant is claimed. What the harness measures instead is the
effectivity eta / ||u - u_h||_a on the exact cases (``study.chain``).
"""
from __future__ import annotations

from collections import OrderedDict

import ngsolve as ngs
import numpy as np

from ..fem.contact_quadrature import at_points, contact_quadrature
from ..fem.element_quadrature import ElementQuadrature, singular_vertices
from ..mesh.points import evaluate, mesh_key
from ..mesh.sides import SIDE_ENDS, MeshSides
from .errors import DiscretePressure, contact_error_points
from .estimator_3d import TetrahedronTerms
from .facets import element_bits, neumann_facets
from .friction_terms import FrictionTerms

# Gauss order of the volume moments f_T and ||f - f_T||_T^2 on the elements away from singular
# points (``ElementQuadrature``: graded on the elements touching one, where f may be singular,
# r^{-1} |log r|^{-beta} in borderline-h2): (f - f_T)^2 exactly for f quadratic on T. A higher
# order on those elements costs more points per triangle and moves eta by far less than its
# accuracy; on the near elements Gauss is not converged, and the graded rule moves eta there.
VOLUME_ORDER = 4


def neumann_sides(mesh: ngs.Mesh, sides: MeshSides) -> tuple:
    """(neumann, along): a piecewise constant on the facets, 1 on those of Gamma_g; and the
    triangles with a side on Gamma_g (a BitArray): the Neumann residual is integrated on those
    triangles' boundaries only."""
    neumann, ends = neumann_facets(mesh)
    own = np.sort(sides.side_vertices(sides.boundary[:, 0], sides.boundary[:, 1]), axis=1)
    hit = np.isin(own[:, 0] * mesh.nv + own[:, 1], ends[:, 0] * mesh.nv + ends[:, 1])
    return neumann, element_bits(mesh, sides.boundary[hit, 0])


class MeshTerms:
    """What the estimator needs of one mesh and the case's data, whatever the finite element
    order: made once per mesh for the problems of both orders (the last few are kept).

    The weights are NGSolve's ``ngsolve.specialcf.mesh_size`` (what an integral written with it
    in NGSolve gives): h_T = |2T|^(1/2) in
    the volume, and on a side E of T the height of T over E, h_{T,E} = 2|T|/|E| (NGSolve's
    det J / |E|), so that the flux-jump term of T on E is |T|/3 (j_a^2 + j_a j_b + j_b^2) for
    the jump j, linear along E with end values j_a, j_b (P2; constant for P1).

    The volume and jump terms of a solution come from grad u_h at the three vertices of every
    triangle (one evaluation per solution, at mesh points made here): grad u_h is linear on a
    P2 triangle, so those values give the jumps at the ends of every side and the (constant)
    Laplacian, sum_k grad u_h(x_k) . grad lambda_k. tests/test_meshes.py holds the result to
    NGSolve's own element-boundary integration of the same terms."""

    _made: OrderedDict = OrderedDict()
    KEPT = 2

    @classmethod
    def of(cls, case, quadrature: ElementQuadrature) -> "MeshTerms":
        mesh = quadrature.mesh
        key = mesh_key(mesh) + (case.source, case.name)
        hit = cls._made.get(key)
        if hit is not None and hit[0] is mesh:
            return hit[1]
        made = cls(case, quadrature)
        cls._made[key] = (mesh, made)
        while len(cls._made) > cls.KEPT:
            cls._made.popitem(last=False)
        return made

    def __init__(self, case, quadrature: ElementQuadrature):
        mesh = quadrature.mesh
        self.quadrature, self.f = quadrature, None if case.f_vanishes else case.f
        self._interior = None           # ``interior_sides``, made when a P_k solution first asks
        sides = MeshSides.of(mesh)
        self.neumann, self.along_neumann = neumann_sides(mesh, sides)
        self.vertex_points = sides.vertex_points(mesh)
        self.area = sides.area
        self.h2 = 2.0 * self.area**2                     # h_T^2 |T|, h_T = |2T|^(1/2)
        # grad lambda_k of the barycentric coordinates (rows of the inverse Jacobian, from the
        # last vertex; lambda_2 = 1 - lambda_0 - lambda_1)
        # (the 2 x 2 inverse written out: faster than np.linalg.inv's batched LAPACK calls)
        e0, e1 = sides.corners[:, 0] - sides.corners[:, 2], sides.corners[:, 1] - sides.corners[:, 2]
        det = e0[:, 0] * e1[:, 1] - e1[:, 0] * e0[:, 1]
        rows = np.stack([np.stack([e1[:, 1], -e1[:, 0]], axis=1), np.stack([-e0[:, 1], e0[:, 0]], axis=1)],
                        axis=1) / det[:, None, None]
        self.grad_lambda = np.concatenate([rows, -rows.sum(axis=1, keepdims=True)], axis=1)     # (ne, 3, 2)
        # each interior edge E = T1 | T2: the rows, in the (3 ne, 2) array of vertex gradients,
        # of its two ends in T1 and in T2 (matched by vertex number), and T1's outward normal
        (first, first_side), (second, second_side) = sides.interior[:, 0].T, sides.interior[:, 1].T
        ends_first = sides.side_vertices(first, first_side)
        ends_second = sides.side_vertices(second, second_side)
        swapped = (ends_second[:, 0] != ends_first[:, 0]).astype(np.int64)
        local_first, local_second = SIDE_ENDS[first_side], SIDE_ENDS[second_side]
        self.ends = [(3 * first + local_first[:, end], 3 * second + local_second[np.arange(len(second)), end ^ swapped])
                     for end in (0, 1)]
        self.jump_normals = np.ascontiguousarray(sides.normals[first, first_side].T)          # (2, k)
        # the jump term of E goes to T1 and to T2, each weighted |T|/3
        self.jump_elements = np.concatenate([first, second])
        self.jump_weights = sides.area[self.jump_elements] / 3.0
        # Laplace(u_h) is constant on each element (P2; zero for P1), so with f_T the mean of f
        #   h_T^2 ||f + Laplace(u_h)||_T^2 = h_T^2 ||f - f_T||_T^2 + h_T^2 |T| (f_T + Laplace_T)^2,
        # the first term (the data's oscillation) made here, the second per solution from one
        # number per element, without cancellation
        # (per component of f in elasticity: |f - f_T|^2 and |f_T + div sigma_T|^2 summed over them)
        components = case.physics.components
        self.mean_f, self.oscillation = np.zeros((mesh.ne, components)), np.zeros(mesh.ne)
        if not case.f_vanishes:
            for i in range(components):
                integral, deviation = quadrature.element_moments(case.f[i], VOLUME_ORDER)
                self.mean_f[:, i] = integral / self.area
                self.oscillation += 2.0 * self.area * deviation              # h_T^2 = 2|T|

    def volume_and_jumps(self, gfu: ngs.GridFunction, order: int, physics) -> np.ndarray:
        """h_T^2 ||f + div F(u_h)||_T^2 + the jumps of F(u_h) n on T's interior sides, per element,
        F the flux of the physics (grad u_h; sigma(u_h) in elasticity, ``physics.flux_array``)."""
        if order > 2:
            return self.integrated_volume_and_jumps(gfu, order, physics)
        ne, components = len(self.area), physics.components
        if order == 1:          # grad u_h is constant on each triangle: evaluated once there
            gradients = np.asarray(ngs.grad(gfu)(self.vertex_points[::3])).reshape(ne, 1, components, 2)
            gradients = np.repeat(gradients, 3, axis=1)
        else:
            gradients = np.asarray(ngs.grad(gfu)(self.vertex_points)).reshape(ne, 3, components, 2)
        flux = physics.flux_array(gradients)                                   # (ne, 3, components, 2)
        # F(u_h) is linear on a P2 triangle: div F = sum_k F(x_k) grad lambda_k, constant
        divergence = np.einsum("ekcd,ekd->ec", flux, self.grad_lambda) if order > 1 else 0.0
        eta2 = self.oscillation + self.h2 * ((self.mean_f + divergence) ** 2).sum(axis=1)
        # the jump of F n at both ends of every interior edge: T1's outward flux plus T2's, T2's
        # normal being -T1's (gathers from the components apart: one-dimensional gathers are
        # faster)
        nx, ny = self.jump_normals
        squares = 0.0
        for i in range(components):
            fx, fy = flux[:, :, i, 0].ravel(), flux[:, :, i, 1].ravel()
            jump_a, jump_b = (nx * (fx[in_first] - fx[in_second]) + ny * (fy[in_first] - fy[in_second])
                              for in_first, in_second in self.ends)
            squares = squares + jump_a**2 + jump_a * jump_b + jump_b**2
        return eta2 + np.bincount(self.jump_elements, weights=self.jump_weights * np.tile(squares, 2), minlength=ne)


    def integrated_volume_and_jumps(self, gfu: ngs.GridFunction, order: int, physics) -> np.ndarray:
        """``volume_and_jumps`` of P_k, k >= 3, where F(u_h) is no longer linear on a triangle:
        NGSolve integrates h_T^2 ||f + div F(u_h)||^2 (div F from its Hessian, the element rules
        of ``ElementQuadrature`` with Gauss order 2k) and, on each element's boundary, half of
        h ||[F(u_h) n]||^2 on its interior sides (``Other()``: the neighbour's trace), with the
        same weights as the P1/P2 path (``ngsolve.specialcf.mesh_size``)."""
        mesh = self.quadrature.mesh
        h, n = ngs.specialcf.mesh_size, ngs.specialcf.normal(mesh.dim)
        residual = physics.divergence(gfu) if self.f is None else self.f + physics.divergence(gfu)
        volume = sum(ngs.Integrate(h * h * ngs.InnerProduct(residual, residual) * dx, mesh, element_wise=True).NumPy()
                     for dx in self.quadrature.measures(2 * order))
        jump = physics.flux(ngs.Grad(gfu), n) - physics.flux(ngs.Grad(gfu).Other(), n)
        jumps = ngs.Integrate(0.5 * h * self.interior_sides() * ngs.InnerProduct(jump, jump)
                              * ngs.dx(element_boundary=True, bonus_intorder=2), mesh, element_wise=True)
        return volume + jumps.NumPy()

    def interior_sides(self) -> ngs.GridFunction:
        """A piecewise constant on the sides: 1 on those inside Omega (the boundary elements
        labelled 'interior' glue two parts of it, ``problem.geometry.split_strip``), 0 on its
        boundary."""
        if self._interior is None:
            mesh = self.quadrature.mesh
            self._interior = ngs.GridFunction(ngs.FacetFESpace(mesh, order=0))
            self._interior.vec[:] = 1.0
            space = self._interior.space
            for element in mesh.Elements(ngs.BND):
                if element.mat != "interior":
                    self._interior.vec[space.GetDofNrs(element)[0]] = 0.0
        return self._interior


def mesh_terms(case, quadrature: ElementQuadrature):
    """The volume, jump and Neumann terms' maker of the mesh's dimension: ``MeshTerms`` on
    triangles, ``estimator_3d.TetrahedronTerms`` on tetrahedra (same interface)."""
    if quadrature.mesh.dim == 2:
        return MeshTerms.of(case, quadrature)
    if quadrature.mesh.dim == 3:
        return TetrahedronTerms.of(case, quadrature, VOLUME_ORDER)
    raise ValueError(f"the residual estimator is for 2D and 3D problems, not {quadrature.mesh.dim}D")


class ResidualEstimator:
    """eta_T^2 of solutions on one discrete problem (2D or 3D, scalar or elastic): ``indicators(u)``.
    The Gamma_C terms are integrated over the cells of Gamma_C, edges in 2D and triangles in 3D
    (``contact_quadrature``), and each cell's go to the element on it."""

    def __init__(self, case, problem):
        self.case, self.problem, mesh = case, problem, problem.mesh
        self.terms = mesh_terms(case, problem.quadrature)
        self.pressure = DiscretePressure.of(problem)
        q = contact_quadrature(problem, contact_error_points(problem.order), graded_at=singular_vertices(case, mesh))
        self.q = q
        self.T_contact = q.T[:, problem.contact_dofs].tocsr()
        self.obstacle = case.physics.obstacle(at_points(case.gap, mesh, q))
        self.load = 0.0 if case.contact_load is None else evaluate(case.contact_load, mesh, q.points)
        # a Tresca case: the friction terms replace the Signorini ones (``friction_terms``)
        self.friction = FrictionTerms(case, problem, q, self.load, self.obstacle) if case.frictional else None
        faces = problem.trace.faces
        self.element_of_edge = problem.trace.volumes if faces is None else faces.volumes

    def indicators(self, u: np.ndarray, previous: np.ndarray | None = None) -> np.ndarray:
        """eta_T^2 for every element of the mesh; ``previous``: u_h at the end of the load step
        before (a friction case's slip is the step's, ``friction_terms``)."""
        mesh, case, terms = self.problem.mesh, self.case, self.terms
        gfu = self.problem.gridfunction(u)
        eta2 = terms.volume_and_jumps(gfu, self.problem.order, case.physics)
        # on the triangles along Gamma_g only (on a boundary element NGSolve's grad is the
        # tangential one: the normal derivative needs the triangle's side)
        h = ngs.specialcf.mesh_size
        n = ngs.specialcf.normal(mesh.dim)
        residual = case.neumann_data(n) - case.physics.flux(ngs.Grad(gfu), n)
        neumann = h * terms.neumann * ngs.InnerProduct(residual, residual) * \
            ngs.dx(element_boundary=True, bonus_intorder=2, definedonelements=terms.along_neumann)
        eta2 += ngs.Integrate(neumann, mesh, element_wise=True).NumPy()
        np.add.at(eta2, self.element_of_edge, self.contact_terms(u, gfu, previous))
        return np.maximum(eta2, 0.0)

    def contact_terms(self, u: np.ndarray, gfu: ngs.GridFunction, previous: np.ndarray | None = None) -> np.ndarray:
        """The Gamma_C terms of each contact edge (``problem.trace``'s order; 3D: each triangle of
        ``problem.trace.faces``): those of the flux (``flux_density``) and of the gap
        (``gap_density``). The coefficients of lambda_h stay in ``pressure_coefficients`` (the
        two-body interface's complementarity uses each side's)."""
        self.pressure_coefficients = self.pressure.coefficients(u)
        lam_h = self.T_contact @ self.pressure_coefficients
        if self.friction is not None:
            before = None if previous is None else self.problem.gridfunction(previous)
            density = self.friction.density(lam_h, u, gfu, before)
        else:
            density = self.flux_density(lam_h, gfu) + self.gap_density(lam_h, u)
        q = self.q
        return np.bincount(q.edge, weights=q.weights * density, minlength=len(self.element_of_edge))

    def flux_density(self, lam_h: np.ndarray, gfu: ngs.GridFunction) -> np.ndarray:
        """At the contact points: the pressure of the flux F(u_h) against lambda_h, lambda_h's
        tension, and in elasticity the tangential traction sigma_t(u_h) - g_t (frictionless)."""
        q, physics = self.q, self.case.physics
        gradients = evaluate(ngs.grad(gfu), self.problem.mesh, q.points).reshape(len(q.h), physics.components, -1)
        flux, tangential = physics.contact_forces(physics.flux_array(gradients), q.normals, self.load)
        density = q.h * ((lam_h - flux) ** 2 + np.minimum(lam_h, 0.0) ** 2)
        if tangential is not None:
            density += q.h * tangential**2
        return density

    def gap_density(self, lam_h: np.ndarray, u: np.ndarray) -> np.ndarray:
        """At the contact points: the penetration below the obstacle and, for P1 and P2, the
        complementarity. The complementarity is linear in the gap, and where u_h binds its gap is
        of the order of the trace error, h^{k + 1/2} at best: against the squared error h^{2k} the
        term is of lower order once k >= 3, dominates eta, and drives adaptive refinement along
        Gamma_C instead of at the singularity (tests/test_degree.py measures both). P_k, k >= 3,
        leave it out: an estimator efficient in practice, with no reliability constant claimed
        (none is, at any order, module docstring)."""
        q = self.q
        gap = q.T @ u - self.obstacle
        penetration = np.maximum(-gap, 0.0) ** 2 / q.h
        if self.problem.order > 2:
            return penetration
        return penetration + np.maximum(lam_h, 0.0) * np.maximum(gap, 0.0)


def estimate(indicators: np.ndarray) -> float:
    """eta = (sum_T eta_T^2)^(1/2)."""
    return float(np.sqrt(np.sum(indicators)))
