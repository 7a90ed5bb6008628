"""The level chain of a two-body case (``problem.bodies``): each body's mesh hierarchy refined
uniformly on its own (the meshes stay non-matching on Gamma_C), each level's two discrete
problems coupled by a mortar method (``methods.mortar``), each body's errors measured as a
one-body chain measures them (``measure.errors.ExactErrors``, the lower body against the same
u in its mirrored frame) and combined over the two bodies:

    err^2 = err_upper^2 + err_lower^2      for every norm (H^1, L^2, energy, best approximation,
                                           trace and pressure on Gamma_C),

so that ``err_h1`` is the H^1 error over both bodies and ``err_h1_over_best`` the ratio of the
combined errors. A case without u (a reference case) measures each body as a one-body reference
case does (``measure.reference.ReferenceErrors``: against the reference method's solution k
levels finer, on uniform pairs, where each body's meshes are nested on their own), combined the
same way once the reference level has completed both bodies' columns. One row per (method, level), with the columns of a one-body chain; ``ndof`` the
two bodies' together, ``h`` the coarser body's mesh size. The level loop is every chain's
(``walk.ChainWalk``); the two bodies' own are their meshes, problems and solves (``TwoBodies``)
and their combined errors (``TwoBodyErrors``).

The meshes (``mesh.two_body_levels``): each body refined uniformly, graded toward its own
singular points, or adaptively by one Dörfler marking over both bodies' elements driven by the
two-body residual estimator (``measure.two_body_estimator``); a graded or adaptive chain stops
at the uniform chain's budget of elements summed over the two bodies. Whatever the meshes, the
mortar coupling of a level is assembled on that level's two meshes (the method's solve).

Every row gets the two-body estimator and its effectivity, on uniform meshes too (it costs a
small share of a uniform chain).

No checkpoints: a killed two-body chain starts again from its first level. The mortar QP
is solved on both bodies' multigrid on uniform pairs from ``solvers.options.SolverOptions.mortar_multigrid_from``
dofs (``solvers.two_body_multigrid``), else by sparse Cholesky; each body's R_h u by Cholesky.
"""
from __future__ import annotations

import math
from collections.abc import Iterator

from ...fem.assembly import discretise
from ...fem.element_quadrature import ElementQuadrature
from ...fem.two_body import TwoBodyProblem
from ...measure.errors import ExactErrors
from ...measure.reference import ReferenceErrors
from ...measure.two_body_estimator import TwoBodyEstimator
from ...measure.two_body_quantities import two_body_exact_quantities, two_body_quantities
from ...mesh.levels import Level
from ...mesh.strategies import UNIFORM, element_budget, singular_lines, singular_points
from ...mesh.two_body_levels import AdaptivePair, GradedPair, UniformPair
from ...methods import methods_for
from ...problem.bodies import lower_body
from ...solvers.multigrid import Multilevel
from ...solvers.two_body_multigrid import JointMultilevel
from ..execution.threads import p2_size
from .rows import ChainOutput, Phases, study_levels
from .walk import MAX_ADAPTIVE_LEVELS, ChainPlan, ChainWalk

# the error columns combined over the bodies as the root of the sum of squares
COMBINED = ("err_h1", "err_h1_semi", "err_l2", "err_energy", "err_best_h1", "err_best_h1_semi", "err_best_energy",
            "err_trace_l2", "err_pressure_l2", "err_pressure_h12", "norm_h1_exact")


def combine(upper: dict, lower: dict) -> dict:
    """The error columns of both bodies' rows as one: sqrt(a^2 + b^2) per norm, and the ratio to
    the best approximation of the combined errors (against u only: a reference measures no best
    approximation and no exact energy, ``measure.reference.ReferenceErrors``)."""
    out = {key: math.hypot(upper[key], lower[key]) for key in COMBINED if key in upper and key in lower}
    if "err_best_h1" in out:
        out["err_h1_over_best"] = out["err_h1"] / out["err_best_h1"]
    if "qoi_energy_exact" in upper and "qoi_energy_exact" in lower:
        out["qoi_energy_exact"] = upper["qoi_energy_exact"] + lower["qoi_energy_exact"]
    return out


