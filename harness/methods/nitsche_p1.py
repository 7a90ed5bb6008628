"""`nitsche-p1`: the `nitsche` method on P1 (same defaults; expected h^{min(nu - 1, 1)} for
nu > 3/2, CHR 2015 Theorem 3.8 with k = 1)."""
from dataclasses import replace

from . import nitsche
from .base import DEGREES

method = replace(nitsche.method, name="nitsche-p1", order=1, contact="Nitsche, as `nitsche`, on P1",
                 expected=nitsche.expected_for(1), roles=frozenset({DEGREES}))
