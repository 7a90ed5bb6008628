"""Methods from outside the package, by every route a Python user expects:

- a file: ``--method path/to/my_method.py`` (its ``method``, its ``methods``, or else every
  ``Method`` it defines) or ``path/to/my_methods.py:quarter_points`` (one name in it);
- a dotted name: ``--method mypkg.contact:quarter_points`` (an attribute of an importable
  module) or ``--method mypkg.contact`` (the module, read as a file is);
- an entry point of an installed package, in the group "signorini_harness.methods" (the
  pattern of pytest's plug-ins), selected by its method's name like a registered method::

      [project.entry-points."signorini_harness.methods"]
      quarter-points = "mypkg.contact:quarter_points"

- an object: ``harness.run(cases, methods=[my_method, "nodal"])``.

The loading is ``core.plugins``'s, as for mesh strategies and cases. Every route, and every
registered method, passes the same checks (``check_method``); a file
that fails to import, defines no method or a malformed one is refused in one line
(``MethodError``, a ValueError: exit 2 on the command line, nothing written).
"""
from __future__ import annotations

import functools
import re
from dataclasses import replace
from pathlib import Path

from ..core.plugins import PluginError, entry_point_objects, load_spec
from ..fem.assembly import ORDERS
from ..fem.contact_laws.protocol import ContactLaw
from .method import Method, no_theory
from .protocol import ContactLawMethod, OwnSolve

ENTRY_POINTS = "signorini_harness.methods"
NAME = re.compile(r"^[A-Za-z0-9][A-Za-z0-9_.+-]*$")


class MethodError(PluginError):
    """A method that cannot be used, in one line."""


def check_method(obj, where: str) -> Method:
    """``obj`` if it is a usable method: a ``Method`` with a name that fits a CSV cell and the
    command line, an order of ``fem.assembly.ORDERS``, a theory (``expected``) to call, the physics, dimensions
    and bodies it discretises, and a ``solve`` of its own; MethodError naming ``where`` else."""
    if not isinstance(obj, Method):
        raise MethodError(f"{where}: {obj!r} is not a method (an instance of harness.methods.Method or a subclass)")
    problems = []
    if not isinstance(obj.name, str) or not NAME.match(obj.name):
        problems.append(f"name {obj.name!r} is not letters, digits and _.+- (no spaces, ':' or ',')")
    if obj.order not in ORDERS:
        problems.append(f"order {obj.order!r} is not one of {', '.join(map(str, ORDERS))}")
    if obj.expected is None:
        obj = replace(obj, expected=no_theory)
    if not callable(obj.expected):
        problems.append("expected (case -> Expectation, or None for no theory) is not callable")
    for field in ("physics", "dimensions", "bodies"):
        if not isinstance(getattr(obj, field), tuple) or not getattr(obj, field):
            problems.append(f"{field} is not a non-empty tuple")
    if type(obj).solve is Method.solve:
        problems.append("it has no solve (use FunctionalCone, ContactLawMethod or OwnSolve, or define solve)")
    if isinstance(obj, ContactLawMethod) and not isinstance(obj.law, ContactLaw):
        problems.append("its law has no branch, term and derivative (harness.methods.ContactLaw)")
    if isinstance(obj, OwnSolve) and not callable(obj.solve_level):
        problems.append("its solve_level (LevelProblem -> OwnSolution) is not callable")
    if problems:
        raise MethodError(f"{where}: method {getattr(obj, 'name', obj)!r} is malformed: {'; '.join(problems)}")
    return obj


def _checked(objects: list, where: str) -> list[Method]:
    return [check_method(obj, where) for obj in objects]


def _with_source(methods: list[Method], source: Path | None) -> list[Method]:
    """The methods, each knowing the file that defines it (its checkpoints and cached results
    are then those of that file's content: ``study.storage.checkpoint``)."""
    return methods if source is None else [replace(m, source=str(source)) for m in methods]


def load_external(spec: str) -> list[Method]:
    """The methods of a Python file (``FILE`` or ``FILE:name``) or of a module (``package.module[:name]``
    or ``package.module:name``): its ``method``, its ``methods``, or every ``Method`` it defines."""
    objects, source = load_spec(spec, ("method", "methods"), Method, "method")
    return _with_source(_checked(objects, spec), source)


@functools.lru_cache(maxsize=1)
def installed_methods() -> dict[str, Method]:
    """The methods installed packages declare in the entry-point group ``ENTRY_POINTS``, by name."""
    found = {}
    for objects, source, where in entry_point_objects(ENTRY_POINTS, ("method", "methods"), Method, "method"):
        for method in _with_source(_checked(objects, where), source):
            found[method.name] = method
    return found
