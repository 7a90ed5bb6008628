"""`nitsche-p1`: the `nitsche` method on P1 (same defaults; expected h^{min(nu - 1, 1)} for
nu > 3/2, CHR 2015 Theorem 3.8 with k = 1)."""
from harness.methods.base import WeakContact
from harness.methods.nitsche import GAMMA0, expected_for

method = WeakContact(
    name="nitsche-p1",
    order=1,
    contact="Nitsche, as `nitsche`, on P1",
    reference="Chouly & Hild 2013; Chouly, Hild & Renard 2015",
    expected=expected_for(1),
    flux=1.0, theta=1.0, gamma0=GAMMA0,
)
