"""`p1`: conforming P1 with v_h(x_i) >= 0 at the vertices of Gamma_C -- the classical linear
method. Its trace is linear on each contact edge, so the cone is exact: u_h >= 0 on all of
Gamma_C (no penetration between nodes, unlike K_h and K~_h).

Expected H^1 rate h^{min(nu - 1, 1)}:
REFERENCES
"""
from harness.methods.base import BoundConstrained, Expectation
from harness.models import ContactModel


def expected(case) -> Expectation:
    return Expectation(min(case.nu - 1.0, 1.0), 0.0, REFERENCE)


REFERENCE = "REF"

method = BoundConstrained(
    name="p1",
    order=1,
    contact="v_h >= 0 at the vertices of Γ_C (exact: the trace is linear)",
    reference="Ben Belgacem 2000; Drouet & Hild 2015",
    expected=expected,
    cone=ContactModel(edge_functional=None),
)
