"""Convergence-study harness for quadratic finite elements on the Signorini problem
(Z. Belhachmi and F. Ben Belgacem, Math. Comp. 72 (2003)); see README.md."""
from .api import case_table, cases, run
from .case import Case, CaseError, load_case, registered_cases
from .models import MODELS

__version__ = "0.1.0"
__all__ = ["run", "cases", "case_table", "load_case", "registered_cases", "Case", "CaseError", "MODELS"]
