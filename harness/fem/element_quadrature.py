"""Quadrature chosen per element: graded where the solution is singular, plain Gauss elsewhere.

The cases' singularities sit at points of the geometry (junctions of Gamma_C with Gamma_g,
transition points; docs/mathematics.md §4). On the few elements touching such a point, integrands
like |grad(u - u_h)|^2 ~ r^{-1} (corner-r12) or the load f ~ r^{-1} |log r|^{-beta}
(borderline-h2) defeat any Gauss rule: there a composite rule geometrically graded towards the
element's vertices is used (``graded_rule``). Every other element is smooth at its own scale
and gets one Gauss rule of a modest order, which the callers choose (errors, load) and the
tests justify against a much more accurate reference.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from functools import lru_cache

import ngsolve as ngs
import numpy as np

from ..mesh.points import cells, coordinates, geometry_vertices, mesh_points, vertices_at

# The graded rule on the elements touching a singular point: Gauss order 12 on leaves of size
# down to 2^-14 h (raising either changes no error of any case by 1e-6 relative; tests).
GRADED_ORDER = 12
GRADING_DEPTH = 14
# elements per batch of point evaluation (``element_moments``): 6 points each, 48 bytes a point
MOMENT_CHUNK = 1 << 17


@lru_cache(maxsize=None)
def gauss_rule(shape, order: int) -> ngs.IntegrationRule:
    """NGSolve's Gauss rule of ``order`` on ``shape``, one object per (shape, order)."""
    return ngs.IntegrationRule(shape, order)


@lru_cache(maxsize=64)
def rule_arrays(rule: ngs.IntegrationRule, dim: int) -> tuple[np.ndarray, np.ndarray]:
    """(points (k, dim), weights (k,)) of ``rule`` on its reference element, read once per rule
    object (the graded rule has hundreds of points; the cache keeps the rule, so its id stays
    its own)."""
    return np.array([ip.point[:dim] for ip in rule]), np.array([ip.weight for ip in rule])


@lru_cache(maxsize=None)
def graded_rule(depth: int = GRADING_DEPTH, order: int = GRADED_ORDER) -> ngs.IntegrationRule:
    """Composite Gauss rule on the reference triangle, graded towards all three vertices."""
    base = ngs.IntegrationRule(ngs.TRIG, order)
    ref_pts = np.array([ip.point[:2] for ip in base])
    ref_w = np.array([ip.weight for ip in base]) * 2.0        # per unit area ratio
    points, weights = [], []

    def leaf(t):
        a, b, c = t
        jac = abs((b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]))
        points.extend(a + ref_pts[:, :1] * (b - a) + ref_pts[:, 1:2] * (c - a))
        weights.extend(ref_w * jac / 2.0)

    def children(t):
        a, b, c = t
        ab, bc, ca = (a + b) / 2, (b + c) / 2, (c + a) / 2
        return [(a, ab, ca), (ab, b, bc), (ca, bc, c)], (ab, bc, ca)

    def toward_first_vertex(t, level):
        corners, centre = children(t)
        if level == 0:
            leaf(t)
            return
        toward_first_vertex(corners[0], level - 1)
        for other in (corners[1], corners[2], centre):
            leaf(other)

    corners, centre = children(tuple(np.array(p, float) for p in ((0, 0), (1, 0), (0, 1))))
    leaf(centre)
    for k, corner in enumerate(corners):
        # rotate so that the vertex of the big triangle comes first
        toward_first_vertex(corner[k:] + corner[:k], depth - 1)
    return ngs.IntegrationRule([tuple(p) for p in points], list(weights))


ELEMENT_TYPE = {2: ngs.TRIG, 3: ngs.TET}


def singular_vertices(case, mesh: ngs.Mesh) -> np.ndarray:
    """The mesh vertices where ``case`` is singular: its declared ``singular_points``, else every
    point of the geometry (corners, label changes, breaks), which is where the cases put them.
    None in 3D: its singular sets are lines (the transition curves), and no graded rule exists
    for them. The Gauss rule then misses a share of the error on the elements along them that
    red refinement leaves unchanged (the singular function is self-similar), so it is a constant
    factor that leaves the rates: tests/test_three_d.py checks the errors and the rates against
    order 12."""
    if mesh.dim == 3:
        return np.zeros(0, np.int64)
    if case.singular_points is None:
        return geometry_vertices(mesh)
    return vertices_at(mesh, case.singular_points) if len(case.singular_points) else np.zeros(0, np.int64)


