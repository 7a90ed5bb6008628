"""`nodal-p4`: P4 with v_h >= alpha at the vertices and the 3 interior Gauss-Lobatto points of each
contact edge (``_nodal_pk.at_order``): the paper's K~_h (Section 5) at degree 4."""
from . import _nodal_pk as nodal_pk

method = nodal_pk.at_order(4)
