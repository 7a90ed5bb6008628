"""`nodal-p3`: P3 with v_h >= alpha at the vertices and the 2 interior Gauss-Lobatto points of each
contact edge (``_nodal_pk.at_order``): the paper's K~_h (Section 5) at degree 3."""
from . import _nodal_pk as nodal_pk

method = nodal_pk.at_order(3)
