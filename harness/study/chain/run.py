"""A convergence study: case -> mesh hierarchy -> discrete problems -> methods -> solve ->
errors -> one tidy row per (case, method, level). ``run_chain`` sets a case's chain up (its
methods, how many levels each solves, its meshes and problems: ``one_body``, or ``two_body``'s
for two bodies; what its errors are measured against); ``walk.ChainWalk`` walks it."""
from __future__ import annotations

import ngsolve as ngs

from ...measure.errors import ExactErrors
from ...measure.level_reference import LevelReferenceErrors
from ...measure.reference import ReferenceErrors, reference_method
from ...mesh.levels import LevelSequence, UniformRefinement
from ...mesh.strategies import UNIFORM, MeshStrategy
from ...methods import Method, methods_for
from ...problem.case import REPORT_PROFILES, Case
from ..execution import threads
from .one_body import OneBody
from .rows import ChainOutput, Phases, study_levels
from .two_body import run_two_body_chain
from .walk import MAX_ADAPTIVE_LEVELS, ChainPlan, ChainWalk

ngs.ngsglobals.msg_level = 0

PROFILES = {
    # finest levels: about 5.8e5 dofs (transition geometry), so that the default report meets its
    # time goal on 2 cores (``python -m harness bench --only report``);
    # the 3D cases (8 times the dofs per level): 1.3e5 P2 dofs
    # the mesh study (graded and adaptive meshes, ``mesh_study``): the budget of uniform level
    # mesh_levels - 1, 9.2e3 P2 dofs on corner-r12
    # a case that declares ``asymptotic_levels`` stops there (``study.planning.cache.case_settings``): six for
    # the cases whose seventh level moves no fitted rate by more than 0.01
    # two bodies (about twice a one-body level's dofs, ``two_body``): at most 6 levels (5.1e5 dofs; see "fine")
    # the 3D mesh study, in the fine profile only (``study.planning.mesh_study.PLAN``): the budget of uniform level
    # mesh_levels_3d - 1, 1.0e6 P2 dofs on transition-line-3d at 4 (3 here: the same rule)
    # the weak methods (contact laws) on 3D cases in the fine profile only: at the default's three
    # 3D levels they would add the 3D error integration of four more methods to every 3D case
    # (``weak_3d``)
    # the orders of the methods a report of all methods runs ("orders"): P1 and P2, the paper's
    # question; the degree axis (P3, P4) is the degree study's (``degree_study``), on the budget
    # of uniform level degree_levels - 1 (9.2e3 P2 dofs on transition-r32 by default: a fifth level
    # moved no uniform fitted rate of the degree study by more than 0.008), and joins
    # the main study when named (``--method high-order``); its hp chains (``mesh.hp``) run
    # hp_levels levels (a layer each; transition-r32's tenth has 9.2e3 dofs at k = 2)
    "default": {"levels": 7, "levels_3d": 3, "levels_two_body": 6, "mesh_levels": 4, "mesh_levels_3d": 3,
                "stop_when_asymptotic": True, "weak_3d": False, "orders": (1, 2), "degree_levels": 4, "hp_levels": 10},
    # finest levels: about 2.3e6 dofs; 3D: 1.3e6; two bodies 5.1e5 (mortar-standard's saddle
    # systems are factorised by SuperLU, whose fill a level finer outgrows the memory of the
    # machines this runs on); the mesh study to 5.8e5 dofs
    "fine": {"levels": 8, "levels_3d": 4, "levels_two_body": 6, "mesh_levels": 7, "mesh_levels_3d": 4,
             "stop_when_asymptotic": False, "weak_3d": True, "orders": (1, 2), "degree_levels": 7, "hp_levels": 14},
}
# the profiles' names and order (cheapest first) are the cases' (``Case.report_profile``,
# ``Case.report_levels``): declared once, in ``problem.contract.REPORT_PROFILES``
assert tuple(PROFILES) == REPORT_PROFILES, "each report profile needs its settings here"

def reference_of(case: Case, methods: list[Method]) -> Method | None:
    """The method whose solution k levels finer is the reference of a case without u
    (``measure.reference.reference_method``: the first of ``methods`` that discretise ``case``,
    then of the registered ones, declaring the role REFERENCE), or None for a case with u."""
    return None if case.exact else reference_method(case, methods_for(case, methods))


def is_reference(case: Case, method: Method, methods: list[Method]) -> bool:
    """Whether ``method`` solves ``case``'s reference in a study of ``methods``."""
    reference = reference_of(case, methods)
    return reference is not None and method.name == reference.name


def chain_methods(case: Case, methods: list[Method]) -> list[Method]:
    """The methods a chain of ``case`` solves: those of ``methods`` that discretise it, and for
    a case measured against a reference, the reference method (``reference_of``) even if it
    was not asked for: it then solves its levels for the reference alone, without rows."""
    own = methods_for(case, methods)
    reference = reference_of(case, methods)
    if reference is None or any(m.name == reference.name for m in own):
        return own
    return own + [reference]


def chain_levels(case: Case, method: Method, levels: int, methods: list[Method]) -> int:
    """Levels a method solves for a case: its studied levels, and for the method that solves a
    case's reference, k more (nested iteration all the way; the last is the reference, with
    4^k times the dofs of every method's finest studied level)."""
    return study_levels(method, levels) + (case.reference_levels if is_reference(case, method, methods) else 0)


