"""The study's module paths of 0.10 (`harness.study.cache`, `harness.study.engines`, ...),
each the module of its subpackage under its old name, with a DeprecationWarning on import
(CHANGELOG 0.11.0): a finder on ``sys.meta_path`` that answers for these names only."""
from __future__ import annotations

import importlib
import importlib.abc
import importlib.util
import sys
import warnings

MOVED = {
    **{name: f"chain.{name}" for name in ("walk", "one_body", "two_body", "rows", "outcome", "snapshots")},
    **{name: f"execution.{name}" for name in ("engines", "processes", "dask_engine", "threads", "budget", "progress")},
    **{name: f"storage.{name}" for name in ("files", "folder", "merge", "store", "checkpoint")},
    **{name: f"planning.{name}" for name in ("cache", "mesh_study", "degree_study", "sweep", "timing")},
}


class _Alias(importlib.abc.MetaPathFinder, importlib.abc.Loader):
    """Imports ``package.old`` as the module ``package.MOVED[old]``, once, warning."""

    def __init__(self, package: str):
        self.package = package
        self.specs = {}

    def find_spec(self, fullname, path=None, target=None):
        head, _, old = fullname.rpartition(".")
        if head != self.package or old not in MOVED:
            return None
        return importlib.util.spec_from_loader(fullname, self)

    def create_module(self, spec):
        old = spec.name.rpartition(".")[2]
        new = f"{self.package}.{MOVED[old]}"
        warnings.warn(f"{spec.name} is {new} since harness 0.11.0", DeprecationWarning, stacklevel=2)
        module = importlib.import_module(new)
        self.specs[spec.name] = module.__spec__
        return module

    def exec_module(self, module):
        # the module is the new one, already executed; the import system, which set its
        # __spec__ to the old name's, binds it under the old name in sys.modules
        module.__spec__ = self.specs.pop(module.__spec__.name)


def install(package: str) -> None:
    """Answer for the old module paths of ``package`` (once per process)."""
    if not any(isinstance(f, _Alias) and f.package == package for f in sys.meta_path):
        sys.meta_path.append(_Alias(package))
