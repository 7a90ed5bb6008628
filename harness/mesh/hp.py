"""hp meshes: geometric refinement toward the case's singular points, the element degree growing
linearly with the number of layers away from them (the ``hp`` mesh strategy).

Where u is analytic (or Gevrey regular) but for point singularities r^lam at known points (a
corner, a junction, a contact/separation transition), geometric meshes with a linearly growing
degree give ||u - u_hp||_1 <= C exp(-b N^{1/(d+1)}): Babuska and Guo's hp theory of the 1980s,
and for C^0 elements on shape-regular simplicial meshes refined geometrically toward the singular
points the paper Numer. Math. (2020), doi:10.1007/s00211-019-01085-z (its introduction states the
bound). How much of each work was read: docs/theory/references.md. The layers of elements at a singular point shrink by a
factor sigma, elements j layers away from it have degree about k + mu j. For contact, Dörsek &
Melenk (2009) report exponential convergence of hp refinement.
No theorem covers Signorini's problem with a free boundary point: the strategy declares no rate,
the study measures one and fits the exponential law (``measure.exponential``).

The layers are made on the arrays of the case's coarse mesh (``newest_vertex.TriangleMesh``):
each layer cuts every triangle (P, A, B) at a singular point P into the triangle (P, A', B'),
A' = P + sigma (A - P), and the trapezoid A' A B B' split in two (``geometric_layer`` says along
which diagonal), so that
the elements at P shrink by sigma per layer and the mesh stays conforming (the edges of the
trapezoids away from P are the old ones). Level l has LAYERS_START + l layers; each level is
made anew from the coarse mesh. Default sigma = 0.15, the value commonly used for corner
singularities; newest vertex bisection could only make sigma = 1/2, with which corner-r12's
error (r^{1/2}) halved every second layer (measured) instead of falling by 0.45 per layer.

Degrees: an element made by layer s of n (the trapezoids of step s) has degree
k + round(mu (n + 1 - s)), the coarse elements k + round(mu (n + 1)), the triangles at the
singular points k: the methods' order k at the singular points, mu more per layer away from them
(capped at ``MAX_DEGREE``).
"""
from __future__ import annotations

from collections.abc import Iterator

import numpy as np

from .levels import Level, coarse_mesh
from .newest_vertex import TriangleMesh
from .points import vertices_at

# the largest element degree (``fem.assembly.set_degrees`` takes any; this bounds the error
# integration's Gauss order, 2p + 4, which NGSolve's triangle rules reach)
MAX_DEGREE = 24
# the first level's layers at each singular point, and the default sigma and mu
LAYERS_START = 1
DEFAULT_SIGMA = 0.15
DEFAULT_MU = 1.0
# the smallest edge of a level, relative to the largest coordinate of the mesh, that the layers may
# make: below it the coordinates of the points nearest a singular point differ from its own by
# few units of round-off. Measured on corner-r12 (sigma = 0.15, its singular point at (0.5, 0)),
# the ratio at L layers being 0.215 sigma^L: the `mean-p3`/`mean-p4` errors leave their line from
# 9.4e-14 (15 layers) on, four times too large; `nitsche` and the nodal cones stay on theirs
# through 2.1e-15 (17 layers); at 3.2e-16 (18) a triangle of Gamma_C's quadrature is degenerate
# in floating point (LinAlgError in the point location), at 19 layers two points coincide.
SMALLEST_RELATIVE_EDGE = 1e-13


