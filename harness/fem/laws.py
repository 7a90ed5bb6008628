"""Deprecated home of the built-in contact laws: ``fem.contact_laws.builtin`` (``Nitsche``,
``Penalty``, ``degree_scale``, ...). A name read here warns and is taken from there."""
from __future__ import annotations

import warnings


def __getattr__(name: str):
    from .contact_laws import builtin
    if name.startswith("__") or not hasattr(builtin, name):
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    warnings.warn(f"harness.fem.laws.{name} is deprecated: use harness.fem.contact_laws.builtin.{name}",
                  DeprecationWarning, stacklevel=2)
    return getattr(builtin, name)
