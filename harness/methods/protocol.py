"""The method protocol, its three levels: a method of your own that the harness measures as it
measures its own (rows, errors, rates, verdicts, cost, report), without touching its
internals. Pick the level that fits what you bring:

1. a **cone** given only by its constraint functionals on Gamma_C: ``FunctionalCone`` below,
   solved exactly by the harness's active set method with its multigrid (2D; scalar and
   elastic);
2. a **weak method** given by its contact law on Gamma_C (a pressure term and a flux term, and
   their derivative): ``ContactLawMethod`` below, solved by the harness's semismooth Newton
   method, its residual recorded (``fem.contact_laws.protocol`` has the law's protocol and checks);
3. a **solve of your own**: ``OwnSolve`` below; the harness hands you the level
   (``LevelProblem``: stiffness, load, free dofs, Gamma_C's quadrature, the coarser level's
   solution interpolated, the multigrid hierarchy) and takes back ``OwnSolution`` (u_h, your
   residual, iterations, status, optionally your pressure); it checks feasibility (the largest
   penetration of the row) and records your residual in the row's ``kkt_residual``.

Levels 2 and 3 run in every physics and dimension by default (``physics=("scalar",
"elasticity")``, ``dimensions=(2, 3)``, one body); a method that does not declares what it
discretises, and a study leaves it out of the cases it does not fit, saying why
(``registry.left_out``).

Each declares its expected rate (``expected``: case -> ``Expectation``) or None: "no theory",
grey in the verdict matrix. ``examples/methods/`` has one method at each level.
"""
from __future__ import annotations

import time
from dataclasses import dataclass, fields, is_dataclass, replace
from functools import partial
from typing import Callable

import numpy as np
import scipy.sparse as sp

from ..fem.assembly import ContactTraceFunction
from ..fem.cones import contact_pressure, end_status
from ..fem.contact_laws.channels import friction_system
from ..fem.contact_laws.friction_laws import law_for
from ..fem.contact_laws.system import contact_data, law_system
from ..fem.contact_laws.two_body import joint_load_step, two_body_system
from ..fem.contact_quadrature import ContactNodes, contact_quadrature, lagrange_nodes
from ..fem.edge_functionals import check_rules, edge_functional_qp
from ..fem.friction import rules_friction_qp
from ..fem.nested import friction_prediction, nearest_status, nested_start, p1_values, start_from
from ..fem.p1_embedding import ContactEdges
from ..fem.penetration import max_penetration
from ..solvers.friction import solve_friction_qp
from ..solvers.general_constraints import GeneralConstraintSolver
from ..solvers.load_steps import previous_state, solve_history
from ..solvers.options import SolverOptions
from ..solvers.projected_multigrid import ProjectedMultigridSystem
from ..solvers.two_body_multigrid import p1_injected
from .method import Carry, ConeCarry, LawCarry, LevelSolve, Method, SolveFields, timer
from .mortar import joint_p1_values
from .mortar import max_penetration as pair_penetration

# Level 1: a cone given by its functionals


def exact_level(case, problem, u, trace_u, pressure, solution) -> LevelSolve:
    """The row of a level solved exactly (a bound or general-constraint QP's ``solution``)."""
    fields = SolveFields.of_exact(solution, max_penetration(case, problem.mesh, trace_u), pressure, len(solution.active))
    return LevelSolve(fields, u, trace_u, pressure, ConeCarry(p1_values(problem, u), trace=trace_u))


def solve_general_rows(case, problem, carry, multilevel, phases, make_qp,
                       options: SolverOptions = SolverOptions()) -> LevelSolve:
    """A level of a cone of general rows B u >= g (``make_qp()``: a ``FaceMeanQP`` or an
    ``EdgeFunctionalQP``), solved exactly by the general-constraint active set method, by
    projected multigrid CG on ``multilevel``'s hierarchy (else SuperLU's factorised saddle
    system), nested from ``carry``."""
    timed = timer(phases)
    embedding = ContactEdges.of(problem, model=False)
    with timed("setup"):
        qp = make_qp()
        start = start_from(carry, multilevel, problem, model=False)
        predicted = qp.predicted_active(None if carry is None else carry.trace)
    with timed("solve"):
        system = None if multilevel is None else ProjectedMultigridSystem(qp.K_ngs, multilevel, embedding, options)
        solution = GeneralConstraintSolver(qp.K, qp.b, qp.free, qp.B, qp.g, lift=qp.lift, system=system,
                                           options=options).solve(predicted, start)
    trace_u = qp.trace_function(solution.z, solution.active)
    return exact_level(case, problem, solution.z, trace_u, qp.pressure(solution.multipliers), solution)


