"""What a discretisation ("method") is to the harness, and the family the paper's models and
the P1 baseline belong to.

A method declares its finite element order, how it imposes the contact condition, the paper
or theorem it comes from, and, for a case of regularity nu, the H^1 rate its theory predicts
(``expected``). It solves one level of a study (``solve``) and returns what the study's rows,
the next level (nested iteration) and the report need (``LevelSolve``).
"""
from __future__ import annotations

import math
from collections.abc import Mapping
from contextlib import nullcontext
from dataclasses import dataclass, field, fields, replace
from typing import Callable

import numpy as np

from ..fem.cones import ContactModel, contact_pressure, contact_qp
from ..fem.edge_functionals import check_rules, edge_functional_qp
from ..fem.face_means import face_mean_qp
from ..fem.penetration import max_penetration
from ..solvers.active_set import solve_contact_qp
from ..solvers.general_constraints import GeneralConstraintSolver
from ..solvers.multigrid import ContactEdges, nested_start, p1_values
from ..solvers.options import SolverOptions
from ..solvers.projected import ProjectedMultigridSystem

# The levels each order runs past a study's P2 levels, so that every method ends at about the
# same number of dofs: P_k on a triangle mesh has about k^2 dofs per vertex, and a uniform
# level four times the vertices of the one before. P1 on level l + 1 has about the dofs of P2 on
# level l, and P4 on level l - 1; P3 stays on P2's levels (its last level 9/4 of P2's dofs, one
# level fewer would be 9/16).
EXTRA_LEVELS = {1: 1, 2: 0, 3: 0, 4: -1}

# What a method may be to the report (``Method.roles``; ``methods.with_role``): the harness names
# no method outside ``methods/``, it asks for the methods that declare a role, so that a method
# of your own can take any of them.
PAPER = "paper"            # the paper's P2 models: compared side by side in the prose and headline tables
BASELINE = "baseline"      # the P1 baseline of the cost at equal accuracy (efficiency) and of P2's verdicts
REFERENCE = "reference"    # computes the reference solution of a case without a closed form (the first
                           # that discretises the case); its solution is the case's picture
SWEPT = "swept"            # the report sweeps its first parameter (each theta, if it has one)
MESH_STUDY = "mesh-study"  # the report also runs it on graded and adaptive meshes (the fine profile
                           # adds the PAPER, BASELINE and SWEPT methods)
DEGREES = "degrees"        # the report's degree study: one of a family (Nitsche, the nodal cone) at each degree k
ROLES = (PAPER, BASELINE, REFERENCE, SWEPT, MESH_STUDY, DEGREES)


@dataclass(frozen=True)
class Expectation:
    """The H^1 bound C h^rate ``|log h|^log_exponent`` a theory predicts, and which theory."""

    rate: float
    log_exponent: float
    reference: str


@dataclass(frozen=True)
class SolveFields(Mapping):
    """The solver columns a level's solve gives its row (docs/guide/results.md), read as a
    mapping too (``fields["status"]``, ``{**fields}``)."""

    max_penetration: float          # the largest penetration of u_h between the nodes of Gamma_C
    min_pressure: float             # the smallest discrete contact pressure (an edge's mean)
    kkt_residual: float             # relative KKT or Newton residual (<= 1e-10: converged)
    status: str                     # "converged", or why not
    solver_iterations: int = 0      # active sets or Newton steps
    linear_iterations: int | None = 0   # CG iterations (multigrid) or factorisations
    active_constraints: int = 0
    n_contact_constraints: int = 0
    backward_error: float = math.nan    # the normwise backward error of the stationarity
    solve_seconds: float = 0.0

    def __getitem__(self, name: str):
        if name not in self._names():
            raise KeyError(name)
        return getattr(self, name)

    def __iter__(self):
        return iter(self._names())

    def __len__(self) -> int:
        return len(self._names())

    @classmethod
    def _names(cls) -> tuple[str, ...]:
        return tuple(f.name for f in fields(cls))

    @classmethod
    def of_exact(cls, solution, max_penetration: float, pressure: np.ndarray, rows: int) -> "SolveFields":
        """The fields of a QP solved exactly (``solvers.active_set.QPSolution`` or
        ``solvers.general_constraints.GeneralQPSolution``) with ``rows`` constraints."""
        return cls(max_penetration=max_penetration, min_pressure=float(pressure.min()), kkt_residual=solution.kkt.residual,
                   status=solution.status, solver_iterations=solution.iterations,
                   linear_iterations=solution.work.get("cg_iterations", solution.work.get("factorizations")),
                   active_constraints=int(solution.active.sum()), n_contact_constraints=rows,
                   backward_error=solution.kkt.backward, solve_seconds=solution.seconds)


