"""The mortar methods' family: two bodies on non-matching meshes, contact imposed weakly on the
opening of the interface against a multiplier space on the upper (slave) body's trace
(``fem.mortar``), solved exactly as a QP with general constraints (``solvers.general_constraints``,
KKT <= 1e-10) on the joint system of both bodies (``fem.two_body``). The variants
(``methods``): `mortar-mean`, `mortar-nodal`, `mortar-standard` (P2) and `mortar-p1`."""
from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from functools import partial
from typing import Callable

import numpy as np
import scipy.sparse as sp

from ..fem.assembly import at_load_step
from ..fem.cones import ContactModel, contact_pressure
from ..fem.mortar import mortar_coupling
from ..fem.nested import friction_prediction, mortar_prediction, p1_values
from ..fem.sparse import ngsolve_matrix
from ..fem.two_body import TwoBodyProblem, dual_bound_qp, joint_qp, opening
from ..problem.bodies import lower_body
from ..solvers.bound_constraints import ActiveSetSolver, FactorisedSystem, MultigridSystem, row_norm
from ..solvers.coulomb_cones import solve_coulomb_history
from ..solvers.friction import solve_friction
from ..solvers.general_constraints import GeneralConstraintSolver
from ..solvers.two_body_multigrid import OpeningLevels, SparseEdges, mortar_coupling_matrix, mortar_injection, p1_injected
from ..solvers.two_body_operator import CoupledBlocks
from .method import (
    MESH_STUDY,
    REFERENCE,
    Expectation,
    LawCarry,
    LevelSolve,
    Method,
    MortarCarry,
    SolveFields,
    capped_expectation,
    timer,
)


def one_body_rate(case, order: int) -> Expectation:
    """min(nu - 1, k): the best approximation's rate on each body, which the one-body theorems
    give the cones (Belhachmi & Ben Belgacem 2003 for P2, Ben Belgacem 2000 and Drouet & Hild
    2015 for P1) and the dual mortar condition reduces to on matching meshes. On non-matching
    meshes it is the rate the mortar analyses aim at (Ben Belgacem, Hild & Laborde 1999 for P1;
    Hild & Laborde 2002 for P2); only their abstracts were read, not their exact statements,
    so the harness holds the methods to the one-body rate and the report says so. With Tresca or
    Coulomb friction between the bodies no analysis was read at all: the same rate, a conjecture."""
    if case.frictional:
        return capped_expectation(case.nu, float(order),
                                  f"conjecture: the one-body rate min(nu - 1, k) ({case.friction.name.capitalize()} on mortar)")
    return capped_expectation(case.nu, float(order),
                              "one-body rate min(nu - 1, k) (mortar: Ben Belgacem, Hild & Laborde 1999; Hild & Laborde 2002)")


def row_points(problem: TwoBodyProblem) -> np.ndarray:
    """x of each mortar row's slave node: the vertices of Gamma_C, then (P2) its edge midpoints."""
    trace = problem.upper.trace
    points = trace.vertex_points[:, 0]
    return np.concatenate([points, trace.midpoints[:, 0]]) if problem.order == 2 else points