def solve_tresca(case, problem, make_qp, carry, multilevel, phases, options) -> LevelSolve:
    """A level of a Tresca case (``problem.friction``) with the cone's quadrature of j(v)
    (``make_qp()``, a ``fem.friction.FrictionQP``: the nodal or mean analogue, P1, or the P_k
    functionals of a ``protocol.FunctionalCone``), solved exactly by the active set
    method on the bound-constrained dual (``solvers.friction``), nested from ``carry``. The row's
    pressure is the discrete flux on Gamma_C, as for the cones (scalar: the friction force
    d_n u_h - g_C in [-s, s] itself; elasticity: the normal reaction of the bilateral contact); its penetration is NaN in the scalar model, which
    has no unilateral condition."""
    timed = timer(phases)
    with timed("setup"):
        qp = make_qp()
        start = None if carry is None or multilevel is None else nested_start(multilevel, carry.p1, problem, qp.edges)
        predicted = friction_prediction(carry, qp.points)
    with timed("solve"):
        solution = solve_friction_qp(qp, predicted, multilevel=multilevel, start=start, options=options)
    u = qp.to_u(solution.z)
    m = len(qp.F)
    stick = ~(solution.active[:m] | solution.active[m:])
    nv = len(problem.vertex_dofs)
    # an edge sticks when all its variables do (P1: when both its ends do, as for the cones)
    edge_stick = np.bincount(qp.edge_of_row, weights=~stick[nv:], minlength=len(problem.trace.edges)) == 0
    if not len(qp.edge_of_row):
        edge_stick = end_status(problem, stick[:nv]).all(axis=1)
    trace_u = ContactTraceFunction.of(problem, u, end_status(problem, stick[:nv]), edge_stick)
    if problem.physics.rotated_frame:
        pressure, penetration = contact_pressure(problem, qp.normal_reaction(u)), max_penetration(case, problem.mesh, trace_u)
    else:
        # the flux d_n u_h - g_C (the case's friction force, ``problem.friction``): the solver's
        # lambda = b - K z is its opposite
        pressure, penetration = contact_pressure(problem, -solution.multipliers), float("nan")
    fields = SolveFields.of_exact(solution, penetration, pressure, 2 * m)
    return LevelSolve(fields, u, trace_u, pressure, LawCarry(p1_values(problem, u), points=qp.points, active=solution.active))


@dataclass(frozen=True)
class FunctionalCone(Method):
    """A cone given only by its constraint functionals on the contact edges (2D;
    ``fem.edge_functionals``): v_h >= alpha at the vertices of Gamma_C and, on every contact
    edge, each rule ((t, w), ...) of ``functionals`` applied to v_h - alpha >= 0 (t in [0, 1]
    along the edge). Solved exactly (KKT residual <= 1e-10) by the general-constraint active set
    method with the projected multigrid, nested from level to level, as the 3D ``mean``. The
    paper's ``nodal`` is ``functionals=(((0.5, 1.0),),)``; "v_h >= alpha at the points 1/4 and
    3/4 of each edge" is ``(((0.25, 1.0),), ((0.75, 1.0),))``. On a Tresca case (if it declares
    ``friction=("frictionless", "tresca")``) with k - 1 functionals per edge of degree k, they are
    the friction variables of j_h (``fem.friction.rules_friction_qp``). Known limit: where Gamma_C is
    wholly in contact at a zero gap (elastic-wedge), the general-constraint solver's relative
    primal residual divides round-off by round-off and the rows read "stalled" though the
    solution is the paper cones' (tests/test_functional_cone.py, a strict xfail)."""

    functionals: tuple = ()
    physics: tuple = ("scalar", "elasticity")
    # the functionals of an edge of degree p, if they depend on it (a module-level function: a
    # method travels to worker processes by pickle): each edge of an hp mesh gets its own degree's
    # (``fem.edge_functionals.rules_per_edge``); ``functionals`` are then those of ``order``
    functionals_of: Callable[[int], tuple] | None = None

    def __post_init__(self):
        super().__post_init__()
        if self.functionals_of is not None and not self.functionals:
            object.__setattr__(self, "functionals", self.functionals_of(self.order))
        object.__setattr__(self, "functionals", check_rules(self.functionals))

    @property
    def variable_degree(self) -> bool:
        return self.functionals_of is not None

    def solve(self, case, problem, carry, multilevel, take_stiffness: bool = False, phases=None) -> LevelSolve:
        if case.frictional:
            return solve_tresca(case, problem, lambda: rules_friction_qp(case, problem, self.functionals_of or self.functionals),
                                carry, multilevel, phases, self.solver)
        # two or more functionals per edge: with both ends active, an edge's rows outnumber its
        # three trace variables, the active rows are linearly dependent, and the projected CG
        # (``solvers.row_projection``) stalls (oscillating-r34 with the quarter points);
        # SuperLU's saddle solve takes dependent rows (KKT 1e-16 on the same levels)
        # (on P_k, k - 1 functionals per edge are independent rows: the projected CG serves them)
        hierarchy = multilevel if len(self.functionals) <= max(problem.order - 1, 1) else None
        return solve_general_rows(case, problem, carry, hierarchy, phases,
                                  lambda: edge_functional_qp(case, problem, self.functionals_of or self.functionals,
                                                             take_stiffness=take_stiffness),
                                  self.solver)


