"""Deprecated: the names this module held live in ``method`` (the method record, its results and
roles), ``protocol`` (``FunctionalCone``, ``solve_general_rows``) and ``cones`` (the paper's
cones and their theories). Reading one here warns and returns it from there."""
from __future__ import annotations

import importlib
import warnings

_MOVED = {
    **dict.fromkeys(("EXTRA_LEVELS", "PAPER", "BASELINE", "REFERENCE", "SWEPT", "MESH_STUDY", "DEGREES", "ROLES",
                     "Expectation", "SolveFields", "Carry", "LevelSolve", "Method", "timer"), "method"),
    **dict.fromkeys(("FunctionalCone", "solve_general_rows"), "protocol"),
    **dict.fromkeys(("BoundConstrained", "CellMean", "paper_theorem", "drouet_hild_for", "DROUET_HILD",
                     "DROUET_HILD_CAP"), "cones"),
}


def __getattr__(name: str):
    if name not in _MOVED:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    home = f"harness.methods.{_MOVED[name]}"
    warnings.warn(f"harness.methods.base.{name} is deprecated: import it from {home} (or harness.methods)",
                  DeprecationWarning, stacklevel=2)
    return getattr(importlib.import_module(home), name)
