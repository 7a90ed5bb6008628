"""A contact law between two bodies, from a file (the method protocol's second level,
``harness.methods.TwoBodyLaw``): the harness's penalty law on the jumps. At each Gauss point of
the upper (slave) body's Γ_C the law sees the opening c₁ + c₂ against the gap α₁ + α₂ (in
elasticity, on a friction case, also the slip t₁ − t₂) and the slave's flux, as it sees the
contact variable of one body against a rigid obstacle; the harness solves both bodies at once by
semismooth Newton, residual recorded. The built-in ``mortar-nitsche`` is ``nitsche``'s law so.

``two-body-penalty``: p = [(α₁ + α₂ − c₁ − c₂)/ε]₊, ε = ε₀h/M (the penalty of Oden & Kikuchi on
the opening; on one body Chouly & Hild's h^{min(ν−1, 1)} for ν > 3/2). No theorem was read for two
bodies: it declares no rate ("no theory", grey) and the study measures one.

Run it::

    python -m harness run --case two-body-transition-r32 --method examples/methods/two_body_penalty.py --levels 3
"""
from harness.methods import Penalty, TwoBodyLaw

method = TwoBodyLaw(
    name="two-body-penalty",
    order=2,
    contact="the penalty [(α₁ + α₂ − c₁ − c₂)/ε]₊ on the opening between two bodies, ε = ε₀h",
    reference="Oden & Kikuchi (penalty); the harness's Penalty law on the jumps",
    expected=None,
    law=Penalty(epsilon0=0.05),
    friction=("frictionless", "tresca", "coulomb"),
)