@dataclass(frozen=True)
class Mortar(Method):
    """Mortar contact of two bodies: ``multipliers`` "dual" or "standard" (``fem.mortar``),
    ``edge_functional`` "midpoint" (a row per multiplier) or "edge-mean" (P2 dual: `mean`'s edge
    means of the dual projection)."""

    multipliers: str = "dual"
    edge_functional: str = "midpoint"
    physics: tuple = ("scalar", "elasticity")
    bodies: tuple = (2,)

    def contact_weight(self, order: int) -> float | None:
        """The weight w of the P2 edge variables (``fem.two_body.dual_bound_qp``): the one-body cones'."""
        return ContactModel(self.edge_functional).weight if order == 2 else None

    def refusal(self, case) -> str | None:
        """Also: Tresca between two bodies on the dual multipliers only (their rows are bounds),
        and in the scalar model only (in elasticity its rows are the normal opening's, not the
        tangential slip's); Coulomb on the dual multipliers with nodal edge variables only
        (``fem.two_body.dual_bound_qp``: `mortar-mean`'s edge means leave vertex rows whose
        forces are no pressure to bound the friction by)."""
        if case.frictional and self.multipliers != "dual" and case.friction.name in self.friction:
            return "its multipliers are not dual: Tresca's rows would not be bounds"
        if case.friction.name == "tresca" and case.physics.rotated_frame and case.friction.name in self.friction:
            return "its Tresca rows are the scalar model's; the elastic tangential slip between two bodies is not implemented"
        if case.friction.name == "coulomb" and self.multipliers != "dual":
            return "its multipliers are not dual: Coulomb's rows would not be bounds"
        if case.friction.name == "coulomb" and self.contact_weight(self.order) == 6.0:
            return "its vertex multipliers are O(h^2) of either sign: no Coulomb threshold mu_F p node by node"
        return super().refusal(case)

    def solve(self, case, problem: TwoBodyProblem, carry, multilevel, take_stiffness: bool = False, phases=None,
              general: bool = False) -> LevelSolve:
        """Dual multipliers: the bounds of ``fem.two_body.dual_bound_qp`` by the active set method
        (``solvers.bound_constraints``), on the two bodies' multigrid where ``multilevel`` is given
        (``solvers.two_body_multigrid``: uniform pairs), else on sparse Cholesky; standard ones, or
        ``general=True`` (the cross-check), the rows themselves by the general-constraint active
        set method on the saddle system (``solvers.general_constraints``)."""
        if case.frictional:
            solver = self.solve_coulomb if case.friction.name == "coulomb" else self.solve_tresca
            return solver(case, problem, carry, multilevel, phases)
        timed = timer(phases)
        with timed("setup"):
            dual = self.multipliers == "dual"
            coupling = mortar_coupling(problem.upper, problem.lower, case.obstacle, self.multipliers,
                                       self.edge_functional if general or not dual else "midpoint")
            points = row_points(problem)
            predicted = mortar_prediction(carry, points, len(problem.upper.trace.vertex_points))
            start = None
            if dual and not general:
                qp = dual_bound_qp(problem, coupling, self.contact_weight(problem.order))
                K, system, start = bound_system(qp, problem, carry, multilevel, self.solver)
        with timed("solve"):
            if dual and not general:
                solution = ActiveSetSolver(K, qp.b, qp.free, qp.C, qp.alpha, lift=qp.lift, system=system,
                                           options=self.solver).solve(predicted, start)
                u = qp.to_u(solution.z)
                # the bound's multiplier is the force on its variable: D_i times the row's
                forces = solution.multipliers
            else:
                solution = _general(problem, coupling, predicted, self.solver)
                u = solution.z
                # the rows were divided by D_i (``_general``): the multiplier of row i is
                # lambda_i D_i, for dual rows int lambda_h phi_i (standard ones: an approximation)
                forces = solution.multipliers
        # per slave edge, as the one-body cones report it: the forces shared among the edges
        pressure = contact_pressure(problem.upper, forces)
        fields = SolveFields.of_exact(solution, max_penetration(case, problem, u), pressure, coupling.rows)
        # each row's slave node and status (the predicted active set) and both bodies' vertex values
        return LevelSolve(fields, u, None, pressure, MortarCarry(joint_p1_values(problem, u), points=points,
                                                                 active=solution.active,
                                                                 vertex_rows=len(problem.upper.trace.vertex_points)))


    def solve_tresca(self, case, problem: TwoBodyProblem, carry, multilevel, phases) -> LevelSolve:
        """Tresca between the bodies (scalar): j(v) = int s |[v]| on the slave's dual mortar
        projection of the jump, j_h = sum_i D_i s(x_i) |pi_i| (D_i = int psi_i: Simpson's weights
        on a P2 slave edge, the nodal analogue; `mortar-mean`: |e| s |mean of pi on e| per slave
        edge, its vertices weightless), solved exactly on the bounds' variables of
        ``fem.two_body.dual_bound_qp`` by ``solvers.friction.solve_friction`` (the dual of
        Hueeber, Stadler & Wohlmuth's friction rows, SISC 30 (2008), with Tresca's given threshold)."""
        timed = timer(phases)
        with timed("setup"):
            coupling = mortar_coupling(problem.upper, problem.lower, None, "dual", "midpoint")
            qp = dual_bound_qp(problem, coupling, self.contact_weight(problem.order))
            K, system, start = bound_system(qp, problem, carry, multilevel, self.solver)
            points = row_points(problem)
            c = mortar_friction_weights(case, problem, coupling.D, self.edge_functional)
            predicted = friction_prediction(carry, points[:, None])
        with timed("solve"):
            solution = solve_friction(K, qp.b, qp.free, qp.C, c, qp.lift, system, self.solver, predicted, start)
        u = qp.to_u(solution.z)
        # the flux's convention (the friction force d_n u - g_C): the solver's lambda = b - K z is its opposite
        pressure = contact_pressure(problem.upper, -solution.multipliers)
        fields = SolveFields.of_exact(solution, float("nan"), pressure, 2 * len(qp.C))
        return LevelSolve(fields, u, None, pressure, MortarCarry(joint_p1_values(problem, u), points=points[:, None],
                                                                 active=solution.active,
                                                                 vertex_rows=len(problem.upper.trace.vertex_points)))


    def solve_coulomb(self, case, problem: TwoBodyProblem, carry, multilevel, phases) -> LevelSolve:
        """Coulomb between the bodies (2D elasticity, dual multipliers, w = 4): the bounds of
        ``fem.two_body.dual_bound_qp`` with the tangential jump's rows, solved by the one-body
        cones' fixed point over unilateral Tresca problems (``solvers.coulomb_cones``,
        c = mu_F p node by node) at every step of the case's load history (``two_body_steps``).
        The fields as ``methods.coulomb_cones``'s: ``kkt_residual`` the worst step's KKT residual
        or last change of the weights; every step nested from the coarser level's same step
        (``coulomb_guess``)."""
        if self.multipliers != "dual":
            raise ValueError(f"{self.name}: its multipliers are not dual: Coulomb's rows would not be bounds")
        timed = timer(phases)
        with timed("setup"):
            coupling = mortar_coupling(problem.upper, problem.lower, case.obstacle, "dual", "midpoint")
            qp = dual_bound_qp(problem, coupling, self.contact_weight(problem.order), tangential=True)
            K, system, _ = bound_system(qp, problem, carry, multilevel, self.solver)
            # on the multigrid K is the coupled operator: the scipy K is never made
            rows = CoulombRows(K, qp.free, qp.C, qp.alpha, qp.T, qp.thresholds)
            K_norm = K.row_norm(qp.free) if hasattr(K, "row_norm") else row_norm(K, qp.free)
            steps, m = two_body_steps(case, problem, qp), len(qp.C)
            guess = partial(coulomb_guess, qp, problem, carry, multilevel if isinstance(system, MultigridSystem) else None)
        with timed("solve"):
            history = solve_coulomb_history(rows, steps, case.friction.coefficient, partial(step_system, system, self.solver),
                                            guess, self.solver, K_norm)
        carries = [coulomb_carry(qp, problem, step.solution) for step in history]
        final = history[-1].solution
        u = qp.to_u(final.z)
        pressure = contact_pressure(problem.upper, final.multipliers[:m])
        failed = [step.status for step in history if step.status != "converged"]
        work = [step.work.get("cg_iterations", step.work.get("factorizations", 0)) for step in history]
        fields = SolveFields(max_penetration(case, problem, u), float(pressure.min()),
                             max(max(step.solution.kkt.residual, step.change) for step in history),
                             failed[0] if failed else "converged", sum(step.iterations for step in history), int(sum(work)),
                             active_constraints=int(final.active[:m].sum()), n_contact_constraints=3 * m,
                             backward_error=max(step.solution.kkt.backward for step in history),
                             solve_seconds=sum(step.seconds for step in history), load_steps=len(history))
        previous = qp.to_u(history[-2].solution.z) if len(history) > 1 else None
        return LevelSolve(fields, u, None, pressure, dataclasses.replace(carries[-1], steps=tuple(carries[:-1])),
                          previous=previous)


