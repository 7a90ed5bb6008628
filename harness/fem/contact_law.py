"""Deprecated home of the contact law's protocol and Newton system: ``fem.contact_laws.protocol``
(``GammaPoints``, ``ContactLaw``, ``LawError``) and ``fem.contact_laws.system`` (``law_system``,
``LawSystem``, ...). A name read here warns and is taken from there."""
from __future__ import annotations

import warnings

_PROTOCOL = ("GammaPoints", "ContactLaw", "LawError")
# the nested iteration's prediction at the Gauss points, under its old name
_NESTED = {"predicted_active": "nearest_status"}


def __getattr__(name: str):
    from . import nested
    from .contact_laws import protocol, system
    if name in _NESTED:
        module, new = nested, _NESTED[name]
    elif name in _PROTOCOL:
        module, new = protocol, name
    elif hasattr(system, name) and not name.startswith("__"):
        module, new = system, name
    else:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    warnings.warn(f"harness.fem.contact_law.{name} is deprecated: use {module.__name__}.{new}",
                  DeprecationWarning, stacklevel=2)
    return getattr(module, new)
