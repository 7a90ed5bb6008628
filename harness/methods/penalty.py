"""The penalty family: `penalty` (P2), `penalty-p1`, and `penalty-p3`, `penalty-p4`
(``at_order``), each a ``protocol.ContactLawMethod`` (``methods``).

`penalty`: P2, u_h minimises 1/2 a(v,v) - L(v) + (1/2 eps) int_{Gamma_C} [alpha - c(v)]_+^2 over
X_h, eps = eps0 h (the law (P) of ``fem.contact_laws.builtin``, c the contact variable: u, or -u . n in
elasticity, 2D and 3D); Chouly & Hild, Appl. Numer. Math. 65 (2013) 27-40.

Default eps0 = 0.05, the scale of `nitsche`'s gamma0 (``python -m harness sweep`` shows others).

Tresca friction (``problem.friction``): the Tresca law of the same eps
(``fem.contact_laws.tresca.PenaltyTresca``: P_s(-u_t/eps), a Huber-regularised |u_t|; in elasticity
the penalty of u . n = 0), expected h^{min(nu - 1, 1)} as below (``TRESCA_REFERENCE``).

Expected H^1 rate: h^{min(nu - 1, 1)} for nu > 3/2, for P1 and P2. Chouly & Hild (abstract): with
eps = h the error estimates are "the same as in the case of the constrained problem"; their
analysis covers u in H^{3/2 + m}, 0 < m <= 1/2 (the abstract was read; the range is recalled,
not checked against the theorem's text, whose number is not given here). Beyond H^2 nothing better holds: the method is not consistent --
in contact u_h sits about eps lambda = eps0 h lambda below the obstacle, an H^1 error of order h
whatever the order of the elements (Gustafsson & Stenberg, J. Struct. Mech. 58 (2025), abstract:
"an optimal convergence rate cannot be achieved"). Nothing is proven for nu <= 3/2.
"""
from dataclasses import replace

from ..fem.contact_laws.builtin import Penalty
from .method import SWEPT, Expectation, capped_expectation, no_result_below
from .nitsche import COULOMB_REFERENCE
from .protocol import ContactLawMethod

REFERENCE = "Chouly & Hild 2013 (Appl. Numer. Math. 65), eps = eps0 h"
EPS0 = 0.05


# Tresca friction (``fem.contact_laws.tresca.PenaltyTresca``): J. Dione, JMAA 2019, read from its
# abstract only: O(h^{1/2+nu} + eps^{1/2+nu}) in P1; with eps ~ h, nu <= 1/2, the same cap at h
TRESCA_REFERENCE = "Dione 2019 (abstract read): O(h^{1/2+nu} + eps^{1/2+nu}) for P1, eps = eps0 h"


def expected(case) -> Expectation:
    cited = {"tresca": TRESCA_REFERENCE, "coulomb": COULOMB_REFERENCE}.get(case.friction.name, REFERENCE)
    return capped_expectation(case.nu, 1.0, cited, 1.5, no_result_below(cited))


def at_order(order: int) -> ContactLawMethod:
    """`penalty` on P_k (k >= 3): the same eps0 and expected rate (the cap at h is the
    consistency error's, not the degree's)."""
    return replace(method, name=f"penalty-p{order}", order=order, contact=f"penalty, as `penalty`, on P{order}",
                   roles=frozenset())


method = ContactLawMethod(
    name="penalty",
    order=2,
    contact="penalty: (1/ε)[α − u]₊ on Γ_C, ε = ε₀h",
    reference="Chouly & Hild 2013 (Appl. Numer. Math.)",
    expected=expected,
    law=Penalty(epsilon0=EPS0),
    roles=frozenset({SWEPT}),
    friction=("frictionless", "tresca", "coulomb"),
)

# `penalty-p1`: the `penalty` method on P1 (same default eps0, same expected rate)
p1 = replace(method, name="penalty-p1", order=1, contact="penalty, as `penalty`, on P1", roles=frozenset())

# the family's variants (``registry``): on P3 and P4 the same eps0 (``at_order``): the
# consistency error eps lambda = O(h) caps the rate at h whatever the degree, which they show plainly
methods = [method, p1, at_order(3), at_order(4)]
