"""Deprecated: harness.geometry moved to ``harness.problem.geometry`` (harness 0.3.0); this alias goes in 0.4.0."""
import warnings

from .problem.geometry import *  # noqa: F401,F403

warnings.warn("harness.geometry is deprecated: import from harness.problem.geometry (harness 0.3.0; the alias goes in 0.4.0)",
              DeprecationWarning, stacklevel=2)