@dataclass(frozen=True)
class Carry:
    """What a level's solve hands the next, finer level (nested iteration): u_h's values at the
    vertices (``p1``: the multigrid's start, prolongated) and what predicts the next active set:
    the trace of u_h with its constraints' status (the cones: ``trace``) or the contact points
    with their branch (contact laws and mortars: ``points``, ``active``; a mortar's first
    ``vertex_rows`` points are its vertex rows, the rest its edge rows)."""

    p1: np.ndarray
    trace: object = None            # fem.assembly.ContactTraceFunction
    points: np.ndarray | None = None
    active: np.ndarray | None = None
    vertex_rows: int | None = None


@dataclass
class LevelSolve:
    """One method on one level: the row's solver fields, u_h (NGSolve numbering of its space),
    its trace on Gamma_C, its discrete contact pressure (mean over each contact edge, in the
    order of ``fem.assembly.DiscreteProblem.trace``), and what the next level starts from."""

    fields: SolveFields
    u: np.ndarray
    trace_u: object
    pressure: np.ndarray
    carry: Carry | None


def timer(phases):
    """``phases`` (``study.rows.Phases``: ``with phases("setup"): ...`` times a phase of the level),
    or, when the solve is not timed, a timer that times nothing."""
    return phases or (lambda phase: nullcontext())


@dataclass(frozen=True)
class Method:
    """A discretisation as the harness measures it: its ``name`` (a CSV cell and a command-line
    word), finite element ``order``, the contact condition in words (``contact``), where it comes
    from (``reference``), the rate its theory predicts for a case (``expected``: case ->
    ``Expectation``, or None: no theory), the physics, dimensions and bodies it discretises, its
    roles (``PAPER``, ``BASELINE``, ``REFERENCE``, ``SWEPT``, ``MESH_STUDY``), its cost model and
    its solver settings (``solvers.options.SolverOptions``). Subclasses solve a level (``solve``): a
    cone (``BoundConstrained``, ``FunctionalCone``), a weak method given by its contact law
    (``protocol.ContactLawMethod``) or a solve of its own (``protocol.OwnSolve``)."""

    name: str
    order: int
    contact: str                                  # how the contact condition is imposed
    reference: str                                # where the method comes from
    expected: Callable[[object], Expectation]     # case -> the rate its theory predicts
    # case -> the rate of a second, later theory (a second verdict), or None
    sharper_theory: Callable[[object], Expectation] | None = None
    physics: tuple = ("scalar",)                  # the physics it discretises (``harness.physics``)
    dimensions: tuple = (2,)                      # the space dimensions it discretises
    bodies: tuple = (1,)                          # the number of bodies it couples (``Case.bodies``)
    # its levels past a study's P2 levels, if not ``EXTRA_LEVELS`` (``with_extra_levels``)
    study_extra_levels: int | None = None
    # what it is to the report (``ROLES``: PAPER, BASELINE, REFERENCE, SWEPT, MESH_STUDY)
    roles: frozenset = frozenset()
    # (name, roles) as declared: a variant that ``dataclasses.replace`` or ``with_parameters``
    # renames keeps none of the roles it copied (``__post_init__``), so that no variant joins the
    # report's sweeps and studies unasked; roles given with it, or by ``with_roles``, it keeps
    roles_of: tuple | None = field(default=None, repr=False, compare=False)
    # how its solve's time is estimated (``study.budget``): "active-set" (an exact QP solve by an
    # active set method), "newton" (semismooth Newton), or a number, its seconds per dof
    cost_model: str | float = "active-set"
    # the file that defines a method from outside the package (``plugins``): what its
    # checkpoints and cached results depend on besides the harness's code
    source: str | None = field(default=None, compare=False)
    # the solvers' tolerances, loose-solve gains and iteration caps (``solvers.options``)
    solver: SolverOptions = field(default=SolverOptions(), compare=True)

    def __post_init__(self):
        roles = frozenset(self.roles)
        if self.roles_of is not None and self.roles_of[0] != self.name and roles == self.roles_of[1]:
            roles = frozenset()             # copied under another name
        object.__setattr__(self, "roles", roles)
        object.__setattr__(self, "roles_of", (self.name, roles))

    def with_roles(self, *roles: str) -> "Method":
        """The same method declaring ``roles`` (``ROLES``), and only those."""
        unknown = set(roles) - set(ROLES)
        if unknown:
            raise ValueError(f"unknown role(s) {', '.join(sorted(unknown))}; the roles are {', '.join(ROLES)}")
        return replace(self, roles=frozenset(roles), roles_of=(self.name, frozenset(roles)))

    def supports(self, case) -> bool:
        """Does it discretise ``case``'s physics, dimension and bodies? Order k >= 3 needs an exact
        solution too: a reference solution is nodal P2 (``measure.reference``), into whose space
        a P_k function does not embed."""
        if self.order > 2 and not case.exact:
            return False
        return case.physics.name in self.physics and case.dimension in self.dimensions and case.bodies in self.bodies

    def sharper(self, case) -> Expectation | None:
        return None if self.sharper_theory is None else self.sharper_theory(case)

    @property
    def variable_degree(self) -> bool:
        """Whether it discretises a space whose degree varies from element to element (hp
        meshes, ``mesh.hp``): a contact law (its terms are integrals of each edge's own degree),
        a cone whose functionals are given per degree; not the paper's cones, written for P1 and
        P2."""
        return False

    @property
    def extra_levels(self) -> int:
        """The levels it runs past a study's P2 levels: ``EXTRA_LEVELS`` of its order, unless a
        study said otherwise (``with_extra_levels``)."""
        return EXTRA_LEVELS[self.order] if self.study_extra_levels is None else self.study_extra_levels

    def with_extra_levels(self, extra: int) -> "Method":
        """The same method run ``extra`` levels past a study's P2 levels (the default report's
        P1 on a case whose P1 fits are asymptotic without P2's finest dofs:
        ``Case.asymptotic_levels_p1``)."""
        return replace(self, study_extra_levels=int(extra))

    @property
    def parameters(self) -> dict:
        """The method's parameters, by name (none for the cones)."""
        return {}

    @property
    def parameter_text(self) -> str:
        return " ".join(f"{name}={_number(value)}" for name, value in self.parameters.items())

    def with_parameters(self, **values) -> "Method":
        raise ValueError(f"method {self.name!r} has no parameters")

    def solve(self, case, problem, carry, multilevel, take_stiffness: bool = False, phases=None) -> LevelSolve:
        """Solve on ``problem`` (a ``fem.assembly.DiscreteProblem`` of this method's order) from
        ``carry`` (what the coarser level's solve left, or None), on ``multilevel``'s hierarchy.
        ``take_stiffness``: this is the level's last method of its order and may take the
        stiffness matrix's memory. ``phases`` (``study.rows.Phases``) times set-up and solve."""
        raise NotImplementedError