@dataclass(frozen=True)
class CoulombMortarCarry(MortarCarry):
    """A mortar's carry on a Coulomb case: its rows' slave nodes and contact status (``points``,
    ``active``), the (slip+, slip-) flags of their tangential rows (``slip``) and the carries of
    the load steps before the last (``steps``)."""

    slip: np.ndarray | None = None


def coulomb_carry(qp, problem: TwoBodyProblem, solution) -> CoulombMortarCarry:
    """One load step's carry: both bodies' vertex values, the rows' contact and slip flags."""
    m = len(qp.C)
    return CoulombMortarCarry(joint_p1_values(problem, qp.to_u(solution.z)), points=row_points(problem),
                              active=solution.active[:m], slip=solution.active[m:],
                              vertex_rows=len(problem.upper.trace.vertex_points))


def coulomb_guess(qp, problem: TwoBodyProblem, carry, multilevel, k: int, solved: list):
    """(predicted rows, start) of load step ``k``, as the one-body cones' (``methods.coulomb_cones``):
    from the coarser level's same step (its rows' contact status by ``fem.nested.mortar_prediction``,
    their slip branches by ``fem.nested.friction_prediction``, none without them; on the multigrid
    its u_h prolongated, in z), else from the step before on this level, else none."""
    coarse = None
    if carry is not None:
        coarse = carry if k == len(carry.steps) else carry.steps[k] if k < len(carry.steps) else None
    if coarse is None:
        return (solved[-1].solution.active, solved[-1].solution.z) if solved else (None, None)
    points, m = row_points(problem), len(qp.C)
    slip = getattr(coarse, "slip", None)
    slip = np.zeros(2 * m, bool) if slip is None else \
        friction_prediction(LawCarry(coarse.p1, points=coarse.points[:, None], active=slip), points[:, None])
    predicted = np.concatenate([mortar_prediction(coarse, points, len(problem.upper.trace.vertex_points)), slip])
    start = None if multilevel is None else qp.to_z(p1_injected(problem, multilevel.prolongated(coarse.p1)))
    return predicted, start


