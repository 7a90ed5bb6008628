"""Deprecated home of ``solvers.projected_multigrid``, read only by methods/ until it imports the new path
(the branch merge removes this module). A name read here warns and is taken from there."""
from __future__ import annotations

import warnings


def __getattr__(name: str):
    from . import projected_multigrid as new
    if name.startswith("__") or not hasattr(new, name):
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    warnings.warn(f"harness.solvers.projected.{name} is deprecated: use harness.solvers.projected_multigrid.{name}",
                  DeprecationWarning, stacklevel=2)
    return getattr(new, name)
