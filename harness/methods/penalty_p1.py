"""`penalty-p1`: the `penalty` method on P1 (same default eps0, same expected rate)."""
from dataclasses import replace

from . import penalty

method = replace(penalty.method, name="penalty-p1", order=1, contact="penalty, as `penalty`, on P1",
                 roles=frozenset())
