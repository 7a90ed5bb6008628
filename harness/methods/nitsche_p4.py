"""`nitsche-p4`: the `nitsche` method on P4, gamma0 scaled with the degree (``nitsche.gamma0_for``);
expected h^{min(nu - 1, 4)} for nu > 3/2 (``nitsche.expected_for``)."""
from . import nitsche

method = nitsche.at_order(4)
