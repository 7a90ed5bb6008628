"""How a one-body chain's levels are meshed, discretised and solved (the ``walk.Discretisation``
of ``chain.run_chain``): the meshes of a level sequence (``mesh.levels``), a graded or adaptive
one within the uniform chain's budget of elements; beside them the P1 hierarchy of the
truncated multigrid; one ``fem.assembly.DiscreteProblem`` per finite element order, solved by
the method itself."""
from __future__ import annotations

from collections.abc import Iterator

from ...fem.assembly import discretise
from ...fem.element_quadrature import ElementQuadrature
from ...measure.estimator import ResidualEstimator
from ...measure.quantities import exact_quantities, quantities
from ...mesh.levels import Level, LevelSequence
from ...mesh.strategies import element_budget
from ...solvers.multigrid import Multilevel
from ..execution.threads import p2_size


def has_estimator(case, sequence: LevelSequence) -> bool:
    """Whether the rows get the residual estimator (``measure.estimator``,
    ``measure.estimator_3d``): in 2D on every mesh; in 3D where it drives or is set against the
    meshes, graded and adaptive ones. On uniform 3D meshes its set-up on the finest P1 level
    costs more than the solves of the whole study, and uniform rows there carry none. An hp mesh
    carries none (the estimator is written for one degree: its h_T / k weights are not hp's)."""
    if getattr(sequence, "variable_degree", False):
        return False
    return case.dimension == 2 or (case.dimension == 3 and getattr(sequence, "budgeted", True))


class OneBody:
    """The levels of ``case`` on ``sequence``'s meshes. A graded or adaptive chain stops before
    its mesh has more elements than the uniform level ``levels`` - 1 (+ ``extra_levels``, P1's):
    the same budget of dofs."""

    def __init__(self, case, sequence: LevelSequence, levels: int, extra_levels: int):
        self.case, self.sequence = case, sequence
        self.budget_levels, self.extra_levels = levels, extra_levels
        # the P1 hierarchy of the truncated multigrid (where the physics has one: ``physics``;
        # nested meshes only: its prolongations are the refinement's); else the solves factorise
        self.hierarchical = case.physics.multigrid and sequence.nested
        self.estimating = has_estimator(case, sequence)
        self.adaptive = sequence.adaptive
        self._multilevel = None
        self._exact = (None, {})        # (the level's quadrature, its exact quantities): one per level
        self._degrees = (None, None)    # (the level's mesh, its elements' degrees: hp meshes)

    def levels(self, count: int) -> Iterator[Level]:
        budget_elements = None
        for index, step in enumerate(self.sequence.levels(count)):
            if getattr(self.sequence, "budgeted", True):
                # the uniform finest level's number of triangles (of the coarse mesh times 4 per
                # level): graded and adaptive meshes get the same budget of dofs
                if budget_elements is None:
                    budget_elements = element_budget(self.case, self.budget_levels, self.extra_levels)
                    # a sequence that can tell a level past the budget before making it
                    # (``mesh.bisection.AdaptiveRefinement``) is told the budget
                    if hasattr(self.sequence, "limit_elements"):
                        self.sequence.limit_elements(budget_elements)
                if index and step.mesh.ne > budget_elements:
                    return
            self._degrees = (step.mesh, step.degrees)
            yield step

    def size(self, mesh) -> int:
        return p2_size(mesh)

    def multilevel(self, level: Level):
        if self.hierarchical:
            self._multilevel = Multilevel(level.mesh, self.case.physics) if self._multilevel is None else \
                self._multilevel.refined(level.mesh, level.prolongation)
        return self._multilevel

    def quadrature(self, mesh) -> ElementQuadrature:
        return ElementQuadrature.of(self.case, mesh)

    def discretise(self, order: int, mesh, quadrature):
        degrees = self._degrees[1] if self._degrees[0] is mesh else None
        return discretise(self.case, mesh, order, quadrature, degrees)

    def solve(self, method, problem, carry, multilevel, last_of_order: bool, phases):
        # the level's last method of its order may take the stiffness matrix
        return method.solve(self.case, problem, carry, multilevel, take_stiffness=last_of_order, phases=phases)

    def estimator(self, problem) -> ResidualEstimator:
        return ResidualEstimator(self.case, problem)

    def observe(self, indicators) -> None:
        if self.sequence.adaptive:
            self.sequence.observe(indicators)

    def quantities(self, problem, u, quadrature, previous=None) -> dict:
        columns = quantities(self.case, problem, u, previous)
        if not self.case.exact:
            return columns
        if self._exact[0] is not quadrature:
            self._exact = (quadrature, exact_quantities(self.case, problem))
        return columns | self._exact[1]
