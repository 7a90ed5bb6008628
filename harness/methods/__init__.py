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
from contextlib import contextmanager

from ..fem.contact_law import ContactLaw, GammaPoints, LawError
from ..fem.laws import Nitsche, Penalty
from ..mesh.plugins import is_external
from ..solvers.options import SolverOptions
from .base import (
    BASELINE,
    DEGREES,
    MESH_STUDY,
    PAPER,
    REFERENCE,
    ROLES,
    SWEPT,
    BoundConstrained,
    Carry,
    Expectation,
    FunctionalCone,
    LevelSolve,
    Method,
    SolveFields,
    timer,
)
from .plugins import MethodError, check_method, installed_methods, load_external
from .protocol import ContactLawMethod, ContactPoints, LevelProblem, OwnSolution, OwnSolve

# Named groups besides the method names themselves.
GROUPS = {
    PAPER: (),              # the methods that declare the role PAPER: mean, nodal (``with_role``, below)
    "cones": ("mean", "nodal", "p1"),                                   # exact discrete inequalities
    "weak": ("nitsche", "penalty", "nitsche-p1", "penalty-p1"),         # contact by a Gamma_C term
    "mortar": ("mortar-mean", "mortar-nodal", "mortar-standard", "mortar-p1"),             # two bodies, non-matching meshes
    DEGREES: (),            # the methods that declare the role DEGREES: Nitsche and the nodal cone of each degree
    "high-order": ("nitsche-p3", "nitsche-p4", "penalty-p3", "penalty-p4", "nodal-p3", "nodal-p4", "mean-p3", "mean-p4"),  # k >= 3
}


def _discover() -> dict[str, Method]:
    found = []
    for info in pkgutil.iter_modules(__path__):
        if info.name in ("base", "plugins", "protocol") or info.name.startswith("_"):
            continue
        module = importlib.import_module(f"{__name__}.{info.name}")
        found.append(check_method(getattr(module, "method", None), f"harness/methods/{info.name}.py (its `method`)"))
    # the cones (the paper's P2 models first), then the weak methods, each by order; then the
    # methods of degree k >= 3, by degree
    def place(m):
        return (m.order > 2, m.order if m.order > 2 else 0, not isinstance(m, BoundConstrained), -m.order, m.name)
    return {m.name: m for m in sorted(found, key=place)}


METHODS = _discover()

# Methods this process was given as objects (``known``): found by name like the registered ones.
_GIVEN: dict[str, Method] = {}


def with_role(role: str, methods=None) -> list[Method]:
    """Those of ``methods`` (default: the registered ones, in registry order) that declare
    ``role`` (``base.ROLES``: PAPER, BASELINE, REFERENCE, SWEPT, MESH_STUDY), in their order.
    Nothing outside ``methods/`` names a method: it asks for a role, which a method of your own
    may declare too (``Method.roles``)."""
    methods = METHODS.values() if methods is None else methods
    return [m for m in methods if isinstance(m, Method) and role in m.roles]


def role_names(role: str, methods=None) -> list[str]:
    """The names of ``with_role(role, methods)``."""
    return [m.name for m in with_role(role, methods)]


GROUPS[PAPER] = tuple(role_names(PAPER))
GROUPS[DEGREES] = tuple(role_names(DEGREES))


def names_with_role(role: str, names, methods=()) -> list[str]:
    """Those of ``names`` (method names: a results column, say) whose method declares ``role``,
    once each in their order: each looked up among ``methods`` (Method objects), then by name
    (``get_method``: the registered methods, those of ``known`` and the installed ones); a name
    this process does not know declares none."""
    given = {m.name: m for m in methods if isinstance(m, Method)}
    out = []
    for name in dict.fromkeys(names):
        try:
            method = given[name] if name in given else get_method(name)
        except ValueError:               # MethodError too: a method this process does not know
            continue
        if with_role(role, [method]):
            out.append(name)
    return out


@contextmanager
def known(methods):
    """Within the block, ``get_method`` and ``methods_named`` find each of ``methods`` (Method
    objects: a method of your own from a file, a module or Python) by its name, as the report's
    study finds the methods of its settings (which hold names)."""
    given = [m for m in methods if isinstance(m, Method) and METHODS.get(m.name) is not m]
    before = dict(_GIVEN)
    _GIVEN.update({m.name: m for m in given})
    try:
        yield
    finally:
        _GIVEN.clear()
        _GIVEN.update(before)


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
        elif name in _GIVEN:
            found = [_GIVEN[name]]
        else:
            external = is_external(name) and name not in installed_methods()
            found = load_external(name) if external else [get_method(name)]
        others += [m for m in found if m.name not in [o.name for o in others]]
    clash = [m.name for m in others if m.name in wanted and m is not METHODS.get(m.name)]
    if clash:
        raise MethodError(f"two methods named {clash[0]!r}: rename yours (the harness has one)")
    return [m for name, m in METHODS.items() if name in wanted] + others


def methods_for(case, methods) -> list[Method]:
    """Those of ``methods`` that discretise ``case``'s physics, dimension and bodies (``Method.
    supports``), in the order given; a study runs each case with these."""
    return [m for m in methods if m.supports(case)]


def get_method(name: str) -> Method:
    """A registered method, or one with parameters: ``nitsche:gamma0=0.5,theta=-1``."""
    if ":" in name:
        return parse_method(name)
    if name in METHODS:
        return METHODS[name]
    if name in _GIVEN:
        return _GIVEN[name]
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


__all__ = ["METHODS", "GROUPS", "BASELINE", "DEGREES", "MESH_STUDY", "PAPER", "REFERENCE", "ROLES", "SWEPT", "known", "names_with_role",
           "role_names", "with_role", "BoundConstrained", "ContactLaw", "ContactLawMethod", "ContactPoints", "GammaPoints", "LawError",
           "LevelProblem", "SolverOptions", "Nitsche", "OwnSolution", "OwnSolve", "Penalty", "Carry", "Expectation", "SolveFields", "timer", "FunctionalCone", "LevelSolve", "Method", "MethodError",
           "check_method", "get_method", "method_choices", "methods_for", "methods_named", "parse_method"]