@dataclass(frozen=True)
class CoulombRows:
    """A dual bound QP with its tangential rows as ``solvers.coulomb_cones.solve_coulomb_history``
    reads it (K, free, C, alpha, F, thresholds), K a scipy matrix or the coupled operator
    (``solvers.two_body_operator.CoupledBlocks``)."""

    K: object
    free: np.ndarray
    C: np.ndarray
    alpha: np.ndarray
    F: np.ndarray
    thresholds: Callable


def step_system(system, options, b: np.ndarray):
    """A new linear system like ``system`` with the load ``b``, one per load step: a factorised
    system keeps its pins' values (``solvers.bound_constraints.FactorisedSystem``: the same pin set at a
    new step's lift would return the old step's solution)."""
    if isinstance(system, FactorisedSystem):
        return FactorisedSystem(system.K, system.K_ngs, b, options.refactor_above)
    return MultigridSystem(system.K_ngs, b, system.multilevel, system.edges, options=options)


def two_body_steps(case, problem: TwoBodyProblem, qp) -> list:
    """(b, lift) in z of every step of the case's load history: each body's own problem at that
    step (``fem.assembly.at_load_step``; the lower body's in its mirrored frame, ``lower_body``)."""
    lower, steps = lower_body(case), []
    for k in range(len(case.history)):
        bodies = (at_load_step(case, problem.upper, k), at_load_step(lower, problem.lower, k))
        steps.append((qp.with_load(np.concatenate([body.b for body in bodies])),
                      np.concatenate([body.lift for body in bodies])))
    return steps


def mortar_friction_weights(case, problem: TwoBodyProblem, D: np.ndarray, edge_functional: str) -> np.ndarray:
    """The weights of j_h on the dual rows (the slave's vertices, then its edges): D_i s(x_i),
    or for the edge means (`mortar-mean`) 0 at the vertices and |e| s(midpoint) on each edge."""
    trace = problem.upper.trace
    nodes = np.concatenate([trace.vertex_points, trace.midpoints[:len(problem.upper.edge_dofs)]])
    s = problem.upper.values_at(case.friction.threshold_function, nodes)
    if edge_functional == "edge-mean" and problem.order == 2:
        nv = len(trace.vertex_points)
        return np.concatenate([np.zeros(nv), trace.lengths * s[nv:]])
    return D * s


