"""What a discretisation ("method") is to the harness: the ``Method`` record (its identity and
theory, where it applies, how it is scheduled, its roles), the rate its theory predicts
(``Expectation``), and what one level's solve gives back (``LevelSolve``: the row's
``SolveFields``, u_h, and the ``Carry`` the next level starts from). How a method solves is the
protocol's (``protocol``: its three levels) and its family's (``cones``, ``nitsche``, ``penalty``,
``mortar``).
"""
from __future__ import annotations

import math
from collections.abc import Mapping
from contextlib import nullcontext
from dataclasses import dataclass, field, fields, replace
from typing import Callable

import numpy as np

from ..problem.regularity import capped_rate
from ..solvers.options import SolverOptions

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
# The role rule: a method has the roles it declares (``Method.roles``, each one of ``ROLES``: an
# unknown name is refused in one line, not ignored). A copy under another name (a variant made
# by ``dataclasses.replace`` or ``with_parameters``) that keeps the roles it copied has none: no
# variant joins the report's sweeps and studies unasked. Roles given with the copy, or by
# ``with_roles``, it keeps.


@dataclass(frozen=True)
class Expectation:
    """The H^1 bound C h^rate ``|log h|^log_exponent`` a theory predicts, and which theory."""

    rate: float
    log_exponent: float
    reference: str


def no_theory(case) -> Expectation:
    """The expectation of a method that declares none: no rate to compare with (grey)."""
    return Expectation(math.nan, 0.0, "no theory declared")


def capped_expectation(nu: float, cap: float, reference: str, cutoff: float | None = None,
                       below: str | None = None) -> Expectation:
    """h^{min(nu - 1, cap)} with no log factor (``problem.regularity.capped_rate``), from
    ``reference``; where ``nu <= cutoff`` the theory says nothing: NaN, from ``below`` (default
    ``reference``)."""
    said_nothing = cutoff is not None and nu <= cutoff
    return Expectation(capped_rate(nu, cap, cutoff), 0.0, (below or reference) if said_nothing else reference)


def no_result_below(reference: str, cutoff: str = "3/2") -> str:
    """The reference text of a theory that says nothing for nu <= ``cutoff``."""
    return f"{reference}: no result for nu <= {cutoff}"


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
    load_steps: int = 1             # the load history's steps solved (each to the tolerance; the worst's residual)

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
        """The fields of a QP solved exactly (``solvers.bound_constraints.QPSolution`` or
        ``solvers.general_constraints.GeneralQPSolution``) with ``rows`` constraints."""
        return cls(max_penetration=max_penetration, min_pressure=float(pressure.min()), kkt_residual=solution.kkt.residual,
                   status=solution.status, solver_iterations=solution.iterations,
                   linear_iterations=solution.work.get("cg_iterations", solution.work.get("factorizations")),
                   active_constraints=int(solution.active.sum()), n_contact_constraints=rows,
                   backward_error=solution.kkt.backward, solve_seconds=solution.seconds)


@dataclass(frozen=True)
class Carry:
    """What a level's solve hands the next, finer level (nested iteration): u_h's values at the
    vertices (``p1``: the multigrid's start, prolongated). A family's carry adds what predicts
    its next active set (``ConeCarry``, ``LawCarry``, ``MortarCarry``); an ``OwnSolve`` hands
    this."""

    p1: np.ndarray


@dataclass(frozen=True)
class ConeCarry(Carry):
    """A cone's: the trace of u_h with its constraints' status (``trace``:
    ``fem.assembly.ContactTraceFunction``)."""

    trace: object = None


@dataclass(frozen=True)
class LawCarry(Carry):
    """A contact law's: its Gauss points (``points``) and their branch (``active``); on a load
    history (``problem.friction.LoadHistory``) ``steps``, the carries of the steps before the last."""

    points: np.ndarray | None = None
    active: np.ndarray | None = None
    steps: tuple = ()


@dataclass(frozen=True)
class MortarCarry(LawCarry):
    """A mortar's: its rows' slave nodes and status; the first ``vertex_rows`` points are its
    vertex rows, the rest its edge rows."""

    vertex_rows: int = 0


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
    # u_h at the end of the load step before the last (``problem.friction.LoadHistory``): the
    # final step's slip is measured from it; None for a static case
    previous: np.ndarray | None = None


def timer(phases):
    """``phases`` (``study.chain.rows.Phases``: ``with phases("setup"): ...`` times a phase of the level),
    or, when the solve is not timed, a timer that times nothing."""
    return phases or (lambda phase: nullcontext())


