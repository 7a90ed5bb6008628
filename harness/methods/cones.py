"""The cones: the paper's models and the P1 method as exact discrete inequalities on Gamma_C,
of every degree. A cone of nodal functionals (``BoundConstrained``: bounds after a local change
of variables) or of general rows (``CellMean`` in 3D; ``protocol.FunctionalCone`` for the
degrees k >= 3), solved exactly (KKT <= 1e-10).

The variants (``methods``): ``mean`` and ``nodal`` (the paper's P2 models, K_h and K~_h),
``mean-edges`` (the 3D counterexample), ``p1`` (the classical linear method), and the two
models at degree k >= 3 (``nodal_at_order``, ``mean_at_order``).
"""
import math
from dataclasses import dataclass

import numpy as np

from ..fem.cones import ContactModel, contact_pressure, contact_qp
from ..fem.face_means import face_mean_qp
from ..fem.friction import friction_qp
from ..fem.nested import start_from
from ..fem.polynomials import lobatto_points
from ..solvers.bound_constraints import solve_contact_qp
from .coulomb_cones import solve_coulomb_cone
from .method import (
    BASELINE,
    DEGREES,
    MESH_STUDY,
    PAPER,
    REFERENCE,
    Expectation,
    LevelSolve,
    Method,
    capped_expectation,
    no_result_below,
    timer,
)
from .protocol import FunctionalCone, exact_level, solve_general_rows, solve_tresca


@dataclass(frozen=True)
class BoundConstrained(Method):
    """A cone of nodal functionals (``fem.cones.ContactModel``), solved exactly (KKT <= 1e-10) by
    the active set method with the truncated multigrid; nested iteration carries the coarser
    level's trace (active set prediction) and vertex values (CG start) to the next level."""

    cone: ContactModel = ContactModel()
    # a cone of the contact variable: u_h, or -u_h . n in the rotated frame (Remark 2.3)
    physics: tuple = ("scalar", "elasticity")
    # in 3D the same cones, edge by edge on the triangles of Gamma_C (``fem.cones``)
    dimensions: tuple = (2, 3)

    def refusal(self, case) -> str | None:
        """Also: Tresca's (and Coulomb's) elastic slip in 3D is a 2-vector whose set is a disc, not two bounds."""
        if case.frictional and case.physics.rotated_frame and case.dimension == 3 and case.friction.name in self.friction:
            return f"its {case.friction.name.capitalize()} rows are bounds; the 3D elastic slip is a 2-vector in a disc " \
                   "(a contact law solves it)"
        return super().refusal(case)

    def solve(self, case, problem, carry, multilevel, take_stiffness: bool = False, phases=None) -> LevelSolve:
        if case.friction.name == "coulomb":
            return solve_coulomb_cone(case, problem, self.cone, carry, multilevel, phases, self.solver)
        if case.frictional:
            return solve_tresca(case, problem, lambda: friction_qp(case, problem, self.cone), carry, multilevel, phases,
                                self.solver)
        timed = timer(phases)
        with timed("setup"):
            qp = contact_qp(case, problem, self.cone, take_stiffness=take_stiffness)
            start = start_from(carry, multilevel, problem)
            predicted = qp.predicted_active(None if carry is None else carry.trace)
        with timed("solve"):
            solution = solve_contact_qp(qp, predicted, multilevel=multilevel, start=start, options=self.solver)
        u = qp.to_u(solution.z)
        trace_u = qp.trace_function(u, solution.active)
        return exact_level(case, problem, u, trace_u, contact_pressure(problem, solution.multipliers), solution)


@dataclass(frozen=True)
class CellMean(BoundConstrained):
    """The paper's K_h on the cells of Gamma_C: v_h >= alpha at its vertices and the mean of
    v_h - alpha >= 0 over each cell. In 2D a cell is an edge and the cone is bounds after a
    local change of variables (``fem.cones``, the ``BoundConstrained`` path); in 3D a cell is a
    triangle, whose P2 mean is the average of its three edge-midpoint values, and the rows
    stay general (``face_means``): solved by the general-constraint active set method with the
    constrained multigrid (``solvers.projected_multigrid``), or by SuperLU without a hierarchy."""

    def refusal(self, case) -> str | None:
        """Also: Tresca on the 3D triangle means (general rows) is not implemented."""
        if case.frictional and case.dimension == 3 and case.friction.name in self.friction:
            return f"its 3D triangle means are general rows, on which {case.friction.name.capitalize()} friction is not implemented"
        return super().refusal(case)

    def solve(self, case, problem, carry, multilevel, take_stiffness: bool = False, phases=None) -> LevelSolve:
        if problem.trace.faces is None:
            return super().solve(case, problem, carry, multilevel, take_stiffness, phases)
        return solve_general_rows(case, problem, carry, multilevel, phases,
                                  lambda: face_mean_qp(case, problem, take_stiffness=take_stiffness), self.solver)