def joint_p1_values(problem: TwoBodyProblem, u: np.ndarray) -> np.ndarray:
    """u's vertex values, body 1's then body 2's, in the joint P1 hierarchy's numbering."""
    return np.concatenate([p1_values(body, part) for body, part in zip(problem.bodies, problem.split(u))])


def bound_system(qp, problem: TwoBodyProblem, carry, multilevel, options):
    """(K, the linear system of the active set iteration, the start): the two bodies' coupled,
    truncated multigrid in the dual variables (``two_body_multigrid``), started from the coarser
    level's u_h prolongated, where ``multilevel`` is given and the QP has at least
    ``options.mortar_multigrid_from`` dofs, K the bodies' own matrices and the coupling
    (``solvers.two_body_operator.CoupledBlocks``); else sparse Cholesky from nothing, K one scipy matrix."""
    if multilevel is None or problem.ndof < options.mortar_multigrid_from:
        return qp.K, FactorisedSystem(qp.K, ngsolve_matrix(qp.K), qp.b, options.refactor_above), None
    # K = diag(A_1, A_2) + (K - A) on the bodies' own NGSolve matrices: not copied into one
    K_ngs = CoupledBlocks([body.A_ngs for body in problem.bodies], qp.K_interface)
    E = mortar_injection(problem, tangential=len(qp.T) > 0)
    coupling = mortar_coupling_matrix(problem, qp.S_rows(qp.changed), qp.changed, E)
    # a contact condition on u itself (scalar): opening variables on every level
    # (``solvers.two_body_multigrid.OpeningLevels``); in a rotated frame (elastic): each body's P1 levels
    # (the slave's trace follows a master hat on the finest level only)
    hierarchy = multilevel.coupled(coupling) if problem.upper.physics.rotated_frame \
        else OpeningLevels(multilevel, problem, coupling)
    # the coarser u_h prolongated body by body (displacements, not openings), in z: S^{-1} of it
    # (E is not: it keeps the slave's trace)
    start = None if carry is None else qp.to_z(p1_injected(problem, multilevel.prolongated(carry.p1)))
    return K_ngs, MultigridSystem(K_ngs, qp.b, hierarchy, SparseEdges(E), options=options), start


def _general(problem: TwoBodyProblem, coupling, predicted, options):
    """The rows B z >= g as general constraints, each divided by its weight D_i = int psi_i (the
    same feasible set; row i in units of the opening). Row equilibration: undivided, a row's
    entries scale with its slave edges' length h_i, and on graded or adaptive meshes (h_i down
    to 1e-6) its part of the saddle system's Schur complement fell far below the regularisation
    d of ``solvers.general_constraints.SaddleSystem`` (relative to K's diagonal): the iterative
    refinement stalled at KKT residuals of 1e-7 (two-body-junction, mortar-standard, 1.4e4 dofs;
    divided: 1e-15)."""
    qp = joint_qp(problem)
    scale = sp.diags(1.0 / coupling.D)
    return GeneralConstraintSolver(qp.K, qp.b, qp.free, (scale @ coupling.B).tocsr(), coupling.g / coupling.D, lift=qp.lift,
                                   options=options).solve(predicted)


def max_penetration(case, problem: TwoBodyProblem, z: np.ndarray) -> float:
    """max over Gamma_C of (2 obstacle - opening): positive where the bodies interpenetrate
    (between the slave's nodes a weak condition allows it), sampled on every intersection segment."""
    x, values = opening(problem, z)
    if case.obstacle is None:
        return float((-values).max())
    gap = problem.upper.values_at(case.obstacle, np.stack([x, np.zeros_like(x)], axis=-1))
    return float((2.0 * gap - values).max())


