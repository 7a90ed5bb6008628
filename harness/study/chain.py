"""A convergence study: case -> mesh hierarchy -> discrete problems -> methods -> solve ->
errors -> one tidy row per (case, method, level)."""
from __future__ import annotations

import inspect
import time
import warnings
from dataclasses import dataclass

import ngsolve as ngs

from ..fem.assembly import discretise
from ..fem.element_quadrature import ElementQuadrature
from ..measure.errors import ExactErrors
from ..measure.estimator import ResidualEstimator, estimate
from ..measure.reference import REFERENCE_METHOD, ReferenceErrors
from ..mesh.levels import LevelSequence
from ..mesh.strategies import UNIFORM, MeshStrategy, element_budget
from ..methods import Method, get_method, methods_for
from ..problem.case import Case
from ..solvers.multigrid import Multilevel
from . import threads
from .rows import COLUMNS, PHASES, ChainOutput, Phases, keep, level_row, study_levels  # noqa: F401 (COLUMNS, PHASES: their home was here)
from .threads import p2_size
from .two_body import run_two_body_chain

ngs.ngsglobals.msg_level = 0

PROFILES = {
    # finest levels: about 5.8e5 dofs (transition geometry), well inside 10 minutes on 2 cores;
    # the 3D cases (8 times the dofs per level): 1.3e5 P2 dofs
    # the mesh study (graded and adaptive meshes, ``mesh_study``): the budget of uniform level
    # mesh_levels - 1, 9.2e3 P2 dofs on corner-r12
    # a case that declares ``asymptotic_levels`` stops there (``cache.case_settings``): six for
    # the cases whose seventh level moved no fitted rate by more than 0.01
    # two bodies (about twice a one-body level's dofs, ``two_body``): at most 6 levels (5.1e5 dofs; see "fine")
    "default": {"levels": 7, "levels_3d": 3, "levels_two_body": 6, "mesh_levels": 4, "stop_when_asymptotic": True},
    # finest levels: about 2.3e6 dofs; 3D: 1.3e6; two bodies 5.1e5 (mortar-standard's saddle
    # systems are factorised by SuperLU, whose fill at 2e6 dofs grew past 19 GB); the mesh study
    # to 5.8e5 dofs
    "fine": {"levels": 8, "levels_3d": 4, "levels_two_body": 6, "mesh_levels": 7, "stop_when_asymptotic": False},
}

def is_reference(case: Case, method: Method) -> bool:
    """Whether ``method`` solves ``case``'s reference (a case without u: ``REFERENCE_METHOD``)."""
    return not case.exact and method.name == REFERENCE_METHOD


def chain_methods(case: Case, methods: list[Method]) -> list[Method]:
    """The methods a chain of ``case`` solves: those of ``methods`` that discretise it, and for
    a case measured against a reference, the reference method (``measure.reference``) even if
    it was not asked for: it then solves its levels for the reference alone, without rows."""
    own = methods_for(case, methods)
    if case.exact or any(m.name == REFERENCE_METHOD for m in own):
        return own
    return own + [get_method(REFERENCE_METHOD)]


def chain_levels(case: Case, method: Method, levels: int) -> int:
    """Levels a method solves for a case: its studied levels, and for the method that solves a
    case's reference, k more (nested iteration all the way; the last is the reference, with
    4^k times the dofs of every method's finest studied level)."""
    return study_levels(method, levels) + (case.reference_levels if is_reference(case, method) else 0)


@dataclass
class ChainState:
    """A method's level chain after its last finished level (``next_level`` - 1): everything
    resuming it needs. Saved by the study after every level (``checkpoints``)."""

    next_level: int
    rows: list[dict]          # its rows so far (a reference case's stay without errors until the reference)
    carry: object             # what the next level's solve starts from (nested iteration)
    pending: list             # what the error measure keeps across levels (``state_of``)
    kept: dict                # level -> what ``on_level`` returned


