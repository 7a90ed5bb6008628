"""Where the minutes of `make report` go: wall seconds by section (study, sweeps, rates,
figures, document), item (a case) and phase (the study's ``PHASES``), written beside the
results as ``report_profile.csv`` and printed by ``python -m harness bench --only report``."""
from __future__ import annotations

import time
from contextlib import contextmanager

import pandas as pd

PROFILE_COLUMNS = ["section", "item", "phase", "seconds"]


class Timings:
    """Rows of (section, item, phase, seconds), recorded as the report runs."""

    def __init__(self):
        self.rows: list[dict] = []

    def add(self, section: str, item: str, phase: str, seconds: float) -> None:
        self.rows.append({"section": section, "item": item, "phase": phase, "seconds": float(seconds)})

    @contextmanager
    def __call__(self, section: str, item: str = "", phase: str = ""):
        start = time.perf_counter()
        try:
            yield
        finally:
            self.add(section, item, phase, time.perf_counter() - start)

    def frame(self) -> pd.DataFrame:
        return pd.DataFrame(self.rows, columns=PROFILE_COLUMNS)


def by_section(profile: pd.DataFrame, wall: float) -> pd.DataFrame:
    """Seconds and share of the wall time per section and item (phases summed); the items of
    the study and the sweeps are cases, whose phases are the work of their jobs (summed over
    workers: on several workers their sum exceeds "jobs (wall)"); the figures are drawn in two
    processes, a case's as soon as it is stored on the cores the study leaves idle: the wall time
    spent waiting for them after the jobs is the "figures" row, the seconds each took in its
    process the "figures (in workers)" rows."""
    table = profile.fillna({"item": "", "phase": ""}).groupby(["section", "item"], sort=False).seconds.sum().reset_index()
    table["share"] = table.seconds / wall
    return table


def by_phase(profile: pd.DataFrame) -> pd.DataFrame:
    """The seconds of the study's and the sweeps' jobs per case (rows) and phase (columns)."""
    jobs = profile[profile.phase.fillna("") != ""]
    return jobs.pivot_table(index=["section", "item"], columns="phase", values="seconds", aggfunc="sum",
                            sort=False).fillna(0.0)
