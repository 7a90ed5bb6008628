"""Which friction law discretises a case's friction (``problem.friction``) with a contact
law's idea: the built-in Nitsche and penalty laws (``builtin``) carry their parameters over to
their Tresca laws (``tresca``) and Coulomb laws (``coulomb``); a law of one's own gives
``for_friction`` or is itself a ``protocol.FrictionLaw``."""
from __future__ import annotations

from .builtin import Nitsche, Penalty
from .coulomb import NitscheCoulomb, PenaltyCoulomb
from .protocol import LawError
from .tresca import NitscheTresca, PenaltyTresca

# the friction laws of the built-in frictionless laws, by the law of ``problem.friction``
FRICTION_OF = {("tresca", Nitsche): NitscheTresca.of, ("tresca", Penalty): PenaltyTresca.of,
               ("coulomb", Nitsche): NitscheCoulomb.of, ("coulomb", Penalty): PenaltyCoulomb.of}


def law_for(law, friction):
    """The law that discretises ``friction`` (``problem.friction``) with ``law``'s idea and
    parameters: ``law`` itself when frictionless or when it is a friction law of that name
    (``protocol.FrictionLaw``); the built-in laws' counterpart (``FRICTION_OF``); a law's own
    ``for_friction(friction)`` if it has one. LawError else."""
    if friction.name == "frictionless" or getattr(law, "friction", None) == friction.name:
        return law
    made = FRICTION_OF.get((friction.name, type(law)))
    if made is not None:
        return made(law)
    if hasattr(law, "for_friction"):
        return law.for_friction(friction)
    raise LawError(f"contact law {type(law).__name__} has no {friction.name} friction law "
                   f"(give it for_friction(friction), or use a friction law)")
