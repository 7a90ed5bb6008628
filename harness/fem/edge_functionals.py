"""A discrete cone given only by constraint functionals on the edges of Gamma_C (2D): v_h >= alpha
at the vertices of Gamma_C and, on every contact edge [a, b] and for each of the cone's
functionals l_j v = sum_k w_jk v(a + t_jk (b - a)),

    l_j(v_h) >= l_j(alpha).

The paper's cones are the case of one functional per edge, the midpoint value (K~_h, Section 5)
or the edge mean (K_h, Section 3); one functional per edge is a bound after a local change of
variables (``cones``). Two or more per edge (values at the points 1/4 and 3/4, say) couple the
edge's three trace variables in more rows than it has bubbles: general rows B u >= g, solved by
the general-constraint active set method (``solvers.general_constraints``) as the 3D ``mean``'s
triangle means are (``face_means``).

Each functional is a row on the trace variables of its edge: for P2, (sum w (1 - t), sum w t,
-sum w t (1 - t) / 2) on (v_a, v_b, c_e) (docs/mathematics.md §3); for P_k the k - 1 edge
dofs of NGSolve's basis too. On P_k with k - 1 functionals per edge (the values at the edge's
interior Gauss-Lobatto points, say) the rows of an edge with its two vertex rows fix its k + 1
trace variables: independent rows.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from ..mesh.points import evaluate
from .assembly import ContactTraceFunction, DiscreteProblem
from .cones import GeneralRowsQP, contact_pressure, end_status, vertex_rows
from .contact_quadrature import trace_rows
from .nested import functional_prediction


def check_rules(rules) -> tuple:
    """``rules`` as a tuple of rules, each a tuple of (t, w) with t in [0, 1] and w finite, and
    sum w != 0; a one-line ValueError otherwise."""
    try:
        checked = tuple(tuple((float(t), float(w)) for t, w in rule) for rule in rules)
    except (TypeError, ValueError):
        raise ValueError(f"edge functionals are rules ((t, w), ...) of points t in [0, 1] and weights w, got {rules!r}") from None
    if not checked:
        raise ValueError("a cone of edge functionals needs at least one functional")
    for rule in checked:
        if not rule or any(not (0.0 <= t <= 1.0 and math.isfinite(w)) for t, w in rule):
            raise ValueError(f"an edge functional is a non-empty rule of points t in [0, 1] with finite weights, got {rule!r}")
        if abs(sum(w for _, w in rule)) < 1e-12:
            raise ValueError(f"an edge functional's weights must not sum to 0 (it would not bound v_h), got {rule!r}")
    return checked


def rules_per_edge(problem: DiscreteProblem, rules) -> list[tuple]:
    """The rules of each contact edge: ``rules`` (``check_rules``) on every edge, or, given a
    function of the degree, that function's rules at each edge's own degree (an hp mesh:
    ``DiscreteProblem.edge_degrees``), checked once per degree."""
    if not callable(rules):
        return [rules] * len(problem.trace.edges)
    of_degree: dict = {}
    return [of_degree.setdefault(int(p), check_rules(rules(int(p)))) for p in problem.edge_degrees]


def _groups(per_edge: list[tuple]):
    """(the edges, their rules) of each distinct rule set, and the first row of each edge (the
    rows run edge by edge: ``len(rules)`` rows per edge)."""
    counts = np.array([len(rules) for rules in per_edge], dtype=np.int64)
    first = np.concatenate([[0], np.cumsum(counts)[:-1]]).astype(np.int64)
    distinct: dict = {}
    for edge, rules in enumerate(per_edge):
        distinct.setdefault(rules, []).append(edge)
    return [(np.array(edges), rules) for rules, edges in distinct.items()], first, int(counts.sum())


def edge_functional_rows(problem: DiscreteProblem, rules) -> sp.csr_matrix:
    """One row per (contact edge, functional), edge by edge, in the problem's variables: each
    functional's weighted sum of the trace rows of the contact variable at its points (NGSolve's
    basis of any order evaluated there, ``contact_quadrature.trace_rows``), exact for every
    function of X_h, whatever the rule. ``rules``: as for ``rules_per_edge``."""
    trace = problem.trace
    groups, first, total = _groups(rules_per_edge(problem, rules))
    blocks, positions = [], []
    for edges, edge_rules in groups:
        m = len(edge_rules)
        t = np.array([point for rule in edge_rules for point, _ in rule])
        weights = np.array([w for rule in edge_rules for _, w in rule])
        functional = np.repeat(np.arange(m), [len(rule) for rule in edge_rules])
        points = trace.a[edges][:, None, :] + t[None, :, None] * (trace.b - trace.a)[edges][:, None, :]
        T = trace_rows(problem.fes, problem.physics, problem.basis, np.repeat(trace.volumes[edges], len(t)),
                       points.reshape(-1, points.shape[-1]), np.repeat(trace.normals[edges], len(t), axis=0))
        ne = len(edges)
        row_of_point = (np.arange(ne)[:, None] * m + functional[None, :]).ravel()
        combine = sp.csr_matrix((np.tile(weights, ne), (row_of_point, np.arange(ne * len(t)))), shape=(ne * m, ne * len(t)))
        blocks.append(combine @ T)
        positions.append((first[edges][:, None] + np.arange(m)[None, :]).ravel())
    order = np.argsort(np.concatenate(positions), kind="stable")
    rows = sp.vstack(blocks).tocsr()[order]
    assert rows.shape[0] == total
    return rows


def edge_functional_values(case, problem: DiscreteProblem, rules) -> np.ndarray:
    """l_j(alpha) per (contact edge, functional), in the order of ``edge_functional_rows``."""
    groups, first, total = _groups(rules_per_edge(problem, rules))
    values = np.zeros(total)
    if case.obstacle is None:
        return values
    trace = problem.trace
    for edges, edge_rules in groups:
        for j, rule in enumerate(edge_rules):
            t = np.array([point for point, _ in rule])
            points = trace.a[edges][:, None, :] + t[None, :, None] * (trace.b - trace.a)[edges][:, None, :]
            at = evaluate(case.obstacle, problem.mesh, points.reshape(-1, points.shape[-1])).reshape(len(edges), len(t))
            values[first[edges] + j] = at @ np.array([w for _, w in rule])
    return values


@dataclass
class EdgeFunctionalQP(GeneralRowsQP):
    """The cone's QP (``cones.GeneralRowsQP``): after the vertex rows, ``counts[e]`` rows of each
    contact edge e, edge by edge."""

    counts: np.ndarray

    @property
    def edge_of_row(self) -> np.ndarray:
        """The contact edge of each edge row."""
        return np.repeat(np.arange(len(self.counts)), self.counts)

    def predicted_active(self, previous: ContactTraceFunction | None) -> np.ndarray | None:
        """Nested iteration: the active set predicted by the previous level's trace
        (``fem.nested.functional_prediction``)."""
        return functional_prediction(previous, self.problem, self.counts)

    def trace_function(self, u: np.ndarray, active: np.ndarray) -> ContactTraceFunction:
        problem, nv = self.problem, self.n_vertices
        edge_active = np.bincount(self.edge_of_row, weights=active[nv:], minlength=len(self.counts)) > 0
        return ContactTraceFunction.of(problem, u, end_status(problem, active[:nv]), edge_active)

    def pressure(self, multipliers: np.ndarray) -> np.ndarray:
        """The discrete pressure per contact edge: the vertex rows' as for the cones, and the
        edge rows' forces spread uniformly over their edge (sum_j lambda_ej / |e|)."""
        problem, nv = self.problem, self.n_vertices
        vertex_part = contact_pressure(problem, np.concatenate([multipliers[:nv], np.zeros(len(problem.edge_dofs))]))
        edge_part = np.bincount(self.edge_of_row, weights=multipliers[nv:], minlength=len(self.counts))
        return vertex_part + edge_part / problem.trace.cell_sizes


def edge_functional_qp(case, problem: DiscreteProblem, rules, take_stiffness: bool = False) -> EdgeFunctionalQP:
    """The QP of the cone of ``rules`` (``check_rules``, or a function of the degree:
    ``rules_per_edge``) on ``problem`` (2D); ``take_stiffness`` as for the cones
    (``cones.contact_qp``): A itself is K, no change of variables."""
    if problem.trace.faces is not None:
        raise ValueError("a cone of edge functionals is 2D (3D: triangle rows, fem/face_means.py)")
    bounds, g_vertices = vertex_rows(case, problem)
    K, K_ngs = problem.take_stiffness() if take_stiffness else (problem.A, problem.A_ngs)
    B = sp.vstack([bounds, edge_functional_rows(problem, rules)]).tocsr()
    counts = np.array([len(edge_rules) for edge_rules in rules_per_edge(problem, rules)], dtype=np.int64)
    return EdgeFunctionalQP(problem, K, K_ngs, problem.b, B, np.concatenate([g_vertices, edge_functional_values(case, problem, rules)]),
                            counts)
