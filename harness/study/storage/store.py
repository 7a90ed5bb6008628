"""Where a study's rows are kept: a results folder that one run owns at a time
(``folder.owned``), its rows merged by key into the folder's results.csv (``merge``), written
atomically with the mode the umask gives (``files.write_csv``). ``harness.run(out=...)``,
``harness.store`` and the command line's ``run`` all keep rows here, so they write the same file
(a whole study run into a folder: ``study.execution.into_folder``).
"""
from __future__ import annotations

from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path

import pandas as pd

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
