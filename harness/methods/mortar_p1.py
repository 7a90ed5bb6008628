"""`mortar-p1`: two bodies, P1 on each, the opening held weakly against the dual (biorthogonal)
linear multipliers of the upper body's trace: int psi_i [u_h] >= int psi_i 2 alpha at every
slave vertex of Gamma_C (Wohlmuth 2000; Hueeber & Wohlmuth 2005; the mortar P1 contact method of
Ben Belgacem, Hild & Laborde 1999 with standard multipliers). On matching meshes it is `p1` on
the jump. Expected: min(nu - 1, 1) (``_mortar.one_body_rate``)."""
from functools import partial

from ._mortar import Mortar, one_body_rate
from .base import MESH_STUDY

method = Mortar(
    name="mortar-p1",
    order=1,
    contact="∫ ψ_i [u_h] >= 0 for the dual linear multipliers ψ_i of the slave's vertices (two bodies)",
    reference="Ben Belgacem, Hild & Laborde 1999; Wohlmuth 2000",
    expected=partial(one_body_rate, order=1),
    multipliers="dual",
    roles=frozenset({MESH_STUDY}),
)
