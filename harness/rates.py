"""Deprecated: harness.rates moved to ``harness.measure.rates`` (harness 0.3.0); this alias goes in 0.4.0."""
import warnings

from .measure.rates import *  # noqa: F401,F403

warnings.warn("harness.rates is deprecated: import from harness.measure.rates (harness 0.3.0; the alias goes in 0.4.0)",
              DeprecationWarning, stacklevel=2)
