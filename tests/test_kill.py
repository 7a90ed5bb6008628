"""Kill tests (issue 50): a report, and two runs sharing one folder, killed with SIGKILL at
several points and started again, end with the results of an uninterrupted run and no orphan
file (no temporary file, lock file or checkpoint). Minutes of work: `make test-full`.

The points are events seen in the folder (a checkpoint written, a CSV stored, the tables
written), not fractions of a clean run's wall time: on a loaded machine a second run can be
faster than the first, and a kill timed by the first then comes after the end."""
import json
import os
import pickle
import signal
import subprocess
import sys
import time
from pathlib import Path

import pandas as pd
import pytest

from harness.study.storage.files import TEMPORARY_MARK
from harness.study.storage.folder import LOCK_NAME

ROOT = Path(__file__).resolve().parent.parent
pytestmark = pytest.mark.slow

# a small report as `make report` runs it (two local processes of one thread: bit for bit)
REPORT = ["report", "--levels", "3", "--case", "transition-r32", "--case", "corner-r12", "--method", "paper", "--workers", "2",
          "--quiet"]


def checkpoint_written(results: Path) -> bool:
    return any(results.rglob("*.ckpt"))


def levels_finished(folder: Path) -> int:
    """Levels the chains checkpointed under ``folder`` have finished, summed over the chains."""
    finished = 0
    for path in folder.rglob("*.ckpt"):
        try:
            finished += pickle.loads(path.read_bytes())[1].next_level
        except (OSError, EOFError, pickle.UnpicklingError):
            pass                                # replaced while read: seen on the next look
    return finished


# where a report is killed: in the study (a chain's first level stored), as figures are drawn
# (the CSVs stored), while the page is written (its tables written, the page not yet)
REPORT_KILLS = (lambda results, report: checkpoint_written(results),
                lambda results, report: (results / "rates.csv").exists(),
                lambda results, report: (report / "tables").exists())


def start(args, env=None):
    """``python -m harness ARGS`` in its own process group (a kill takes its workers too)."""
    return subprocess.Popen([sys.executable, "-m", "harness", *args], cwd=ROOT, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            text=True, start_new_session=True, env=env)


def finish(args) -> float:
    clock = time.perf_counter()
    process = start(args)
    _, err = process.communicate()
    assert process.returncode == 0, err
    return time.perf_counter() - clock


def kill_when(process, event, timeout: float = 600.0) -> bool:
    """SIGKILL to ``process`` and its workers as soon as ``event()`` holds; False if the process
    ended first."""
    clock = time.perf_counter()
    while process.poll() is None and time.perf_counter() - clock < timeout:
        if event():
            os.killpg(process.pid, signal.SIGKILL)
            process.wait()
            return True
        time.sleep(0.002)
    return False


def measured(path: Path) -> pd.DataFrame:
    """A CSV's columns that do not measure time, in a fixed row order."""
    frame = pd.read_csv(path)
    frame = frame[[c for c in frame.columns if "seconds" not in c]]
    return frame.sort_values([c for c in ("case", "method", "mesh", "level") if c in frame.columns]).reset_index(drop=True)


def orphans(*folders: Path) -> list[Path]:
    return [p for folder in folders for p in folder.rglob("*")
            if TEMPORARY_MARK in p.name or p.name in (LOCK_NAME, ".checkpoints")]


def test_a_report_killed_anywhere_and_run_again_gives_the_same_results_and_no_orphan(tmp_path):
    clean = tmp_path / "clean"
    finish([*REPORT, "--results", str(clean / "results"), "--report", str(clean / "report")])
    for k, event in enumerate(REPORT_KILLS):
        folder = tmp_path / f"killed-{k}"
        args = [*REPORT, "--results", str(folder / "results"), "--report", str(folder / "report")]
        assert kill_when(start(args), lambda: event(folder / "results", folder / "report")), k
        finish(args)
        for name in ("results.csv", "rates.csv"):
            pd.testing.assert_frame_equal(measured(folder / "results" / name), measured(clean / "results" / name))
        assert orphans(folder) == []
        assert sorted(p.relative_to(folder) for p in folder.rglob("*")) == \
            sorted(p.relative_to(clean) for p in clean.rglob("*")), k


def wait_for_owner(folder: Path, process, timeout: float = 60.0) -> None:
    """Wait until ``process`` owns ``folder`` (its pid in the lock file), so that a second
    command is started only once the first holds the folder: which of two commands started
    together wins the lock is a race the machine's scheduler decides."""
    clock = time.perf_counter()
    while time.perf_counter() - clock < timeout:
        assert process.poll() is None, process.communicate()[1]
        try:
            if json.loads((folder / LOCK_NAME).read_text() or "{}").get("pid") == process.pid:
                return
        except (OSError, ValueError):
            pass
        time.sleep(0.01)
    raise AssertionError(f"{process.args} did not take {folder} in {timeout} s")


def test_two_runs_on_one_folder_killed_and_run_again_keep_every_row_and_no_orphan(tmp_path):
    first = ["run", "--case", "transition-r32", "--method", "nodal", "--method", "p1", "--levels", "6", "--threads", "1", "--quiet"]
    second = ["run", "--case", "corner-r12", "--method", "mean", "--levels", "5", "--threads", "1", "--quiet"]
    clean = tmp_path / "clean"
    finish([*first, "--out", str(clean)])
    finish([*second, "--out", str(clean)])
    # the first is killed as soon as the second is refused (its two chains of six levels part-way,
    # the second's start-up takes seconds) and once one chain is complete (11 of 12 levels done)
    for finished in (0, 11):
        folder = tmp_path / f"killed-{finished}"
        a = start([*first, "--out", str(folder)])
        wait_for_owner(folder, a)
        b = start([*second, "--out", str(folder)])
        _, err = b.communicate()
        # the second is refused in one line naming the first, before it writes anything
        assert b.returncode == 2 and err.count("\n") == 1 and "is in use by" in err and f"pid {a.pid}" in err, err
        assert kill_when(a, lambda: levels_finished(folder) >= finished), finished
        for args in (first, second):
            finish([*args, "--out", str(folder)])
        pd.testing.assert_frame_equal(measured(folder / "results.csv"), measured(clean / "results.csv"))
        assert orphans(folder) == []
