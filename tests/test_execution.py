"""Running studies (issue 17): local worker processes and Dask workers give the serial results
bit for bit, a study killed at any moment (the process with SIGKILL, a worker mid-job) continues from its last finished
level with the same results, a study that cannot fit is refused at once, and one progress bar
counts every level once."""
from __future__ import annotations

import os
import pickle
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

import pandas as pd
import pytest

from harness.cli import main
from harness.fem.assembly import discretise
from harness.mesh.levels import mesh_hierarchy
from harness.methods import METHODS, methods_for, methods_named
from harness.problem.case import load_case, registered_cases
from harness.study import DaskEngine, InProcess, LocalProcesses, run_study
from harness.study.execution import budget
from harness.study.execution.budget import BudgetError, LevelSizes, estimate
from harness.study.execution.engines import chains, study_weights
from harness.study.execution.progress import StudyProgress
from harness.study.storage.checkpoint import CheckpointStore
from harness.study.storage.files import write_csv

REPOSITORY = Path(__file__).resolve().parents[1]
# what may differ between two runs of one study: wall times
TIMINGS = ["solve_seconds", "total_seconds", "estimate_seconds", "measure_seconds"]


def assert_same_results(a: pd.DataFrame, b: pd.DataFrame) -> None:
    """Every column but the timings equal, bit for bit (NaN where NaN), row by row."""
    assert list(a.columns) == list(b.columns) and len(a) == len(b)
    for column in a.columns.drop(TIMINGS):
        x, y = a[column].reset_index(drop=True), b[column].reset_index(drop=True)
        same = (x == y) | (x.isna() & y.isna())
        assert same.all(), (column, a.loc[~same.values, ["case", "method", "level"]].values.tolist()[:3],
                            x[~same].tolist()[:3], y[~same].tolist()[:3])


def harness_command(*args: str) -> list[str]:
    return [sys.executable, "-m", "harness", *args]


def saved_levels(folder: Path) -> dict[str, int]:
    """Checkpoint file name -> the chain's next level, for the checkpoints under ``folder``."""
    levels = {}
    for path in folder.rglob("*.ckpt"):
        try:
            _key, state = pickle.loads(path.read_bytes())
        except (OSError, EOFError, pickle.UnpicklingError):
            continue            # being replaced right now
        levels[path.stem] = state.next_level
    return levels


# --- what a study will cost ------------------------------------------------------------------

# 3D: test_three_d.py; the two-body Cattaneo cases' (upper) body is hertz-line's geometry and maxh
# (``problem.cattaneo.cattaneo_two_body_case``), whose sizes hertz-line's parameter checks (0.4 s each)
@pytest.mark.parametrize("case_name", [name for name, case in registered_cases(dimension=2).items()
                                       if not name.startswith("cattaneo-two-body")])
def test_level_sizes_from_the_coarse_mesh_are_those_of_the_refined_meshes(case_name):
    """The budget never builds a fine mesh: its vertex, triangle and dof counts come from the
    coarse mesh by the red-refinement recurrence, and they are exact (two bodies: both bodies'
    together, each refined on its own)."""
    from harness.problem.bodies import lower_body
    case = registered_cases()[case_name]
    sizes = LevelSizes.of(case, 4)
    bodies = (case,) if case.bodies == 1 else (case, lower_body(case))
    for pairs in zip(*(mesh_hierarchy(body, 4) for body in bodies)):     # each mesh is refined in place
        level, meshes = pairs[0][0], [mesh for _, mesh in pairs]
        assert (sum(m.nv for m in meshes), sum(m.ne for m in meshes)) == (sizes.vertices[level], sizes.triangles[level])
        for order in (1, 2):
            ndof = sum(discretise(body, m, order).ndof for body, m in zip(bodies, meshes))
            assert ndof == sizes.ndof(level, order, case.physics.components)


