"""Stage 7, the study: the level chain of a case and its methods (``chain``), parameter
sweeps (``sweep``), the report's computations and their cache (``cache``); where its jobs run
(this process or Dask workers: ``engines``), what makes every finished level durable
(``checkpoint``), what it will cost before it starts (``budget``), and one progress bar for all
of it (``progress``). Imports the stages before it."""
from .engines import DaskEngine, InProcess, run_jobs, run_study

__all__ = ["DaskEngine", "InProcess", "run_jobs", "run_study"]
