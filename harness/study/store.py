"""Where a study's rows are kept: a results folder that one run owns at a time
(``folder.owned``), its rows merged by key into the folder's results.csv (``merge``), written
atomically with the mode the umask gives (``files.write_csv``). ``harness.run(out=...)``,
``harness.store`` and the command line's ``run`` all keep rows here, so they write the same file.
"""
from __future__ import annotations

from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path

import pandas as pd

from .checkpoint import CheckpointStore
from .engines import run_study
from .files import write_csv
from .folder import owned
from .merge import Merged, merge_rows, read_rows

RESULTS_FILE = "results.csv"
CHECKPOINTS = ".checkpoints"


class StudyFailed(RuntimeError):
    """A study that stopped on an error after it started (its ``__cause__``: the error), as
    opposed to input refused before it: the command line exits 3, not 2."""


@contextmanager
def study_phase():
    """Errors raised inside, but for an interruption, become ``StudyFailed`` (the original chained)."""
    try:
        yield
    except StudyFailed:
        raise
    except Exception as error:
        raise StudyFailed(f"{type(error).__name__}: {error}") from error


@dataclass(frozen=True)
class Stored:
    """Rows kept in a results file: its ``path``, and what the merge added, replaced and kept."""

    path: Path
    merged: Merged

    def summary(self) -> str:
        """One line: what the rows added to the file, replaced in it and kept of it."""
        return self.merged.summary(self.path)


def store_rows(rows: pd.DataFrame, folder) -> Stored:
    """``rows`` merged into ``folder``/results.csv (made if needed) while this process owns the
    folder; ``folder.FolderBusy`` if another command owns it, before anything is written."""
    with owned(Path(folder)) as out:
        return merge_into(out, rows)


def merge_into(out: Path, rows: pd.DataFrame) -> Stored:
    """``rows`` merged into ``out``/results.csv; the caller owns ``out``."""
    path = out / RESULTS_FILE
    merged = merge_rows(read_rows(path), rows)
    write_csv(merged.frame, path)
    return Stored(path, merged)


def run_into(folder, cases, methods, levels: int, *, engine=None, meshes, show_progress: bool = True,
             on_level=None) -> tuple[pd.DataFrame, Stored]:
    """The study (``engines.run_study``) into ``folder``, which this process owns while it runs:
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
