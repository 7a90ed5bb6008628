"""The weak methods' contact laws on Gamma_C: the law's protocol (``protocol``: ``GammaPoints``,
``ContactLaw``, ``LawError``), its semismooth Newton system on one level (``system``:
``law_system``, ``LawSystem``) and the built-in Nitsche and penalty laws (``builtin``); friction
laws (``protocol``: ``FrictionPoints``, ``FrictionLaw``) on several channels per point, their
system (``channels``: ``friction_system``) and the built-in Tresca laws (``tresca``)."""
