"""Errors of u_h against the exact solution, and the nonconformity of the discrete cones.

The theorems bound ||u - u_h||_{H^1}. The cases' singularities sit at corners of the polygon
(junctions, transition points), where |grad(u - u_h)|^2 ~ r^{-1} (corner-r12) makes Gauss
quadrature on the elements touching the corner converge very slowly: there an O(1) share of
the error lives, and order 12 vs order 40 differ by 5%. Those few elements get a composite
rule geometrically graded towards their vertices (14 levels, leaves of size 2^-14 h), every
other element a Gauss rule of order 12; tests/test_errors.py shows that raising both changes
the finest-level errors of every case by less than 1%.
"""

from __future__ import annotations

from functools import lru_cache

import ngsolve as ngs
import numpy as np

from .discrete import ContactTraceFunction
from .mesh import evaluate

ERROR_QUADRATURE_ORDER = 12
PENETRATION_SAMPLES_PER_EDGE = 33


GRADING_DEPTH = 14


@lru_cache(maxsize=None)
def graded_rule(depth: int, order: int) -> ngs.IntegrationRule:
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


def corner_vertices(mesh: ngs.Mesh) -> list[int]:
    """Boundary vertices where the boundary turns or changes label: the polygon's corners."""
    segments = {}
    for el in mesh.Elements(ngs.BND):
        va, vb = el.vertices
        d = np.subtract(mesh[vb].point, mesh[va].point)
        for v in (va.nr, vb.nr):
            segments.setdefault(v, []).append((el.mat, d / np.linalg.norm(d)))
    corners = []
    for v, ((label1, d1), (label2, d2)) in segments.items():
        if label1 != label2 or abs(d1[0] * d2[1] - d1[1] * d2[0]) > 1e-10:
            corners.append(v)
    return corners


def integrate(cf, mesh: ngs.Mesh, order: int = ERROR_QUADRATURE_ORDER, depth: int = GRADING_DEPTH) -> float:
    near = ngs.BitArray(mesh.ne)
    near.Clear()
    for v in corner_vertices(mesh):
        for el in mesh[ngs.NodeId(ngs.VERTEX, v)].elements:
            near.Set(el.nr)
    graded = ngs.dx(definedonelements=near, intrules={ngs.TRIG: graded_rule(depth, order)})
    plain = ngs.dx(definedonelements=~near, intrules={ngs.TRIG: ngs.IntegrationRule(ngs.TRIG, order)})
    return ngs.Integrate(cf * graded, mesh) + ngs.Integrate(cf * plain, mesh)


def error_norms(case, gfu: ngs.GridFunction, order: int = ERROR_QUADRATURE_ORDER,
                depth: int = GRADING_DEPTH) -> dict:
    mesh = gfu.space.mesh
    diff = case.u - gfu
    grad_diff = case.grad_u - ngs.grad(gfu)
    l2_sq = integrate(diff * diff, mesh, order, depth)
    semi_sq = integrate(grad_diff * grad_diff, mesh, order, depth)
    return {
        "err_h1": float(np.sqrt(l2_sq + semi_sq)),
        "err_h1_semi": float(np.sqrt(semi_sq)),
        "err_l2": float(np.sqrt(l2_sq)),
    }


def max_penetration(case, mesh: ngs.Mesh, trace_u: ContactTraceFunction) -> float:
    """max over Gamma_C of (gap - u_h): positive where u_h dips below the obstacle.

    Sampled densely on every contact edge and at the stationary point of its quadratic, so
    the value between nodes is seen (K_h and K~_h only constrain nodes and edge means).
    """
    dense = np.linspace(0.0, 1.0, PENETRATION_SAMPLES_PER_EDGE)
    t_star = trace_u.minimum_parameters()
    values = np.concatenate([trace_u.at(dense), trace_u.value(np.arange(len(t_star)), t_star)[:, None]], axis=1)
    params = np.concatenate([np.broadcast_to(dense, (len(t_star), len(dense))), t_star[:, None]], axis=1)
    points = trace_u.a[:, None, :] + params[..., None] * (trace_u.b - trace_u.a)[:, None, :]
    gap = evaluate(case.gap_or_zero, mesh, points) if case.gap is not None else 0.0
    return float((gap - values).max())

