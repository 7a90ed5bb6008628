"""Convergence-study harness for the Signorini problem: the quadratic finite elements of
Z. Belhachmi and F. Ben Belgacem, Math. Comp. 72 (2003), beside other discretisations; see
README.md."""
from .api import case_table, cases, method_table, run
from .case import Case, CaseError, load_case, registered_cases
from .methods import METHODS, methods_named

__version__ = "0.2.0"
__all__ = ["run", "cases", "case_table", "method_table", "load_case", "registered_cases", "Case", "CaseError",
           "METHODS", "methods_named"]
