"""Plug-ins from outside the package, whatever their kind (methods: ``harness.methods.plugins``;
mesh strategies: ``harness.mesh.strategies``; cases: ``harness.problem.case``): a file
(``path/to/file.py[:name]``), an attribute of an importable module (``package.module[:name]``),
an installed package's entry point or an object. The loading is one piece of code for every
kind; each kind says what it looks for and checks what it finds. It knows no stage, so that
every stage may use it.
"""
from __future__ import annotations

import hashlib
import importlib
import importlib.metadata
import importlib.util
import re
import sys
import traceback
from pathlib import Path


class PluginError(ValueError):
    """A plug-in that cannot be used, in one line."""


def is_external(spec: str) -> bool:
    """A plug-in given by a file or a dotted module name, not by a registered name (registered
    names have neither dots nor slashes before their parameters)."""
    base = spec.partition(":")[0]
    return base.endswith(".py") or "/" in base or "\\" in base or "." in base


def import_file(path: Path, kind: str, cached: bool = True):
    """The module of the Python file ``path``, pickled by value to worker processes (which
    cannot import a file by its path); ``cached``: a file imported before is not run again. A
    file that fails is one line naming it and the line of it that failed."""
    digest = hashlib.sha1(str(path).encode()).hexdigest()[:8]
    name = f"_signorini_{kind.replace(' ', '_')}_{re.sub(r'[^A-Za-z0-9_]', '_', path.stem)}_{digest}"
    if cached and name in sys.modules:
        return sys.modules[name]
    spec = importlib.util.spec_from_file_location(name, path)
    if spec is None or spec.loader is None:
        raise PluginError(f"{kind} file {path} cannot be imported")
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module
    try:
        spec.loader.exec_module(module)
    except (Exception, SystemExit) as exc:  # a broken user file: one clear line, not a traceback or its exit
        del sys.modules[name]
        raise PluginError(f"{kind} file {path}{_line_in(exc, path)} failed to import: {type(exc).__name__}"
                          + (f": {exc}" if str(exc) else "")) from exc
    import cloudpickle
    cloudpickle.register_pickle_by_value(module)
    return module


def _line_in(exc: BaseException, path: Path) -> str:
    """", line N": the last line of the file in the exception's traceback (or a syntax error's
    own line)."""
    if isinstance(exc, SyntaxError) and exc.lineno:
        return f", line {exc.lineno}"
    lines = [lineno for frame, lineno in traceback.walk_tb(exc.__traceback__)
             if Path(frame.f_code.co_filename).resolve() == Path(path).resolve()]
    return f", line {lines[-1]}" if lines else ""


def import_module(name: str, kind: str):
    try:
        return importlib.import_module(name)
    except ImportError as exc:
        raise PluginError(f"{kind} module {name!r} cannot be imported: {exc}") from exc
    except Exception as exc:
        raise PluginError(f"{kind} module {name!r} failed to import: {type(exc).__name__}: {exc}") from exc


def objects_in(module, attribute: str | None, names: tuple[str, ...], kind_type: type, where: str, kind: str) -> list:
    """What a module gives: ``attribute`` if named (one object or a list), else the first of
    ``names`` it defines, else every instance of ``kind_type`` at its top level (in the order
    defined); PluginError if there is none."""
    def listed(obj, label):
        items = list(obj) if isinstance(obj, (list, tuple)) else [obj]
        if not items:
            raise PluginError(f"{label} is an empty list")
        return items
    if attribute:
        if not hasattr(module, attribute):
            raise PluginError(f"{where} defines no {attribute!r}")
        return listed(getattr(module, attribute), f"{where}:{attribute}")
    for name in names:
        if hasattr(module, name):
            return listed(getattr(module, name), f"{where}:{name}")
    found = [value for value in vars(module).values() if isinstance(value, kind_type)]
    if not found:
        raise PluginError(f"{where} defines no {kind} (a `{names[0]}`, or any at top level)")
    return found


def load_spec(spec: str, names: tuple[str, ...], kind_type: type, kind: str) -> tuple[list, Path | None]:
    """(the objects of ``path.py[:name]`` or ``package.module[:name]``, the file that defines them)."""
    base, _, attribute = spec.partition(":")
    if base.endswith(".py") or "/" in base or "\\" in base:
        path = Path(base).expanduser()
        if not path.is_file():
            raise PluginError(f"{kind} file not found: {base}")
        path = path.resolve()
        return objects_in(import_file(path, kind), attribute, names, kind_type, base, kind), path
    module = import_module(base, kind)
    source = Path(module.__file__) if getattr(module, "__file__", None) else None
    return objects_in(module, attribute, names, kind_type, base, kind), source


def entry_point_objects(group: str, names: tuple[str, ...], kind_type: type, kind: str) -> list[tuple[list, Path | None, str]]:
    """(objects, defining file, where) of every entry point of ``group``: an object, a list of them or
    a module (read as a file is)."""
    found = []
    for entry in importlib.metadata.entry_points(group=group):
        where = f"entry point {entry.name} = {entry.value} ({group})"
        try:
            obj = entry.load()
        except Exception as exc:
            raise PluginError(f"{where} failed to load: {type(exc).__name__}: {exc}") from exc
        if isinstance(obj, type(sys)):
            objects = objects_in(obj, None, names, kind_type, where, kind)
        else:
            objects = list(obj) if isinstance(obj, (list, tuple)) else [obj]
        source = getattr(sys.modules.get(entry.module), "__file__", None)
        found.append((objects, Path(source) if source else None, where))
    return found


def entry_point_files(group: str, kind: str) -> list[Path]:
    """The files of the modules the entry points of ``group`` name (each a module of ``kind``,
    a .py file), found without importing them; PluginError in one line for one that is not."""
    files = []
    for entry in importlib.metadata.entry_points(group=group):
        try:
            spec = importlib.util.find_spec(entry.module)
        except (ImportError, ValueError) as exc:
            raise PluginError(f"{kind} entry point {entry.name} = {entry.value} ({group}): {exc}") from exc
        if spec is None or not spec.origin or not spec.origin.endswith(".py"):
            raise PluginError(f"{kind} entry point {entry.name} = {entry.value} ({group}) is not a {kind} module (.py)")
        files.append(Path(spec.origin))
    return files
