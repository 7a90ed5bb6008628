"""`nitsche-p3`: the `nitsche` method on P3, gamma0 scaled with the degree (``nitsche.gamma0_for``);
expected h^{min(nu - 1, 3)} for nu > 3/2 (``nitsche.expected_for``)."""
from . import nitsche

method = nitsche.at_order(3)
