"""Deprecated: harness.functions moved to ``harness.problem.functions`` (harness 0.3.0); this alias goes in 0.4.0."""
import warnings

from .problem.functions import *  # noqa: F401,F403

warnings.warn("harness.functions is deprecated: import from harness.problem.functions (harness 0.3.0; the alias goes in 0.4.0)",
              DeprecationWarning, stacklevel=2)
