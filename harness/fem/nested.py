"""Nested iteration: what a level's solve takes from the coarser level's solution, in one place
for every method family. Two things:

* a **start** for the iterative solver: the coarser u_h at the vertices (``p1_values``, carried
  from level to level), interpolated by the P1 prolongation of the hierarchy into the finer
  level's variables (``nested_start``; ``start_from``: none without a hierarchy or a coarser
  level);
* a **predicted active set** for the active set or Newton iteration, each constraint taking
  the status of the coarse constraint at its place:
  - the cones and general rows on Gamma_C (``cone_prediction``, ``functional_prediction``,
    ``face_mean_prediction``), from the coarse trace (``fem.assembly.ContactTraceFunction``):
    a vertex row from the coarse vertex or edge it lies at (``vertex_status``), an edge row from
    the coarse edge it is or halves (``edge_status``), a triangle row from the coarse triangle
    holding it (``face_status``);
  - a contact law's Gauss points (``nearest_status``): the nearest coarse Gauss point's branch;
  - the mortar rows of two bodies (``mortar_prediction``): the one-body cones' rule on the
    slave's trace, a line.

A prediction is usually a few rows off; the iteration corrects it (a full-depth solve per
level costs several more sets: ``python -m harness bench --only adaptive`` counts them).
"""
from __future__ import annotations

import numpy as np
from scipy.spatial import cKDTree

from .p1_embedding import ContactEdges


def p1_values(problem, u: np.ndarray) -> np.ndarray:
    """u's values at the vertices in the P1 hierarchy's numbering and variables:
    what a level carries to the next one's ``nested_start``."""
    return ContactEdges.of(problem, model=False).values(u, problem.mesh.nv * problem.physics.components)


def nested_start(multilevel, coarse_values: np.ndarray, problem, edges=None) -> np.ndarray:
    """A start for the finest level's CG: the coarser level's u_h at the vertices (in the P1
    hierarchy's numbering and variables, ``p1_values``), interpolated by the P1 prolongation of
    ``multilevel`` (a ``solvers.multigrid.Multilevel``), in the variables of ``edges`` (a
    ``fem.p1_embedding.ContactEdges``; default: the contact model's; bubbles zero)."""
    fine = multilevel.matrices[-1].CreateColVector()
    fine[:] = 0.0
    fine.FV().NumPy()[: len(coarse_values)] = coarse_values
    multilevel.prolongate(len(multilevel.matrices) - 1, fine)
    z = np.zeros(problem.ndof)
    (ContactEdges.of(problem) if edges is None else edges).prolongate(fine.FV().NumPy(), z)
    return z


def start_from(carry, multilevel, problem, model: bool = True) -> np.ndarray | None:
    """``nested_start`` from the coarser level's ``carry`` (its ``p1``), in the contact model's
    variables (``model``) or NGSolve's own (``ContactEdges.of(problem, model=False)``); None on
    the first level or without a hierarchy (the solver starts from nothing)."""
    if multilevel is None or carry is None:
        return None
    return nested_start(multilevel, carry.p1, problem, None if model else ContactEdges.of(problem, model=False))


