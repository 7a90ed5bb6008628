"""The Nitsche family: `nitsche` (P2), `nitsche-p1`, and `nitsche-p3`, `nitsche-p4`
(``at_order``), each a ``protocol.ContactLawMethod`` (``methods``).

`nitsche`: P2 with Nitsche's treatment of the contact condition, the law (N) of ``fem.contact_laws.builtin``:
Chouly & Hild, SIAM J. Numer. Anal. 51 (2013) 1295-1307 (theta = 1, the scalar problem); the
variants theta = 0, -1 of Chouly, Hild & Renard, Math. Comp. 84 (2015) 1089-1112, whose eq. (10)
is (N) for elasticity (eps = gamma0 h_T). The same law runs on the scalar problem and on
elasticity, in 2D and 3D (``fem.contact_laws``: one law on the contact variable).

Default theta = 1, gamma0 = 0.05. theta = 1 is coercive only while gamma0 C_h < 1, C_h the largest
ratio of int (h/M) flux(v)^2 over Gamma_C to a(v, v) on X_h (CHR 2015 Theorem 3.4: "gamma0
sufficiently small"; M = lambda + 2 mu in elasticity, ``fem.contact_laws.builtin``): a discrete trace-inverse
constant of the order and the elements along Gamma_C, about 7 for P2 and 2 for P1 on the
registered cases, scalar and elastic alike (tests/test_weak_contact.py checks that 0.05 keeps a
factor 2.5 below the bound, also at lambda/mu = 49). The report's sweep shows the rest of the range.

Tresca friction (``problem.friction``): each method runs the Tresca law of its parameters
(``fem.contact_laws.tresca.NitscheTresca``: P_s(sigma_t(u) - u_t/gamma), the same theta and gamma; in
elasticity Nitsche's bilateral term for u . n = 0), expected h^{min(nu - 1, k)} for nu > 3/2
(``TRESCA_REFERENCE``).

Expected H^1 rate (``expected_for``): CHR 2015 Theorem 3.8 (stated for d = 2 and 3, k = 1 and 2,
every theta under Theorem 3.4's conditions; read through a detailed review of the paper, not its
text), u in H^{3/2 + m}, 0 < m <= k - 1/2, gives h^{1/2 + m}: h^{nu - 1} for 3/2 < nu <= k + 1,
capped at h^k beyond. Nothing is proven for nu <= 3/2 (corner-r12): no expected rate, the study
measures one.
"""
from dataclasses import replace

from ..fem.contact_laws.builtin import Nitsche
from .method import DEGREES, MESH_STUDY, SWEPT, Expectation, capped_expectation, no_result_below
from .method import REFERENCE as REFERENCE_ROLE
from .protocol import ContactLawMethod, TwoBodyLaw

REFERENCE = "Chouly & Hild 2013 (SINUM 51); Chouly, Hild & Renard 2015 (Math. Comp. 84), Thm 3.8"
GAMMA0 = 0.05


# k >= 3: the theorem above is stated for k <= 2; Gustafsson & Stenberg's abstract calls the method
# optimally convergent, and a third-party summary of arXiv 2505.21776 (sciencestack.ai) gives their
# estimate as ||u - u_h||_E <= C h^{s-1} ||u||_s for 1 <= s <= p + 1 at every degree p, with an
# edgewise penalty scaling (what of it was read: docs/theory/references.md)
REFERENCE_HIGH_ORDER = "Gustafsson & Stenberg 2025 (J. Struct. Mech. 58; abstract); CHR 2015 Thm 3.8 for k <= 2"


# Tresca friction (``fem.contact_laws.tresca.NitscheTresca``): F. Chouly, J. Math. Anal. Appl. 411
# (2014) 329-339, whose statement was not available to read here; the issue (74) gives it
# as h^{1/2+nu} for u in H^{3/2+nu}, as for contact, capped here as the contact rate is
TRESCA_REFERENCE = "Chouly 2014 (statement not read here): h^{1/2+nu} for u in H^{3/2+nu}"
# Coulomb friction (``fem.contact_laws.coulomb.NitscheCoulomb``): no rate theorem (existence for
# every mu_F, uniqueness for small mu_F only: Chouly, Hild, Lleras & Renard); the Tresca rate of
# the same regularity is what the rows are read against, as a conjecture
COULOMB_REFERENCE = "no theorem for Coulomb: Tresca's rate of the same regularity, conjectured"