class TwoBodies:
    """The levels of a two-body case (the ``walk.Discretisation`` of ``run_two_body_chain``):
    the pairs of meshes of ``sequence`` (``mesh.two_body_levels``), a level's mesh and
    quadrature the pair of the bodies', its h the coarser body's; each order's problem a
    ``fem.two_body.TwoBodyProblem``, its multigrid hierarchy both bodies' on uniform pairs. A graded or
    adaptive chain stops before its two meshes have more elements than ``budget``. Its rows get
    the two-body estimator (``measure.two_body_estimator``), whose indicators drive an adaptive
    sequence."""

    def __init__(self, case, bodies: tuple, sequence=None, budget: float = float("inf")):
        self.case, self.bodies = case, bodies
        self.sequence = sequence or UniformPair(bodies)
        self.budget = budget
        self.estimating = True
        self.adaptive = self.sequence.adaptive
        self._exact = (None, {})        # (the level's quadratures, their exact quantities)
        self._multilevel = None

    def levels(self, count: int) -> Iterator[Level]:
        for step in self.sequence.levels(count):
            if step.index and self.sequence.budgeted and sum(mesh.ne for mesh in step.mesh) > self.budget:
                return
            yield step

    def size(self, meshes) -> int:
        return p2_size(*meshes)

    def multilevel(self, level: Level):
        """Both bodies' P1 hierarchies as one (``solvers.two_body_multigrid``) on uniform pairs, whose
        meshes are refined in place level by level; graded and adaptive pairs factorise."""
        if not (self.case.physics.multigrid and isinstance(self.sequence, UniformPair)):
            return None
        if self._multilevel is None:
            self._multilevel = JointMultilevel(*(Multilevel(mesh, self.case.physics) for mesh in level.mesh))
            return self._multilevel
        return self._multilevel.refined(level.mesh)

    def quadrature(self, meshes) -> tuple:
        return tuple(ElementQuadrature.of(body, mesh) for body, mesh in zip(self.bodies, meshes))

    def discretise(self, order: int, meshes, quadratures) -> TwoBodyProblem:
        return TwoBodyProblem(*(discretise(body, mesh, order, quadrature)
                                for body, mesh, quadrature in zip(self.bodies, meshes, quadratures)))

    def solve(self, method, problem, carry, multilevel, last_of_order: bool, phases):
        return method.solve(self.case, problem, carry, multilevel, phases=phases)

    def estimator(self, problem: TwoBodyProblem) -> TwoBodyEstimator:
        return TwoBodyEstimator(self.bodies, problem)

    def observe(self, indicators) -> None:
        self.sequence.observe(indicators)

    def quantities(self, problem, u, quadratures, previous=None) -> dict:
        """The quantities of the two-body u_h (``measure.two_body_quantities``): the upper
        (slave) body's force and peak pressure (the lower body's balance them), the energy of
        both, the contact zone and (friction) the slip zone from the jumps between the bodies."""
        columns = two_body_quantities(self.bodies, problem, u, previous)
        if self.case.exact:
            if self._exact[0] is not quadratures:
                self._exact = (quadratures, two_body_exact_quantities(self.bodies, problem))
            columns |= self._exact[1]
        return columns


class TwoBodyErrors:
    """Each body's errors measured as a one-body chain measures them (``measures``: the upper
    body's, the lower body's: ``ExactErrors`` against u, or ``ReferenceErrors`` against the
    reference method's solution k levels finer, each body's uniform meshes nested on their own),
    combined into a row (``combine``) at the end of the level that completes both bodies'
    columns: its own against u, the reference's for every studied row."""

    def __init__(self, measures: list):
        self.measures = measures
        self.pending: list[tuple[dict, list[dict]]] = []       # (row, its two bodies' columns)

    def begin_level(self, level: int, meshes, problems: dict, quadratures, multilevel) -> None:
        for k, (measure, mesh, quadrature) in enumerate(zip(self.measures, meshes, quadratures)):
            measure.begin_level(level, mesh, {order: pair.bodies[k] for order, pair in problems.items()}, quadrature, None)

    def solved(self, method, level: int, problem: TwoBodyProblem, u, row: dict | None) -> dict:
        """Each body's solve measured; ``row`` None: a reference chain's solve (no row)."""
        body_rows = [{}, {}]
        for k, (measure, body_u) in enumerate(zip(self.measures, problem.split(u))):
            body_rows[k].update(measure.solved(method, level, problem.bodies[k], body_u, body_rows[k]))
        if row is not None:
            self.pending.append((row, body_rows))
        return {}

    def end_level(self) -> None:
        for measure in self.measures:
            measure.end_level()
        waiting = []
        for row, (upper, lower) in self.pending:
            if "err_h1" in upper and "err_h1" in lower:
                row.update(combine(upper, lower))
            else:
                waiting.append((row, (upper, lower)))
        self.pending = waiting


