"""Convergence-study harness for the Signorini problem: the quadratic finite elements of
Z. Belhachmi and F. Ben Belgacem, Math. Comp. 72 (2003), beside other discretisations; see
docs/development/architecture.md ("How the code is laid out")."""
__version__ = "0.10.3"      # the one version: pyproject.toml reads it

# The public names, each imported from its stage when first used (PEP 562): `import harness`
# and the listing commands cost the standard library, not NGSolve, pandas or SciPy. The
# protocols of what a user brings are in `harness.methods`, `harness.mesh` and `harness.problem`.
_PUBLIC = {
    "run": "api", "rates": "api", "quantities": "api", "efficiency": "api", "plot": "api", "store": "api",
    "cases": "api", "case_table": "api", "method_table": "api", "StudyWarning": "api",
    "report": "api", "sweep": "api", "latex_tables": "api", "Engine": "study.execution.engines",
    "load_case": "problem.case", "registered_cases": "problem.case", "Case": "problem.case",
    "CaseError": "problem.case", "METHODS": "methods", "methods_named": "methods",
    "InProcess": "study", "LocalProcesses": "study", "DaskEngine": "study",
    "FolderBusy": "study.storage.folder", "StudyFailed": "study.storage.store", "VtkWriter": "report.vtk",
}
# the report package, imported once here, where the import system binds it as `harness.report`;
# unbound again, so that `harness.report` is the function of _PUBLIC and stays so after
# `import harness.report.plots` (the package is bound once, when first imported)
from . import report as _report_package  # noqa: E402

del globals()["report"], _report_package
__all__ = list(_PUBLIC)


def lazy(package: str, public: dict[str, str]):
    """(``__getattr__``, ``__dir__``) of a package whose ``public`` names (name -> module, relative
    to ``package``) are imported from their modules when first used (PEP 562); a name that is its
    module's own is the module."""
    import importlib
    import sys

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


__getattr__, __dir__ = lazy(__name__, _PUBLIC)