def expected_for(order: int):
    reference = REFERENCE if order <= 2 else REFERENCE_HIGH_ORDER

    def expected(case) -> Expectation:
        cited = {"tresca": TRESCA_REFERENCE, "coulomb": COULOMB_REFERENCE}.get(case.friction.name, reference)
        return capped_expectation(case.nu, order, cited, 1.5, no_result_below(cited))
    return expected


def gamma0_for(order: int) -> float:
    """gamma0 of P_k, k >= 2: ``GAMMA0`` times (2/k)^2. The discrete trace-inverse constant C_h
    grows like k^2: on a simplex ||w||^2_{dT} <= (n + 1)(n + d)/d |dT|/|T| ||w||^2_T for w of
    degree n (Warburton & Hesthaven, CMAME 192 (2003) 2765-2773), here w = grad v of degree
    k - 1. So gamma0 C_h < 1 keeps P2's margin at every degree; tests/test_weak_contact.py
    measures C_h per order and checks the margin."""
    return GAMMA0 * (2.0 / order) ** 2


def at_order(order: int) -> ContactLawMethod:
    """`nitsche` on P_k (k >= 3): gamma0 scaled with the degree (``gamma0_for``), the rate
    min(nu - 1, k) (``expected_for``); in 2D and 3D, scalar and elastic."""
    return replace(method, name=f"nitsche-p{order}", order=order, contact=f"Nitsche, as `nitsche`, on P{order} (γ₀ = {gamma0_for(order):.4g})",
                   expected=expected_for(order), law=Nitsche(gamma0=gamma0_for(order), theta=1.0), roles=frozenset({DEGREES}))


method = ContactLawMethod(
    name="nitsche",
    order=2,
    contact="Nitsche: (1/ε)[ε ∂ₙu − (u − α)]₊ on Γ_C, ε = γ₀h (θ-variants; −σₙ, −u·n in elasticity)",
    reference="Chouly & Hild 2013; Chouly, Hild & Renard 2015",
    expected=expected_for(2),
    law=Nitsche(gamma0=GAMMA0, theta=1.0),
    # the reference of the cases the nodal cone does not discretise (3D Coulomb's): the first
    # method of the role that discretises a case is its reference (``measure.reference.reference_method``)
    roles=frozenset({SWEPT, MESH_STUDY, DEGREES, REFERENCE_ROLE}),
    friction=("frictionless", "tresca", "coulomb"),
)

# `nitsche-p1`: the `nitsche` method on P1 (same defaults; expected h^{min(nu - 1, 1)} for
# nu > 3/2, CHR 2015 Theorem 3.8 with k = 1)
p1 = replace(method, name="nitsche-p1", order=1, contact="Nitsche, as `nitsche`, on P1",
             expected=expected_for(1), roles=frozenset({DEGREES}))

# Between two bodies (``protocol.TwoBodyLaw``): the master-slave form of the same law on the jumps;
# no theorem read for it (Chouly, Mlika & Renard 2018 analyse the unbiased variant instead;
# ``fem.contact_laws.two_body``): the one-body rate, conjectured, as for the mortar methods
TWO_BODY_REFERENCE = "conjecture: the one-body Nitsche rate (master-slave Nitsche between two bodies)"


def two_body_expected(order: int):
    def expected(case) -> Expectation:
        return capped_expectation(case.nu, order, TWO_BODY_REFERENCE, 1.5, no_result_below(TWO_BODY_REFERENCE))
    return expected


# `mortar-nitsche`: two bodies on non-matching meshes, P2 on each, `nitsche`'s law (its gamma0
# and theta) on the jumps at Gauss points of the two trace meshes' common refinement, the
# slave's (upper body's) flux; frictionless, Tresca and Coulomb. `mortar-nitsche-p1`: on P1.
two_body = TwoBodyLaw(name="mortar-nitsche", order=2, contact="Nitsche on the jumps [u]ₙ, [u]ₜ between two bodies, the slave's σₙ (master-slave)",
                      reference="Chouly, Mlika & Renard 2018 (Numer. Math. 139), the biased form", expected=two_body_expected(2),
                      law=Nitsche(gamma0=GAMMA0, theta=1.0), friction=("frictionless", "tresca", "coulomb"))
two_body_p1 = replace(two_body, name="mortar-nitsche-p1", order=1, contact="Nitsche between two bodies, as `mortar-nitsche`, on P1",
                      expected=two_body_expected(1))

# the family's variants (``registry``): P3 and P4 with gamma0 scaled with the degree
# (``gamma0_for``), expected h^{min(nu - 1, k)} for nu > 3/2 (``expected_for``); the two-body ones
methods = [method, p1, at_order(3), at_order(4), two_body, two_body_p1]
