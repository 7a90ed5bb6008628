"""The Python API, for scripts and notebooks:

    >>> import harness
    >>> df = harness.run(["transition-r32"], models="all", levels=5)
    >>> harness.cases()
"""
from __future__ import annotations

import pandas as pd

from .case import Case, fraction, load_case, registered_cases
from .models import MODELS, get_model
from .study import run_study


def models_named(name: str):
    return list(MODELS.values()) if name == "all" else [get_model(name)]


def run(cases, models: str = "all", levels: int = 5, show_progress: bool = True, on_level=None) -> pd.DataFrame:
    """Run a convergence study; ``cases`` are names, paths or Case objects (or one of them)."""
    if isinstance(cases, (str, Case)):
        cases = [cases]
    loaded = [c if isinstance(c, Case) else load_case(c) for c in cases]
    return run_study(loaded, models_named(models), levels, show_progress=show_progress, on_level=on_level)


def case_table(cases=None) -> pd.DataFrame:
    """One row per case: regularity, theorem and the rate it predicts."""
    cases = list(registered_cases().values()) if cases is None else cases
    return pd.DataFrame([{
        "case": c.name, "nu": fraction(c.nu), "regime": c.regime, "theorem": c.theorem,
        "expected_rate": c.expected_rate, "expected_log_exponent": c.expected_log_exponent,
        "bound": c.expected_bound, "description": c.description,
    } for c in cases])


cases = case_table
