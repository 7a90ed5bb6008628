"""Deprecated: harness.execution moved to ``harness.study`` (harness 0.3.0); this alias goes in 0.4.0."""
import warnings

from ..study import *  # noqa: F401,F403

warnings.warn("harness.execution is deprecated: import from harness.study (harness 0.3.0; the alias goes in 0.4.0)",
              DeprecationWarning, stacklevel=2)
