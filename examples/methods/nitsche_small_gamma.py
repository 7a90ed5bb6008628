"""A method of your own, in a file outside the harness: Nitsche's method (P2, θ = 1) with
γ₀ = 0.02 where the harness's `nitsche` takes 0.05 (Chouly, Hild & Renard, Math. Comp. 84
(2015), Theorem 3.4: θ = 1 is coercive for γ₀ small enough; a smaller γ₀ keeps more margin and
penalises less). Run it by its path::

    python -m harness run --case transition-r32 --method examples/methods/nitsche_small_gamma.py --levels 4

It is checked, solved, measured and rated as the registered methods are; its name is the one
its rows carry.
"""
from dataclasses import replace

from harness.methods import get_method

method = replace(get_method("nitsche").with_parameters(gamma0=0.02), name="nitsche-g002",
                 reference="Chouly, Hild & Renard 2015, Thm 3.8 (γ₀ = 0.02)")