# Level 2: a weak method given by its contact law




@dataclass(frozen=True)
class ContactLawMethod(Method):
    """A weak method given by its contact law (``fem.contact_laws.protocol.ContactLaw``; the built-in
    ``fem.contact_laws.builtin.Nitsche`` and ``fem.contact_laws.builtin.Penalty`` are such laws): F(u) = A u - b - int p c(v) +
    int f flux(v), in every physics (c and its flux: u and d_n u, or -u . n and -sigma_n(u)) and
    dimension, solved by semismooth Newton (nested iteration, multigrid CG when the law's
    Jacobian is symmetric and the case has a hierarchy, a factorisation else) to a relative
    residual <= 1e-10. The law's parameters, if it is a dataclass, are the method's
    (``nitsche:gamma0=0.1,theta=-1`` on the command line), checked by the law itself. A law with
    a field ``degree`` left None (``fem.contact_laws.builtin``) is told the method's order: the k its parameter
    is chosen for, which an hp mesh scales by (k / p)^2 in an element of degree p.

    Friction: on a case with a friction law (``problem.friction``) among the method's
    ``friction``, the law is replaced by its friction law (``fem.contact_laws.friction_laws.law_for``:
    the built-in Nitsche and penalty laws carry their parameters over; a law of your own gives
    ``for_friction``, or is itself a ``fem.contact_laws.protocol.FrictionLaw``), solved by the same Newton
    method on the channels of ``fem.contact_laws.channels``."""

    law: object = None
    physics: tuple = ("scalar", "elasticity")
    dimensions: tuple = (2, 3)
    cost_model: str | float = "newton"

    def system(self, case, problem, take_stiffness: bool = False):
        """The law's system on ``problem``; on a case with friction (``problem.friction``) the
        system of the friction law that carries the law's idea and parameters
        (``fem.contact_laws.friction_laws.law_for``): the method is the discretisation, the friction
        law the case's physics."""
        if case.frictional:
            return friction_system(case, problem, law_for(self.calibrated_law, case.friction), take_stiffness)
        return law_system(case, problem, self.calibrated_law, take_stiffness)

    @property
    def variable_degree(self) -> bool:
        return True

    @property
    def calibrated_law(self):
        """The law, told the method's order if it has a ``degree`` of its own to be told."""
        if is_dataclass(self.law) and "degree" in {f.name for f in fields(self.law)} and self.law.degree is None:
            return replace(self.law, degree=self.order)
        return self.law

    @property
    def parameters(self) -> dict:
        # the law's ``degree`` is the method's order, not a parameter (``calibrated_law``)
        return {f.name: getattr(self.law, f.name) for f in fields(self.law) if f.name != "degree"} \
            if is_dataclass(self.law) else {}

    def with_parameters(self, **values) -> "ContactLawMethod":
        """The same method with other parameter values, named by them (nitsche:gamma0=0.1,
        theta=-1). Another parameter value makes another method: it takes none of this one's
        roles (the report's sweeps and studies ask for roles)."""
        unknown = set(values) - set(self.parameters)
        if unknown:
            raise ValueError(f"method {self.name!r} has parameters {', '.join(self.parameters) or 'none'}, not {', '.join(sorted(unknown))}")
        try:
            law = replace(self.law, **{k: float(v) for k, v in values.items()})
        except (TypeError, ValueError) as error:
            raise ValueError(f"method {self.name!r}: {error}") from None
        label = ",".join(f"{name}={float(values[name]):g}" for name in self.parameters if name in values)
        base = self.name.split(":")[0]
        return replace(self, name=f"{base}:{label}" if label else base, law=law)

    def solve(self, case, problem, carry, multilevel, take_stiffness: bool = False, phases=None) -> LevelSolve:
        timed = timer(phases)
        with timed("setup"):
            system = self.system(case, problem, take_stiffness)
        with timed("solve"):
            # a load history's steps in order (``solvers.load_steps``), each nested from the
            # coarser level's same step; a static case is one step
            history = solve_history(case, system, lambda k, steps: step_guess(system, carry, multilevel, k, steps),
                                    multilevel, self.solver)
        trace_u = ContactTraceFunction.of(problem, history.final.u)
        # the scalar Tresca model has no unilateral condition: no penetration (as the cones')
        penetration = float("nan") if case.frictional and not problem.physics.rotated_frame else \
            max_penetration(case, problem.mesh, trace_u)
        return law_level(system, history, penetration, trace_u, partial(p1_values, problem))