@dataclass(frozen=True)
class ElementQuadrature:
    """Per-element quadrature on one mesh: ``graded_rule`` on the elements touching a singular
    vertex (``near``), a Gauss rule of the caller's order on all others."""

    mesh: ngs.Mesh
    near: ngs.BitArray
    graded: ngs.IntegrationRule
    near_elements: np.ndarray = field(default_factory=lambda: np.zeros(0, np.int64))   # the set bits of ``near``

    @classmethod
    def of(cls, case, mesh: ngs.Mesh, depth: int = GRADING_DEPTH, order: int = GRADED_ORDER) -> "ElementQuadrature":
        near = ngs.BitArray(mesh.ne)
        near.Clear()
        elements = sorted({element.nr for vertex in singular_vertices(case, mesh)
                           for element in mesh[ngs.NodeId(ngs.VERTEX, int(vertex))].elements})
        for element in elements:
            near.Set(element)
        return cls(mesh, near, graded_rule(depth, order), np.array(elements, dtype=np.int64))

    def _gauss(self, order: int, elements: ngs.BitArray):
        shape = ELEMENT_TYPE[self.mesh.dim]
        return ngs.dx(definedonelements=elements, intrules={shape: ngs.IntegrationRule(shape, order)})

    def measures(self, order: int) -> tuple:
        """(dx on the plain elements with Gauss order ``order``, dx on the near elements graded),
        for integrands of forms: their sum integrates over Omega (in 3D the first alone)."""
        plain = self._gauss(order, ~self.near)
        if self.mesh.dim == 3:
            return (plain,)
        return plain, ngs.dx(definedonelements=self.near, intrules={ngs.TRIG: self.graded})

    def integrate(self, cf: ngs.CoefficientFunction, order: int) -> np.ndarray:
        """Integral over Omega of every component of ``cf`` in one pass over the elements.

        NGSolve integrates a vector-valued function only with one Gauss rule on every element,
        so the pass runs with order ``order`` everywhere, and the few near elements are then
        integrated again, with the plain and the graded rule, to swap one for the other.
        """
        cf = cf.Compile()
        total = np.atleast_1d(np.array(ngs.Integrate(cf, self.mesh, order=order), dtype=float))
        if self.mesh.dim == 3 or not len(self.near_elements):
            return total
        # the swap on the near elements: every component at once, at mesh points made directly
        # (ngs.Integrate over a subset of elements takes scalar functions only and visits every
        # element of the mesh: per component, as long as the whole pass above)
        return total + self._on_near(cf, self.graded) - self._on_near(cf, gauss_rule(ngs.TRIG, order))

    def element_moments(self, cf: ngs.CoefficientFunction, order: int) -> tuple[np.ndarray, np.ndarray]:
        """((ne,) int_T g, (ne,) int_T (g - g_T)^2 with g_T the mean of g on T) of the scalar
        g = ``cf``: Gauss order ``order`` away from singular points, the graded rule on the near
        elements (2D). g is evaluated once per point, at mesh points made directly, and both
        moments come from the same values (the second without cancellation). One evaluation at 6
        points per triangle instead of two ``Integrate(element_wise=True)`` passes, whose cost
        is per element at any order up to 8."""
        cf = cf.Compile()
        integral, deviation = np.zeros(self.mesh.ne), np.zeros(self.mesh.ne)
        plain = gauss_rule(ELEMENT_TYPE[self.mesh.dim], order)
        corners = coordinates(self.mesh)[cells(self.mesh)]
        for elements in np.array_split(np.arange(self.mesh.ne), max(1, self.mesh.ne // MOMENT_CHUNK)):
            values, weights = self._values(cf, elements, plain, corners[elements])
            integral[elements], deviation[elements] = _moments(values[..., 0], weights)
        if self.mesh.dim == 2 and len(self.near_elements):
            values, weights = self._values(cf, self.near_elements, self.graded, corners[self.near_elements])
            integral[self.near_elements], deviation[self.near_elements] = _moments(values[..., 0], weights)
        return integral, deviation

    def _on_near(self, cf: ngs.CoefficientFunction, rule: ngs.IntegrationRule) -> np.ndarray:
        """Integral of every component of ``cf`` over the near elements with ``rule``."""
        return self._per_near_element(cf, rule).sum(axis=0)

    def _per_near_element(self, cf: ngs.CoefficientFunction, rule: ngs.IntegrationRule) -> np.ndarray:
        """(near elements, components): the integral of every component of ``cf`` over each near
        element with ``rule``."""
        corners = coordinates(self.mesh)[cells(self.mesh)[self.near_elements]]
        values, weights = self._values(cf, self.near_elements, rule, corners)
        return np.einsum("ekd,ek->ed", values, weights)

    def _values(self, cf: ngs.CoefficientFunction, elements: np.ndarray, rule: ngs.IntegrationRule,
                corners: np.ndarray) -> tuple:
        """((e, k, components) ``cf`` at the points of ``rule`` in each of ``elements``, (e, k)
        the weights there) at mesh points made directly; ``corners``: (e, dim + 1, dim) their
        vertices (elements affine: the weight of a point is its reference weight times the
        Jacobian determinant, dim! times the volume)."""
        mesh, dim = self.mesh, self.mesh.dim
        reference, weights = rule_arrays(rule, dim)
        jacobian = np.abs(np.linalg.det(corners[:, 1:] - corners[:, :1]))
        points = mesh_points(mesh, len(elements) * len(weights))
        for axis, name in enumerate("xyz"[:dim]):
            points[name] = np.tile(reference[:, axis], len(elements))
        points["nr"] = np.repeat(elements, len(weights))
        values = np.asarray(cf(points), dtype=float).reshape(len(elements), len(weights), cf.dim)
        return values, weights[None, :] * jacobian[:, None]


def _moments(values: np.ndarray, weights: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Per row: (the integral, the integral of the squared deviation from the mean)."""
    integral = (values * weights).sum(axis=1)
    mean = integral / weights.sum(axis=1)
    return integral, ((values - mean[:, None]) ** 2 * weights).sum(axis=1)
