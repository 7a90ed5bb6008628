"""
Bringing your own method
========================

A weak method given only by its contact law (the protocol's second level): the penalty method
with ε = ε₀h² instead of ε₀h. The harness checks the law (affine on each branch, its derivative
its own), solves the nonlinear system exactly with its semismooth Newton method, and measures it
beside the built-in methods. It declares no theory: its verdict is "no theory".
"""

# %%
from dataclasses import dataclass

import numpy as np

import harness
from harness.methods import ContactLawMethod


@dataclass(frozen=True)
class PenaltyH2:
    """p = (1/ε)[α − u]₊, f = 0, ε = ε₀h² at each Gauss point of Γ_C."""

    epsilon0: float = 0.05

    def branch(self, at):
        return at.gap - at.u > 0

    def term(self, at, branch):
        return np.where(branch, (at.gap - at.u) / (self.epsilon0 * at.h**2), 0.0), 0.0

    def derivative(self, at, branch):
        return np.where(branch, -1.0 / (self.epsilon0 * at.h**2), 0.0), 0.0, 0.0, 0.0


mine = ContactLawMethod(name="penalty-h2", order=2, contact="penalty, ε = ε₀h²", reference="this tutorial",
                        expected=None, law=PenaltyH2())

# %%
# Beside the built-in penalty method (ε = ε₀h) and the paper's ``nodal`` cone:
rows = harness.run("transition-r32", methods=[mine, "penalty", "nodal"], levels=4, show_progress=False)
finest = rows[rows.level == rows.level.max()]
print(finest[["method", "ndof", "err_h1", "max_penetration", "kkt_residual"]].to_string(index=False))
print(harness.rates(rows)[["method", "expected_rate", "fitted_rate", "verdict"]].to_string(index=False))
