"""`mean-edges`: the counterexample -- K_h extended to 3D edge by edge: v_h >= 0 at the vertices of
Gamma_C and int_e v_h >= 0 on every *edge* of its triangles (bounds after the 2D change of
variables, ``cones``). Edge means do not control the trace inside the triangles: a function
whose edge means and vertex values vanish may still dip below the obstacle in every triangle,
and the H^1 rate stalls near 1/2 on transition-line-3d (the 3D report shows it). It is kept, with
the paper's 2D rate as its expectation, to show that the 3D `mean` has to constrain the
triangles (``base.CellMean``)."""
from ..fem.cones import ContactModel
from .base import BoundConstrained, paper_theorem

method = BoundConstrained(
    name="mean-edges",
    order=2,
    contact="v_h >= 0 at the vertices of Γ_C, ∫ v_h >= 0 on the edges of its triangles (3D; the counterexample)",
    reference="the 2D K_h of Belhachmi & Ben Belgacem 2003 applied edge by edge",
    expected=paper_theorem,
    dimensions=(3,),
    cone=ContactModel(edge_functional="edge-mean"),
)
