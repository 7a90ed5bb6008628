"""The Python API, for scripts and notebooks:

    >>> import harness
    >>> df = harness.run(["transition-r32"], methods="all", levels=5)
    >>> harness.cases(), harness.method_table()
    >>> from harness.report.build import make_report     # a method object of your own in the report too
    >>> make_report(case_names=["transition-r32"], methods=[my_method, "paper"], levels=3)
"""
from __future__ import annotations

from typing import TYPE_CHECKING

if TYPE_CHECKING:
    import pandas as pd

# Every stage is imported by the function that needs it: listing the cases must not cost
# pandas, SciPy or the methods' modules (``harness/__init__``).


def run(cases, methods="all", levels: int = 5, show_progress: bool = True, on_level=None,
        models=None, engine=None, checkpoints=None, meshes="uniform") -> pd.DataFrame:
    """Run a convergence study; ``cases`` are names, paths or Case objects (or one of them);
    ``methods`` names, groups ('paper' = mean + nodal) or 'all' (``models`` is the old name:
    'all' there means the paper's two models). ``engine``: ``harness.study.LocalProcesses(2)`` (local
    processes), ``DaskEngine(scheduler="tcp://...")`` to run on Dask (default: this process);
    ``checkpoints``: a folder that makes every finished level durable (run again to resume).
    ``meshes``: a mesh strategy or a list of them -- "uniform" (the default), "graded",
    "adaptive" (or "adaptive:theta=0.3"), "all", a file or a module of your own, or a strategy
    object (``harness.mesh.strategies.Strategy``); ``methods`` may hold ``Method`` objects and
    files or modules of your own beside names (``harness.methods.plugins``); each case runs on
    each strategy that applies to it, and the rows say which in their ``mesh`` column."""
    from .mesh.strategies import parse_meshes
    from .methods import PAPER, methods_named, role_names
    from .problem.case import Case, load_case
    from .study import run_study
    if isinstance(cases, (str, Case)):
        cases = [cases]
    if models is not None:
        methods = role_names(PAPER) if models == "all" else models
    loaded = [c if isinstance(c, Case) else load_case(c) for c in cases]
    strategies = parse_meshes(list(meshes) if isinstance(meshes, (list, tuple)) else [meshes])
    return run_study(loaded, methods_named(methods), levels, show_progress=show_progress, on_level=on_level,
                     engine=engine, checkpoints=checkpoints, meshes=strategies)


def case_rows(cases=None) -> list[dict]:
    """One dict per case: regularity, theorem and the rate it predicts (``case_table``'s rows)."""
    from .problem.case import fraction, registered_cases
    cases = list(registered_cases().values()) if cases is None else cases
    return [{
        "case": c.name, "nu": fraction(c.nu), "regime": c.regime, "theorem": c.theorem,
        "expected_rate": c.expected_rate, "expected_log_exponent": c.expected_log_exponent,
        "bound": c.expected_bound, "description": c.description,
    } for c in cases]


def case_table(cases=None) -> pd.DataFrame:
    """One row per case: regularity, theorem and the rate it predicts."""
    import pandas as pd
    return pd.DataFrame(case_rows(cases))


def method_rows() -> list[dict]:
    """One dict per registered method: order, how it imposes contact, where it comes from."""
    from .methods import METHODS
    return [{"method": m.name, "order": m.order, "contact condition": m.contact,
             "parameters": m.parameter_text, "reference": m.reference} for m in METHODS.values()]


def method_table() -> pd.DataFrame:
    """One row per method: order, how it imposes contact, where it comes from."""
    import pandas as pd
    return pd.DataFrame(method_rows())


cases = case_table

