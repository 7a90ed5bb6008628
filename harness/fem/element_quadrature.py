"""Quadrature chosen per element: graded where the solution is singular, subdivided where a
derivative of it jumps inside the element, plain Gauss elsewhere.

The cases' singularities sit at points of the geometry (junctions of Gamma_C with Gamma_g,
transition points; docs/mathematics.md §4). On the few elements touching such a point, integrands
like |grad(u - u_h)|^2 ~ r^{-1} (corner-r12) or the load f ~ r^{-1} |log r|^{-beta}
(borderline-h2) defeat any Gauss rule: there a composite rule geometrically graded towards the
element's vertices is used (``graded_rule``). A case may also declare lines across which a
derivative of u or f jumps (``derivative_jumps``: smooth's D^3 u across x = 0), which no mesh
follows: on the elements they cross, the integrand is piecewise smooth with a kink at an
arbitrary place, which no Gauss rule integrates as accurately as the P3/P4 errors need, whatever
its order (tests/test_rates.py measures it); there the reference triangle is uniformly
subdivided with the caller's Gauss rule on each piece (``split_rule``), whose error shrinks with
the pieces the line crosses. Every other element is smooth at its own scale and gets one Gauss
rule of a modest order, which the callers choose (errors, load) and the tests justify against a
much more accurate reference.
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
# The composite rule on the elements a derivative jump crosses: the reference triangle red-refined
# this many times (4^5 pieces), the caller's Gauss order on each: the shallowest depth at which
# the P4 error of smooth on levels 0 and 1 agrees with one level more to 1e-7 (tests/test_rates.py).
SPLIT_DEPTH = 5
# elements per batch of point evaluation (``element_moments``): 6 points each, 48 bytes a point
MOMENT_CHUNK = 1 << 17
# NGSolve's Integrate and forms evaluate an element's rule on one local heap of a fixed size,
# shared among the threads: under a task manager the whole split rule (tens of thousands of
# points) overflows it (the P4 estimator's Hessians, on two threads already). ``measures`` gives
# it in parts of at most this many points, one dx each, no larger than the graded rule.
SPLIT_PART = 2048
# values (points times components) per batch of evaluation on the graded and split elements: a
# split element has tens of thousands of points, and the errors of a level evaluate dozens of
# components at each
VALUE_CHUNK = 1 << 22
# a vertex is on a jump's line when its distance to it is below this share of the element's size
ON_LINE = 1e-10


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


@lru_cache(maxsize=None)
def split_points(depth: int, order: int) -> tuple[np.ndarray, np.ndarray]:
    """(points (k, 2), weights (k,)) of the composite Gauss rule of ``order`` on the reference
    triangle red-refined ``depth`` times (4^depth similar pieces), piece after piece: for an
    integrand with a kink along a line at an unknown place, the pieces the line crosses carry
    all of the rule's error, and fewer of them, and smaller, at each level."""
    base = ngs.IntegrationRule(ngs.TRIG, order)
    reference = np.array([ip.point[:2] for ip in base])
    weights = np.array([ip.weight for ip in base])
    pieces = np.array([[[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]])
    for _ in range(depth):
        a, b, c = pieces[:, 0], pieces[:, 1], pieces[:, 2]
        ab, bc, ca = (a + b) / 2, (b + c) / 2, (c + a) / 2
        pieces = np.concatenate([np.stack(piece, axis=1) for piece in ((a, ab, ca), (ab, b, bc), (ca, bc, c), (bc, ca, ab))])
    a, b, c = pieces[:, 0], pieces[:, 1], pieces[:, 2]
    (ux, uy), (vx, vy) = (b - a).T, (c - a).T
    jacobian = np.abs(ux * vy - uy * vx)        # twice the piece's area (the reference's is 1)
    points = a[:, None] + reference[None, :, :1] * (b - a)[:, None] + reference[None, :, 1:] * (c - a)[:, None]
    return points.reshape(-1, 2), (weights[None] * jacobian[:, None]).ravel()


@lru_cache(maxsize=None)
def split_rule(depth: int, order: int) -> ngs.IntegrationRule:
    """``split_points`` as one rule: for the integrals made here, at mesh points."""
    points, weights = split_points(depth, order)
    return ngs.IntegrationRule([tuple(p) for p in points], list(weights))


@lru_cache(maxsize=None)
def split_parts(depth: int, order: int) -> tuple[ngs.IntegrationRule, ...]:
    """``split_points`` in rules of whole pieces, at most ``SPLIT_PART`` points each (one piece
    at least): for NGSolve's forms and integrals, one ``dx`` each."""
    points, weights = split_points(depth, order)
    per_piece = len(points) // 4 ** depth
    size = max(1, SPLIT_PART // per_piece) * per_piece
    return tuple(ngs.IntegrationRule([tuple(p) for p in points[i:i + size]], list(weights[i:i + size]))
                 for i in range(0, len(weights), size))


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


def crossed_elements(case, mesh: ngs.Mesh) -> np.ndarray:
    """The elements whose interior one of the case's ``derivative_jumps`` passes through: the
    signed distances of their vertices to the segment's line take both signs (a line through a
    vertex or along a side leaves the element smooth inside) and their extent along the segment
    overlaps it. Beyond round-off: a vertex within ``ON_LINE`` of the element's size is on the
    line. None in 3D (no case declares jumps there)."""
    segments = case.derivative_jumps or ()
    if mesh.dim == 3 or not len(segments):
        return np.zeros(0, np.int64)
    corners = coordinates(mesh)[cells(mesh)]                                  # (ne, 3, 2)
    size = np.linalg.norm(corners - np.roll(corners, 1, axis=1), axis=2).max(axis=1)
    crossed = np.zeros(mesh.ne, bool)
    for start, end in np.asarray(segments, float):
        direction = end - start
        length = np.linalg.norm(direction)
        relative = corners - start
        distance = (direction[0] * relative[..., 1] - direction[1] * relative[..., 0]) / length   # (ne, 3), signed
        along = relative @ direction / length                                 # (ne, 3), 0..length on it
        tol = ON_LINE * size[:, None]
        both_sides = (distance < -tol).any(axis=1) & (distance > tol).any(axis=1)
        overlaps = ((along > tol).any(axis=1)) & ((along < length - tol).any(axis=1))
        crossed |= both_sides & overlaps
    return np.flatnonzero(crossed)


def _bits(size: int, elements) -> ngs.BitArray:
    """A BitArray of ``size`` bits, ``elements`` set (``ngs.dx(definedonelements=...)`` takes one)."""
    bits = ngs.BitArray(size)
    bits.Clear()
    for element in elements:
        bits.Set(int(element))
    return bits


@dataclass(frozen=True)
class ElementQuadrature:
    """Per-element quadrature on one mesh: ``graded_rule`` on the elements touching a singular
    vertex (``near``), ``split_rule`` on the other elements a derivative jump crosses
    (``crossed``; an element both near and crossed keeps the graded rule, which a singularity
    needs), a Gauss rule of the caller's order on all others."""

    mesh: ngs.Mesh
    near: ngs.BitArray
    graded: ngs.IntegrationRule
    near_elements: np.ndarray = field(default_factory=lambda: np.zeros(0, np.int64))   # the set bits of ``near``
    crossed: ngs.BitArray | None = None
    crossed_elements: np.ndarray = field(default_factory=lambda: np.zeros(0, np.int64))   # the set bits of ``crossed``
    split_depth: int = SPLIT_DEPTH

    @classmethod
    def of(cls, case, mesh: ngs.Mesh, depth: int = GRADING_DEPTH, order: int = GRADED_ORDER,
           split_depth: int = SPLIT_DEPTH) -> "ElementQuadrature":
        elements = sorted({element.nr for vertex in singular_vertices(case, mesh)
                           for element in mesh[ngs.NodeId(ngs.VERTEX, int(vertex))].elements})
        crossed = np.setdiff1d(crossed_elements(case, mesh), elements)
        return cls(mesh, _bits(mesh.ne, elements), graded_rule(depth, order), np.array(elements, dtype=np.int64),
                   _bits(mesh.ne, crossed), crossed, split_depth)

    def _gauss(self, order: int, elements: ngs.BitArray):
        shape = ELEMENT_TYPE[self.mesh.dim]
        return ngs.dx(definedonelements=elements, intrules={shape: ngs.IntegrationRule(shape, order)})

    def measures(self, order: int) -> tuple:
        """(dx on the plain elements with Gauss order ``order``, dx on the near elements graded[,
        the dx of each part of the crossed elements' split rule, Gauss order ``order`` on each
        piece: ``SPLIT_PART``]), for integrands of forms: their sum integrates over Omega (in 3D
        the first alone)."""
        if self.mesh.dim == 3:
            return (self._gauss(order, ~self.near),)
        graded = ngs.dx(definedonelements=self.near, intrules={ngs.TRIG: self.graded})
        if not len(self.crossed_elements):
            return self._gauss(order, ~self.near), graded
        split = [ngs.dx(definedonelements=self.crossed, intrules={ngs.TRIG: part})
                 for part in split_parts(self.split_depth, order)]
        return self._gauss(order, ~(self.near | self.crossed)), graded, *split

    def _special(self, order: int) -> list[tuple[np.ndarray, ngs.IntegrationRule]]:
        """(elements, their rule) of the sets integrated otherwise than by Gauss (2D): the near
        elements graded, the crossed ones split with Gauss order ``order`` on each piece."""
        if self.mesh.dim == 3:
            return []
        sets = [(self.near_elements, self.graded), (self.crossed_elements, split_rule(self.split_depth, order))]
        return [(elements, rule) for elements, rule in sets if len(elements)]

    def integrate(self, cf: ngs.CoefficientFunction, order: int) -> np.ndarray:
        """Integral over Omega of every component of ``cf`` in one pass over the elements.

        NGSolve integrates a vector-valued function only with one Gauss rule on every element,
        so the pass runs with order ``order`` everywhere, and the few near and crossed elements
        are then integrated again, with the plain and their own rule, to swap one for the other.
        """
        cf = cf.Compile()
        total = np.atleast_1d(np.array(ngs.Integrate(cf, self.mesh, order=order), dtype=float))
        # the swaps: every component at once, at mesh points made directly (ngs.Integrate over a
        # subset of elements takes scalar functions only and visits every element of the mesh:
        # per component, as long as the whole pass above)
        for elements, rule in self._special(order):
            total = total + self._on(cf, elements, rule) - self._on(cf, elements, gauss_rule(ngs.TRIG, order))
        return total

    def element_moments(self, cf: ngs.CoefficientFunction, order: int) -> tuple[np.ndarray, np.ndarray]:
        """((ne,) int_T g, (ne,) int_T (g - g_T)^2 with g_T the mean of g on T) of the scalar
        g = ``cf``: Gauss order ``order`` away from singular points and jumps, the graded rule on
        the near elements and the split one on the crossed elements (2D). g is evaluated once
        per point, at mesh points made directly, and both moments come from the same values
        (the second without cancellation). One evaluation at 6 points per triangle instead of
        two ``Integrate(element_wise=True)`` passes, whose cost is per element at any order up
        to 8."""
        cf = cf.Compile()
        integral, deviation = np.zeros(self.mesh.ne), np.zeros(self.mesh.ne)
        plain = gauss_rule(ELEMENT_TYPE[self.mesh.dim], order)
        corners = coordinates(self.mesh)[cells(self.mesh)]
        for elements in np.array_split(np.arange(self.mesh.ne), max(1, self.mesh.ne // MOMENT_CHUNK)):
            values, weights = self._values(cf, elements, plain, corners[elements])
            integral[elements], deviation[elements] = _moments(values[..., 0], weights)
        for special, rule in self._special(order):
            for batch in _batches(len(special), len(rule_arrays(rule, 2)[1])):
                elements = special[batch]
                values, weights = self._values(cf, elements, rule, corners[elements])
                integral[elements], deviation[elements] = _moments(values[..., 0], weights)
        return integral, deviation

    def _on(self, cf: ngs.CoefficientFunction, special: np.ndarray, rule: ngs.IntegrationRule) -> np.ndarray:
        """Integral of every component of ``cf`` over the elements ``special`` with ``rule``."""
        corners = coordinates(self.mesh)[cells(self.mesh)[special]]
        per_element = []
        for batch in _batches(len(special), len(rule_arrays(rule, 2)[1]) * cf.dim):
            values, weights = self._values(cf, special[batch], rule, corners[batch])
            per_element.append(np.einsum("ekd,ek->ed", values, weights))
        return np.concatenate(per_element).sum(axis=0)

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


def _batches(count: int, values: int) -> list[slice]:
    """``count`` elements in consecutive batches of at most ``VALUE_CHUNK`` values (``values``
    each), at least one element a batch."""
    size = max(1, VALUE_CHUNK // values)
    return [slice(i, i + size) for i in range(0, count, size)]


def _moments(values: np.ndarray, weights: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Per row: (the integral, the integral of the squared deviation from the mean)."""
    integral = (values * weights).sum(axis=1)
    mean = integral / weights.sum(axis=1)
    return integral, ((values - mean[:, None]) ** 2 * weights).sum(axis=1)