# Tresca friction (``problem.friction``): no error analysis of the P2 models' friction analogues
# (the nodal quadrature of j, the edge means) was available to read here; a Tresca case declares
# the rate of the paper's theorems for its regularity, the best approximation's, read as a
# conjecture the verdicts test
FRICTION_CONJECTURE = "conjecture: the paper's rate for the same regularity (no theorem for the friction analogues)"


def paper_theorem(case) -> Expectation:
    """The rate the case declares from the paper's theorems (Theorems 4.1, 4.2, 5.1, 5.2,
    Remark 4.9): the same for both P2 models; on a Tresca case a conjecture
    (``FRICTION_CONJECTURE``)."""
    if case.frictional:
        return Expectation(case.expected_rate, case.expected_log_exponent, FRICTION_CONJECTURE)
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
        if case.frictional:
            return Expectation(math.nan, 0.0, f"{DROUET_HILD}: frictionless contact only")
        return capped_expectation(case.nu, DROUET_HILD_CAP[order], DROUET_HILD, 1.5, no_result_below(DROUET_HILD))
    return drouet_hild


# `mean`: the paper's first model, K_h of Section 3 -- P2 with v_h(x_i) >= 0 at the vertices of
# Gamma_C and int_{t_i} v_h >= 0 on every cell t_i of Gamma_C (3.6), the degrees of freedom of
# J_h. A cell is an edge in 2D (Section 3) and a triangle in 3D (Section 6 leaves 3D open; on a
# triangle the P2 mean is the average of the three edge-midpoint values, so its rows are general:
# ``CellMean``). Rates: Theorems 4.1 and 4.2 (and Remark 4.9), declared by each case; in 3D no
# theorem covers it (the 2D rate is the expectation).
mean = CellMean(
    name="mean",
    order=2,
    contact="v_h >= 0 at the vertices of Γ_C, ∫ v_h >= 0 on its edges (2D, K_h (3.6)) or triangles (3D)",
    reference="Belhachmi & Ben Belgacem 2003, Section 3",
    expected=paper_theorem,
    sharper_theory=drouet_hild_for(2),
    cone=ContactModel(edge_functional="edge-mean"),
    roles=frozenset({PAPER}),
    friction=("frictionless", "tresca", "coulomb"),
)

# `mean-edges`: the counterexample -- K_h extended to 3D edge by edge: v_h >= 0 at the vertices
# of Gamma_C and int_e v_h >= 0 on every *edge* of its triangles (bounds after the 2D change of
# variables, ``fem.cones``). Edge means do not control the trace inside the triangles: a function
# whose edge means and vertex values vanish may still dip below the obstacle in every triangle,
# and the H^1 rate stalls near 1/2 on transition-line-3d (the 3D report shows it). It is kept,
# with the paper's 2D rate as its expectation, to show that the 3D `mean` has to constrain the
# triangles (``CellMean``).
mean_edges = BoundConstrained(
    name="mean-edges",
    order=2,
    contact="v_h >= 0 at the vertices of Γ_C, ∫ v_h >= 0 on the edges of its triangles (3D; the counterexample)",
    reference="the 2D K_h of Belhachmi & Ben Belgacem 2003 applied edge by edge",
    expected=paper_theorem,
    dimensions=(3,),
    cone=ContactModel(edge_functional="edge-mean"),
)

# `nodal`: the paper's second model, K~_h of Section 5 -- P2 with v_h >= 0 at the vertices and
# the edge midpoints of Gamma_C (before (5.1)), the degrees of freedom of the Lagrange
# interpolant I_h. K~_h lies in K_h (Simpson's rule). Rates: Theorems 5.1 and 5.2, the same as
# for `mean`, declared by each case.
nodal = BoundConstrained(
    name="nodal",
    order=2,
    contact="v_h >= 0 at the vertices and edge midpoints of Γ_C (K̃_h, (5.1))",
    reference="Belhachmi & Ben Belgacem 2003, Section 5",
    expected=paper_theorem,
    sharper_theory=drouet_hild_for(2),
    cone=ContactModel(edge_functional="midpoint"),
    roles=frozenset({PAPER, REFERENCE, MESH_STUDY, DEGREES}),
    friction=("frictionless", "tresca", "coulomb"),
)

