"""Methods from outside the package, by every route a Python user expects:

- a file: ``--method path/to/my_method.py`` (its ``method``, its ``methods``, or else every
  ``Method`` it defines) or ``path/to/my_methods.py:quarter_points`` (one name in it);
- a dotted name: ``--method mypkg.contact:quarter_points`` (an attribute of an importable
  module) or ``--method mypkg.contact`` (the module, read as a file is);
- an entry point of an installed package, in the group ``signorini_harness.methods`` (the
  pattern of pytest's plug-ins), selected by its method's name like a registered method::

      [project.entry-points."signorini_harness.methods"]
      quarter-points = "mypkg.contact:quarter_points"

- an object: ``harness.run(cases, methods=[my_method, "nodal"])``.

Every route, and every registered method, passes the same checks (``check_method``); a file
that fails to import, defines no method or a malformed one is refused in one line
(``MethodError``, a ValueError: exit 2 on the command line, nothing written).
"""
from __future__ import annotations

import functools
import hashlib
import importlib
import importlib.metadata
import importlib.util
import re
import sys
from dataclasses import replace
from pathlib import Path

from .base import Method

ENTRY_POINTS = "signorini_harness.methods"
NAME = re.compile(r"^[A-Za-z0-9][A-Za-z0-9_.+-]*$")


class MethodError(ValueError):
    """A method that cannot be used, in one line."""


def check_method(obj, where: str) -> Method:
    """``obj`` if it is a usable method: a ``Method`` with a name that fits a CSV cell and the
    command line, an order of 1 or 2, a theory (``expected``) to call, the physics, dimensions
    and bodies it discretises, and a ``solve`` of its own; MethodError naming ``where`` else."""
    if not isinstance(obj, Method):
        raise MethodError(f"{where}: {obj!r} is not a method (an instance of harness.methods.Method or a subclass)")
    problems = []
    if not isinstance(obj.name, str) or not NAME.match(obj.name):
        problems.append(f"name {obj.name!r} is not letters, digits and _.+- (no spaces, ':' or ',')")
    if obj.order not in (1, 2):
        problems.append(f"order {obj.order!r} is not 1 or 2")
    if not callable(obj.expected):
        problems.append("expected (case -> Expectation, or None for no theory) is not callable")
    for field in ("physics", "dimensions", "bodies"):
        if not isinstance(getattr(obj, field), tuple) or not getattr(obj, field):
            problems.append(f"{field} is not a non-empty tuple")
    if type(obj).solve is Method.solve:
        problems.append("it has no solve (subclass BoundConstrained or WeakContact, or define solve)")
    if problems:
        raise MethodError(f"{where}: method {getattr(obj, 'name', obj)!r} is malformed: {'; '.join(problems)}")
    return obj


def _import_file(path: Path):
    """The module of the Python file ``path``, importable by its workers (pickled by value)."""
    digest = hashlib.sha1(str(path).encode()).hexdigest()[:8]
    name = f"_signorini_method_{re.sub(r'[^A-Za-z0-9_]', '_', path.stem)}_{digest}"
    if name in sys.modules:
        return sys.modules[name]
    spec = importlib.util.spec_from_file_location(name, path)
    if spec is None or spec.loader is None:
        raise MethodError(f"method file {path} cannot be imported")
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module
    try:
        spec.loader.exec_module(module)
    except (Exception, SystemExit) as exc:
        del sys.modules[name]
        raise MethodError(f"method file {path} failed to import: {type(exc).__name__}" + (f": {exc}" if str(exc) else "")) from exc
    import cloudpickle
    # its methods go to worker processes by value: the workers cannot import a file by path
    cloudpickle.register_pickle_by_value(module)
    return module


def _import_module(name: str):
    try:
        return importlib.import_module(name)
    except ImportError as exc:
        raise MethodError(f"method module {name!r} cannot be imported: {exc}") from exc
    except Exception as exc:
        raise MethodError(f"method module {name!r} failed to import: {type(exc).__name__}: {exc}") from exc


def _as_methods(obj, where: str) -> list[Method]:
    items = list(obj) if isinstance(obj, (list, tuple)) else [obj]
    if not items:
        raise MethodError(f"{where} is an empty list of methods")
    return [check_method(item, where) for item in items]


def methods_in(module, attribute: str | None, where: str) -> list[Method]:
    """The methods a module gives: ``attribute`` if named, else its ``method``, its ``methods``,
    or every ``Method`` it defines at top level (in the order defined)."""
    if attribute:
        if not hasattr(module, attribute):
            raise MethodError(f"{where} defines no {attribute!r}")
        return _as_methods(getattr(module, attribute), f"{where}:{attribute}")
    for name in ("method", "methods"):
        if hasattr(module, name):
            return _as_methods(getattr(module, name), f"{where}:{name}")
    found = [value for value in vars(module).values() if isinstance(value, Method)]
    if not found:
        raise MethodError(f"{where} defines no method (a harness.methods.Method named `method`, or any at top level)")
    return [check_method(m, where) for m in found]


def _with_source(methods: list[Method], source: Path | None) -> list[Method]:
    """The methods, each knowing the file that defines it (its checkpoints and cached results
    are then those of that file's content: ``study.checkpoint``)."""
    return methods if source is None else [replace(m, source=str(source)) for m in methods]


def is_external(spec: str) -> bool:
    """A method given by a file or a dotted module name, not by a registered name (registered
    names have neither dots nor slashes)."""
    base = spec.partition(":")[0]
    return base.endswith(".py") or "/" in base or "\\" in base or "." in base


def load_external(spec: str) -> list[Method]:
    """The methods of ``path.py``, ``path.py:name``, ``package.module`` or ``package.module:name``."""
    base, _, attribute = spec.partition(":")
    if base.endswith(".py") or "/" in base or "\\" in base:
        path = Path(base).expanduser()
        if not path.is_file():
            raise MethodError(f"method file not found: {base}")
        path = path.resolve()
        return _with_source(methods_in(_import_file(path), attribute, str(base)), path)
    module = _import_module(base)
    source = Path(module.__file__) if getattr(module, "__file__", None) else None
    return _with_source(methods_in(module, attribute, base), source)


@functools.lru_cache(maxsize=1)
def installed_methods() -> dict[str, Method]:
    """The methods installed packages declare in the entry-point group ``ENTRY_POINTS``, by name."""
    found = {}
    for entry in importlib.metadata.entry_points(group=ENTRY_POINTS):
        where = f"entry point {entry.name} = {entry.value} ({ENTRY_POINTS})"
        try:
            obj = entry.load()
        except Exception as exc:
            raise MethodError(f"{where} failed to load: {type(exc).__name__}: {exc}") from exc
        methods = methods_in(obj, None, where) if isinstance(obj, type(sys)) else _as_methods(obj, where)
        source = getattr(sys.modules.get(entry.module), "__file__", None)
        for method in _with_source(methods, Path(source) if source else None):
            found[method.name] = method
    return found
