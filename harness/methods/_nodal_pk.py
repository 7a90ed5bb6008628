"""The paper's nodal cone K~_h (Section 5) at degree k >= 3: v_h >= alpha at the vertices of
Gamma_C and at the k - 1 interior Gauss-Lobatto points of each contact edge. For k = 2 the one
interior point is the midpoint: `nodal`. The k + 1 points of an edge fix its degree-k trace, so
the rows are independent and the cone is a ``FunctionalCone`` (level 1 of the method protocol)
solved exactly by the general-constraint active set method on the projected multigrid.

Why Gauss-Lobatto points: they are the nodes of the well-conditioned Lagrange interpolant of
degree k on the edge (Lebesgue constant O(log k)), and their quadrature has positive weights, so
v_h >= alpha at them implies that the Gauss-Lobatto quadrature of v_h - alpha over each edge is
>= 0, the analogue of K~_h lying in K_h (Simpson's rule, the paper's Section 5).

Expected rate: no theorem covers k >= 3 (the paper's analysis, Theorems 5.1-5.2, and Drouet &
Hild 2015 stop at k = 2). The declared rate min(nu - 1, k) is a conjecture, the rate of the best
approximation; the report's verdict against it is a measurement, labelled so.
"""
import math

from ..fem.assembly import lobatto_points
from .base import DEGREES, Expectation, FunctionalCone

CONJECTURE = "conjecture (no theorem for k >= 3): the best approximation's min(nu - 1, k)"


def expected_for(order: int):
    def expected(case) -> Expectation:
        if case.nu <= 1.0 or math.isnan(case.nu):
            return Expectation(math.nan, 0.0, CONJECTURE)
        return Expectation(min(case.nu - 1.0, order), 0.0, CONJECTURE)
    return expected


def lobatto_rules(degree: int) -> tuple:
    """v_h >= alpha at each of the degree - 1 interior Gauss-Lobatto points of an edge of
    ``degree``: on an hp mesh each edge its own degree's points (``FunctionalCone.functionals_of``),
    the vertices and these fixing the edge's trace of that degree."""
    return tuple(((float(t), 1.0),) for t in lobatto_points(degree)[1:-1])


def at_order(order: int) -> FunctionalCone:
    return FunctionalCone(
        name=f"nodal-p{order}",
        order=order,
        contact=f"v_h >= 0 at the vertices and the {order - 1} interior Gauss–Lobatto points of each edge of Γ_C "
                "(on hp meshes, of each edge's own degree)",
        reference="Belhachmi & Ben Belgacem 2003, Section 5, at degree k",
        expected=expected_for(order),
        functionals_of=lobatto_rules,
        physics=("scalar", "elasticity"),
        roles=frozenset({DEGREES}),
    )