@dataclass(frozen=True)
class BoundConstrained(Method):
    """A cone of nodal functionals (``fem.cones.ContactModel``), solved exactly (KKT <= 1e-10) by
    the active set method with the truncated multigrid; nested iteration carries the coarser
    level's trace (active set prediction) and vertex values (CG start) to the next level."""

    cone: ContactModel = ContactModel()
    # a cone of the contact variable: u_h, or -u_h . n in the rotated frame (Remark 2.3)
    physics: tuple = ("scalar", "elasticity")
    # in 3D the same cones, edge by edge on the triangles of Gamma_C (``models``)
    dimensions: tuple = (2, 3)

    def solve(self, case, problem, carry, multilevel, take_stiffness: bool = False, phases=None) -> LevelSolve:
        timed = timer(phases)
        with timed("setup"):
            qp = contact_qp(case, problem, self.cone, take_stiffness=take_stiffness)
            start = None
            if multilevel is not None and carry is not None:
                start = nested_start(multilevel, carry.p1, problem)
            predicted = qp.predicted_active(None if carry is None else carry.trace)
        with timed("solve"):
            solution = solve_contact_qp(qp, predicted, multilevel=multilevel, start=start, options=self.solver)
        u = qp.to_u(solution.z)
        trace_u = qp.trace_function(u, solution.active)
        return _exact_level(case, problem, u, trace_u, contact_pressure(problem, solution.multipliers), solution)


def _exact_level(case, problem, u, trace_u, pressure, solution) -> LevelSolve:
    """The row of a level solved exactly (a bound or general-constraint QP's ``solution``)."""
    fields = SolveFields.of_exact(solution, max_penetration(case, problem.mesh, trace_u), pressure, len(solution.active))
    return LevelSolve(fields, u, trace_u, pressure, Carry(p1_values(problem, u), trace=trace_u))


