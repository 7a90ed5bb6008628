"""`penalty-p3`: the `penalty` method on P3 (same eps0; ``penalty.at_order``): its consistency
error eps lambda = O(h) caps the rate at h whatever the degree, which P3 shows plainly."""
from . import penalty

method = penalty.at_order(3)