def law_level(system, history, penetration: float, trace_u, vertex_values) -> LevelSolve:
    """The level's solve of a contact law: the row's fields from the load ``history`` on
    ``system`` (``solvers.load_steps.HistorySolution``), its pressure (edge means of the law's),
    and the carry of every load step (``vertex_values(u)``: u_h at the vertices; the branches at
    the Gauss points)."""
    solution = history.combined()
    u = solution.u
    pressure = system.quadrature.edge_means(system.pressure(u))
    fields = SolveFields(penetration, float(pressure.min()), solution.residual,
                         solution.status, solution.iterations, solution.linear_iterations,
                         active_constraints=int(np.count_nonzero(solution.active)), backward_error=solution.backward,
                         solve_seconds=solution.seconds, load_steps=len(history.steps))
    points = system.quadrature.points
    earlier = tuple(LawCarry(vertex_values(s.u), points=points, active=s.active) for s in history.steps[:-1])
    return LevelSolve(fields, u, trace_u, pressure,
                      LawCarry(vertex_values(u), points=points, active=solution.active, steps=earlier),
                      previous=history.steps[-2].u if len(history.steps) > 1 else None)


def step_guess(system, carry, multilevel, step: int, steps: list):
    """(start, predicted branch) of load step ``step``: nested from the coarser level's same step
    (``nested_guess``), or, on the first level, the previous step's state."""
    if carry is not None:
        same = carry if step == len(carry.steps) else carry.steps[step] if step < len(carry.steps) else None
        if same is not None:
            return nested_guess(system, same, multilevel)
    return previous_state(steps)


def nested_guess(system, carry, multilevel):
    """(start, predicted branch at the Gauss points) from the coarser level's ``carry``: its u_h
    interpolated, and the branch of its nearest Gauss points."""
    if carry is None:
        return None, None
    return (start_from(carry, multilevel, system.problem, model=False),
            nearest_status(carry.points, carry.active, system.quadrature.points))


# Level 2 between two bodies: the law on the jumps


@dataclass(frozen=True)
class TwoBodyLaw(ContactLawMethod):
    """A ``ContactLawMethod`` between two bodies on non-matching meshes: the one-body law's
    master-slave form on the jumps (``fem.contact_laws.two_body``), solved by the same
    semismooth Newton method on the joint system of both bodies, load step by load step, to a
    relative residual <= 1e-10; its law, parameters and friction as on one body. The Nitsche
    family's `mortar-nitsche` and `mortar-nitsche-p1` are such methods (``methods.nitsche``).

    The linear solves, as on one body (``solvers.newton``): on uniform pairs, which have a joint
    hierarchy, CG (GMRES for Coulomb's nonsymmetric Jacobian) preconditioned by a V-cycle whose
    finest level is the joint Jacobian and whose coarse levels are its Galerkin products, each
    body's own levels plus the law's coupling (``solvers.two_body_multigrid.law_hierarchy``); on
    graded and adaptive pairs a sparse factorisation of the joint Jacobian. Each load step starts
    from the coarser level's same step: its u_h prolongated body by body (a hierarchy's), the
    branches of its nearest points."""

    bodies: tuple = (2,)
    dimensions: tuple = (2,)

    def system(self, case, problem, take_stiffness: bool = False):
        """The law's system on the pair (``fem.contact_laws.two_body``); on a frictional case
        its friction law's (``fem.contact_laws.friction_laws.law_for``)."""
        law = law_for(self.calibrated_law, case.friction) if case.frictional else self.calibrated_law
        return two_body_system(case, problem, law)

    def refusal(self, case) -> str | None:
        """Also: Coulomb in elasticity only (its law needs the normal and the slip channels)."""
        if case.friction.name == "coulomb" and not case.physics.rotated_frame and case.friction.name in self.friction:
            return "Coulomb's law needs elasticity's normal and slip channels"
        return super().refusal(case)

    def solve(self, case, problem, carry, multilevel, take_stiffness: bool = False, phases=None) -> LevelSolve:
        timed = timer(phases)
        with timed("setup"):
            system = self.system(case, problem)
        with timed("solve"):
            history = solve_history(case, system, lambda k, steps: _step_guess(system, carry, multilevel, k, steps),
                                    multilevel, self.solver, at_step=joint_load_step)
        return law_level(system, history, pair_penetration(case, problem, history.final.u), None,
                         partial(joint_p1_values, problem))