def test_twelve_levels_of_transition_r32_are_refused_with_the_estimate_before_any_refinement(tmp_path, monkeypatch, capsys):
    # the refusal is read off the coarse mesh: no level is refined (netgen's Refine would take
    # minutes and gigabytes at level 12), nothing is written
    import netgen.meshing

    def refused(*args, **kwargs):
        raise AssertionError("a mesh was refined before the memory check")
    monkeypatch.setattr(netgen.meshing.Mesh, "Refine", refused)
    out = tmp_path / "out"
    assert main(["run", "--case", "transition-r32", "--levels", "12", "--out", str(out)]) == 2
    (line,) = capsys.readouterr().err.strip().splitlines()
    assert "level 12" in line and "estimated peak memory" in line and "GB" in line and "--skip-memory-check" in line
    assert not out.exists()         # refused before anything was written


def test_a_study_beyond_the_memory_is_refused_unless_the_check_is_skipped(tmp_path, monkeypatch, capsys):
    monkeypatch.setattr(budget, "machine_memory", lambda: 200 * budget.MB)
    args = ["run", "--case", "transition-r32", "--method", "nodal", "--levels", "2", "--quiet", "--threads", "1"]
    assert main(args + ["--out", str(tmp_path / "refused")]) == 2
    assert "more than the 200 MB of this machine" in capsys.readouterr().err
    assert not (tmp_path / "refused").exists()
    assert main(args + ["--out", str(tmp_path / "forced"), "--skip-memory-check"]) == 0
    assert (tmp_path / "forced" / "results.csv").is_file()


def test_the_memory_estimate_grows_with_the_finest_mesh_and_the_reference_levels():
    case = load_case("transition-r32")
    nodal, p1 = methods_named(["nodal"]), methods_named(["p1"])
    # P1 reaches P2's dofs on a mesh four times as fine: more memory for as many dofs
    assert estimate(case, p1, 7).ndof == estimate(case, nodal, 7).ndof
    assert estimate(case, p1, 7).peak_bytes > estimate(case, nodal, 7).peak_bytes
    assert estimate(case.with_reference(2), nodal, 5).peak_bytes > estimate(case, nodal, 7).peak_bytes
    with pytest.raises(BudgetError, match="level 6"):
        budget.check_fits([estimate(case, nodal, 7)], 100 * budget.MB, "a test")



def test_the_memory_estimate_of_3d_elasticity_covers_its_measured_peak():
    """3D vector P2 holds more per dof (``budget.PEAK_PER_DOF_BY_KIND``): elastic-transition-3d
    on 4 levels, every cone and p1 in one process, measured 2.11 GB (2026-11-26); the estimate
    is at or above it, and five levels (4.8e6 P2 dofs) are estimated past 10 GB, not at the 2D
    rate's 5 GB."""
    case = load_case("elastic-transition-3d")
    everything = methods_named(["mean", "mean-edges", "nodal", "p1"])
    assert 2.11 * 2**30 <= estimate(case, everything, 4).peak_bytes <= 1.2 * 2.11 * 2**30
    assert estimate(case, everything, 5).peak_bytes > 10 * 2**30


# --- one progress bar --------------------------------------------------------------------------

def test_the_progress_bar_weighs_levels_by_size_and_counts_each_once():
    case = load_case("transition-r32")
    methods = methods_named(["nodal"])
    weights = budget.solve_weights(case, methods, 4)
    progress = StudyProgress(weights, show=False)
    assert progress.weights[("transition-r32", "nodal", 3)] > 3 * progress.weights[("transition-r32", "nodal", 2)]
    total = progress.total
    progress.restored("transition-r32", "nodal", 2)          # levels 0, 1 from a checkpoint
    assert progress.total == total - sum(progress.weights[("transition-r32", "nodal", k)] for k in (0, 1))
    for level in (2, 3, 3, 2):                                 # a rerun job reports again
        progress.solved("transition-r32", "nodal", level)
    assert progress.count == progress.total
    progress.close()


