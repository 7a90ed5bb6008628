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
import matplotlib.pyplot as plt
import numpy as np

import harness

LEVELS = 4
case = harness.registered_cases()["tresca-r32"]
print(case.friction.describe(), "on Γ_C;", case.description)

# %%
# Run the three methods for four levels. The ``on_level`` hook keeps each method's finest level
# along Γ_C: its trace u_h (``solve.trace_u``, sampled along each contact edge) and its discrete
# flux per edge (``solve.pressure``: here the friction force, ∂ₙu_h − g_C, mean per edge). Every discrete problem is solved exactly
# (the bound-constrained dual by the primal-dual active set method): the largest KKT residual of
# the rows is printed.
finest = {}


def keep_finest(case, method, level, problem, solve):
    t = np.linspace(0.0, 1.0, 9)
    trace = solve.trace_u
    x = (trace.a[:, None, 0] + t * (trace.b - trace.a)[:, None, 0]).ravel()
    order = np.argsort(x, kind="stable")
    middle = 0.5 * (trace.a[:, 0] + trace.b[:, 0])
    finest[method.name] = {"x": x[order], "u": trace.at(t).ravel()[order],
                           "edge_x": np.sort(middle), "force": solve.pressure[np.argsort(middle)]}


rows = harness.run(case, methods=["nodal", "mean", "p1"], levels=LEVELS, show_progress=False, on_level=keep_finest)
print(f"{len(rows)} rows; largest KKT residual {rows.kkt_residual.max():.1e}")

# %%
# The fitted H¹ rate of each method over its last three levels, against the rate its theory
# expects: 3/2 for the P2 cones, 1 for P1 (the verdict says whether they meet within ±0.1).
rates = harness.rates(rows)
print(rates[["method", "expected_rate", "fitted_rate", "pairwise_rates", "verdict"]].to_string(index=False))

# %%
# The stick/slip picture (the report draws it for every friction case): along Γ_C the slip u_h
# and the friction force λ_h = ∂ₙu_h − g_C per edge against the threshold ±s, the exact ones
# dashed: u = x^{3/2} and ∂ₙu = −s on the slip side, u = 0 and ∂ₙu = −s + (3/2)|x|^{1/2} on the
# stick side.
x = np.linspace(-1.0, 1.0, 801)
exact_u = np.where(x > 0, np.abs(x) ** 1.5, 0.0)
exact_force = np.where(x > 0, -1.0, -1.0 + 1.5 * np.sqrt(np.abs(x)))
fig, (top, bottom) = plt.subplots(2, 1, sharex=True, figsize=(8, 5.5))
top.plot(x, exact_u, "k--", lw=1, label="exact u")
bottom.plot(x, exact_force, "k--", lw=1, label="exact λ = ∂ₙu")
for name, kept in finest.items():
    top.plot(kept["x"], kept["u"], lw=1.1, label=f"{name}: $u_h$")
    bottom.step(kept["edge_x"], kept["force"], where="mid", lw=1.1, label=f"{name}: $\\lambda_h$")
for bound in (1.0, -1.0):
    bottom.axhline(bound, color="0.5", ls=":", lw=1.2)
for ax in (top, bottom):
    ax.axvspan(-1.0, 0.0, color="0.85", alpha=0.6, lw=0)
    ax.grid(True, alpha=0.25)
    ax.legend(fontsize=7)
top.set_ylabel("slip $u_h$")
bottom.set_ylabel("friction force")
bottom.set_xlabel("x along Γ_C (shaded: the stick zone; dotted: ±s)")
plt.show()
