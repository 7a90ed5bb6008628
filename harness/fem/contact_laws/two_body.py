"""A contact law between two bodies (``fem.two_body.TwoBodyProblem``): the master-slave (biased)
form of the one-body laws, on the joint dofs z = (u_1, u_2) -- the system ``solvers.newton``
solves, as ``system.LawSystem`` and ``channels.FrictionSystem`` are for one body against a
rigid obstacle.

Both bodies' frames have Gamma_C on y = 0 with n = -e_y (``problem.bodies``: the lower body in
its mirrored frame, which fixes Gamma_C's points), so at a point x of the upper (slave) body's
Gamma_C the interface's variables are the jumps (``measure.two_body_quantities``, whose
definitions these are):

* the opening c_1(x) + c_2(x), each body's contact variable in its own frame, against the gap
  alpha_1 + alpha_2 (each body carries its own, ``Case.gap``);
* in elasticity the slip t_1(x) - t_2(x), t_k = u_k . e_x in both frames; in the scalar model
  the jump c_1 + c_2 (the lower body's variable is -u_2), as for the mortar's Tresca rows;
* the flux: the slave's own, -sigma_n(u_1) and its tangential traction (scalar: d_n u_1), and
  the pressure its flux less the slave's contact load g_C (``Case.contact_load``), as the mortar's
  multiplier is the slave's reaction; each body's own g_C is in its load vector b.

So a channel's rows are T_j = [T_j(slave) | s_j M_j] and N_j = [N_j(slave) | 0], M_j the master's
trace at the slave's points (``fem.mortar.trace_rows_at``; s = +1 for the opening, -1 for the
slip), and the law's terms are the one body's:

    F(z) = diag(A_1, A_2) z - b - sum_j T_j^T W p_j + sum_j N_j^T W f_j.

The pressure p acts on both bodies through the jump's variation (action and reaction); the
flux term, Nitsche's consistency and symmetry term theta gamma (p - lambda), reads the slave's
stress only: the biased (master-slave) Nitsche method, the one-body law's "natural extension"
to two bodies (F. Chouly, R. Mlika & Y. Renard, Numer. Math. 139 (2018), doi
10.1007/s00211-018-0950-x, Section 1, who call it without a complete theoretical justification
and analyse the unbiased variant instead, which averages both bodies' fluxes; that one is not
built here). gamma = gamma0 h / M with h the slave's edge: the law's own, unchanged.

The quadrature: Gauss points on every segment of the common refinement of the two trace meshes
(``fem.mortar.intersection``, as the mortar's coupling integrates), on which both traces are
polynomials: the terms are integrated exactly wherever the law's branch does not switch within a
segment, as on one body.
"""
from __future__ import annotations

from dataclasses import dataclass, replace
from functools import cached_property

import numpy as np
import scipy.sparse as sp

from ...problem.bodies import lower_body
from ..assembly import at_load_step
from ..contact_quadrature import GAUSS_POINTS, ContactQuadrature, at_points, edge_quadrature, gauss
from ..mortar import TraceElements, intersection, trace_rows_at
from ..sparse import csr_block_diag, csr_positions, csr_view, ngsolve_matrix
from ..two_body import TwoBodyProblem
from .channels import FrictionSystem, channel_data, check_friction_law, slip_rows
from .system import LawSystem, check_law, contact_data, obstacle_force


@dataclass
class JointProblem:
    """Both bodies' discrete problems as the one problem Newton solves: the joint dofs (upper
    then lower), their load, lift and free dofs; the slave's physics and mesh (the law's scales,
    the dimension)."""

    pair: TwoBodyProblem
    b: np.ndarray
    lift: np.ndarray
    free: np.ndarray

    @classmethod
    def of(cls, pair: TwoBodyProblem) -> "JointProblem":
        return cls(pair, *(np.concatenate([getattr(body, name) for body in pair.bodies]) for name in ("b", "lift", "free")))

    @property
    def ndof(self) -> int:
        return self.pair.ndof

    @property
    def bodies(self) -> tuple:
        """The two bodies' problems (``system.touched_p1``: body by body)."""
        return self.pair.bodies

    @property
    def physics(self):
        return self.pair.upper.physics

    @property
    def mesh(self):
        return self.pair.upper.mesh

    def at_step(self, case, step: int) -> "JointProblem":
        """Both bodies at load step ``step`` (``fem.assembly.at_load_step``; the lower body with
        its own data, ``problem.bodies.lower_body``)."""
        bodies = TwoBodyProblem(at_load_step(case, self.pair.upper, step), at_load_step(lower_body(case), self.pair.lower, step))
        return JointProblem.of(bodies)


def joint_load_step(case, problem: JointProblem, step: int) -> JointProblem:
    """``JointProblem.at_step``: the step's problem, as ``fem.assembly.at_load_step`` is for one body
    (``solvers.load_steps.solve_history``'s ``at_step``)."""
    return problem.at_step(case, step)


def interface_quadrature(pair: TwoBodyProblem) -> ContactQuadrature:
    """The slave's quadrature (its rows on its own dofs) at Gauss points of every segment of the
    intersection of the two trace meshes (the module's note), each point in the slave edge that
    holds its segment; ``h`` that edge's length."""
    upper = pair.upper
    slave = TraceElements.of(upper)
    segments = intersection(slave, TraceElements.of(pair.lower))
    t, w = gauss(max(GAUSS_POINTS, upper.order + 1))
    x = (segments[:, :1] + t[None, :] * (segments[:, 1:] - segments[:, :1])).ravel()
    weights = ((segments[:, 1] - segments[:, 0])[:, None] * w[None, :]).ravel()
    edge = slave.edge_index[slave.locate(np.repeat(segments.mean(axis=1), len(t)))]
    trace = upper.trace
    a, b = trace.a[edge, 0], trace.b[edge, 0]
    return edge_quadrature(upper, edge, (x - a) / (b - a), weights)