def test_the_bar_of_a_case_without_u_off_uniform_meshes_ends_with_its_studied_levels():
    """Graded and adaptive levels have their own references: the reference chain's finer levels
    are never solved there, so the bar weighs each studied level with its reference instead."""
    from harness.mesh.strategies import MeshStrategy
    case, methods = load_case("smooth-obstacle"), methods_named(["nodal", "p1"])
    uniform = study_weights([case], methods, 3)
    adaptive = study_weights([case], methods, 3, meshes=(MeshStrategy("adaptive"),))
    assert max(level for _, method, level in uniform if method == "nodal") == 3 - 1 + case.reference_levels
    assert {(method, level) for _, method, level in adaptive} == {("nodal", k) for k in range(3)} | {("p1", k) for k in range(4)}
    progress = StudyProgress(adaptive, show=False)
    for scoped_case, method, level in adaptive:
        progress.solved(scoped_case, method, level)
    assert progress.count == progress.total
    # a studied level weighs more with its own reference than without
    assert adaptive[("adaptive smooth-obstacle", "nodal", 2)] > uniform[("smooth-obstacle", "nodal", 2)]
    progress.close()


def test_the_progress_line_fits_a_100_column_terminal_and_counts_methods_done():
    """One line (issue 28): the case, level, dofs and how many of the level's methods are done,
    whatever the names; the bar takes what is left of 100 columns."""
    from tqdm import tqdm

    from harness.study.execution.progress import BAR_FORMAT
    case = load_case("transition-r32")
    progress = StudyProgress(budget.solve_weights(case, methods_named(["all"]), 3), show=False)
    progress.solving("transition-r32", "nodal", 2, 36225)
    progress.solved("transition-r32", "nodal", 2)
    progress.solving("transition-r32", "mean", 2, 36225)
    at_level_2 = [m for m in methods_for(case, METHODS.values()) if 3 + m.extra_levels > 2]       # not P4: it stops at L1
    assert f"transition-r32 L2 36,225 dofs 1/{len(at_level_2)} methods" in progress.bar.desc
    # an adaptive chain's level past the budget's: no "0/0 methods"
    progress.solving("adaptive transition-r32", "nodal", 13, 6878)
    assert "L13 6,878 dofs" in progress.bar.desc and "methods" not in progress.bar.desc
    progress.solving("sweep elastic-transition-incompressible", "nitsche:gamma0=0.0001,theta=-1", 12, 123456789, "reference chain")
    line = tqdm.format_meter(n=progress.count, total=progress.total, elapsed=3600.0, ncols=100, prefix=progress.bar.desc,
                             bar_format=BAR_FORMAT)
    assert len(line) <= 100 and "\n" not in line, line
    progress.close()


# --- nothing lost on a kill ---------------------------------------------------------------------

def test_a_corrupt_checkpoint_is_ignored_and_the_chain_starts_afresh(tmp_path):
    case, (method,) = load_case("transition-r32"), methods_named(["nodal"])
    store = CheckpointStore(tmp_path, 3)
    path = store.path(case, method)
    path.parent.mkdir(parents=True)
    path.write_bytes(b"\x80\x05 half a pickle")
    assert store.load(case, method) is None
    frame = run_study([case], [method], 3, show_progress=False, checkpoints=tmp_path, engine=InProcess(threads=1))
    assert frame.attrs["resumed"] == {("transition-r32", "nodal"): 0} and len(frame) == 3


class Interrupt(Exception):
    pass


class InterruptAt:
    """A progress listener that stops the study when ``method`` starts ``level``."""

    def __init__(self, method: str, level: int):
        self.method, self.level = method, level

    def solving(self, case, method, level, ndof, stage=""):
        if (method, level) == (self.method, self.level):
            raise Interrupt

    def solved(self, *args):
        pass

    def restored(self, *args):
        pass


