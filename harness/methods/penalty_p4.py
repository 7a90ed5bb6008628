"""`penalty-p4`: the `penalty` method on P4 (same eps0; ``penalty.at_order``): its consistency
error eps lambda = O(h) caps the rate at h whatever the degree, which P4 shows plainly."""
from . import penalty

method = penalty.at_order(4)