# `mortar-mean`: two bodies, P2 on each; `mean`'s K_h on the dual mortar projection Pi of the
# jump onto the upper body's P2 trace: Pi [u_h] >= 2 alpha at the slave's vertices of Gamma_C and
# its mean over every slave edge >= that of 2 alpha (``fem.mortar``, edge_functional "edge-mean").
# On matching meshes it is `mean`'s K_h on the jump. Expected: the one-body rate min(nu - 1, 2)
# (``one_body_rate``).
mortar_mean = Mortar(
    name="mortar-mean",
    order=2,
    contact="Π[u_h] >= 0 at the slave's vertices, ∫ Π[u_h] >= 0 on its edges (Π: dual mortar projection; two bodies)",
    reference="Belhachmi & Ben Belgacem 2003 (K_h) on Wohlmuth's dual mortar projection",
    expected=partial(one_body_rate, order=2),
    multipliers="dual",
    friction=("frictionless", "tresca"),
    edge_functional="edge-mean",
)

# `mortar-nodal`: two bodies, P2 on each, the opening of the interface held weakly against the
# dual (biorthogonal) quadratic multipliers of the upper body's trace (Wohlmuth 2000; for contact
# Hueeber & Wohlmuth 2005): int psi_i [u_h] >= int psi_i 2 alpha at every vertex and edge midpoint
# of the slave's Gamma_C (``fem.mortar``). On matching meshes it is `nodal`'s K~_h on the jump.
# Expected: the one-body rate min(nu - 1, 2) (``one_body_rate``).
mortar_nodal = Mortar(
    name="mortar-nodal",
    order=2,
    contact="∫ ψ_i [u_h] >= 0 for the dual quadratic multipliers ψ_i of the slave's nodes (two bodies)",
    reference="Wohlmuth 2000; Hüeber & Wohlmuth 2005; Hild & Laborde 2002 (quadratic mortar)",
    expected=partial(one_body_rate, order=2),
    multipliers="dual",
    friction=("frictionless", "tresca", "coulomb"),
    roles=frozenset({REFERENCE, MESH_STUDY}),     # of the two-body cases (and their picture)
)

# `mortar-standard`: two bodies, P2 on each, the opening held weakly against the continuous
# piecewise quadratic multipliers of the upper body's trace -- its own Lagrange basis, the
# multiplier space of Hild & Laborde, Appl. Numer. Math. 41 (2002), with their nodal condition
# int phi_i ([u_h] - 2 alpha) >= 0 for every slave node i (``fem.mortar``). The rows couple
# neighbouring nodes: no local change of variables makes them bounds, so they are solved as general
# constraints (``solvers.general_constraints``, the saddle system by SuperLU). Expected: the
# one-body rate min(nu - 1, 2) (``one_body_rate``).
mortar_standard = Mortar(
    name="mortar-standard",
    order=2,
    contact="∫ φ_i [u_h] >= 0 for the slave's own quadratic basis φ_i (continuous multipliers; two bodies)",
    reference="Hild & Laborde 2002 (continuous quadratic multipliers)",
    expected=partial(one_body_rate, order=2),
    multipliers="standard",
)

# `mortar-p1`: two bodies, P1 on each, the opening held weakly against the dual (biorthogonal)
# linear multipliers of the upper body's trace: int psi_i [u_h] >= int psi_i 2 alpha at every
# slave vertex of Gamma_C (Wohlmuth 2000; Hueeber & Wohlmuth 2005; the mortar P1 contact method of
# Ben Belgacem, Hild & Laborde 1999 with standard multipliers). On matching meshes it is `p1` on
# the jump. Expected: min(nu - 1, 1) (``one_body_rate``).
mortar_p1 = Mortar(
    name="mortar-p1",
    order=1,
    contact="∫ ψ_i [u_h] >= 0 for the dual linear multipliers ψ_i of the slave's vertices (two bodies)",
    reference="Ben Belgacem, Hild & Laborde 1999; Wohlmuth 2000",
    expected=partial(one_body_rate, order=1),
    multipliers="dual",
    friction=("frictionless", "tresca", "coulomb"),
    roles=frozenset({MESH_STUDY}),
)

# the family's variants (``registry``)
methods = [mortar_mean, mortar_nodal, mortar_standard, mortar_p1]
