"""`mortar-standard`: two bodies, P2 on each, the opening held weakly against the continuous
piecewise quadratic multipliers of the upper body's trace -- its own Lagrange basis, the
multiplier space of Hild & Laborde, Appl. Numer. Math. 41 (2002), with their nodal condition
∫ phi_i ([u_h] - 2 alpha) >= 0 for every slave node i (``fem.mortar``). The rows couple
neighbouring nodes: no local change of variables makes them bounds, so they are solved as general
constraints (``solvers.general_constraints``, the saddle system by SuperLU). Expected: the
one-body rate min(nu - 1, 2) (``_mortar.one_body_rate``)."""
from functools import partial

from ._mortar import Mortar, one_body_rate

method = Mortar(
    name="mortar-standard",
    order=2,
    contact="∫ φ_i [u_h] >= 0 for the slave's own quadratic basis φ_i (continuous multipliers; two bodies)",
    reference="Hild & Laborde 2002 (continuous quadratic multipliers)",
    expected=partial(one_body_rate, order=2),
    multipliers="standard",
)