def run_two_body_chain(case, methods, levels: int, progress=None, phases=None, on_level=None,
                       mesh=UNIFORM, plan: ChainPlan | None = None) -> ChainOutput:
    """The rows of ``methods`` (those that couple two bodies) on the two-body ``case``, levels
    0 .. ``levels`` - 1 (+ the methods' extra levels, P1's), sharing each level's meshes and
    each order's pair of discrete problems, on the meshes of the ``mesh`` strategy
    (``pair_sequence``; an adaptive chain serves one method and runs until the budget).
    ``on_level(case, method, level, problem, solve)`` as in ``chain.run_chain``, with
    ``problem`` a ``fem.two_body.TwoBodyProblem``; what it returns is kept by (method, level).
    A case without u needs ``plan`` (``chain.run.chain_plan``: the reference method's chain k
    levels longer, ``methods`` holding it) and uniform pairs. Returns ``rows.ChainOutput``."""
    phases = phases or Phases()
    methods = methods_for(case, methods)
    if not case.exact and (plan is None or plan.reference is None):
        raise ValueError(f"case {case.name}: a two-body case without u is measured against a reference: "
                         f"run it through harness.study.chain.run_chain (its reference plan)")
    if not case.exact and getattr(mesh, "name", None) != "uniform":
        raise ValueError(f"case {case.name}: a two-body case without u runs on uniform pairs only "
                         f"(each body's meshes nested in its reference's)")
    bodies = (case, lower_body(case))
    extra = max(m.extra_levels for m in methods)
    budget = sum(element_budget(body, levels, extra) for body in bodies)
    sequence = pair_sequence(mesh, bodies, max(m.order for m in methods), budget)
    if sequence.adaptive:
        if len(methods) != 1:
            raise ValueError("an adaptive mesh serves one method: run one chain per method")
        studied = {m.name: MAX_ADAPTIVE_LEVELS for m in methods}
    else:
        studied = {m.name: study_levels(m, levels) for m in methods}
    orders = {m.name: m.order for m in methods}
    if case.exact:
        plan = ChainPlan(studied, studied)
        measure = TwoBodyErrors([ExactErrors(body, phases, orders) for body in bodies])
    else:
        measure = TwoBodyErrors([ReferenceErrors(plan.studied, orders, plan.reference, plan.chain[plan.reference] - 1, phases)
                                 for _ in bodies])
    return ChainWalk(case, methods, plan, TwoBodies(case, bodies, sequence, budget), measure,
                     mesh.label, phases, progress, on_level).run()



def pair_sequence(mesh, bodies: tuple, order: int, budget: float):
    """The two bodies' level sequence for the ``mesh`` strategy (``mesh.strategies.MeshStrategy``):
    uniform, graded toward each body's singular points for P_order, or adaptive."""
    name = getattr(mesh, "name", None)
    if name == "uniform":
        return UniformPair(bodies)
    if name == "graded":
        return GradedPair(bodies, bodies[0].nu - 1.0, order, [singular_points(b) for b in bodies],
                          [singular_lines(b) for b in bodies], budget)
    if name == "adaptive":
        return AdaptivePair(bodies, mesh.theta)
    raise ValueError(f"two bodies are meshed by the package's strategies only (uniform, graded, adaptive), not {mesh.label!r}")
