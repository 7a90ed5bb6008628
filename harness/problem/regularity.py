"""The H^1 rate a case's regularity allows: u in H^{nu - eps} is approximated at h^{nu - 1} on
uniform meshes, up to a cap (the degree k of P_k, or a consistency error). One helper for every
expected rate of that form (the methods' theories, the Ritz projection's rate): imports nothing."""
from __future__ import annotations

import math


def capped_rate(nu: float, cap: float, cutoff: float | None = None) -> float:
    """min(nu - 1, cap), or NaN where ``nu <= cutoff`` (a theory that says nothing there). A NaN
    ``nu`` (a case without a declared regularity) gives NaN."""
    if cutoff is not None and nu <= cutoff:
        return math.nan
    return min(nu - 1.0, cap)
