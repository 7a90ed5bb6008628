"""The one level loop of every chain, one body or two: level by level, the case's meshes ->
one discrete problem per finite element order (shared by the methods of that order) -> each
method's solve -> its errors -> its row; after every level, each chain's state is checkpointed.

What differs between chains comes in from outside: how a level's meshes, problems and solves
are made (a ``Discretisation``: ``one_body.OneBody``, ``two_body.TwoBodies``), what the errors
are measured against (``measure.errors.ExactErrors``, ``measure.reference.ReferenceErrors``,
``two_body.TwoBodyErrors``) and how many levels each method solves (``ChainPlan``).
"""
from __future__ import annotations

import time
from collections.abc import Iterator
from dataclasses import dataclass, field
from typing import Protocol

from ...measure.estimator import estimate
from ...mesh.levels import Level
from ..execution import threads
from .rows import ChainOutput, Phases, keep, level_row

# an adaptive chain, of one body or two, stops when its mesh has more elements than the uniform
# level it replaces (the same budget of dofs as the uniform chain), or after this many levels
MAX_ADAPTIVE_LEVELS = 60


@dataclass
class ChainState:
    """A method's level chain after its last finished level (``next_level`` - 1): everything
    resuming it needs. Saved by the study after every level (``checkpoints``)."""

    next_level: int
    rows: list[dict]          # its rows so far (a reference case's stay without errors until the reference)
    carry: object             # what the next level's solve starts from (nested iteration)
    pending: list             # what the error measure keeps across levels (``state_of``)
    kept: dict                # level -> what ``on_level`` returned


@dataclass(frozen=True)
class ChainPlan:
    """How many levels each method solves: ``studied`` ones, with rows, and ``chain`` ones in
    all (a reference chain's finer levels too); ``reference``: the method whose last level is
    the reference the rows are measured against (None: against u)."""

    studied: dict[str, int]
    chain: dict[str, int]
    reference: str | None = None

    def last_level(self, start: dict[str, int]) -> int:
        """Levels to walk for chains resumed at ``start``: to the end of the longest unfinished one."""
        return max((self.chain[n] for n in self.chain if start[n] < self.chain[n]), default=0)


class Discretisation(Protocol):
    """How a chain's levels are meshed, discretised and solved. A level's ``mesh`` and
    ``quadrature`` are whatever the discretisation makes (two bodies: a pair of each)."""

    estimating: bool        # the studied solves get the residual estimator's indicators
    adaptive: bool          # the indicators drive the next mesh (ESTIMATE and MARK are the algorithm's)

    def levels(self, count: int) -> Iterator[Level]:
        """At most ``count`` levels, coarse to fine."""

    def size(self, mesh) -> int:
        """The level's scalar P2 dofs, for its threads (``study.execution.threads.p2_size``)."""

    def multilevel(self, level: Level):
        """The multigrid hierarchy up to the ``level``'s mesh (None: the solves factorise)."""

    def quadrature(self, mesh):
        """The level's element quadrature."""

    def discretise(self, order: int, mesh, quadrature):
        """The level's discrete problem of one finite element order."""

    def solve(self, method, problem, carry, multilevel, last_of_order: bool, phases):
        """``method``'s ``methods.LevelSolve`` of ``problem``."""

    def estimator(self, problem):
        """The residual estimator of ``problem``'s solutions (``indicators(u)``: eta_T^2 per element)."""

    def observe(self, indicators) -> None:
        """A studied solve's error indicators (an adaptive sequence's next mesh needs them)."""

    def quantities(self, problem, u, quadrature, previous=None) -> dict:
        """The quantities of interest of a studied solve (``measure.quantities``), with their
        exact values on a case with u."""


@dataclass
class LevelProblems:
    """One level's discrete problems by finite element order, with what the level needs to
    solve them and what making them cost (a row's ``total_seconds``)."""

    index: int
    h: float
    multilevel: object
    mesh_seconds: float
    quadrature: object = None                               # the level's ElementQuadrature
    problems: dict = field(default_factory=dict)            # order -> discrete problem
    assembly_seconds: dict = field(default_factory=dict)    # order -> its assembly's seconds
    estimators: dict = field(default_factory=dict)          # order -> its estimator (``Discretisation.estimator``)
    estimator_seconds: dict = field(default_factory=dict)   # order -> its set-up's seconds
    measure_seconds: float = 0.0                            # the level's shared measurement (begin, end)
    rows: list = field(default_factory=list)                # the level's studied rows


def reference_columns(rows: list[dict], method: str, level: int, ndof: int, fields: dict) -> None:
    """What the rows of a case without u say about the reference they were measured against."""
    for row in rows:
        row.update({"reference_level": level, "reference_ndof": ndof, "reference_method": method,
                    "reference_kkt_residual": fields["kkt_residual"], "reference_status": fields["status"]})


