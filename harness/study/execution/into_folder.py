"""A whole study run into a results folder, as ``harness.run(out=...)`` and the command line's
``run`` do: the folder owned while it runs, every finished level durable under its
.checkpoints, the rows merged into its results.csv (``storage.store``)."""
from __future__ import annotations

from pathlib import Path

import pandas as pd

from ..storage.checkpoint import CheckpointStore
from ..storage.folder import owned
from ..storage.merge import read_rows
from ..storage.store import CHECKPOINTS, RESULTS_FILE, Stored, merge_into, study_phase
from .engines import run_study


def run_into(folder, cases, methods, levels: int, *, engine=None, meshes, show_progress: bool = True,
             on_level=None) -> tuple[pd.DataFrame, Stored]:
    """The study (``study.execution.engines.run_study``) into ``folder``, which this process owns while it runs:
    every finished level made durable under ``folder``/.checkpoints (a study started again
    resumes there), the rows merged into ``folder``/results.csv, then the checkpoints deleted.
    A results.csv that is not one is refused before the study starts."""
    with owned(Path(folder)) as out:
        read_rows(out / RESULTS_FILE)
        checkpoints = out / CHECKPOINTS
        with study_phase():
            frame = run_study(cases, methods, levels, show_progress=show_progress, engine=engine,
                              checkpoints=checkpoints, check_memory=False, meshes=meshes, on_level=on_level)
        stored = merge_into(out, frame)
        store = CheckpointStore(checkpoints, levels)
        for case in cases:
            store.forget(case, every_mesh=True)
        if checkpoints.is_dir() and not any(checkpoints.iterdir()):
            checkpoints.rmdir()
    return frame, stored