@dataclass
class InterfaceRows:
    """The channels' rows on the joint dofs (the module's note) and their data at the points."""

    quadrature: ContactQuadrature   # on the joint dofs: T, N the normal channel's
    T: list
    N: list
    gap: np.ndarray
    load: np.ndarray
    threshold: np.ndarray | None = None
    coefficient: np.ndarray | None = None

    @cached_property
    def pattern(self) -> sp.csr_matrix:
        """Every (i, j) a term of the law can couple: the rows' columns pairwise."""
        touched = sum((abs(M) for M in self.T[1:] + self.N), abs(self.T[0])).tocsr()
        return (touched.T @ touched).tocsr()


def interface_rows(case, pair: TwoBodyProblem, friction: bool) -> InterfaceRows:
    """The normal channel's rows (and, with ``friction``, the slip channels' before it, as
    ``channels.friction_system`` orders them) at the points of ``interface_quadrature``."""
    upper, lower = pair.bodies
    q = interface_quadrature(pair)
    x = q.points[:, 0]
    zero = sp.csr_matrix((len(x), lower.ndof))
    opening = trace_rows_at(lower, x)           # c_2 at the slave's points
    joint = replace(q, T=sp.hstack([q.T, opening]).tocsr(), _flux=sp.hstack([q.N, zero]).tocsr())
    master_gap = upper.physics.obstacle(at_points(lower_body(case).gap, lower.mesh, q))
    if not friction:
        gap, load = contact_data(case, upper, q)
        return InterfaceRows(joint, [joint.T], [joint.N], gap + master_gap, load)
    T, N = slip_rows(upper, q)
    tangential = len(T)
    rotated = upper.physics.rotated_frame
    # the slip: t_1 - t_2 in elasticity; the jump c_1 + c_2 in the scalar model (the module's note)
    master = [-trace_rows_at(lower, x, tangential=True)] if rotated else [opening]
    T = [sp.hstack([own, m]).tocsr() for own, m in zip(T, master)]
    N = [sp.hstack([own, zero]).tocsr() for own in N]
    if rotated:
        T, N = T + [joint.T], N + [joint.N]
    gap, load, threshold, coefficient = channel_data(case, upper, q, tangential)
    return InterfaceRows(joint, T, N, gap + master_gap, load, threshold, coefficient)


def joint_jacobian(pair: TwoBodyProblem, pattern: sp.csr_matrix):
    """(J, J_ngs, delta, positions) as ``system.boundary_jacobian`` makes them for one body, on
    the joint dofs: J = diag(A_1, A_2) on the union of its pattern and ``pattern`` (the terms
    couple the slave's and the master's dofs across Gamma_C), one NGSolve matrix (a
    factorisation's) with a scipy view of its memory."""
    A = csr_block_diag([body.A for body in pair.bodies]).tocoo()
    extra = pattern.tocoo()
    J_ngs = ngsolve_matrix(sp.coo_matrix((np.concatenate([A.data, np.zeros(extra.nnz)]),
                                          (np.concatenate([A.row, extra.row]), np.concatenate([A.col, extra.col]))),
                                         shape=A.shape))
    J = csr_view(J_ngs)
    delta = pattern.copy()
    delta.sum_duplicates()
    delta.sort_indices()
    delta.data[:] = 0.0
    coo = delta.tocoo()
    return J, J_ngs, delta, csr_positions(J, coo.row.astype(np.int64), coo.col.astype(np.int64))


def pair_obstacle_force(case, pair: TwoBodyProblem) -> float:
    """``system.obstacle_force`` of each body at its own gap, the larger: a scale of F."""
    return max(obstacle_force(body_case, body, body.A) for body_case, body in zip((case, lower_body(case)), pair.bodies))


def two_body_system(case, pair: TwoBodyProblem, law):
    """The system of ``law`` between the two bodies (a contact law, or on a frictional case a
    friction law: ``friction_laws.law_for``), its law checked as on one body, its Jacobian set
    for no active point (a friction law: the stick branch everywhere)."""
    rows = interface_rows(case, pair, case.frictional)
    problem = JointProblem.of(pair)
    J, J_ngs, delta, positions = joint_jacobian(pair, rows.pattern)
    force = pair_obstacle_force(case, pair)
    if not case.frictional:
        system = LawSystem(problem, rows.quadrature, law, rows.gap, rows.load, problem.b.copy(), J, J_ngs, delta, positions,
                           force, symmetric=True)
        system.symmetric = check_law(system)
        system.set_jacobian(np.zeros(len(rows.gap), bool))
        return system
    tangential = len(rows.T) - 1 if problem.physics.rotated_frame else 1
    system = FrictionSystem(problem, rows.quadrature, law, rows.T, rows.N, rows.gap, rows.load, rows.threshold, tangential,
                            problem.b.copy(), J, J_ngs, delta, positions, force, coefficient=rows.coefficient,
                            nonsymmetric_krylov=rows.coefficient is not None)
    system.symmetric, system.affine = check_friction_law(system)
    system.set_jacobian(np.zeros(len(rows.gap), np.int64))
    return system
