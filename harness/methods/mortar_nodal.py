"""`mortar-nodal`: two bodies, P2 on each, the opening of the interface held weakly against the
dual (biorthogonal) quadratic multipliers of the upper body's trace (Wohlmuth 2000; for contact
Hueeber & Wohlmuth 2005): int psi_i [u_h] >= int psi_i 2 alpha at every vertex and edge midpoint
of the slave's Gamma_C (``fem.mortar``). On matching meshes it is `nodal`'s K~_h on the jump.
Expected: the one-body rate min(nu - 1, 2) (``_mortar.one_body_rate``)."""
from functools import partial

from ._mortar import Mortar, one_body_rate
from .base import MESH_STUDY, REFERENCE

method = Mortar(
    name="mortar-nodal",
    order=2,
    contact="∫ ψ_i [u_h] >= 0 for the dual quadratic multipliers ψ_i of the slave's nodes (two bodies)",
    reference="Wohlmuth 2000; Hüeber & Wohlmuth 2005; Hild & Laborde 2002 (quadratic mortar)",
    expected=partial(one_body_rate, order=2),
    multipliers="dual",
    roles=frozenset({REFERENCE, MESH_STUDY}),     # of the two-body cases (and their picture)
)