def geometric_layer(arrays: TriangleMesh, depth: np.ndarray, vertices: np.ndarray, sigma: float,
                    layer: int) -> tuple[TriangleMesh, np.ndarray]:
    """One layer at each of ``vertices`` (the module's note): the arrays refined, and the depth
    of each element (``layer`` for the trapezoids made now, ``layer`` + 1 for the new triangles
    at the singular points, unchanged elsewhere)."""
    points, triangles, segments = arrays.points, arrays.triangles, arrays.segments
    at = np.isin(triangles, vertices)
    touching = at.any(axis=1)
    if (at.sum(axis=1) > 1).any():
        raise ValueError("an hp mesh needs singular points that share no element of the coarse mesh")
    # each touching triangle turned (cyclically, keeping its orientation) to (P, A, B)
    turn = at[touching].argmax(axis=1)
    P, A, B = np.take_along_axis(triangles[touching], (turn[:, None] + np.arange(3)) % 3, axis=1).T
    # one new point on each edge (P, X) of the patches
    ends = np.unique(np.stack([np.concatenate([P, P]), np.concatenate([A, B])], axis=1), axis=0)
    new = len(points) + np.arange(len(ends))
    key = ends[:, 0] * len(points) + ends[:, 1]
    point_of = dict(zip(key.tolist(), new.tolist()))
    a = np.array([point_of[k] for k in (P * len(points) + A).tolist()], dtype=np.int64)
    b = np.array([point_of[k] for k in (P * len(points) + B).tolist()], dtype=np.int64)
    points = np.concatenate([points, points[ends[:, 0]] + sigma * (points[ends[:, 1]] - points[ends[:, 0]])])
    # the trapezoid A' A B B' along a diagonal from the new point of a boundary side (P, A) to B
    # (or of (P, B) to A): the child on the boundary then keeps its parent's height over that
    # side. The other diagonal leaves it sigma times as high, its discrete trace-inverse constant
    # 1/sigma times as large, and Nitsche's theta = 1 past its coercivity bound (C_h 29 for 7).
    # Elsewhere the shorter diagonal.
    n = len(arrays.points)
    boundary = set((segments.min(axis=1) * n + segments.max(axis=1)).tolist())
    on_a = np.array([min(p, x) * n + max(p, x) in boundary for p, x in zip(P.tolist(), A.tolist())], dtype=bool)
    on_b = np.array([min(p, x) * n + max(p, x) in boundary for p, x in zip(P.tolist(), B.tolist())], dtype=bool)
    shorter = np.linalg.norm(points[a] - points[B], axis=1) <= np.linalg.norm(points[A] - points[b], axis=1)
    short = on_a | (~on_b & shorter)
    first = np.where(short[:, None], np.stack([a, A, B], axis=1), np.stack([a, A, b], axis=1))
    second = np.where(short[:, None], np.stack([a, B, b], axis=1), np.stack([A, B, b], axis=1))
    inner = np.stack([P, a, b], axis=1)
    domains = arrays.domains[touching]
    triangles = np.concatenate([triangles[~touching], first, second, inner])
    domains = np.concatenate([arrays.domains[~touching], domains, domains, domains])
    depth = np.concatenate([depth[~touching], np.full(2 * len(P), layer), np.full(len(P), layer + 1)])
    order = np.argsort(domains, kind="stable")      # ``ngsolve_mesh`` adds one domain at a time
    return TriangleMesh(points, triangles[order], domains[order], *_split_boundary(segments, arrays.segment_index, point_of,
                                                                                     len(arrays.points)),
                        arrays.materials, arrays.boundaries), depth[order]


def _split_boundary(segments: np.ndarray, index: np.ndarray, point_of: dict, n: int) -> tuple[np.ndarray, np.ndarray]:
    """Each boundary segment on an edge (P, X) of a patch split at its new point, orientation kept."""
    out, out_index = [], []
    for (s, t), i in zip(segments.tolist(), index.tolist()):
        m = point_of.get(s * n + t, point_of.get(t * n + s))
        out += [(s, t)] if m is None else [(s, m), (m, t)]
        out_index += [i] if m is None else [i, i]
    return np.array(out, dtype=np.int64), np.array(out_index, dtype=np.int32)


def degrees_of(depth: np.ndarray, layers: int, order: int, mu: float, max_degree: int) -> np.ndarray:
    """p_T = k + round(mu (n + 1 - depth_T)) (depth 0: the coarse elements), within k ..
    ``max_degree``."""
    return np.clip(order + np.rint(mu * (layers + 1 - depth)).astype(np.int64), order, max_degree)


