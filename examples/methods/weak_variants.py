"""Several methods in one file: pick one with ``path.py:name``::

    python -m harness run --case corner-r12 --method examples/methods/weak_variants.py:nitsche_skew --levels 4

(without ``:name`` every method of the file runs.) The skew-symmetric Nitsche variant θ = -1
is coercive for every γ₀ > 0 (Chouly, Hild & Renard 2015, Theorem 3.4); the stiffer penalty
ε = 0.01 h follows the constrained solution more closely (Chouly & Hild, Appl. Numer. Math. 2013).
"""
from dataclasses import replace

from harness.methods import get_method

nitsche_skew = replace(get_method("nitsche").with_parameters(theta=-1), name="nitsche-skew")
penalty_stiff = replace(get_method("penalty").with_parameters(epsilon0=0.01), name="penalty-stiff")
