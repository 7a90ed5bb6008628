"""`mortar-mean`: two bodies, P2 on each; `mean`'s K_h on the dual mortar projection Pi of the
jump onto the upper body's P2 trace: Pi [u_h] >= 2 alpha at the slave's vertices of Gamma_C and
its mean over every slave edge >= that of 2 alpha (``fem.mortar``, edge_functional "edge-mean"). On
matching meshes it is `mean`'s K_h on the jump. Expected: the one-body rate min(nu - 1, 2)
(``_mortar.one_body_rate``)."""
from functools import partial

from ._mortar import Mortar, one_body_rate

method = Mortar(
    name="mortar-mean",
    order=2,
    contact="Π[u_h] >= 0 at the slave's vertices, ∫ Π[u_h] >= 0 on its edges (Π: dual mortar projection; two bodies)",
    reference="Belhachmi & Ben Belgacem 2003 (K_h) on Wohlmuth's dual mortar projection",
    expected=partial(one_body_rate, order=2),
    multipliers="dual",
    edge_functional="edge-mean",
)
