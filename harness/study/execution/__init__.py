"""Where a study's jobs run and what they cost: in this process, on local worker processes or on
Dask workers (``engines``, ``processes``, ``dask_engine``; ``engines.Engine``, what the three
have in common), a study run into a results folder (``into_folder``), how many threads a level
gets (``threads``), what a study will cost before it starts (``budget``) and one progress bar for
all of it (``progress``)."""