class _LevelHook_0_1:
    """A hook written for harness 0.1, ``on_level(case, model, level, problem, u, solution,
    trace_u)``, called as one of 0.2 on: ``model`` is now the method (it has ``.name``, as the
    model had), ``solution`` the ``methods.LevelSolve`` (its ``fields`` hold status, iterations
    and residual), ``u`` and ``trace_u`` as before."""

    def __init__(self, hook):
        self.hook = hook

    def __call__(self, case, method, level, problem, solve):
        return self.hook(case, method, level, problem, solve.u, solve, solve.trace_u)


def level_hook(on_level):
    """``on_level`` as the study calls it, ``(case, method, level, problem, solve)``; a hook with
    the seven positional parameters of harness 0.1 is adapted, with a DeprecationWarning (the
    adapter goes in 0.4)."""
    if on_level is None:
        return None
    try:
        parameters = inspect.signature(on_level).parameters.values()
    except (TypeError, ValueError):         # a callable without a signature: taken as it is
        return on_level
    positional = [p for p in parameters if p.kind in (p.POSITIONAL_ONLY, p.POSITIONAL_OR_KEYWORD) and p.default is p.empty]
    if len(positional) == 7 and not any(p.kind == p.VAR_POSITIONAL for p in parameters):
        warnings.warn("on_level(case, model, level, problem, u, solution, trace_u) is the hook of harness 0.1; "
                      "since 0.2 it is on_level(case, method, level, problem, solve) with solve.u, solve.trace_u, "
                      "solve.fields (adapted until 0.4)", DeprecationWarning, stacklevel=3)
        return _LevelHook_0_1(on_level)
    return on_level


class BothHooks:
    """Two ``on_level`` hooks as one: both see every solve, the study keeps what ``first``
    returns (the report's snapshots beside ``report --vtk``'s writer)."""

    def __init__(self, first, second):
        self.first, self.second = first, second

    def __call__(self, case, method, level, problem, solve):
        kept = self.first(case, method, level, problem, solve)
        self.second(case, method, level, problem, solve)
        return kept


# an adaptive chain stops when its mesh has more elements than the uniform level it replaces
# (the same budget of dofs as the uniform chain), or after this many levels
MAX_ADAPTIVE_LEVELS = 60


def has_estimator(case) -> bool:
    """The residual estimator has terms for 2D scalar problems (``measure.estimator``)."""
    return case.dimension == 2 and not case.physics.elastic