def _nearest(anchors: np.ndarray, points: np.ndarray, reach: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(index of the nearest anchor to each point, whether it lies within that anchor's reach)."""
    distance, index = cKDTree(anchors).query(points)
    return index, distance <= reach[index]


def vertex_status(previous, points: np.ndarray) -> np.ndarray:
    """Active status of the vertex constraint at each point of the next (red-refined) level, from
    the coarse trace ``previous``: that of the coarse vertex it coincides with, or, at a coarse
    edge midpoint, that of the edge constraint: the coarse function meets the gap at the
    midpoint (nodal) or dips to it on the edge (mean). (A refinement that moves new boundary
    vertices onto a curved geometry moves them by O(h^2): matched within a quarter of the coarse
    edge.)"""
    length = np.linalg.norm(previous.b - previous.a, axis=1)
    anchors = np.concatenate([previous.a, previous.b, 0.5 * (previous.a + previous.b)])
    status = np.concatenate([previous.end_active[:, 0], previous.end_active[:, 1], previous.edge_active])
    index, near = _nearest(anchors, points, 0.25 * np.tile(length, 3))
    return status[index] & near


def face_status(previous, corners: np.ndarray) -> np.ndarray:
    """3D: active status of the mean constraint of each fine triangle (corners (f, 3, 3)): that
    of the coarse triangle of ``previous`` holding its centroid (the candidates: the coarse
    triangles with the nearest centroids; the one whose smallest barycentric coordinate of the
    point is largest holds it)."""
    coarse = previous.face_points
    points = corners.mean(axis=1)
    k = min(6, len(coarse))
    _, candidates = cKDTree(coarse.mean(axis=1)).query(points, k=k)
    candidates = candidates.reshape(len(points), k)
    origin = coarse[candidates, 0]                                            # (n, k, 3)
    e1, e2 = coarse[candidates, 1] - origin, coarse[candidates, 2] - origin
    d = points[:, None] - origin
    # the point's coordinates (s, t) in the triangle's plane: the 2 x 2 normal equations
    a11, a12, a22 = (e1 * e1).sum(-1), (e1 * e2).sum(-1), (e2 * e2).sum(-1)
    r1, r2 = (e1 * d).sum(-1), (e2 * d).sum(-1)
    det = a11 * a22 - a12 * a12
    s, t = (a22 * r1 - a12 * r2) / det, (a11 * r2 - a12 * r1) / det
    smallest = np.minimum(np.minimum(s, t), 1.0 - s - t)
    holder = candidates[np.arange(len(points)), smallest.argmax(axis=1)]
    return previous.face_active[holder]


def edge_status(previous, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Active status of the edge constraint of each fine edge [a, b], from the coarse trace
    ``previous``: that of the coarse edge it is (a refinement that leaves it whole: bisection on
    adaptive and graded meshes) or halves (its midpoint at the coarse edge's midpoint or at one
    of its quarter points); a fine edge inside a coarse triangle (3D) is predicted active when
    both its ends are. (An edge left whole keeps its own status rather than one predicted from
    its ends: in `mean`'s binding zones the vertex constraints are degenerate and often
    inactive, so the ends would set free edges that are in contact, and the active set method
    would spend sets on taking them back; ``python -m harness bench --only adaptive`` counts
    the sets.)"""
    length = np.linalg.norm(previous.b - previous.a, axis=1)
    anchors = np.concatenate([0.5 * (previous.a + previous.b), 0.75 * previous.a + 0.25 * previous.b,
                              0.25 * previous.a + 0.75 * previous.b])
    index, near = _nearest(anchors, 0.5 * (a + b), 0.125 * np.tile(length, 3))
    inherited = np.tile(previous.edge_active, 3)[index]
    return np.where(near, inherited, vertex_status(previous, a) & vertex_status(previous, b))


def cone_prediction(previous, problem) -> np.ndarray | None:
    """The cones' rows (``fem.cones.ContactQP``: the vertices of Gamma_C, then, P2, its edges):
    a fine vertex at a coarse vertex inherits its status, a fine vertex at a coarse midpoint and
    both halves of a coarse edge inherit its edge constraint's status (asking for the whole
    coarse edge in contact instead misses the first vertex past a transition point for `mean`,
    costing two more active set iterations on every level). (Predicting from the sign of the
    coarse function instead fails for `mean` near a pressure singularity, where vertex values
    are positive and edge means zero on alternate nodes.) None on the first level."""
    if previous is None:
        return None
    trace = problem.trace
    edges = edge_status(previous, trace.a, trace.b) if len(problem.edge_dofs) else np.zeros(0, bool)
    return np.concatenate([vertex_status(previous, trace.vertex_points), edges])


def functional_prediction(previous, problem, counts: np.ndarray) -> np.ndarray | None:
    """The rows of a cone of edge functionals (``fem.edge_functionals.EdgeFunctionalQP``, ``counts``
    rows per contact edge): a fine vertex inherits the status of the coarse vertex or edge it
    lies at, each functional of a fine edge that of the coarse edge it lies in."""
    if previous is None:
        return None
    trace = problem.trace
    return np.concatenate([vertex_status(previous, trace.vertex_points),
                           np.repeat(edge_status(previous, trace.a, trace.b), counts)])


def face_mean_prediction(previous, problem) -> np.ndarray | None:
    """The 3D face-mean rows (``fem.face_means.FaceMeanQP``): a fine vertex inherits the status of
    the coarse vertex it is (or, at a coarse edge midpoint, of both ends of that edge), a fine
    triangle that of the coarse triangle it lies in."""
    if previous is None:
        return None
    trace = problem.trace
    return np.concatenate([vertex_status(previous, trace.vertex_points),
                           face_status(previous, trace.faces.corners(trace))])


def nearest_status(coarse_points: np.ndarray, coarse_active: np.ndarray, points: np.ndarray) -> np.ndarray:
    """A contact law's Gauss points: each takes the status of the nearest Gauss point of the
    coarser level's solution. (The sign of the bracket of the interpolated coarse solution is a
    poor guess: its bubbles are zero and near a transition where c - alpha and lambda both vanish
    smoothly (the smooth case) it is wrong at many points, which Newton corrects a few per step.)"""
    return coarse_active[cKDTree(coarse_points).query(points)[1]]


def friction_prediction(carry, points: np.ndarray) -> np.ndarray | None:
    """The Tresca rows (``solvers.friction``: slip+ rows, then slip- rows) at the nodes
    ``points``: each node takes the branch of the coarser level's node it lies at (``carry``:
    its nodes and their (slip+, slip-) flags, vertex rows first, then edge rows), or None on the
    first level.

    A node of a finer level that is no coarse node (a P2 midpoint at a coarse quarter point, a
    P1 vertex at a coarse midpoint) lies as far from two coarse nodes, and takes the branch of
    the later one in the carry's order: for P2 the edge row of the coarse edge holding it, as
    ``cone_prediction`` takes the parent edge's. Not the vertex's: `mean`'s vertex rows weigh
    nothing and carry the sign of their round-off value in its stick zones (every fine edge
    there predicted slipping, 5-7 sets a level on tresca-r32 and tresca-r72 instead of 2-3),
    and `nodal`'s first node past a stick-slip point lies between the stick vertex at the point
    and a slipping midpoint (one more set a level). (Near: within 1% of the distance, which
    covers a curved Gamma_C's O(h^2) shift of refined nodes.)"""
    if carry is None or carry.points is None:
        return None
    m = len(carry.points)
    distance, index = cKDTree(carry.points).query(points, k=min(2, m))
    index = index.reshape(len(points), -1)
    distance = distance.reshape(len(points), -1)
    if index.shape[1] == 2:
        tied = distance[:, 1] <= 1.01 * distance[:, 0]
        index = np.where(tied, index.max(axis=1), index[:, 0])
    else:
        index = index[:, 0]
    return np.concatenate([carry.active[:m][index], carry.active[m:][index]])


def mortar_prediction(carry, points: np.ndarray, vertex_rows: int) -> np.ndarray | None:
    """The mortar rows of two bodies (their slave nodes at ``points``, on a line), by the one-body
    cones' rule (``cone_prediction``, ``edge_status``): a vertex row (the first ``vertex_rows``
    of ``points``) takes the status of the coarser level's row at its point (a coarse vertex,
    or a coarse edge at its midpoint); one between two coarse rows (P1: a vertex new at a coarse
    edge's midpoint) is active when both are; an edge row takes the status of the nearest coarse
    edge row, its parent edge's. (The nearest row of either kind gives the first edge past a
    transition point the status of the vertex there, the edge's midpoint being as near to it as
    to its parent's, which `mortar-mean` corrects with two more active sets on every level.)
    ``carry``: the coarser level's rows (``points``, ``active``, ``vertex_rows``), or None."""
    if carry is None:
        return None
    edges_from = len(carry.points) if carry.vertex_rows is None else carry.vertex_rows
    coarse_edges = slice(edges_from if edges_from < len(carry.points) else 0, None)
    return np.concatenate([_line_status(carry.points, carry.active, points[:vertex_rows]),
                           nearest_status(carry.points[coarse_edges, None], carry.active[coarse_edges],
                                          points[vertex_rows:, None])])


def _line_status(coarse_points: np.ndarray, coarse_active: np.ndarray, points: np.ndarray) -> np.ndarray:
    """Each point (on a line) takes the status of the coarse point it lies on, else is active
    when the coarse points on both sides of it are (beyond the ends: the end's status)."""
    order = np.argsort(coarse_points)
    sorted_points, sorted_active = coarse_points[order], coarse_active[order]
    position = np.searchsorted(sorted_points, points)
    right = np.clip(position, 0, len(sorted_points) - 1)
    left = np.clip(position - 1, 0, len(sorted_points) - 1)
    scale = np.abs(sorted_points).max(initial=1.0)
    on_right = np.abs(sorted_points[right] - points) <= 1e-12 * scale
    on_left = np.abs(sorted_points[left] - points) <= 1e-12 * scale
    between = sorted_active[left] & sorted_active[right]
    return np.where(on_right, sorted_active[right], np.where(on_left, sorted_active[left], between))