class BothHooks:
    """Two ``on_level`` hooks as one: both see every solve, the study keeps what ``first``
    returns (the report's snapshots beside ``report --vtk``'s writer)."""

    def __init__(self, first, second):
        self.first, self.second = first, second

    def __call__(self, case, method, level, problem, solve):
        kept = self.first(case, method, level, problem, solve)
        self.second(case, method, level, problem, solve)
        return kept



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
    ``walk.ChainState`` or None, ``save(case, method, state)``) makes every finished level durable
    and lets a chain killed at any moment continue from its last finished level: the meshes
    and the multigrid's hierarchy are rebuilt (they are determined by the case), the solves
    start again from the saved coarser solution.

    Per level: one mesh, one discrete problem per finite element order shared by the methods
    of that order (the last of them takes its stiffness matrix), one error measurement for all:
    ``measure.errors.ExactErrors`` against u, or ``measure.reference.ReferenceErrors`` against one reference
    solution, k levels finer (``chain_methods``: the rows get their errors when it is solved).
    ``total_seconds`` of a row: what the level costs a user of that method alone -- the
    refinement, its order's assembly, its own set-up and solve; not the error measurement.
    """
    phases = phases or Phases()
    if case.bodies == 2:
        # two bodies on their own meshes, coupled by a mortar method (``two_body``): the pairs of
        # meshes are the strategy's (``two_body.pair_sequence``), not one body's sequence
        if sequence is not None:
            raise ValueError(f"case {case.name}: two bodies take a mesh strategy, not one body's level sequence")
        return two_body_chain(case, methods, levels, progress, phases, on_level, mesh)
    own = methods_for(case, methods)        # those that discretise its physics, dimension and bodies
    requested = {m.name for m in own}
    sequence = sequence or mesh.sequence(case, max(m.order for m in own))
    per_level = per_level_reference(case, sequence)
    reference = reference_of(case, methods)
    methods = own if per_level else chain_methods(case, methods)
    if getattr(sequence, "variable_degree", False):
        # an hp level is a number of layers, the same for every degree: no P1 level more, no P4
        # level less (``methods.method.EXTRA_LEVELS`` equalises the dofs of uniform chains)
        methods = [m.with_extra_levels(0) for m in methods]
    if sequence.adaptive:
        check_adaptive(case, methods)
        # its meshes come from its solves: a killed adaptive chain starts again (no checkpoints)
        checkpoints = None
    plan = chain_plan(case, methods, requested, levels, sequence.adaptive, per_level)
    discretisation = OneBody(case, sequence, levels, max(m.extra_levels for m in methods))
    measure = (LevelReferenceErrors(case, {m.name: m.order for m in methods}, reference, phases, threads.level)
               if per_level else error_measure(case, methods, plan, phases))
    return ChainWalk(case, methods, plan, discretisation, measure, mesh.label, phases, progress, on_level,
                     checkpoints).run()


def two_body_chain(case: Case, methods: list[Method], levels: int, progress, phases: Phases, on_level,
                   mesh: MeshStrategy) -> ChainOutput:
    """``two_body.run_two_body_chain``; a case without u with the reference method's chain k
    levels longer (``chain_methods``, ``chain_plan``: each body against its solution)."""
    if case.exact:
        return run_two_body_chain(case, methods, levels, progress, phases, on_level, mesh)
    requested = {m.name for m in methods_for(case, methods)}
    chained = chain_methods(case, methods)
    return run_two_body_chain(case, chained, levels, progress, phases, on_level, mesh,
                              chain_plan(case, chained, requested, levels, False))


def per_level_reference(case: Case, sequence: LevelSequence) -> bool:
    """Whether a chain of ``case`` on ``sequence`` measures each level against its own
    reference (``measure.level_reference``): a case without u on meshes that are not the
    uniform red refinements one reference k levels finer is nested in (graded, adaptive, a
    strategy of your own)."""
    return not case.exact and not isinstance(sequence, UniformRefinement)


def check_adaptive(case: Case, methods: list[Method]) -> None:
    """Refuse what an adaptive mesh cannot serve."""
    if len(methods) != 1:
        raise ValueError("an adaptive mesh serves one method: run one chain per method")


def chain_plan(case: Case, methods: list[Method], requested: set[str], levels: int, adaptive: bool,
               per_level: bool = False) -> ChainPlan:
    """How many levels each of ``methods`` solves (``chain_levels``); one not ``requested`` (the
    reference method a case without u needs) none with rows. ``per_level``: each level has its
    own reference (``per_level_reference``), no chain runs past its studied levels."""
    if adaptive:
        # every level of an adaptive chain after the first: as many as it takes to reach the
        # budget (or MAX_ADAPTIVE_LEVELS)
        every = {m.name: MAX_ADAPTIVE_LEVELS for m in methods}
        return ChainPlan(every, every)
    studied = {m.name: study_levels(m, levels) if m.name in requested else 0 for m in methods}
    if per_level:
        return ChainPlan(studied, dict(studied))
    chain = {m.name: chain_levels(case, m, levels, methods) for m in methods}
    reference = reference_of(case, methods)
    return ChainPlan(studied, chain, None if reference is None else reference.name)


def error_measure(case: Case, methods: list[Method], plan: ChainPlan, phases: Phases):
    """What the rows' errors are measured against: u (``measure.errors.ExactErrors``), or one
    reference solution k levels finer (``measure.reference.ReferenceErrors``)."""
    orders = {m.name: m.order for m in methods}
    if case.exact:
        return ExactErrors(case, phases, orders)
    return ReferenceErrors(plan.studied, orders, plan.reference, plan.chain[plan.reference] - 1, phases)