def uniform_equivalent(coarse_elements: int, order: int, levels: int, mu: float = DEFAULT_MU) -> int:
    """The uniform P2 levels whose finest has about the dofs of the finest of ``levels`` hp levels
    (the study's memory and time plan, ``study.execution.engines.plan``, is written for uniform levels): the
    coarse elements, and about six per layer at each singular point, each with about p^2 / 2
    dofs at the largest degree p."""
    p = order + mu * (LAYERS_START + levels)
    dofs = (coarse_elements + 6 * (LAYERS_START + levels)) * p * p / 2
    return max(1, int(np.ceil(np.log(max(dofs / (2 * coarse_elements), 1.0)) / np.log(4.0))) + 1)


class HpRefinement:
    """The levels of the ``hp`` strategy (the module's note): level l has LAYERS_START + l
    geometric layers of ratio ``sigma`` at each of ``points`` (vertices of the coarse mesh) and
    degrees k + mu j, j the layers between an element and the singular points."""

    name = "hp"
    nested = False      # every level is made anew, its degrees change everywhere: the solves factorise
    adaptive = False
    budgeted = False    # its own levels: N grows like l^3, not 4^l
    variable_degree = True      # its levels carry ``Level.degrees``

    def __init__(self, case, order: int, points: np.ndarray, sigma: float = DEFAULT_SIGMA, mu: float = DEFAULT_MU):
        if not len(points):
            raise ValueError(f"case {case.name}: an hp mesh refines toward singular points, and it declares none")
        self.case, self.order, self.sigma, self.mu, self.max_degree = case, order, float(sigma), float(mu), MAX_DEGREE
        self.points = np.asarray(points, dtype=float).reshape(-1, 2)

    def observe(self, indicators) -> None:
        pass

    def largest_count(self, coarse: TriangleMesh, vertices: np.ndarray) -> int:
        """The most levels whose layers keep every edge at least ``SMALLEST_RELATIVE_EDGE`` times
        the largest coordinate: a layer scales the edges of the triangles at a singular point by
        sigma, so the smallest edge of L layers is sigma^L times the smallest coarse edge there."""
        at = coarse.triangles[np.isin(coarse.triangles, vertices).any(axis=1)]
        ends = np.concatenate([at[:, [0, 1]], at[:, [1, 2]], at[:, [2, 0]]])
        shortest = np.linalg.norm(coarse.points[ends[:, 0]] - coarse.points[ends[:, 1]], axis=1).min()
        ratio = shortest / np.abs(coarse.points).max()
        layers = int(np.floor(np.log(SMALLEST_RELATIVE_EDGE / ratio) / np.log(self.sigma))) if 0.0 < self.sigma < 1.0 else 0
        return max(0, layers - LAYERS_START + 1)

    def level_refusal(self, count: int) -> str | None:
        """Why ``count`` levels cannot be made (their layers would reach below round-off:
        ``largest_count``), or None; the study asks before its first solve."""
        mesh = coarse_mesh(self.case)
        largest = self.largest_count(TriangleMesh.of(mesh), vertices_at(mesh, self.points))
        if 0.0 < self.sigma < 1.0 and count > largest:
            return (f"case {self.case.name}: hp meshes with sigma={self.sigma:g} reach at most {largest} levels "
                    f"(their layers at the singular points would go below round-off), not {count}")
        return None

    def levels(self, count: int) -> Iterator[Level]:
        """The ``count`` levels; a ValueError before the first if they cannot be made
        (``level_refusal``)."""
        refused = self.level_refusal(count)
        if refused:
            raise ValueError(refused)
        mesh = coarse_mesh(self.case)
        coarse = TriangleMesh.of(mesh)
        vertices = vertices_at(mesh, self.points)
        for index in range(count):
            arrays, depth = coarse, np.zeros(coarse.ne, dtype=np.int64)
            layers = LAYERS_START + index
            for layer in range(1, layers + 1):
                arrays, depth = geometric_layer(arrays, depth, vertices, self.sigma, layer)
            fine = arrays.ngsolve_mesh()
            yield Level(index, fine, float(arrays.element_sizes()[0].max()), None,
                        degrees_of(depth, layers, self.order, self.mu, self.max_degree))
