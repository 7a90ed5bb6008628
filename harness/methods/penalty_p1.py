"""`penalty-p1`: the `penalty` method on P1 (same default eps0, same expected rate)."""
from harness.methods.base import WeakContact
from harness.methods.penalty import EPS0, expected

method = WeakContact(
    name="penalty-p1",
    order=1,
    contact="penalty, as `penalty`, on P1",
    reference="Chouly & Hild 2013 (Appl. Numer. Math.)",
    expected=expected,
    flux=0.0, gamma0=EPS0, parameter_names=("epsilon0",),
)