def _step_guess(system, carry, multilevel, step: int, steps: list):
    """(start, predicted branch) of load step ``step``: from the coarser level's same step (its
    u_h prolongated body by body where the pair has a hierarchy, the branch of its nearest
    points), else the previous step's state (``methods.protocol.step_guess``, for two bodies)."""
    same = None
    if carry is not None:
        same = carry if step == len(carry.steps) else carry.steps[step] if step < len(carry.steps) else None
    if same is None:
        return previous_state(steps)
    pair = system.problem.pair
    start = None if multilevel is None else p1_injected(pair, multilevel.prolongated(same.p1))
    return start, nearest_status(same.points, same.active, system.quadrature.points)


# Level 3: a solve of your own


@dataclass(frozen=True)
class ContactPoints:
    """Gamma_C's Gauss points as a user's solve sees them, on the contact variable of the case's
    physics (as a contact law does, ``fem.contact_laws.protocol.GammaPoints``): ``T @ u`` is c(u_h) there
    (u_h, or -u_h . n in elasticity), ``N @ u`` its flux (d_n u_h, or -sigma_n(u_h)); the
    contact condition is T u >= gap, the pressure N u - load >= 0; ``weights`` integrate over
    Gamma_C. The same rows in 2D and 3D, P1 and P2."""

    x: np.ndarray               # (q, dim)
    weights: np.ndarray         # (q,)
    h: np.ndarray               # (q,) size of the point's cell
    cell: np.ndarray            # (q,) the point's contact cell
    T: sp.csr_matrix            # (q, ndof)
    N: sp.csr_matrix            # (q, ndof)
    gap: np.ndarray             # (q,) the obstacle: alpha, or -g (u . n <= g)
    load: np.ndarray            # (q,) g_C, or -g_n
    physics: str = "scalar"     # "scalar" or "elasticity"
    normals: np.ndarray | None = None   # (q, dim) the outward unit normal
    modulus: float = 1.0        # the flux's stiffness scale: 1, or lambda + 2 mu (``GammaPoints.modulus``)


@dataclass(frozen=True)
class LevelProblem:
    """One level, as a method with its own solve receives it. Vectors are over the level's
    dofs (NGSolve's numbering of the P_k space of ``order``; in elasticity its vector space, the
    dofs of Gamma_C's nodes in the rotated frame (t, c = -u . n), ``fem.rotated_frame``); u_h must
    equal ``lift`` where ``free`` is False (Gamma_u). Read-only: the harness's matrices are shared."""

    case: object                # the case (its ``gap``, ``nu``, ... if a solver wants them)
    A: sp.csr_matrix            # stiffness a(phi_j, phi_i), all dofs
    b: np.ndarray               # load L(phi_i)
    free: np.ndarray            # bool: dofs not on Gamma_u
    lift: np.ndarray            # Dirichlet values on Gamma_u, zero elsewhere
    vertex_dofs: np.ndarray     # the dofs of Gamma_C's vertices (u_h there is the trace's value)
    edge_dofs: np.ndarray       # the bubble dof of each contact edge (empty for P1)
    gap_at_vertices: np.ndarray  # the obstacle of the contact variable at Gamma_C's vertices (alpha, or -g)
    contact: ContactPoints
    start: np.ndarray | None    # the coarser level's u_h interpolated (nested iteration), or None
    hierarchy: object = None    # the multigrid hierarchy (``solvers.multigrid.Multilevel``), or None
    # Gamma_C's Lagrange nodes and the values of the contact variable there (``nodes.L @ u``):
    # ``edge_dofs`` are NGSolve's hierarchical bubble coefficients, not values at nodes
    nodes: ContactNodes | None = None

    @property
    def ndof(self) -> int:
        return len(self.b)


