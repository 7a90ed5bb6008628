"""Convergence-study harness for the Signorini problem: the quadratic finite elements of
Z. Belhachmi and F. Ben Belgacem, Math. Comp. 72 (2003), beside other discretisations; see
docs/development/architecture.md ("How the code is laid out")."""
from .core.lazy import lazy as _lazy

__version__ = "0.17.0"      # the one version: pyproject.toml reads it

# The public names, each imported from its stage when first used (PEP 562): `import harness`
# and the listing commands cost the standard library, not NGSolve, pandas or SciPy. The
# protocols of what a user brings are in `harness.methods`, `harness.mesh` and `harness.problem`.
_PUBLIC = {
    "run": "api", "rates": "api", "quantities": "api", "efficiency": "api", "plot": "api", "store": "api",
    "cases": "api", "case_table": "api", "method_table": "api", "StudyWarning": "api",
    "report": "api", "sweep": "api", "export": "api", "coulomb_axis": "api", "external": "methods", "solution_writer": "study.export", "latex_tables": "api", "Engine": "study.execution.engines",
    "load_case": "problem.case", "registered_cases": "problem.case", "Case": "problem.case",
    "CaseError": "problem.case", "METHODS": "methods", "methods_named": "methods",
    "InProcess": "study", "LocalProcesses": "study", "DaskEngine": "study",
    "methods": "methods", "mesh": "mesh", "problem": "problem",     # the protocols' packages, as attributes
    "FolderBusy": "study.storage.folder", "StudyFailed": "study.storage.store", "VtkWriter": "report.vtk",
}
# the report package, imported once here, where the import system binds it as `harness.report`;
# unbound again, so that `harness.report` is the function of _PUBLIC and stays so after
# `import harness.report.plots` (the package is bound once, when first imported)
from . import report as _report_package  # noqa: E402

del globals()["report"], _report_package
__all__ = list(_PUBLIC)


__getattr__, __dir__ = _lazy(__name__, _PUBLIC)
del _lazy
