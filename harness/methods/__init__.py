"""Discretisations as plug-ins: one short module per method in this folder, each defining
``method`` (a ``base.Method``). Adding a method is adding a module; nothing else changes.

    >>> from harness.methods import METHODS, methods_named
    >>> methods_named(["paper", "p1"])     # mean, nodal, p1
    >>> methods_named("nitsche:gamma0=0.5,theta=-1")   # a method with other parameter values
"""
from __future__ import annotations

import importlib
import pkgutil

from .base import BoundConstrained, Expectation, LevelSolve, Method, WeakContact

# Named groups besides the method names themselves.
GROUPS = {
    "paper": ("mean", "nodal"),
    "cones": ("mean", "nodal", "p1"),                                   # exact discrete inequalities
    "weak": ("nitsche", "penalty", "nitsche-p1", "penalty-p1"),         # contact by a Gamma_C term
    "mortar": ("mortar-mean", "mortar-nodal", "mortar-standard", "mortar-p1"),             # two bodies, non-matching meshes
}


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
    # the cones (the paper's P2 models first), then the weak methods, each by order
    return {m.name: m for m in sorted(found, key=lambda m: (not isinstance(m, BoundConstrained), -m.order, m.name))}


METHODS = _discover()


def method_choices() -> list[str]:
    return [*METHODS, *GROUPS, "all"]


def methods_named(names) -> list[Method]:
    """Methods by name, group ('paper' = mean + nodal) or 'all', in registry order, once each;
    then methods with parameters (``parse_method``), in the order given."""
    names = [names] if isinstance(names, str) else list(names)
    wanted, parametrised = set(), []
    for name in names:
        if name == "all":
            wanted |= set(METHODS)
        elif name in GROUPS:
            wanted |= set(GROUPS[name])
        elif ":" in name:
            method = parse_method(name)
            if method.name not in [m.name for m in parametrised]:
                parametrised.append(method)
        else:
            wanted.add(get_method(name).name)
    return [m for name, m in METHODS.items() if name in wanted] + parametrised


def methods_for(case, methods) -> list[Method]:
    """Those of ``methods`` that discretise ``case``'s physics and dimension (the weak methods
    are scalar and 2D only), in the order given; a study runs each case with these."""
    return [m for m in methods if m.supports(case)]


def get_method(name: str) -> Method:
    """A registered method, or one with parameters: ``nitsche:gamma0=0.5,theta=-1``."""
    if ":" in name:
        return parse_method(name)
    if name not in METHODS:
        raise ValueError(f"unknown method {name!r}; expected one of: {', '.join(method_choices())}")
    return METHODS[name]


def parse_method(spec: str) -> Method:
    """``name:key=value,...``: the registered method ``name`` with those parameter values."""
    base, _, assignments = spec.partition(":")
    method = get_method(base)
    values = {}
    for item in filter(None, assignments.split(",")):
        key, sep, value = item.partition("=")
        try:
            values[key.strip()] = float(value)
        except ValueError:
            sep = ""
        if not sep:
            raise ValueError(f"method parameters look like {base}:name=number,..., got {spec!r}")
    if not values:
        raise ValueError(f"no parameter values in {spec!r}")
    return method.with_parameters(**values)


__all__ = ["METHODS", "GROUPS", "BoundConstrained", "Expectation", "LevelSolve", "Method", "WeakContact", "get_method",
           "method_choices", "methods_for", "methods_named", "parse_method"]