@dataclass(frozen=True)
class Method:
    """A discretisation as the harness measures it. Its fields, by what they say:

    - identity and theory: its ``name`` (a CSV cell and a command-line word), finite element
      ``order``, the contact condition in words (``contact``), where it comes from
      (``reference``), the rate its theory predicts for a case (``expected``: case ->
      ``Expectation``, or None: no theory) and a second theory's (``sharper_theory``), and, for a
      method from outside the package, the file that defines it (``source``);
    - applicability: the ``physics``, ``dimensions``, ``bodies`` and ``friction`` laws it
      discretises (``refusal`` says why a case is not among them);
    - scheduling: its levels past a study's P2 levels (``study_extra_levels``), its cost model
      (``cost_model``) and its solver settings (``solver``: ``solvers.options.SolverOptions``);
    - roles: what it is to the report (``roles``, the rule above ``ROLES``).

    Subclasses solve a level (``solve``): the three levels of the protocol (``protocol``:
    ``FunctionalCone``, ``ContactLawMethod``, ``OwnSolve``) and the families built on them
    (``cones.BoundConstrained``, ``mortar.Mortar``)."""

    # identity and theory
    name: str
    order: int
    contact: str                                  # how the contact condition is imposed
    reference: str                                # where the method comes from
    expected: Callable[[object], Expectation]     # case -> the rate its theory predicts
    # case -> the rate of a second, later theory (a second verdict), or None
    sharper_theory: Callable[[object], Expectation] | None = None
    # applicability
    physics: tuple = ("scalar",)                  # the physics it discretises (``problem.physics``)
    dimensions: tuple = (2,)                      # the space dimensions it discretises
    bodies: tuple = (1,)                          # the number of bodies it couples (``Case.bodies``)
    friction: tuple = ("frictionless",)           # the friction laws it discretises (``problem.friction``)
    # scheduling: its levels past a study's P2 levels, if not ``EXTRA_LEVELS`` (``with_extra_levels``)
    study_extra_levels: int | None = None
    # roles: what it is to the report (``ROLES``), and (name, roles) as declared (the role rule)
    roles: frozenset = frozenset()
    roles_of: tuple | None = field(default=None, repr=False, compare=False)
    # scheduling: how its solve's time is estimated (``study.execution.budget``): "active-set" (an exact QP
    # solve by an active set method), "newton" (semismooth Newton), or a number, its seconds per dof
    cost_model: str | float = "active-set"
    # identity: the file that defines a method from outside the package (``plugins``): what its
    # checkpoints and cached results depend on besides the harness's code
    source: str | None = field(default=None, compare=False)
    # scheduling: the solvers' tolerances, loose-solve gains and iteration caps (``solvers.options``)
    solver: SolverOptions = field(default=SolverOptions(), compare=True)

    def __post_init__(self):
        roles = frozenset(self.roles)
        unknown = sorted(map(str, roles - set(ROLES)))
        if unknown:
            raise ValueError(f"method {self.name!r}: unknown role(s) {', '.join(unknown)}; the roles are {', '.join(ROLES)}")
        if self.roles_of is not None and self.roles_of[0] != self.name and roles == self.roles_of[1]:
            roles = frozenset()             # copied under another name: the role rule
        object.__setattr__(self, "roles", roles)
        object.__setattr__(self, "roles_of", (self.name, roles))

    def with_roles(self, *roles: str) -> "Method":
        """The same method declaring ``roles`` (``ROLES``), and only those."""
        unknown = set(roles) - set(ROLES)
        if unknown:
            raise ValueError(f"unknown role(s) {', '.join(sorted(unknown))}; the roles are {', '.join(ROLES)}")
        return replace(self, roles=frozenset(roles), roles_of=(self.name, frozenset(roles)))

    def supports(self, case) -> bool:
        """Does it discretise ``case``'s physics, dimension and bodies (``refusal``)?"""
        return self.refusal(case) is None

    def refusal(self, case) -> str | None:
        """Why it does not discretise ``case`` (one clause), or None if it does. Order k >= 3
        needs an exact solution too: a reference solution is nodal P2 (``measure.reference``),
        into whose space a P_k function does not embed."""
        if self.order > 2 and not case.exact:
            return f"P{self.order} needs the case's exact solution (a reference solution is P2)"
        if case.physics.name not in self.physics:
            return f"it discretises {' and '.join(self.physics)}, not {case.physics.name}"
        if case.dimension not in self.dimensions:
            return f"it runs in {' and '.join(f'{d}D' for d in self.dimensions)}, not {case.dimension}D"
        if case.friction.name not in self.friction:
            return f"it discretises {' and '.join(self.friction)} contact, not {case.friction.name} friction"
        if case.bodies not in self.bodies:
            return f"it couples {' or '.join(map(str, self.bodies))} bod{'y' if self.bodies == (1,) else 'ies'}, not {case.bodies}"
        return None

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
        stiffness matrix's memory. ``phases`` (``study.chain.rows.Phases``) times set-up and solve."""
        raise NotImplementedError


def _number(value: float) -> str:
    return f"{value:g}"


