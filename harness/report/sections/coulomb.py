"""The report's section on Coulomb friction (``problem.friction.Coulomb``): what the law is and
how each method discretises it, the Coulomb cases' rates against the Tresca rate of the same
regularity (no theorem gives one for Coulomb: a conjecture the rows test), the methods left
out and why, the friction quantities with their GCI bands and the stick/slip pictures -- the
Tresca section's views (``sections.friction.write_common``). A study without a Coulomb case
writes nothing."""
from __future__ import annotations

from ..document import Document
from ..plan import ReportPlan
from .friction import friction_cases, write_common

COULOMB_NOTE = (
    "Coulomb's law on Γ_C (docs: theory/coulomb): unilateral contact, u·n ≤ g with the pressure p = −(σ_n − g_n) ≥ 0 "
    "and p (u·n − g) = 0, and Tresca's conditions whose threshold is the pressure itself: |σ_t| ≤ μ_F p, "
    "σ_t = −μ_F p w_t/|w_t| where the slip w_t (of the last load step) is not zero. Nitsche's method (the θ family) "
    "and the penalty method carry it as one law of both channels, p_t = P_{μ_F p_n}(σ_t − w_t/γ); the Jacobian is "
    "not symmetric for any θ, and each Newton step is solved by GMRES with the harness's multigrid V-cycle, every "
    "load step to a residual ≤ 1e-10. The cones (the paper's nodal and mean models) do not discretise Coulomb yet. "
    "No theorem gives a rate: each case declares the best approximation's h^{min(ν−1, k)} for its regularity, the "
    "Tresca rate of the same ν, as a conjecture. The stick–slip exponent of Coulomb is not Tresca's 3/2 but "
    "3/2 + arctan(μ_F(κ−1)/(κ+1))/π (the slip side's shear follows the pressure), so ν moves with μ_F.")


def write(doc: Document, plan: ReportPlan) -> None:
    """The section, where the report has a Coulomb case."""
    cases = friction_cases(plan, "coulomb")
    if not cases:
        return
    doc.heading("Coulomb friction")
    doc.paragraph(COULOMB_NOTE)
    write_common(doc, plan, cases)
