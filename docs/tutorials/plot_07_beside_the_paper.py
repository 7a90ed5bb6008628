"""
Your method beside the paper's, on every regime
===============================================

What most users come for: a discretisation of their own, run beside the paper's two P2 methods
on one case per regularity regime of the paper's theorems, and read in one figure, the verdict
matrix. The group of cases ``paper`` (``--case paper`` on the command line) is the seven scalar
2D cases that declare it, from the corner singularity r^{1/2} (ν = 3/2) to the smooth case
(ν = 7/2); ``python -m harness cases`` lists every group.

The method here is a cone given only by its constraint functionals (the method protocol's first
level, as in :doc:`plot_03_your_own_method` for the second): P2 with v_h ≥ α at the vertices of
Γ_C and at the two Gauss points of each contact edge. No theorem covers it; it declares the
paper's rates as a conjecture, and the verdicts say whether the data bear it out.
"""

# %%
import math

import harness
from harness.methods import Expectation, FunctionalCone

cases = harness.case_table()            # every registered case, with the groups it is in
paper = cases[cases.groups.str.split().map(lambda groups: "paper" in groups)]
print(paper[["case", "nu", "theorem", "bound"]].to_string(index=False))


def as_the_paper(case):
    # a conjecture, not a theorem: the rate of the paper's cones (Theorems 4.1, 4.2, 5.1, 5.2)
    return Expectation(case.expected_rate, case.expected_log_exponent, "conjecture: as the paper's P2 cones")


gauss = 0.5 - math.sqrt(3) / 6          # the Gauss-Legendre points of [0, 1]: t and 1 - t
mine = FunctionalCone(name="gauss-points", order=2, contact="v_h ≥ α at the vertices and the 2 Gauss points of each edge",
                      reference="this tutorial", expected=as_the_paper,
                      functionals=(((gauss, 1.0),), ((1 - gauss, 1.0),)))

# %%
# One call runs the group: every case with the paper's ``mean`` and ``nodal`` and the new cone,
# four levels each (``make report`` runs six; the command line is
# ``python -m harness run --case paper --method mine.py --method paper --levels 4``). Every
# discrete problem is solved exactly: the largest KKT residual of the rows is printed.
rows = harness.run("paper", methods=[mine, "paper"], levels=4, show_progress=False)
print(f"{len(rows)} rows, {rows.case.nunique()} cases; largest KKT residual {rows.kkt_residual.max():.1e}")

# %%
# The fitted H¹ rate of each case and method over its last three levels, against the rate its
# theory (or, for ``gauss-points``, its conjecture) predicts.
rates = harness.rates(rows)
print(rates.pivot(index="case", columns="method", values="fitted_rate").round(2).to_string())

# %%
# The verdict matrix: each cell the fitted rate over the expected one, coloured by the verdict
# (the colours: :doc:`../guide/report`, "The verdict matrix and its colours"). borderline-h2 is
# blue, *above*, for all three: the paper's h|log h|^{1/4} is an upper bound, and its data follow
# Drouet & Hild's h (:doc:`../guide/findings`). ``python -m harness report --case paper --method
# mine.py --method paper`` writes the whole report of the same study.
figure = harness.plot(rows, kind="verdicts")
