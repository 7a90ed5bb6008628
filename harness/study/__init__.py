"""Stage 7, the study, in four subpackages: the level chain of a case and its methods
(``chain``: the computing code), where its jobs run and what they cost (``execution``), the
results folder and what is kept in it (``storage``), and what the report asks of the study
(``planning``: the report's studies, sweeps and their cache, outside the code digest). Imports
the stages before it."""
from ._moved import install as _install
from .execution.dask_engine import DaskEngine
from .execution.engines import Engine, InProcess, run_jobs, run_study
from .execution.processes import LocalProcesses

__all__ = ["DaskEngine", "Engine", "InProcess", "LocalProcesses", "run_jobs", "run_study"]
_install(__name__)
