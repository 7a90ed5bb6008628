"""Rows of several runs in one results file: a run adds its rows to what the folder holds,
replacing only the rows it computed again (same case, method and parameters, mesh, level),
and says so in one line (``Merged.summary``). A results folder then holds every row computed
into it, and no run -- nor a report -- silently drops another's.
"""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import pandas as pd

from ...measure.results_file import NotResults, read_results
from .files import OutputError

# what identifies a row: the same key computed again replaces it
ROW_KEY = ["case", "method", "parameters", "mesh", "level"]


def read_rows(path: Path) -> pd.DataFrame | None:
    """The rows already in results file ``path`` (None if there is none; read by
    ``measure.results_file.read_results``); OutputError, naming it, if it is not one this harness
    can merge into (nothing is then written over it)."""
    path = Path(path)
    if not path.is_file():
        return None
    try:
        frame = read_results(path, ("case", "method", "level"))
    except NotResults as exc:
        raise OutputError(f"{exc}: move it away or choose another output folder") from None
    if "parameters" not in frame.columns:
        frame["parameters"] = ""
    return frame


def _keys(frame: pd.DataFrame) -> pd.MultiIndex:
    key = frame[ROW_KEY].copy()
    key["parameters"] = key["parameters"].astype(object).fillna("").astype(str)
    key["level"] = key["level"].astype(int)
    return pd.MultiIndex.from_frame(key)


@dataclass
class Merged:
    """The rows of a results file after a run: ``frame`` (the kept rows of earlier runs, then the
    run's), how many of the run's rows replaced earlier ones and which (case, method) they were."""

    frame: pd.DataFrame
    new: int
    replaced: pd.DataFrame
    kept: int

    def summary(self, path: Path) -> str:
        """One line: what the run added, replaced and kept."""
        words = [f"wrote {path}: {self.new} row{'s' * (self.new != 1)} of this run"]
        if len(self.replaced):
            chains = sorted({f"{r.case} {r.method}" for r in self.replaced.itertuples()})
            shown = ", ".join(chains[:4]) + (f" and {len(chains) - 4} more" if len(chains) > 4 else "")
            words.append(f"replaced {len(self.replaced)} earlier row{'s' * (len(self.replaced) != 1)} ({shown})")
        if self.kept:
            words.append(f"kept {self.kept} row{'s' * (self.kept != 1)} of other runs")
        return "; ".join(words)


def merge_rows(earlier: pd.DataFrame | None, rows: pd.DataFrame) -> Merged:
    """``rows`` added to ``earlier`` (a results file's rows, or None): an earlier row with the
    key (``ROW_KEY``) of one of ``rows`` is replaced, every other kept, in its place."""
    if earlier is None or earlier.empty:
        return Merged(rows, len(rows), rows.iloc[:0], 0)
    again = _keys(earlier).isin(_keys(rows))
    kept = earlier[~again]
    columns = list(rows.columns) + [c for c in earlier.columns if c not in rows.columns]
    frame = pd.concat([kept, rows], ignore_index=True)[columns] if len(kept) else rows
    return Merged(frame, len(rows), earlier[again], len(kept))