@dataclass(frozen=True)
class CellMean(BoundConstrained):
    """The paper's K_h on the cells of Gamma_C: v_h >= alpha at its vertices and the mean of
    v_h - alpha >= 0 over each cell. In 2D a cell is an edge and the cone is bounds after a
    local change of variables (``cones``, the ``BoundConstrained`` path); in 3D a cell is a
    triangle, whose P2 mean is the average of its three edge-midpoint values, and the rows
    stay general (``face_means``): solved by the general-constraint active set method with the
    constrained multigrid (``solvers.projected``), or by SuperLU without a hierarchy."""

    def solve(self, case, problem, carry, multilevel, take_stiffness: bool = False, phases=None) -> LevelSolve:
        if problem.trace.faces is None:
            return super().solve(case, problem, carry, multilevel, take_stiffness, phases)
        return solve_general_rows(case, problem, carry, multilevel, phases,
                                  lambda: face_mean_qp(case, problem, take_stiffness=take_stiffness), self.solver)


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
        start = None
        if multilevel is not None and carry is not None:
            start = nested_start(multilevel, carry.p1, problem, embedding)
        predicted = qp.predicted_active(None if carry is None else carry.trace)
    with timed("solve"):
        system = None if multilevel is None else ProjectedMultigridSystem(qp.K_ngs, multilevel, embedding, options)
        solution = GeneralConstraintSolver(qp.K, qp.b, qp.free, qp.B, qp.g, lift=qp.lift, system=system,
                                           options=options).solve(predicted, start)
    trace_u = qp.trace_function(solution.z, solution.active)
    return _exact_level(case, problem, solution.z, trace_u, qp.pressure(solution.multipliers), solution)


@dataclass(frozen=True)
class FunctionalCone(Method):
    """A cone given only by its constraint functionals on the contact edges (2D;
    ``fem.edge_functionals``): v_h >= alpha at the vertices of Gamma_C and, on every contact
    edge, each rule ((t, w), ...) of ``functionals`` applied to v_h - alpha >= 0 (t in [0, 1]
    along the edge). Solved exactly (KKT residual <= 1e-10) by the general-constraint active set
    method with the projected multigrid, nested from level to level, as the 3D ``mean``. The
    paper's ``nodal`` is ``functionals=(((0.5, 1.0),),)``; "v_h >= alpha at the points 1/4 and
    3/4 of each edge" is ``(((0.25, 1.0),), ((0.75, 1.0),))``. Known limit: where Gamma_C is
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
        # two or more functionals per edge: with both ends active, an edge's rows outnumber its
        # three trace variables, the active rows are linearly dependent, and the projected CG
        # (``solvers.projection``) stalls (oscillating-r34 with the quarter points);
        # SuperLU's saddle solve takes dependent rows (KKT 1e-16 on the same levels)
        # (on P_k, k - 1 functionals per edge are independent rows: the projected CG serves them)
        hierarchy = multilevel if len(self.functionals) <= max(problem.order - 1, 1) else None
        return solve_general_rows(case, problem, carry, hierarchy, phases,
                                  lambda: edge_functional_qp(case, problem, self.functionals_of or self.functionals,
                                                             take_stiffness=take_stiffness),
                                  self.solver)


def _number(value: float) -> str:
    return f"{value:g}"


def paper_theorem(case) -> Expectation:
    """The rate the case declares from the paper's theorems (Theorems 4.1, 4.2, 5.1, 5.2,
    Remark 4.9): the same for both P2 models."""
    return Expectation(case.expected_rate, case.expected_log_exponent,
                       f"Belhachmi & Ben Belgacem 2003, {_theorem_label(case.theorem)}")


def _theorem_label(theorem: str) -> str:
    return theorem if theorem.lower().startswith(("remark", "thm", "theorem", "section")) else f"Thm {theorem}"


DROUET_HILD = "Drouet & Hild 2015 (SINUM 53)"
# The highest rate Drouet & Hild's optimal estimate gives P_k: u in H^{3/2 + m} with m below
# 1/2 (P1) and below 1 (P2: the Signorini solution is at most H^{5/2 - eps} near a transition).
DROUET_HILD_CAP = {1: 1.0, 2: 1.5}


def drouet_hild_for(order: int):
    """The H^1 bound of G. Drouet and P. Hild, SIAM J. Numer. Anal. 53 (2015) 1488-1507, for P_k
    (abstract: "optimal H^1-error estimates with the only standard Sobolev regularity", P1 and
    P2, 2D and 3D, no assumption on the contact set, O(h) for P1 with H^2 alone): h^{nu - 1} for
    3/2 < nu, up to DROUET_HILD_CAP[k], with no log factor. Only the abstract was read, not
    the theorems' text: the ranges are read from "optimal" (the best approximation's rate) and
    the H^{3/2 + m}, m > 0, of the whole literature, not checked against their statements. For
    nu <= 3/2 it says nothing (NaN)."""
    def drouet_hild(case) -> Expectation:
        if case.nu <= 1.5:
            return Expectation(float("nan"), 0.0, f"{DROUET_HILD}: no result for nu <= 3/2")
        return Expectation(min(case.nu - 1.0, DROUET_HILD_CAP[order]), 0.0, DROUET_HILD)
    return drouet_hild