# `p1`: conforming P1 with v_h(x_i) >= 0 at the vertices of Gamma_C -- the classical linear
# method. Its trace is linear on each contact edge, so the cone is exact: u_h >= 0 on all of
# Gamma_C (no penetration between nodes, unlike K_h and K~_h).
#
# Expected H^1 rate h^{min(nu - 1, 1)}, no log factor:
# * F. Ben Belgacem, SIAM J. Numer. Anal. 37 (2000) 1198-1216, the paper's reference [3], which
#   its Section 1 cites for the quasi-optimal analysis of linear elements; the paper (Section 2,
#   after Remark 2.2) adds that affine elements cannot profit from regularity beyond H^2 ("the
#   effective useful regularity is that of H^2"): the rate stops at 1. (Its statements and regime
#   assumptions are taken from the paper's summary: docs/theory/references.md.)
# * G. Drouet and P. Hild, SIAM J. Numer. Anal. 53 (2015) 1488-1507: optimal H^1 estimates for
#   linear (and quadratic) elements, 2D and 3D, "with the only standard Sobolev regularity" and
#   no assumption on the contact set -- in particular order h for u in H^2 with P1, without the
#   finite-transition assumption or a |log h| factor. (Read from the abstract only: its theorem
#   numbers are not given here.)
P1_REFERENCE = "Drouet & Hild 2015 (SINUM 53); Ben Belgacem 2000 (SINUM 37)"


# P1 for Tresca: h^{min(nu - 1, 1)}, the best approximation's rate in H^1 (the P1 analyses of
# Tresca's problem, Nitsche's of Chouly 2014 and the penalty's of Dione 2019, were read from their
# abstracts only: h^{1/2 + nu} for u in H^{3/2 + nu}, 0 < nu <= 1/2)
P1_TRESCA = "P1 for Tresca: the best approximation's h^min(ν−1, 1) (Chouly 2014, Dione 2019: abstracts only)"


# P1 for Coulomb: no theorem (the discrete problem's uniqueness holds for small mu_F only); the
# best approximation's rate, conjectured, as for the P2 cones (``FRICTION_CONJECTURE``)
P1_COULOMB = "P1 for Coulomb: the best approximation's h^min(ν−1, 1), conjectured (no theorem for Coulomb)"


def p1_expected(case) -> Expectation:
    cited = {"tresca": P1_TRESCA, "coulomb": P1_COULOMB}.get(case.friction.name, P1_REFERENCE)
    return capped_expectation(case.nu, 1.0, cited)


p1 = BoundConstrained(
    name="p1",
    order=1,
    contact="v_h >= 0 at the vertices of Γ_C (exact: the trace is linear)",
    reference="Ben Belgacem 2000; Drouet & Hild 2015",
    expected=p1_expected,
    sharper_theory=drouet_hild_for(1),
    cone=ContactModel(edge_functional=None),
    roles=frozenset({BASELINE, MESH_STUDY, DEGREES}),
    friction=("frictionless", "tresca", "coulomb"),
)


# The paper's nodal cone K~_h (Section 5) at degree k >= 3: v_h >= alpha at the vertices of
# Gamma_C and at the k - 1 interior Gauss-Lobatto points of each contact edge. For k = 2 the one
# interior point is the midpoint: `nodal`. The k + 1 points of an edge fix its degree-k trace, so
# the rows are independent and the cone is a ``FunctionalCone`` (level 1 of the method protocol)
# solved exactly by the general-constraint active set method on the projected multigrid.
#
# Why Gauss-Lobatto points: they are the nodes of the well-conditioned Lagrange interpolant of
# degree k on the edge (Lebesgue constant O(log k)), and their quadrature has positive weights, so
# v_h >= alpha at them implies that the Gauss-Lobatto quadrature of v_h - alpha over each edge is
# >= 0, the analogue of K~_h lying in K_h (Simpson's rule, the paper's Section 5).
#
# Expected rate: no theorem covers k >= 3 (the paper's analysis, Theorems 5.1-5.2, and Drouet &
# Hild 2015 stop at k = 2). The declared rate min(nu - 1, k) is a conjecture, the rate of the best
# approximation; the report's verdict against it is a measurement, labelled so.
CONJECTURE = "conjecture (no theorem for k >= 3): the best approximation's min(nu - 1, k)"


