"""Stage 7, the study: the level chain of a case and its methods (``chain``), parameter
sweeps (``sweep``), the report's computations and their cache (``cache``); where its jobs run
(this process, local processes or Dask workers: ``engines``, ``processes``,
``dask_engine``), what makes every finished level durable
(``checkpoint``), what it will cost before it starts (``budget``), and one progress bar for all
of it (``progress``). Imports the stages before it."""
from .dask_engine import DaskEngine
from .engines import InProcess, run_jobs, run_study
from .processes import LocalProcesses

__all__ = ["DaskEngine", "InProcess", "LocalProcesses", "run_jobs", "run_study"]
