"""The load rows of `bench`: a study's wall time on an idle machine and beside one
busy process (a Python loop holding a core, as a browser tab, a second study or a CI
neighbour does), with the default thread policy (``study.execution.threads``: per level, the cores the
other processes leave free), with one thread, and with every core on every level (``--threads``
= the core count, which the goals label 0.3.10). Each run is a fresh ``python -m harness run``,
timed from outside, all in one command so that the ratios are measured in one sitting."""
from __future__ import annotations

import subprocess
import sys
import tempfile
import time
from pathlib import Path

import pandas as pd


def load_runs() -> tuple:
    """(label, the run's arguments): a two-level study (every level below the serial threshold)
    and one to 5.7e5 dofs (two levels above it) of the reference method and the P1 baseline (the
    methods that declare the roles REFERENCE and BASELINE)."""
    from ..measure.reference import REFERENCE_METHOD
    from ..methods import BASELINE, role_names
    pair = [arg for name in (REFERENCE_METHOD, *role_names(BASELINE)[:1]) for arg in ("--method", name)]
    return (("2 levels (609 dofs)", ["--case", "transition-r32", "--levels", "2"]),
            ("7 levels (5.7e5 dofs)", ["--case", "transition-r32", *pair, "--levels", "7"]))


LOAD_COLUMNS = ["run", "threads", "load", "seconds"]

BUSY_LOOP = "while True: pass"


def _timed_run(arguments: list[str], threads: str, folder: Path) -> float:
    extra = [] if threads == "auto" else ["--threads", threads]
    start = time.perf_counter()
    done = subprocess.run([sys.executable, "-m", "harness", "run", *arguments, *extra, "--out", str(folder), "--quiet"],
                          capture_output=True, text=True)
    seconds = time.perf_counter() - start
    if done.returncode:
        raise RuntimeError(f"bench load: run {' '.join(arguments)} failed: {done.stderr.strip().splitlines()[-1:]}")
    return seconds


# each time is the fastest of this many runs, interleaved with the other settings' (the same
# run's idle time varies from run to run on a shared machine)
LOAD_REPEATS = {"2 levels (609 dofs)": 3, "7 levels (5.7e5 dofs)": 2}


def run_load_bench(runs=None, progress=print) -> pd.DataFrame:
    """Every run of ``runs`` (default ``load_runs()``) with each thread setting, idle and beside
    one busy process; each the fastest of its ``LOAD_REPEATS``, the settings interleaved."""
    from ..study.execution.threads import usable_cpus
    runs = runs or load_runs()
    settings = ["auto", "1", str(usable_cpus())]
    best: dict = {}
    with tempfile.TemporaryDirectory(prefix="harness-bench-load-") as folder:
        for load in ("idle", "one busy process"):
            busy = subprocess.Popen([sys.executable, "-c", BUSY_LOOP]) if load != "idle" else None
            try:
                for label, arguments in runs:
                    for repeat in range(LOAD_REPEATS.get(label, 1)):
                        for threads in settings:
                            seconds = _timed_run(arguments, threads, Path(folder) / f"{len(best)}-{repeat}")
                            key = (label, threads, load)
                            best[key] = min(best.get(key, seconds), seconds)
                            progress(f"load {label:22s} threads {threads:4s} {load:17s} {seconds:7.2f} s")
            finally:
                if busy is not None:
                    busy.kill()
                    busy.wait()
    return pd.DataFrame([(*key, seconds) for key, seconds in best.items()], columns=LOAD_COLUMNS)


def load_goals(frame: pd.DataFrame) -> list[tuple[str, bool, str]]:
    """The goals: beside one busy process the two-level run takes at most twice its idle time
    and the large one at most 1.3 times its one-thread time; idle, no slower than every core on
    every level (within 10%, for the noise of shared machines)."""
    t = frame.set_index(["run", "threads", "load"]).seconds
    labels = list(dict.fromkeys(frame.run))
    small, large = labels[0], labels[-1]
    every = frame.threads[~frame.threads.isin(["auto", "1"])].iloc[0]
    busy = "one busy process"
    out = [(f"{small}, busy / idle <= 2 (default threads)", t[small, "auto", busy] / t[small, "auto", "idle"] <= 2,
            f"{t[small, 'auto', busy] / t[small, 'auto', 'idle']:.2f} ({t[small, 'auto', busy]:.1f} s / {t[small, 'auto', 'idle']:.1f} s; "
            f"0.3.10's {every} threads: {t[small, every, busy] / t[small, every, 'idle']:.2f})"),
           (f"{large}, busy: default / --threads 1 <= 1.3", t[large, "auto", busy] / t[large, "1", busy] <= 1.3,
            f"{t[large, 'auto', busy] / t[large, '1', busy]:.2f} ({t[large, 'auto', busy]:.1f} s / {t[large, '1', busy]:.1f} s; "
            f"0.3.10's {every} threads: {t[large, every, busy] / t[large, '1', busy]:.2f})")]
    for label in labels:
        ratio = t[label, "auto", "idle"] / t[label, every, "idle"]
        out.append((f"{label}, idle: default / {every} threads on every level (0.3.10) <= 1.1", ratio <= 1.1, f"{ratio:.2f}"))
    return out
