"""A mesh strategy of your own, in a file outside the harness: Remark 4.4's graded meshes with
the grading exponent you choose. The harness's `graded` takes μ just below λ/k (Apel, Sändig &
Whiteman 1996: order-k elements reach N^{-k/2} near an r^λ singularity when h_T ≈ H r^{1-μ}
with μ < λ/k); a smaller μ grades harder, spending dofs near the singular points. Run it::

    python -m harness run --case corner-r12 --method nodal --mesh examples/meshes/strong_grading.py --levels 5

A strategy is any object with a ``label`` (the rows' ``mesh`` column), ``applies_to(case)``
(None, or why not), ``group_key(method)`` (methods with equal keys share a sequence) and
``sequence(case, order)`` (a ``harness.mesh.LevelSequence``).
"""
from dataclasses import dataclass

from harness.mesh import GradedRefinement, MeshStrategy, singular_lines, singular_points


@dataclass(frozen=True)
class Grading:
    mu: float

    @property
    def label(self) -> str:
        return f"graded-mu{self.mu:g}"

    def applies_to(self, case):
        return MeshStrategy("graded").applies_to(case)

    def group_key(self, method):
        return method.order         # the grading does not depend on k here, but its budget does

    def sequence(self, case, order: int):
        return GradedRefinement(case, case.nu - 1.0, order, singular_points(case), singular_lines(case), mu=self.mu)


strategy = Grading(mu=0.1)
