"""Public names imported from their modules when first used (PEP 562): a package's
``import`` costs the standard library, not NGSolve, pandas or SciPy."""
from __future__ import annotations

import importlib
import sys


def lazy(package: str, public: dict[str, str]):
    """(``__getattr__``, ``__dir__``) of a package whose ``public`` names (name -> module, relative
    to ``package``) are imported from their modules when first used (PEP 562); a name that is its
    module's own is the module. ``__dir__`` lists the public names and the package's own public
    attributes (not its imports' private names)."""

    def __getattr__(name: str):
        if name not in public:
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        module = importlib.import_module(f"{package}.{public[name]}")
        value = module if public[name] == name else getattr(module, name)
        setattr(sys.modules[package], name, value)
        return value

    def __dir__() -> list[str]:
        return sorted({*vars(sys.modules[package]), *public})
    return __getattr__, __dir__