def conjectured_for(order: int):
    """The expectation of a cone of degree k >= 3: the conjecture min(nu - 1, k) (NaN for
    nu <= 1 and for a case without nu)."""
    def expected(case) -> Expectation:
        return capped_expectation(case.nu, order, CONJECTURE, 1.0)
    return expected


def lobatto_rules(degree: int) -> tuple:
    """v_h >= alpha at each of the degree - 1 interior Gauss-Lobatto points of an edge of
    ``degree``: on an hp mesh each edge its own degree's points (``FunctionalCone.functionals_of``),
    the vertices and these fixing the edge's trace of that degree."""
    return tuple(((float(t), 1.0),) for t in lobatto_points(degree)[1:-1])


def nodal_at_order(order: int) -> FunctionalCone:
    """`nodal-pk`: P_k with v_h >= alpha at the vertices and the k - 1 interior Gauss-Lobatto
    points of each contact edge: the paper's K~_h (Section 5) at degree k."""
    return FunctionalCone(
        name=f"nodal-p{order}",
        order=order,
        contact=f"v_h >= 0 at the vertices and the {order - 1} interior Gauss–Lobatto points of each edge of Γ_C "
                "(on hp meshes, of each edge's own degree)",
        reference="Belhachmi & Ben Belgacem 2003, Section 5, at degree k",
        expected=conjectured_for(order),
        functionals_of=lobatto_rules,
        physics=("scalar", "elasticity"),
        friction=("frictionless", "tresca"),
        roles=frozenset({DEGREES}),
    )


# The paper's mean cone K_h (Section 3, (3.6)) at degree k >= 3: v_h >= alpha at the vertices of
# Gamma_C and the mean of v_h - alpha >= 0 over each of k - 1 equal sub-edges of every contact
# edge. For k = 2 the one sub-edge is the edge: `mean` (tests/test_degree.py solves both and finds
# the same u_h). A ``FunctionalCone`` (level 1 of the method protocol), its rules given per degree
# (``functionals_of``), so that on an hp mesh each edge has its own degree's sub-edges.
#
# Why sub-edge means, not moments. K_h asks for a mean of the trace where K~_h asks for values: an
# average of v_h - alpha >= 0, the weak form of v_h >= alpha that the paper's mean model uses.
# Moments against polynomials of degree >= 1 are not averages (they change sign) and bound
# nothing; means over k - 1 sub-edges are averages, and with the two vertex rows they are k + 1
# functionals that fix the edge's degree-k trace (independent rows: the projected multigrid serves
# them, as for the nodal cone). Each sub-edge mean is a Gauss rule exact for degree k
# (ceil((k + 1) / 2) points).
#
# Expected rate: no theorem covers k >= 3; the declared min(nu - 1, k) is a conjecture, as for the
# nodal cone of degree k (``conjectured_for``).
def sub_edge_means(degree: int) -> tuple:
    """The means over the degree - 1 equal sub-edges of an edge (one for degree <= 2: the edge)."""
    pieces = max(degree - 1, 1)
    t, w = np.polynomial.legendre.leggauss(math.ceil((degree + 1) / 2))
    t, w = 0.5 * (t + 1.0), 0.5 * w
    return tuple(tuple((float((j + x) / pieces), float(y)) for x, y in zip(t, w)) for j in range(pieces))


def mean_at_order(order: int) -> FunctionalCone:
    """`mean-pk`: P_k with v_h >= alpha at the vertices and the mean of v_h - alpha >= 0 over the
    k - 1 equal sub-edges of each contact edge: the paper's K_h (Section 3) at degree k."""
    return FunctionalCone(
        name=f"mean-p{order}",
        order=order,
        contact=f"v_h >= 0 at the vertices and ∫ v_h >= 0 over the {order - 1} equal sub-edges of each edge of Γ_C "
                "(on hp meshes, of each edge's own degree)",
        reference="Belhachmi & Ben Belgacem 2003, Section 3, at degree k",
        expected=conjectured_for(order),
        functionals_of=sub_edge_means,
        physics=("scalar", "elasticity"),
        friction=("frictionless", "tresca"),
    )


# the family's variants (``registry``)
methods = [mean, mean_edges, nodal, p1, nodal_at_order(3), nodal_at_order(4), mean_at_order(3), mean_at_order(4)]
