"""Discretisations as plug-ins: one short module per method in this folder, each defining
``method`` (a ``base.Method``). Adding a method is adding a module; nothing else changes.

    >>> from harness.methods import METHODS, methods_named
    >>> methods_named(["paper", "p1"])     # mean, nodal, p1
"""
from __future__ import annotations

import importlib
import pkgutil

from .base import BoundConstrained, Expectation, LevelSolve, Method

# Named groups besides the method names themselves.
GROUPS = {"paper": ("mean", "nodal")}


def _discover() -> dict[str, Method]:
    found = []
    for info in pkgutil.iter_modules(__path__):
        if info.name == "base" or info.name.startswith("_"):
            continue
        module = importlib.import_module(f"{__name__}.{info.name}")
        method = getattr(module, "method", None)
        if not isinstance(method, Method):
            raise TypeError(f"harness/methods/{info.name}.py must define `method`, a harness.methods.base.Method")
        found.append(method)
    # the paper's P2 models first, then by order
    return {m.name: m for m in sorted(found, key=lambda m: (-m.order, m.name))}


METHODS = _discover()


def method_choices() -> list[str]:
    return [*METHODS, *GROUPS, "all"]


def methods_named(names) -> list[Method]:
    """Methods by name, group ('paper' = mean + nodal) or 'all', in registry order, once each."""
    names = [names] if isinstance(names, str) else list(names)
    wanted = set()
    for name in names:
        if name == "all":
            wanted |= set(METHODS)
        elif name in GROUPS:
            wanted |= set(GROUPS[name])
        elif name in METHODS:
            wanted.add(name)
        else:
            raise ValueError(f"unknown method {name!r}; expected one of: {', '.join(method_choices())}")
    return [m for name, m in METHODS.items() if name in wanted]


def get_method(name: str) -> Method:
    if name not in METHODS:
        raise ValueError(f"unknown method {name!r}; expected one of: {', '.join(METHODS)}")
    return METHODS[name]


__all__ = ["METHODS", "GROUPS", "BoundConstrained", "Expectation", "LevelSolve", "Method", "get_method",
           "method_choices", "methods_named"]
