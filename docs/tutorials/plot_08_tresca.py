"""
Tresca friction: stick and slip
===============================

A case with Tresca friction on Γ_C (:doc:`../theory/friction`): tresca-r32, u = s·y + r^{3/2}
cos(3θ/2) on (−1, 1) × (0, 1), which sticks (u = 0) on the left half of Γ_C and slips on the
right, with ∂ₙu = −s there. At the stick-slip point u carries r^{3/2}, as a contact-separation
point does: u ∈ H^{5/2−ε}, and the contact theorems read for friction expect h^{3/2} of P2 and h
of P1. The case declares ``friction = Tresca(threshold=1.0)``; the methods that discretise
Tresca's law declare it (``Method.friction``): the paper's two P2 ideas, ``nodal`` (Simpson's
quadrature of s|v| at Γ_C's P2 nodes) and ``mean`` (edge means, a P0 multiplier), and ``p1``.
"""

# %%
import tempfile
from pathlib import Path

import harness
from harness.report.sections.friction import stick_slip
from harness.study.chain.snapshots import contact_snapshot

LEVELS = 4
case = harness.registered_cases()["tresca-r32"]
print(case.friction.describe(), "on Γ_C;", case.description)

# %%
# Run the three methods for four levels. The ``on_level`` hook keeps each method's finest level
# along Γ_C (the slip u_h and the discrete friction force λ_h per edge, with the exact ones):
# what the report's stick/slip figure is drawn from. Every discrete problem is solved exactly
# (the bound-constrained dual by the primal-dual active set method): the largest KKT residual of
# the rows is printed.
finest = {}


def keep_finest(case, method, level, problem, solve):
    finest[method.name] = contact_snapshot(case, problem, solve.trace_u, solve.pressure)


rows = harness.run(case, methods=["nodal", "mean", "p1"], levels=LEVELS, show_progress=False, on_level=keep_finest)
print(f"{len(rows)} rows; largest KKT residual {rows.kkt_residual.max():.1e}")

# %%
# The fitted H¹ rate of each method over its last three levels, against the rate its theory
# expects: 3/2 for the P2 cones, 1 for P1 (the verdict says whether they meet within ±0.1).
rates = harness.rates(rows)
print(rates[["method", "expected_rate", "fitted_rate", "pairwise_rates", "verdict"]].to_string(index=False))

# %%
# The stick/slip picture (the report's, ``harness.report.sections.friction.stick_slip``): along
# Γ_C the slip u_h and the friction force λ_h = g_C − ∂ₙu_h against the threshold ±s, the exact
# ones dashed, the exact stick zone shaded; on the right, zoomed on the stick-slip point, where
# the discrete forces leave the threshold one edge apart.
figure = stick_slip(case, finest, Path(tempfile.mkdtemp()))
print(figure["png"].name)

# %%
# The same in the notebook or the documentation page: the PNG the report embeds.
import matplotlib.image as mpimg  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402

plt.figure(figsize=(11, 5.6))
plt.imshow(mpimg.imread(figure["png"]))
plt.axis("off")
plt.show()
