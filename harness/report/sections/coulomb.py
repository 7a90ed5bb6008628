"""The report's section on Coulomb friction (``problem.friction.Coulomb``): what the law is and
how each method discretises it, the Coulomb cases' rates against the Tresca rate of the same
regularity (no theorem gives one for Coulomb: a conjecture the rows test), the methods left
out and why, the friction quantities with their GCI bands and the stick/slip pictures -- the
Tresca section's views (``sections.friction.write_common``). A study without a Coulomb case
writes nothing."""
from __future__ import annotations

import numpy as np
import pandas as pd

from ..document import Document
from ..plan import ReportPlan
from ..tables import _fmt
from .friction import friction_cases, quantity_text, write_common

COULOMB_NOTE = (
    "Coulomb's law on Γ_C (docs: theory/coulomb): unilateral contact, u·n ≤ g with the pressure p = −(σ_n − g_n) ≥ 0 "
    "and p (u·n − g) = 0, and Tresca's conditions whose threshold is the pressure itself: |σ_t| ≤ μ_F p, "
    "σ_t = −μ_F p w_t/|w_t| where the slip w_t (of the last load step) is not zero. Nitsche's method (the θ family) "
    "and the penalty method carry it as one law of both channels, p_t = P_{μ_F p_n}(σ_t − w_t/γ); the Jacobian is "
    "not symmetric for any θ, and each Newton step is solved by GMRES with the harness's multigrid V-cycle, every "
    "load step to a residual ≤ 1e-10. The cones (the paper's nodal and mean models, P1) carry Tresca's rows with the threshold "
    "from their own contact multiplier, s_i = μ_F λ_n,i, solved by a fixed point over unilateral Tresca problems "
    "(Signorini and Tresca rows in one active set iteration). "
    "No theorem gives a rate: each case declares the best approximation's h^{min(ν−1, k)} for its regularity, the "
    "Tresca rate of the same ν, as a conjecture. The stick–slip exponent of Coulomb is not Tresca's 3/2 but "
    "3/2 + arctan(μ_F(κ−1)/(κ+1))/π (the slip side's shear follows the pressure), so ν moves with μ_F.")


CATTANEO_NOTE = (
    "Against Cattaneo (line) and Mindlin (sphere), finest level of each method (docs: theory/coulomb): a rigid "
    "indenter pressed (first load step), then sheared with the depth held (second step); P = qoi_force and "
    "Q = qoi_tangential_force are computed and each closed form is read at them: the contact zone against Hertz's, "
    "the stick zone's size c_h (2c = its length, πc² its area) against c = a(1 − Q/(μ_F P))^{1/2} (line) or "
    "^{1/3} (sphere), and the shear traction's relative L² error on Γ_C against the closed form q. The closed "
    "forms are exact only when the normal and tangential responses uncouple (Dundurs' β = 0: two identical "
    "bodies, or ν = 1/2 against a rigid one); a rigid indenter on a ν = 0.3 body has β = 0.286 and the deviation "
    "measured there is the coupling's share (Spence), not a discretisation error; the near-incompressible pair "
    "(β = 0.057) comes closer. Two identical bodies (the cattaneo-two-body cases, mortar methods) have β = 0 exactly, "
    "in finite blocks too (their normal and tangential problems uncouple by symmetry): there what is left is the "
    "blocks' finite size and the discretisation. A two-body row's zones are read from the jumps between the bodies.")


def write(doc: Document, plan: ReportPlan) -> None:
    """The section, where the report has a Coulomb case."""
    cases = friction_cases(plan, "coulomb")
    if not cases:
        return
    doc.heading("Coulomb friction")
    doc.paragraph(COULOMB_NOTE)
    write_common(doc, plan, cases)
    closed = cattaneo_view(plan.results, cases)
    if not closed.empty:
        doc.paragraph(CATTANEO_NOTE)
        doc.table(closed)


def cattaneo_view(results: pd.DataFrame, cases) -> pd.DataFrame:
    """Per case read against a closed form of friction (``Case.predicted_friction``: Cattaneo,
    Mindlin) and method, at the finest level: the computed P and Q/(mu_F P), the contact zone
    against Hertz's and the stick zone against the closed form at that P and Q (with the stick
    zone's band over the levels, ``friction.quantity_text``), the shear traction's relative L²
    error against the closed form (``err_traction_prediction``), the residual and the solve."""
    rows = []
    for case in cases:
        if getattr(case, "predicted_friction", None) is None:
            continue
        mu = case.friction.coefficient
        for method, group in results[results.case == case.name].groupby("method", sort=False):
            group = group.sort_values("level")
            last = group.iloc[-1]
            P, Q = float(last.qoi_force), float(last.qoi_tangential_force)
            hertz = case.predicted_quantities(P)["qoi_contact_measure"] if case.predicted_quantities else np.nan
            stick = case.predicted_friction(P, Q)["qoi_stick_measure"]
            # the stick zone's size c: its length 2c (2D) or its area pi c^2 (3D) against the closed form's
            ratio = (last.qoi_stick_measure / stick) ** (1.0 / (case.dimension - 1))
            rows.append({"case": case.name, "method": method, "ndof": _fmt(last.ndof, ".3g"), "P": f"{P:.4g}",
                         "Q/(μ_F P)": f"{Q / (mu * P):.3f}", "contact / Hertz": f"{last.qoi_contact_measure / hertz:.4f}",
                         "stick zone (band)": quantity_text(group, "qoi_stick_measure", "value"),
                         "c_h / c": f"{ratio:.4f}",
                         "traction error": _fmt(last.get("err_traction_prediction", np.nan), ".3g"),
                         "KKT": _fmt(last.kkt_residual, ".1e"), "status": last.status})
    return pd.DataFrame(rows)
