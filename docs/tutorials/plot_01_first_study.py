"""
A first study: rates, quantities, a plot and the report
=======================================================

The paper's two P2 methods (``mean``, ``nodal``: the group ``paper``) and the P1 method on
``transition-r32``, whose solution has the contact/separation transition r^{3/2} sin(3θ/2) of
the paper's Remark 2.2 (u ∈ H^{5/2−ε}: Theorems 4.1 ii and 5.1 ii give h^{3/2} for P2). Everything
here is ``import harness``: the same functions the command line calls.
"""

# %%
# Each row is one method on one level, solved exactly: ``kkt_residual`` is the relative KKT
# residual of the discrete variational inequality (≤ 1e-10 in every row). ``out=`` keeps the rows
# in a results folder, as ``python -m harness run --out`` does: the folder is this run's while it
# lasts, every finished level is durable there, and the rows are merged by key into its
# results.csv.
import tempfile
from pathlib import Path

import harness

folder = Path(tempfile.mkdtemp())
rows = harness.run("transition-r32", methods=["paper", "p1"], levels=4, out=folder / "results", show_progress=False)
print(rows[["method", "level", "ndof", "err_h1", "kkt_residual", "status"]].to_string(index=False))
print(rows.attrs["stored"])

# %%
# Rates fitted over the finest levels, each against the rate its own theory predicts; the
# verdict is ``meets`` within ±0.1 (on four levels the fit is still close to pre-asymptotic:
# ``make report`` runs six).
rates = harness.rates(rows)
print(rates[["method", "expected_rate", "fitted_rate", "verdict"]].to_string(index=False))

# %%
# Quantities of interest (the contact force, the extent of the contact zone, ...): each
# chain's observed order, Richardson's extrapolation and the grid convergence index band, and
# whether the band holds the exact value where the case knows it.
quantities = harness.quantities(rows)
print(quantities[["method", "quantity", "value", "observed_order", "extrapolated", "gci_relative", "covered"]]
      .head(8).to_string(index=False))

# %%
# The errors against h, with each theory's slope.
figure = harness.plot(rows, case="transition-r32")

# %%
# The report of this case and these methods, as ``python -m harness report`` writes it: an
# HTML page with every table, figure and verdict (here three levels, to stay quick).
page = harness.report(cases=["transition-r32"], methods=["paper", "p1"], levels=3, results=folder / "results",
                      out=folder / "report", show_progress=False)
print(page.name, f"{page.stat().st_size / 1e6:.2f} MB")
