"""`mean-p4`: P4 with v_h >= alpha at the vertices and the mean of v_h - alpha >= 0 over the
3 equal sub-edges of each contact edge (``_mean_pk.at_order``): the paper's K_h (Section 3) at
degree 4."""
from . import _mean_pk as mean_pk

method = mean_pk.at_order(4)