class ChainWalk:
    """The level chains of ``methods`` on ``case``, walked together level by level (each
    level's meshes and problems shared), and what they have produced so far. Listeners as in
    ``chain.run_chain``: ``progress``, ``on_level``, ``checkpoints``."""

    def __init__(self, case, methods, plan: ChainPlan, discretisation: Discretisation, measure, mesh_label: str,
                 phases: Phases, progress=None, on_level=None, checkpoints=None):
        self.case, self.methods, self.plan = case, methods, plan
        self.discretisation, self.measure, self.mesh_label = discretisation, measure, mesh_label
        self.phases, self.progress, self.on_level, self.checkpoints = phases, progress, on_level, checkpoints
        self.start = {m.name: 0 for m in methods}
        self.carry = {m.name: None for m in methods}
        self.rows: dict[str, list[dict]] = {m.name: [] for m in methods}
        self.kept: dict = {}
        self.reference_fields = None        # (level, ndof, fields) of the reference solve, once solved
        self.reference_solve_seconds = 0.0
        self.expectations = {m.name: m.expected(case) for m in methods}
        self.sharper = {m.name: m.sharper(case) for m in methods}

    def run(self) -> ChainOutput:
        """Every chain from its saved state (or its first level) to its last level."""
        self.resume()
        last_level = self.plan.last_level(self.start)
        # The meshes are made outside NGSolve's task manager, each level's work under it: bisection
        # (Mesh.Refine with flags) under the task manager can crash, rarely (munmap_chunk), and
        # NGSolve's own adaptive tutorials refine outside it.
        meshes = self.discretisation.levels(last_level)
        for level in range(last_level):
            clock = time.perf_counter()
            with self.phases("mesh"):
                step = next(meshes, None)
            if step is None:
                break
            with threads.level(self.discretisation.size(step.mesh)):
                self.solve_level(level, step, clock)
        return self.output()

    def resume(self) -> None:
        """Each chain's state as its checkpoint saved it (if any)."""
        if self.checkpoints is None:
            return
        for method in self.methods:
            state = self.checkpoints.load(self.case, method)
            if state is None:
                continue
            name = method.name
            self.start[name], self.carry[name], self.rows[name] = state.next_level, state.carry, list(state.rows)
            self.kept |= {(name, level): value for level, value in state.kept.items()}
            self.measure.restore(name, state.pending, self.rows[name])
            if self.progress is not None:
                self.progress.restored(self.case.name, name, state.next_level)

    def solve_level(self, level: int, step: Level, clock: float) -> None:
        """One level of the chains that have it to solve: its discrete problems, each method's
        solve, errors and row, then the chains' checkpoints."""
        with self.phases("mesh"):
            # under the level's threads: the P1 levels' assembly, which outside the task manager
            # runs on one thread
            multilevel = self.discretisation.multilevel(step)
        active = [m for m in self.methods if self.start[m.name] <= level < self.plan.chain[m.name]]
        if not active:          # a level every method has finished: rebuilt, not solved
            self.measure.skip_level(level, step.mesh)
            return
        with self.phases("mesh"):
            quadrature = self.discretisation.quadrature(step.mesh)
        problems = LevelProblems(level, step.h, multilevel, time.perf_counter() - clock, quadrature)
        self.discretise(problems, step.mesh, quadrature, active)
        # before a method takes the stiffness matrix (the best approximation needs it)
        clock = time.perf_counter()
        self.measure.begin_level(level, step.mesh, problems.problems, quadrature, multilevel)
        problems.measure_seconds += time.perf_counter() - clock
        for method in active:
            last_of_order = method is [m for m in active if m.order == method.order][-1]
            self.solve_method(method, problems, last_of_order)
        self.finish_level(problems)
        self.checkpoint(level, active)

    def discretise(self, level: LevelProblems, mesh, quadrature, active: list) -> None:
        """The level's discrete problem of each order of ``active`` (finest order first), and
        its estimator where a studied row of that order needs one."""
        for order in sorted({m.order for m in active}, reverse=True):
            clock = time.perf_counter()
            with self.phases("assembly"):
                level.problems[order] = self.discretisation.discretise(order, mesh, quadrature)
            level.assembly_seconds[order] = time.perf_counter() - clock
            # in 3D the residual estimator is P1/P2's (``measure.estimator_3d``): 3D P_k rows carry none
            if self.discretisation.estimating and (order <= 2 or mesh.dim == 2) and any(
                    level.index < self.plan.studied[m.name] for m in active if m.order == order):
                clock = time.perf_counter()
                with self.phases("estimate"):
                    level.estimators[order] = self.discretisation.estimator(level.problems[order])
                level.estimator_seconds[order] = time.perf_counter() - clock

    def solve_method(self, method, level: LevelProblems, last_of_order: bool) -> None:
        """``method``'s solve of the level, its errors and (on a studied level) its row."""
        problem, name = level.problems[method.order], method.name
        studied = level.index < self.plan.studied[name]
        if self.progress is not None:
            self.progress.solving(self.case.name, name, level.index, problem.ndof, "" if studied else "reference chain")
        clock = time.perf_counter()
        solve = self.discretisation.solve(method, problem, self.carry[name], level.multilevel, last_of_order, self.phases)
        own_seconds = time.perf_counter() - clock
        self.carry[name] = solve.carry
        # the studied rows' estimator (a reference chain's finer solves need none)
        indicators, clock = None, time.perf_counter()
        if studied and method.order in level.estimators:
            with self.phases("estimate"):
                estimator = level.estimators[method.order]
                # a load history's last step: its slip is u_h less the step before's (one body only)
                indicators = (estimator.indicators(solve.u) if solve.previous is None
                              else estimator.indicators(solve.u, previous=solve.previous))
        estimate_seconds = time.perf_counter() - clock + level.estimator_seconds.get(method.order, 0.0)
        self.discretisation.observe(indicators)
        if studied:
            row = self.row(method, level, problem, solve, own_seconds, indicators, estimate_seconds)
        else:
            row = self.reference_chain_solve(method, level.index, problem, solve)
        clock = time.perf_counter()
        with self.phases("errors"):
            columns = self.measure.solved(method, level.index, problem, solve.u, row)
            if row is not None:
                columns |= self.discretisation.quantities(problem, solve.u, level.quadrature, solve.previous)
        if row is not None:
            row.update(columns)
            row["measure_seconds"] = time.perf_counter() - clock
            keep(self.on_level, self.phases, self.kept, self.case, method, level.index, problem, solve)
        if self.progress is not None:
            self.progress.solved(self.case.name, name, level.index)

    def row(self, method, level: LevelProblems, problem, solve, own_seconds: float, indicators,
            estimate_seconds: float) -> dict:
        """A studied solve's row, before its errors; ``total_seconds``: what the level costs a
        user of that method alone (the refinement, its order's assembly, its own set-up and
        solve, and where the estimator drives the mesh, ESTIMATE and MARK; not the error
        measurement, ``measure_seconds``)."""
        total = level.mesh_seconds + level.assembly_seconds[method.order] + own_seconds
        if indicators is not None and self.discretisation.adaptive:
            total += estimate_seconds
        row = level_row(self.case, method, self.mesh_label, level.index, level.h, problem.ndof, solve.fields, total,
                        estimate(indicators) if indicators is not None else float("nan"),
                        self.expectations[method.name], self.sharper[method.name])
        if indicators is not None:
            row["estimate_seconds"] = estimate_seconds
        self.rows[method.name].append(row)
        level.rows.append(row)
        return row

    def reference_chain_solve(self, method, level: int, problem, solve) -> None:
        """A solve past the studied levels (no row): the last of the reference method's is the
        reference."""
        self.reference_solve_seconds += solve.fields["solve_seconds"]
        if method.name == self.plan.reference and level == self.plan.chain[method.name] - 1:
            self.reference_fields = (level, problem.ndof, solve.fields)

    def finish_level(self, problems: LevelProblems) -> None:
        """The level's errors that need all its solves, the effectivity of its rows measured
        against u (NaN without an estimator), and once the reference is solved, its columns and
        the effectivity of every row against it;
        the level's shared measurement time split over its rows (``measure_seconds``)."""
        level, clock = problems.index, time.perf_counter()
        with self.phases("errors"):
            self.measure.end_level()
        shared = problems.measure_seconds + time.perf_counter() - clock
        for row in problems.rows:
            row["measure_seconds"] += shared / len(problems.rows)
        for row in (rows[-1] for rows in self.rows.values() if rows and rows[-1]["level"] == level):
            if row["errors_against"] == "exact":
                row["effectivity"] = row["estimator"] / row["err_energy"]
        if self.reference_fields is not None:
            for rows in self.rows.values():
                reference_columns(rows, self.plan.reference, *self.reference_fields)
                # the reference's level has measured every row: eta against the distance to
                # the reference, as against u (the reference's own error is not in it)
                for row in rows:
                    if row["errors_against"] == "reference":
                        row["effectivity"] = row["estimator"] / row["err_energy"]

    def checkpoint(self, level: int, active: list) -> None:
        """The state of every chain the level changed, made durable."""
        if self.checkpoints is None:
            return
        saved_now = active
        if self.reference_fields is not None:
            # the reference level completes every method's rows: all are saved again, the
            # reference method last (a kill in between leaves its level to be solved again)
            saved_now = sorted(self.methods, key=lambda m: m.name == self.plan.reference)
        for method in saved_now:
            self.checkpoints.save(self.case, method, self.state(method.name, level))

    def state(self, name: str, level: int) -> ChainState:
        """What resuming ``name``'s chain after ``level`` needs."""
        return ChainState(min(level + 1, self.plan.chain[name]), self.rows[name], self.carry[name],
                          self.measure.state_of(name),
                          {lev: value for (method, lev), value in self.kept.items() if method == name})

    def output(self) -> ChainOutput:
        """The rows level by level, methods in the order given."""
        order = {m.name: k for k, m in enumerate(self.methods)}
        rows = sorted((row for rows in self.rows.values() for row in rows), key=lambda r: (r["level"], order[r["method"]]))
        # the solves of a per-level reference (graded and adaptive meshes) are the measure's own
        own = getattr(self.measure, "reference_solve_seconds", 0.0)
        return ChainOutput(rows, self.kept, self.phases.as_dict(), dict(self.start), self.reference_solve_seconds + own)