@dataclass
class OwnSolution:
    """What a method's own solve gives back. ``residual``: its own measure of how well u solves
    its discrete problem, relative (the row's ``kkt_residual``); ``pressure``: its contact
    pressure at ``LevelProblem.contact`` (``ContactPoints.x``) if it has one (else the harness takes the discrete contact force
    a(u_h, phi_i) - L(phi_i) of Gamma_C's vertex hats)."""

    u: np.ndarray
    residual: float
    iterations: int = 0
    status: str = "converged"
    pressure: np.ndarray | None = None


@dataclass(frozen=True)
class OwnSolve(Method):
    """A method with its own solve: ``solve_level(level: LevelProblem) -> OwnSolution``, in
    every physics and dimension (``LevelProblem`` holds the contact variable of either physics),
    one body; declare fewer (``physics``, ``dimensions``) if yours does not."""

    solve_level: Callable | None = None
    physics: tuple = ("scalar", "elasticity")
    dimensions: tuple = (2, 3)

    def solve(self, case, problem, carry, multilevel, take_stiffness: bool = False, phases=None) -> LevelSolve:
        timed = timer(phases)
        with timed("setup"):
            level = level_problem(case, problem, carry, multilevel)
        with timed("solve"):
            clock = time.perf_counter()
            solution = self.solve_level(level)
            seconds = time.perf_counter() - clock
        u = checked_solution(self.name, solution, level)
        trace_u = ContactTraceFunction.of(problem, u)
        if solution.pressure is not None:
            pressure = contact_quadrature(problem).edge_means(np.asarray(solution.pressure, float))
        else:
            pressure = vertex_force_pressure(problem, u)
        fields = SolveFields(max_penetration(case, problem.mesh, trace_u), float(pressure.min()), float(solution.residual),
                             str(solution.status), int(solution.iterations), solve_seconds=seconds)
        return LevelSolve(fields, u, trace_u, pressure, Carry(p1_values(problem, u)))


def vertex_force_pressure(problem, u: np.ndarray) -> np.ndarray:
    """The discrete contact pressure of a solve that gives none: the contact force a(u_h, phi_i) -
    L(phi_i) of Gamma_C's vertex hats, per contact edge (``fem.cones.contact_pressure``)."""
    force = np.concatenate([problem.contact_residual(u)[:len(problem.vertex_dofs)], np.zeros(len(problem.edge_dofs))])
    return contact_pressure(problem, force)


def level_problem(case, problem, carry, multilevel) -> LevelProblem:
    """The level as ``OwnSolve`` hands it over, with the coarser level's u_h interpolated."""
    quadrature = contact_quadrature(problem)
    contact = ContactPoints(quadrature.points, quadrature.weights, quadrature.h, quadrature.edge, quadrature.T,
                            quadrature.N, *contact_data(case, problem, quadrature), problem.physics.name, quadrature.normals,
                            problem.physics.modulus)
    start = start_from(carry, multilevel, problem, model=False)
    gap = np.zeros(len(problem.vertex_dofs))
    if case.gap is not None:
        gap = problem.physics.obstacle(problem.values_at(case.gap, problem.trace.vertex_points))
    return LevelProblem(case, problem.A, problem.b, problem.free, problem.lift, problem.vertex_dofs, problem.edge_dofs, gap,
                        contact, start, multilevel, lagrange_nodes(problem))


def checked_solution(name: str, solution, level: LevelProblem) -> np.ndarray:
    """u_h of a user's ``OwnSolution``: a finite vector of the level's dofs, with the Dirichlet
    values on Gamma_u; a one-line ValueError naming the method else."""
    if not isinstance(solution, OwnSolution):
        raise ValueError(f"method {name!r}: its solver returned {type(solution).__name__}, not an OwnSolution")
    u = np.asarray(solution.u, float)
    if u.shape != (level.ndof,) or not np.all(np.isfinite(u)):
        raise ValueError(f"method {name!r}: u has shape {u.shape} or non-finite values; the level has {level.ndof} dofs")
    pinned = ~level.free
    if not np.allclose(u[pinned], level.lift[pinned], rtol=1e-12, atol=1e-12 * max(np.abs(level.lift).max(initial=0.0), 1.0)):
        raise ValueError(f"method {name!r}: u does not take the Dirichlet values on Gamma_u (level.lift where not level.free)")
    return u
