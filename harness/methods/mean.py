"""`mean`: the paper's first model, K_h of Section 3 -- P2 with v_h(x_i) >= 0 at the vertices of
Gamma_C and int_{t_i} v_h >= 0 on every contact edge (3.6), the degrees of freedom of J_h.
Rates: Theorems 4.1 and 4.2 (and Remark 4.9), declared by each case."""
from ..fem.cones import ContactModel
from .base import BoundConstrained, drouet_hild_for, paper_theorem

method = BoundConstrained(
    name="mean",
    order=2,
    contact="v_h >= 0 at the vertices of Γ_C, ∫ v_h >= 0 on its edges (K_h, (3.6))",
    reference="Belhachmi & Ben Belgacem 2003, Section 3",
    expected=paper_theorem,
    sharper_theory=drouet_hild_for(2),
    cone=ContactModel(edge_functional="mean"),
)
