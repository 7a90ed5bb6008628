"""`p1`: conforming P1 with v_h(x_i) >= 0 at the vertices of Gamma_C -- the classical linear
method. Its trace is linear on each contact edge, so the cone is exact: u_h >= 0 on all of
Gamma_C (no penetration between nodes, unlike K_h and K~_h).

Expected H^1 rate h^{min(nu - 1, 1)}, no log factor:
* F. Ben Belgacem, SIAM J. Numer. Anal. 37 (2000) 1198-1216, the paper's reference [3], which
  its Section 1 cites for the quasi-optimal analysis of linear elements; the paper (Section 2,
  after Remark 2.2) adds that affine elements cannot profit from regularity beyond H^2 ("the
  effective useful regularity is that of H^2"): the rate stops at 1. (Ben Belgacem 2000 itself
  was not read: its exact statements and regime assumptions are taken from the paper's summary.)
* G. Drouet and P. Hild, SIAM J. Numer. Anal. 53 (2015) 1488-1507: optimal H^1 estimates for
  linear (and quadratic) elements, 2D and 3D, "with the only standard Sobolev regularity" and
  no assumption on the contact set -- in particular order h for u in H^2 with P1, without the
  finite-transition assumption or a |log h| factor. (Read from the abstract only: its theorem
  numbers are not given here.)
"""
from ..fem.cones import ContactModel
from .base import BASELINE, DEGREES, MESH_STUDY, BoundConstrained, Expectation, drouet_hild_for


def expected(case) -> Expectation:
    return Expectation(min(case.nu - 1.0, 1.0), 0.0, REFERENCE)


REFERENCE = "Drouet & Hild 2015 (SINUM 53); Ben Belgacem 2000 (SINUM 37)"

method = BoundConstrained(
    name="p1",
    order=1,
    contact="v_h >= 0 at the vertices of Γ_C (exact: the trace is linear)",
    reference="Ben Belgacem 2000; Drouet & Hild 2015",
    expected=expected,
    sharper_theory=drouet_hild_for(1),
    cone=ContactModel(edge_functional=None),
    roles=frozenset({BASELINE, MESH_STUDY, DEGREES}),
)