@pytest.mark.slow          # 3-5 s each: studies run twice
@pytest.mark.parametrize("case_name, stop_level", [("transition-r32", 2), ("smooth-obstacle", 4)])
def test_an_interrupted_study_resumes_from_its_checkpoints_with_the_same_rows(tmp_path, case_name, stop_level):
    """Every method of a case in one process, stopped when nodal starts ``stop_level`` (for
    smooth-obstacle: in its reference chain, with the studied solutions kept for the reference),
    then run again: the methods continue from their last saved level and every row is the
    uninterrupted study's."""
    case, methods, levels = load_case(case_name), methods_named(["all"]), 3
    whole = run_study([case], methods, levels, show_progress=False, engine=InProcess(threads=1))
    with pytest.raises(Interrupt):
        run_study([case], methods, levels, progress=InterruptAt("nodal", stop_level), engine=InProcess(threads=1),
                  checkpoints=tmp_path)
    resumed = run_study([case], methods, levels, show_progress=False, engine=InProcess(threads=1), checkpoints=tmp_path)
    assert resumed.attrs["resumed"][(case_name, "nodal")] == stop_level
    assert_same_results(whole, resumed)


@pytest.mark.slow          # 7 s: a study in a process killed and run again
def test_run_killed_after_its_second_level_resumes_to_the_same_csv(tmp_path):
    """SIGKILL of `run` as soon as its second level is durable; the same command again continues
    from there and writes the CSV of an uninterrupted run."""
    args = ["run", "--case", "transition-r32", "--method", "nodal", "--levels", "5", "--threads", "1"]
    subprocess.run(harness_command(*args, "--out", str(tmp_path / "whole"), "--quiet"), check=True, cwd=REPOSITORY,
                   capture_output=True, timeout=300)
    out = tmp_path / "killed"
    process = subprocess.Popen(harness_command(*args, "--out", str(out), "--quiet"), cwd=REPOSITORY,
                               stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    deadline = time.time() + 120
    while not any(level >= 2 for level in saved_levels(out).values()):
        assert process.poll() is None and time.time() < deadline, "the run ended before its second level was saved"
        time.sleep(0.01)
    process.send_signal(signal.SIGKILL)
    process.wait(timeout=30)
    assert not (out / "results.csv").exists()
    (killed_at,) = saved_levels(out).values()
    assert 2 <= killed_at < 5
    again = subprocess.run(harness_command(*args, "--out", str(out)), cwd=REPOSITORY, capture_output=True, text=True,
                           timeout=300)
    assert again.returncode == 0, again.stderr[-2000:]
    assert f"transition-r32 nodal: resumed after level {killed_at - 1}" in again.stdout
    assert_same_results(pd.read_csv(tmp_path / "whole" / "results.csv"), pd.read_csv(out / "results.csv"))
    assert not (out / ".checkpoints").exists()      # forgotten once the results are written


ENGINES = {"local processes": lambda: LocalProcesses(2), "Dask LocalCluster": lambda: DaskEngine(workers=2)}


# 7 s each, in the slow tier; `make test` runs two local processes in the progress bar's test
@pytest.mark.slow
@pytest.mark.parametrize("engine_name", ["local processes", "Dask LocalCluster"])
def test_two_workers_give_the_serial_results_bit_for_bit(engine_name):
    """Two worker processes, local or a real Dask LocalCluster (transition-r32, the larger,
    split by order; smooth-obstacle whole: its methods wait for one reference solve), against
    one process running every method of a case on shared levels -- an exact case and a case
    measured against a reference, every method."""
    cases, methods = [load_case("transition-r32"), load_case("smooth-obstacle")], methods_named(["all"])
    serial = run_study(cases, methods, 3, show_progress=False, engine=InProcess(threads=1))
    engine = ENGINES[engine_name]()
    jobs = engine.split(chains(cases, methods, 3))
    assert [(job.case.name, {m.order for m in job.methods}) for job in jobs] == \
        [("transition-r32", {4}), ("transition-r32", {3}), ("transition-r32", {2}), ("transition-r32", {1}),
         ("smooth-obstacle", {1, 2})]
    try:
        distributed = run_study(cases, methods, 3, show_progress=False, engine=engine)
    finally:
        engine.close()
    assert_same_results(serial, distributed)


def test_local_processes_report_every_solve_to_the_one_bar():
    """Workers' solves reach the client's bar over the queue: every level counted, once."""
    cases, methods = [load_case("transition-r32"), load_case("wedge-r23")], methods_named(["nodal", "p1"])
    progress = StudyProgress(study_weights(cases, methods, 3), show=False)
    run_study(cases, methods, 3, progress=progress, engine=LocalProcesses(2))
    assert progress.count == progress.total and len(progress.done) == 2 * (3 + 4)


@pytest.mark.slow          # 25 s; make test resumes a killed run (test_run_killed_after_its_second_level...)
def test_a_killed_local_worker_is_one_line_and_the_same_command_resumes(tmp_path):
    """SIGKILL of a worker process of `run --workers 2` mid-study: the run stops with one line
    naming the job and exit 1, writes no results file, and the same command resumes from the
    checkpoints with the serial study's rows."""
    import psutil
    args = ["run", "--case", "transition-r32", "--method", "nodal", "--method", "p1", "--levels", "6", "--workers", "2"]
    out = tmp_path / "killed"
    process = subprocess.Popen(harness_command(*args, "--out", str(out), "--quiet"), cwd=REPOSITORY,
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    deadline = time.time() + 120
    while not any(level >= 3 for level in saved_levels(out).values()):
        assert process.poll() is None and time.time() < deadline, "the run ended before its third level was saved"
        time.sleep(0.01)
    workers = [child for child in psutil.Process(process.pid).children(recursive=True) if "spawn_main" in " ".join(child.cmdline())]
    os.kill(workers[-1].pid, signal.SIGKILL)
    _, err = process.communicate(timeout=120)
    assert process.returncode == 3 and len(err.strip().splitlines()) == 1, err     # the study stopped on an error
    assert "a worker process died during transition-r32" in err and not (out / "results.csv").exists()
    again = subprocess.run(harness_command(*args, "--out", str(out)), cwd=REPOSITORY, capture_output=True, text=True, timeout=300)
    assert again.returncode == 0, again.stderr[-2000:]
    assert "resumed after level" in again.stdout
    serial = run_study([load_case("transition-r32")], methods_named(["nodal", "p1"]), 6, show_progress=False,
                       engine=InProcess(threads=1))
    write_csv(serial, tmp_path / "serial.csv")          # written as results.csv is (10 digits; empty text: NaN)
    assert_same_results(pd.read_csv(tmp_path / "serial.csv"), pd.read_csv(out / "results.csv"))


@pytest.mark.slow          # 19 s; as above
def test_a_killed_dask_worker_is_replaced_and_the_study_completes(tmp_path):
    """SIGKILL of the worker running p1's chain while it solves its finest level: Dask reruns
    the job, which resumes from its checkpoint; nothing is missing and every row is the serial
    study's."""
    cases, methods, levels = [load_case("transition-r32")], methods_named(["nodal", "p1"]), 6
    engine = DaskEngine(workers=2)
    outcome = {}

    def study():
        try:
            outcome["frame"] = run_study(cases, methods, levels, show_progress=False, engine=engine, checkpoints=tmp_path)
        except BaseException as exc:        # reported by the test thread
            outcome["error"] = exc
    try:
        client = engine.client
        pids = client.run(os.getpid)
        runner = threading.Thread(target=study)
        runner.start()
        deadline, victim = time.time() + 120, None
        while victim is None:
            assert runner.is_alive() and time.time() < deadline, outcome.get("error", "p1 finished before it was killed")
            # p1's chain has levels + 1 levels: next_level == levels is its finest, the longest solve
            if any(name.startswith("p1") and level == levels for name, level in saved_levels(tmp_path).items()):
                busy = [address for address, keys in client.processing().items() if any("-p1-" in str(k) for k in keys)]
                if busy:
                    victim = busy[0]
                    os.kill(pids[victim], signal.SIGKILL)
            time.sleep(0.01)
        runner.join(timeout=240)
        assert not runner.is_alive() and "error" not in outcome, outcome.get("error")
    finally:
        engine.close()
    frame = outcome["frame"]
    assert frame.attrs["resumed"][("transition-r32", "p1")] == levels
    serial = run_study(cases, methods, levels, show_progress=False, engine=InProcess(threads=1))
    assert_same_results(serial, frame)
