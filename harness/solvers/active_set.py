"""Deprecated home of ``solvers.bound_constraints``, read only by methods/ until it imports the new path
(the branch merge removes this module). A name read here warns and is taken from there."""
from __future__ import annotations

import warnings


def __getattr__(name: str):
    from . import bound_constraints as new
    if name.startswith("__") or not hasattr(new, name):
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    warnings.warn(f"harness.solvers.active_set.{name} is deprecated: use harness.solvers.bound_constraints.{name}",
                  DeprecationWarning, stacklevel=2)
    return getattr(new, name)
