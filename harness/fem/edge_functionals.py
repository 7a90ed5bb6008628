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


def edge_functional_rows(problem: DiscreteProblem, rules) -> sp.csr_matrix:
    """One row per (contact edge, functional), edge by edge, in the problem's variables: each
    functional's weighted sum of the trace rows of the contact variable at its points (NGSolve's
    basis of any order evaluated there, ``contact_quadrature.trace_rows``), exact for every
    function of X_h, whatever the rule."""
    trace = problem.trace
    ne, m = len(trace.edges), len(rules)
    t = np.array([point for rule in rules for point, _ in rule])
    weights = np.array([w for rule in rules for _, w in rule])
    functional = np.repeat(np.arange(m), [len(rule) for rule in rules])
    points = trace.a[:, None, :] + t[None, :, None] * (trace.b - trace.a)[:, None, :]         # (ne, p, dim)
    T = trace_rows(problem.fes, problem.physics, problem.basis, np.repeat(trace.volumes, len(t)),
                   points.reshape(-1, points.shape[-1]), np.repeat(trace.normals, len(t), axis=0))
    row_of_point = (np.arange(ne)[:, None] * m + functional[None, :]).ravel()
    combine = sp.csr_matrix((np.tile(weights, ne), (row_of_point, np.arange(ne * len(t)))), shape=(ne * m, ne * len(t)))
    return (combine @ T).tocsr()


def edge_functional_values(case, problem: DiscreteProblem, rules) -> np.ndarray:
    """l_j(alpha) per (contact edge, functional), in the order of ``edge_functional_rows``."""
    ne, m = len(problem.end_dofs), len(rules)
    if case.obstacle is None:
        return np.zeros(ne * m)
    columns = [np.ravel(evaluate(case.obstacle, problem.mesh, problem.trace.points(np.array([t for t, _ in rule])))
                        .reshape(ne, len(rule)) @ np.array([w for _, w in rule])) for rule in rules]
    return np.stack(columns, axis=1).ravel()


@dataclass
class EdgeFunctionalQP(GeneralRowsQP):
    """The cone's QP (``cones.GeneralRowsQP``): after the vertex rows, ``m`` rows per contact edge."""

    m: int

    def predicted_active(self, previous: ContactTraceFunction | None) -> np.ndarray | None:
        """Nested iteration: a fine vertex inherits the status of the coarse vertex or edge it
        lies at, each functional of a fine edge that of the coarse edge it lies in."""
        if previous is None:
            return None
        trace = self.problem.trace
        return np.concatenate([previous.vertex_status(trace.vertex_points),
                               np.repeat(previous.edge_status(trace.a, trace.b), self.m)])

    def trace_function(self, u: np.ndarray, active: np.ndarray) -> ContactTraceFunction:
        problem, nv = self.problem, self.n_vertices
        edge_active = active[nv:].reshape(-1, self.m).any(axis=1)
        return ContactTraceFunction.of(problem, u, end_status(problem, active[:nv]), edge_active)

    def pressure(self, multipliers: np.ndarray) -> np.ndarray:
        """The discrete pressure per contact edge: the vertex rows' as for the cones, and the
        edge rows' forces spread uniformly over their edge (sum_j lambda_ej / |e|)."""
        problem, nv = self.problem, self.n_vertices
        vertex_part = contact_pressure(problem, np.concatenate([multipliers[:nv], np.zeros(len(problem.edge_dofs))]))
        return vertex_part + multipliers[nv:].reshape(-1, self.m).sum(axis=1) / problem.trace.cell_sizes


def edge_functional_qp(case, problem: DiscreteProblem, rules, take_stiffness: bool = False) -> EdgeFunctionalQP:
    """The QP of the cone of ``rules`` (``check_rules``) on ``problem`` (2D); ``take_stiffness``
    as for the cones (``cones.contact_qp``): A itself is K, no change of variables."""
    if problem.trace.faces is not None:
        raise ValueError("a cone of edge functionals is 2D (3D: triangle rows, fem/face_means.py)")
    bounds, g_vertices = vertex_rows(case, problem)
    K, K_ngs = problem.take_stiffness() if take_stiffness else (problem.A, problem.A_ngs)
    B = sp.vstack([bounds, edge_functional_rows(problem, rules)]).tocsr()
    return EdgeFunctionalQP(problem, K, K_ngs, problem.b, B, np.concatenate([g_vertices, edge_functional_values(case, problem, rules)]),
                            len(rules))
