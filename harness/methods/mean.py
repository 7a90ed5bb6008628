"""`mean`: the paper's first model, K_h of Section 3 -- P2 with v_h(x_i) >= 0 at the vertices of
Gamma_C and int_{t_i} v_h >= 0 on every cell t_i of Gamma_C (3.6), the degrees of freedom of
J_h. A cell is an edge in 2D (Section 3) and a triangle in 3D (Section 6 leaves 3D open; on a
triangle the P2 mean is the average of the three edge-midpoint values, so its rows are general:
``base.CellMean``). Rates: Theorems 4.1 and 4.2 (and Remark 4.9), declared by each case; in 3D
no theorem covers it (the 2D rate is the expectation)."""
from ..fem.cones import ContactModel
from .base import PAPER, CellMean, drouet_hild_for, paper_theorem

method = CellMean(
    name="mean",
    order=2,
    contact="v_h >= 0 at the vertices of Γ_C, ∫ v_h >= 0 on its edges (2D, K_h (3.6)) or triangles (3D)",
    reference="Belhachmi & Ben Belgacem 2003, Section 3",
    expected=paper_theorem,
    sharper_theory=drouet_hild_for(2),
    cone=ContactModel(edge_functional="edge-mean"),
    roles=frozenset({PAPER}),
)
