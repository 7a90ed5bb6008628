"""
Graded and adaptive meshes
==========================

On ``corner-r12`` (u ~ r^{1/2} at a corner of Γ_C: ν = 3/2) uniform refinement gives the
rate N^{-1/4} in the number of dofs whatever the order. A mesh graded towards the singular
point (Remark 4.4) or refined adaptively by the residual estimator (Dörfler marking) recovers
the optimal N^{-k/2}.
"""

# %%
import harness

rows = harness.run("corner-r12", methods=["nodal", "p1"], levels=4, meshes=["uniform", "graded", "adaptive"],
                   show_progress=False)
rates = harness.rates(rows)
print(rates[["mesh", "method", "fitted_rate_ndof", "optimal_rate_ndof", "ndof_verdict", "effectivity_finest"]]
      .to_string(index=False))

# %%
# The finest adaptive level of each method: its dofs and the estimator's effectivity
# (η / energy error; between 1 and 10 on every level of the exact cases):
adaptive = rows[rows["mesh"] == "adaptive"]
print(adaptive.groupby("method")[["ndof", "effectivity"]].last().to_string())
