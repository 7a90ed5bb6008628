"""
Coulomb friction: a manufactured case, two solvers, and the coefficient as an axis
===================================================================================

Coulomb's law (:doc:`../theory/coulomb`) puts Tresca's friction on top of unilateral contact with
the threshold μ_F p, p the contact pressure: the problem is not convex, unique only for small μ_F,
and no theorem gives a rate. elastic-coulomb-r32 is an exact plane-strain field with a stick-slip
point at the middle of Γ_C, exact for Coulomb with μ_F = 1/2 and no contact load: its slip side's
shear follows the pressure, which moves the stick-slip exponent from Tresca's 3/2 to
l = 3/2 + arctan(μ_F(κ−1)/(κ+1))/π ≈ 1.545 (κ = 3 − 4ν). The case declares
``friction = Coulomb(coefficient=0.5)``; ``nitsche`` and ``penalty`` discretise it (P1 and P2),
and so do the cones ``nodal``, ``mean`` (the paper's) and ``p1``: Tresca's rows with the threshold
μ_F times the cone's own contact multiplier, by a fixed point over unilateral Tresca problems.
"""

# %%
import matplotlib.pyplot as plt

import harness

LEVELS = 4
case = harness.registered_cases()["elastic-coulomb-r32"]
print(case.friction.describe(), "on Γ_C;", case.description)
print(f"ν = {case.nu:.4f}: the expected P2 rate is the best approximation's, {case.expected_rate:.4f} (conjectured)")

# %%
# Run Nitsche (P2 and P1) and the nodal cone for four levels. Each level is one load step. Nitsche's
# is solved by semismooth Newton whose linear systems -- nonsymmetric for every θ -- go to GMRES
# preconditioned by the harness's multigrid; the cone's by the fixed point (``solver_iterations``:
# its unilateral Tresca problems). Every row's residual is <= 1e-10.
rows = harness.run(case, methods=["nitsche", "nitsche-p1", "nodal"], levels=LEVELS, show_progress=False)
print(rows[["method", "level", "ndof", "err_h1", "solver_iterations", "linear_iterations", "kkt_residual", "status"]]
      .to_string(index=False))
rates = harness.rates(rows)
print(rates[["method", "expected_rate", "fitted_rate", "pairwise_rates", "verdict"]].to_string(index=False))

# %%
# An independent solver on the same discrete problems, and the coefficient as an axis.
# ``harness.coulomb_axis`` solves the case's data with Coulomb(μ_F) for each μ_F twice on one
# level from the same nested start: by the coupled Newton method, and by the fixed point over
# Tresca problems -- freeze the threshold s = μ_F p at Γ_C's Gauss points, solve unilateral
# contact with that Tresca friction (a symmetric Jacobian: multigrid CG), update s from the new
# pressure, until s no longer moves. The fixed point never linearises the coupling; where both
# converge on one solution, the discrete solution is confirmed; where they disagree, the row says
# so plainly (uniqueness is proven for small μ_F only).
axis = harness.coulomb_axis(case, coefficients=(0.1, 0.5, 2.0), level=2)
print(axis[["mu_F", "newton_status", "newton_steps", "gmres_iterations", "fixed_point_status", "tresca_problems",
            "difference", "stick", "slip", "separated"]].to_string(index=False))

# %%
# The convergence picture of the three methods: P2 Nitsche and the nodal cone on the Coulomb
# exponent's h^{1.545}, P1 on h.
harness.plot(rows, case=case.name)
plt.show()
