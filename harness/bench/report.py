"""`python -m harness bench --only report`: where the minutes of `make report` go, and what
Dask workers buy. Each variant (this process; N local Dask workers) runs the whole default
report from empty results in a fresh process and a fresh folder, so that its wall time, its
peak memory (the process and, for workers, theirs) and its profile (``timing``) are its own;
ratios are measured within the one run."""
from __future__ import annotations

import resource
import tempfile
import time
from pathlib import Path

import pandas as pd

from ..study.planning.timing import by_phase, by_section

# job_seconds: the work of every job, summed over processes; jobs_wall: the wall time of the
# jobs (their ratio: how busy the workers kept the cores); figures_wall: the figures' wall time
REPORT_BENCH_COLUMNS = ["engine", "workers", "wall_seconds", "peak_rss_mb", "job_seconds", "jobs_wall", "figures_wall", "speedup"]


def _measure_report(workers: int, profile: str, cases, levels, connection) -> None:
    from ..report.build import make_report
    from ..study import InProcess, LocalProcesses

    engine = LocalProcesses(workers) if workers else InProcess()
    with tempfile.TemporaryDirectory(prefix="harness-bench-report-") as folder:
        start = time.perf_counter()
        try:
            make_report(profile, Path(folder) / "results", Path(folder) / "report", cases, show_progress=False,
                        levels=levels, engine=engine)
        finally:
            engine.close()
        wall = time.perf_counter() - start
        timings = pd.read_csv(Path(folder) / "results" / "report_profile.csv")
    rss = max(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss, resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss)
    connection.send({"engine": engine.describe(), "workers": workers, "wall_seconds": wall, "peak_rss_mb": rss / 1024,
                     "profile": timings.to_dict("records")})
    connection.close()


def run_report_bench(workers=(0,), profile: str = "default", progress=print, cases=None,
                     levels: int | None = None) -> tuple[pd.DataFrame, pd.DataFrame]:
    """(one row per variant: wall seconds, peak RSS, speedup over the first; the first
    variant's profile rows). ``workers``: 0 for this process, N for N local worker processes;
    ``cases``, ``levels``: a smaller report than the profile's (tests)."""
    from .solvers import in_fresh_process
    rows, profile_rows = [], None
    for count in workers:
        progress(f"report ({'in process' if not count else f'{count} local processes'}) ...")
        out = in_fresh_process(_measure_report, (count, profile, cases, levels), f"the {profile} report")
        own = pd.DataFrame(out.pop("profile"))
        profile_rows = profile_rows if profile_rows is not None else own
        jobs = own[own.phase.fillna("") != ""]
        out |= {"job_seconds": jobs.seconds.sum(), "jobs_wall": own[own.section == "jobs (wall)"].seconds.sum(),
                "figures_wall": own[own.section == "figures"].seconds.sum()}
        rows.append(out)
    frame = pd.DataFrame(rows, columns=REPORT_BENCH_COLUMNS[:-1])
    frame["speedup"] = frame.wall_seconds.iloc[0] / frame.wall_seconds
    return frame, profile_rows


def profile_tables(profile_rows: pd.DataFrame) -> tuple[pd.DataFrame, pd.DataFrame]:
    """(seconds by section and item with their share of the wall time, the study's seconds by
    case and phase)."""
    wall = float(profile_rows[profile_rows.section == "total"].seconds.sum())
    sections = by_section(profile_rows[profile_rows.section != "total"], wall)
    return sections, by_phase(profile_rows)


def report_goals(frame: pd.DataFrame, make_workers: int | None = None) -> list[tuple[str, bool, str]]:
    """The goals: ``make report`` (the variant with ``make_workers`` workers, the
    Makefile's one per core; else the first) within 3 minutes and 3 GB per process on 2 cores;
    2 local processes at least 1.2x faster than this process."""
    out = []
    chosen = frame[frame.workers == make_workers] if make_workers is not None else frame.iloc[:0]
    made = (chosen if len(chosen) else frame).iloc[0]
    out.append(("make report <= 3 min", made.wall_seconds <= 180, f"{made.wall_seconds:.0f} s ({made.engine})"))
    out.append(("make report peak RSS <= 3 GB (largest process)", made.peak_rss_mb <= 3 * 1024, f"{made.peak_rss_mb:.0f} MB"))
    for row in frame.iloc[1:].itertuples():
        goal = f"report on {row.workers} local processes against the first variant"
        out.append((goal + (" >= 1.2x" if row.workers == 2 else " (shown)"), row.speedup >= 1.2 or row.workers != 2,
                    f"{row.wall_seconds:.0f} s, {row.speedup:.2f}x"))
    return out
