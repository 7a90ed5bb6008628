"""`nodal`: the paper's second model, K~_h of Section 5 -- P2 with v_h >= 0 at the vertices and
the edge midpoints of Gamma_C (before (5.1)), the degrees of freedom of the Lagrange
interpolant I_h. K~_h lies in K_h (Simpson's rule). Rates: Theorems 5.1 and 5.2, the same as
for `mean`, declared by each case."""
from ..fem.cones import ContactModel
from .base import DEGREES, MESH_STUDY, PAPER, REFERENCE, BoundConstrained, drouet_hild_for, paper_theorem

method = BoundConstrained(
    name="nodal",
    order=2,
    contact="v_h >= 0 at the vertices and edge midpoints of Γ_C (K̃_h, (5.1))",
    reference="Belhachmi & Ben Belgacem 2003, Section 5",
    expected=paper_theorem,
    sharper_theory=drouet_hild_for(2),
    cone=ContactModel(edge_functional="midpoint"),
    roles=frozenset({PAPER, REFERENCE, MESH_STUDY, DEGREES}),
)
