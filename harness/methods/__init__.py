"""Discretisations as plug-ins: one short module per method in this folder, each defining
``method`` (a ``base.Method``), and methods from outside the package: a file, a dotted name,
an installed package's entry point or an object (``plugins``). Every one passes the same
checks (``plugins.check_method``).

    >>> from harness.methods import METHODS, methods_named
    >>> methods_named(["paper", "p1"])     # mean, nodal, p1
    >>> methods_named("nitsche:gamma0=0.5,theta=-1")   # a method with other parameter values
"""
from __future__ import annotations

import importlib
import pkgutil

from ..mesh.plugins import is_external
from .base import BoundConstrained, Expectation, FunctionalCone, LevelSolve, Method, WeakContact
from .plugins import MethodError, check_method, installed_methods, load_external

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
        if info.name in ("base", "plugins") or info.name.startswith("_"):
            continue
        module = importlib.import_module(f"{__name__}.{info.name}")
        found.append(check_method(getattr(module, "method", None), f"harness/methods/{info.name}.py (its `method`)"))
    # the cones (the paper's P2 models first), then the weak methods, each by order
    return {m.name: m for m in sorted(found, key=lambda m: (not isinstance(m, BoundConstrained), -m.order, m.name))}


METHODS = _discover()


def method_choices() -> list[str]:
    return [*METHODS, *installed_methods(), *GROUPS, "all"]


def methods_named(names) -> list[Method]:
    """Methods by name, group ('paper' = mean + nodal) or 'all' (the package's own), in registry
    order, once each; then methods with parameters (``parse_method``), methods from files,
    modules and installed packages (``plugins``) and ``Method`` objects, in the order given."""
    names = [names] if isinstance(names, (str, Method)) else list(names)
    wanted, others = set(), []
    for name in names:
        if isinstance(name, Method):
            found = [check_method(name, "a method object")]
        elif name == "all":
            wanted |= set(METHODS)
            continue
        elif name in GROUPS:
            wanted |= set(GROUPS[name])
            continue
        elif name in METHODS:
            wanted.add(name)
            continue
        else:
            external = is_external(name) and name not in installed_methods()
            found = load_external(name) if external else [get_method(name)]
        others += [m for m in found if m.name not in [o.name for o in others]]
    clash = [m.name for m in others if m.name in wanted and m is not METHODS.get(m.name)]
    if clash:
        raise MethodError(f"two methods named {clash[0]!r}: rename yours (the harness has one)")
    return [m for name, m in METHODS.items() if name in wanted] + others


def methods_for(case, methods) -> list[Method]:
    """Those of ``methods`` that discretise ``case``'s physics and dimension (the weak methods
    are scalar and 2D only), in the order given; a study runs each case with these."""
    return [m for m in methods if m.supports(case)]


def get_method(name: str) -> Method:
    """A registered method, or one with parameters: ``nitsche:gamma0=0.5,theta=-1``."""
    if ":" in name:
        return parse_method(name)
    if name in METHODS:
        return METHODS[name]
    if name in installed_methods():
        return installed_methods()[name]
    raise MethodError(f"unknown method {name!r}; expected one of: {', '.join(method_choices())}, "
                      f"a file (path/to/method.py[:name]) or a module (package.module[:name])")


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


__all__ = ["METHODS", "GROUPS", "BoundConstrained", "Expectation", "FunctionalCone", "LevelSolve", "Method", "MethodError", "WeakContact",
           "check_method", "get_method", "method_choices", "methods_for", "methods_named", "parse_method"]
