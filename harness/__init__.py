"""Convergence-study harness for the Signorini problem: the quadratic finite elements of
Z. Belhachmi and F. Ben Belgacem, Math. Comp. 72 (2003), beside other discretisations; see
docs/development/architecture.md ("How the code is laid out")."""
__version__ = "0.7.0"      # the one version: pyproject.toml reads it

from .api import case_table, cases, method_table, run  # noqa: E402
from .methods import METHODS, methods_named  # noqa: E402
from .problem.case import Case, CaseError, load_case, registered_cases  # noqa: E402

__all__ = ["run", "cases", "case_table", "method_table", "load_case", "registered_cases", "Case", "CaseError",
           "METHODS", "methods_named"]