def run_chain(case: Case, methods: list[Method], levels: int, progress=None, on_level=None,
              phases: Phases | None = None, checkpoints=None, sequence: LevelSequence | None = None,
              mesh: MeshStrategy = UNIFORM) -> ChainOutput:
    """The level chains of ``methods`` on one case, sharing each level's mesh and assembly.

    The meshes, and the h of each row, are ``sequence``'s (``mesh.levels``; default the
    ``mesh`` strategy's sequence for the methods' order: the caller groups methods that can
    share one, ``MeshStrategy.group_key``). An adaptive sequence is driven by the estimator of
    the (one) method's solutions. A graded or adaptive chain stops before its mesh has more
    triangles than the uniform level ``levels`` - 1 (+ the methods' extra levels): the same
    budget of dofs (a graded mesh has about 13 times the triangles of the uniform one of the
    same H on corner-r12: its levels stop earlier).

    ``on_level(case, method, level, problem, solve)`` sees every studied solve (``solve``: a
    ``methods.LevelSolve``); what it returns (if not None) is kept, by (method, level). The
    report keeps the finest solutions that way. ``progress`` (if given) hears
    ``solving(case, method, level, ndof, stage)``, ``solved(case, method, level)`` and
    ``restored(case, method, levels)``. ``checkpoints`` (if given: ``load(case, method)`` ->
    ``ChainState`` or None, ``save(case, method, state)``) makes every finished level durable
    and lets a chain killed at any moment continue from its last finished level: the meshes
    and the multigrid's hierarchy are rebuilt (they are determined by the case), the solves
    start again from the saved coarser solution.

    Per level: one mesh, one discrete problem per finite element order shared by the methods
    of that order (the last of them takes its stiffness matrix), one error measurement for all:
    ``errors.ExactErrors`` against u, or ``reference.ReferenceErrors`` against one reference
    solution, k levels finer (``chain_methods``: the rows get their errors when it is solved).
    ``total_seconds`` of a row: what the level costs a user of that method alone -- the
    refinement, its order's assembly, its own set-up and solve; not the error measurement.
    """
    phases = phases or Phases()
    if case.bodies == 2:
        # two bodies on their own meshes, coupled by a mortar method (``two_body``)
        if mesh != UNIFORM or sequence is not None:
            raise ValueError(f"case {case.name}: two bodies are refined uniformly only (graded and adaptive meshes: not yet)")
        return run_two_body_chain(case, methods, levels, progress, phases, on_level)
    requested = {m.name for m in methods_for(case, methods)}      # the weak methods are scalar and 2D only
    methods = chain_methods(case, methods)
    sequence = sequence or mesh.sequence(case, max(m.order for m in methods))
    if sequence.adaptive:
        if not case.exact:
            raise ValueError(f"case {case.name}: adaptive meshes need an exact case (reference errors need uniform refinement)")
        if len(methods) != 1:
            raise ValueError("an adaptive mesh serves one method: run one chain per method")
        # its meshes come from its solves: a killed adaptive chain starts again (no checkpoints)
        checkpoints = None
    studied = {m.name: study_levels(m, levels) if m.name in requested else 0 for m in methods}
    chain = {m.name: chain_levels(case, m, levels) for m in methods}
    if case.exact:
        measure = ExactErrors(case, phases, {m.name: m.order for m in methods})
    else:
        measure = ReferenceErrors(studied, {m.name: m.order for m in methods}, REFERENCE_METHOD,
                                  chain[REFERENCE_METHOD] - 1, phases)
    reference_fields, reference_solve_seconds = None, 0.0
    saved = {m.name: checkpoints.load(case, m) if checkpoints is not None else None for m in methods}
    start = {name: state.next_level if state else 0 for name, state in saved.items()}
    carry = {name: state.carry if state else None for name, state in saved.items()}
    method_rows = {name: list(state.rows) if state else [] for name, state in saved.items()}
    kept = {(name, level): value for name, state in saved.items() if state for level, value in state.kept.items()}
    for method in methods:
        if saved[method.name]:
            measure.restore(method.name, saved[method.name].pending, method_rows[method.name])
            if progress is not None:
                progress.restored(case.name, method.name, start[method.name])
    expectations = {m.name: m.expected(case) for m in methods}
    sharper = {m.name: m.sharper(case) for m in methods}
    last_level = max((chain[n] for n in chain if start[n] < chain[n]), default=0)
    mesh_label = mesh.label
    multilevel = None
    budget_elements = None
    if sequence.adaptive:
        # every level of an adaptive chain after the first: as many as it takes to reach the
        # budget (or MAX_ADAPTIVE_LEVELS)
        studied = chain = {m.name: MAX_ADAPTIVE_LEVELS for m in methods}
        last_level = MAX_ADAPTIVE_LEVELS
    # the P1 hierarchy of the truncated multigrid (where the physics has one: ``physics``;
    # nested meshes only: its prolongations are the refinement's); else the solves factorise
    hierarchical = case.physics.multigrid and sequence.nested
    estimating = has_estimator(case)
    # The meshes are made outside NGSolve's task manager, each level's work under it: a study
    # whose bisections (Mesh.Refine with flags) ran under it crashed once here (munmap_chunk,
    # not reproduced in 30 runs since; NGSolve's own adaptive tutorials refine outside it).
    walk = sequence.levels(last_level)
    for level in range(last_level):
        clock = time.perf_counter()
        with phases("mesh"):
            step = next(walk, None)
            if step is None:
                break
            mesh, h = step.mesh, step.h
            if getattr(sequence, "budgeted", True):
                # the uniform finest level's number of triangles (of the coarse mesh times 4 per
                # level): graded and adaptive meshes get the same budget of dofs
                if budget_elements is None:
                    budget_elements = element_budget(case, levels, max(m.extra_levels for m in methods))
                if level and mesh.ne > budget_elements:
                    break
        with threads.level(p2_size(mesh)):
            if hierarchical:
                # the P1 levels' assembly, threaded (outside the task manager it was 5 s of the
                # paper methods' default study)
                with phases("mesh"):
                    multilevel = Multilevel(mesh, case.physics) if multilevel is None else multilevel.refined()
            active = [m for m in methods if start[m.name] <= level < chain[m.name]]
            if not active:          # a level every method has finished: rebuilt, not solved
                measure.skip_level(level, mesh)
                continue
            with phases("mesh"):
                quadrature = ElementQuadrature.of(case, mesh)
            mesh_seconds = time.perf_counter() - clock
            problems, assembly_seconds, estimators = {}, {}, {}
            for order in sorted({m.order for m in active}, reverse=True):
                clock = time.perf_counter()
                with phases("assembly"):
                    problems[order] = discretise(case, mesh, order, quadrature)
                assembly_seconds[order] = time.perf_counter() - clock
                if estimating and any(level < studied[m.name] for m in active if m.order == order):
                    with phases("errors"):
                        estimators[order] = ResidualEstimator(case, problems[order])
            # before a method takes the stiffness matrix (the best approximation needs it)
            measure.begin_level(level, mesh, problems, quadrature, multilevel)
            for method in active:
                problem = problems[method.order]
                stage = "" if level < studied[method.name] else "reference chain"
                if progress is not None:
                    progress.solving(case.name, method.name, level, problem.ndof, stage)
                last = method is [m for m in active if m.order == method.order][-1]
                clock = time.perf_counter()
                solve = method.solve(case, problem, carry[method.name], multilevel, take_stiffness=last, phases=phases)
                own_seconds = time.perf_counter() - clock
                carry[method.name] = solve.carry
                indicators = None
                # the studied rows' estimator (a reference chain's finer solves need none)
                if estimating and level < studied[method.name]:
                    with phases("errors"):
                        indicators = estimators[method.order].indicators(solve.u)
                if sequence.adaptive:
                    sequence.observe(indicators)
                row = None
                if level < studied[method.name]:
                    row = level_row(case, method, mesh_label, level, h, problem.ndof, solve.fields,
                                    mesh_seconds + assembly_seconds[method.order] + own_seconds,
                                    estimate(indicators) if indicators is not None else float("nan"),
                                    expectations[method.name], sharper[method.name])
                    method_rows[method.name].append(row)
                else:
                    reference_solve_seconds += solve.fields["solve_seconds"]
                    if is_reference(case, method) and level == chain[method.name] - 1:
                        reference_fields = (level, problem.ndof, solve.fields)
                with phases("errors"):
                    columns = measure.solved(method, level, problem, solve.u, row)
                if row is not None:
                    row.update(columns)
                    keep(on_level, phases, kept, case, method, level, problem, solve)
                if progress is not None:
                    progress.solved(case.name, method.name, level)
            with phases("errors"):
                measure.end_level()
            for row in (rows[-1] for rows in method_rows.values() if rows and rows[-1]["level"] == level):
                if row["errors_against"] == "exact":
                    row["effectivity"] = row["estimator"] / row["err_energy"]
            # the reference level completes every method's rows: all are saved again, the
            # reference method last (a kill in between leaves its level to be solved again)
            saved_now = active
            if reference_fields is not None:
                for rows in method_rows.values():
                    _reference_fields(rows, *reference_fields)
                saved_now = sorted(methods, key=lambda m: is_reference(case, m))
            for method in saved_now:
                if checkpoints is not None:
                    checkpoints.save(case, method, ChainState(
                        min(level + 1, chain[method.name]), method_rows[method.name], carry[method.name],
                        measure.state_of(method.name),
                        {lev: value for (name, lev), value in kept.items() if name == method.name}))
    order = {m.name: k for k, m in enumerate(methods)}
    rows = sorted((row for name in method_rows for row in method_rows[name]), key=lambda r: (r["level"], order[r["method"]]))
    return ChainOutput(rows, kept, phases.as_dict(), {name: start[name] for name in start}, reference_solve_seconds)


def _reference_fields(rows: list[dict], level: int, ndof: int, fields: dict) -> None:
    """What the rows of a case without u say about the reference they were measured against."""
    for row in rows:
        row.update({"reference_level": level, "reference_ndof": ndof, "reference_method": REFERENCE_METHOD,
                    "reference_kkt_residual": fields["kkt_residual"], "reference_status": fields["status"]})
