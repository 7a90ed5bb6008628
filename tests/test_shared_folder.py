"""A results folder shared by runs and people: one command owns it at a time, runs merge their
rows by key, files get the umask's mode, a killed run leaves nothing the next one does not
clear or reuse; and threads that fit the machine (``study.execution.threads``)."""
import os
import stat
import subprocess
import sys
from pathlib import Path

import pandas as pd
import pytest

from harness.cli import main
from harness.study.execution import threads
from harness.study.storage.files import TEMPORARY_MARK, write_atomic
from harness.study.storage.folder import LOCK_NAME, FolderBusy, owned
from harness.study.storage.merge import ROW_KEY, merge_rows, read_rows

ROOT = Path(__file__).resolve().parent.parent


def run(folder, case, method, levels=1):
    return main(["run", "--case", case, "--method", method, "--levels", str(levels), "--out", str(folder), "--quiet"])


def test_runs_one_after_another_keep_every_row_and_say_what_they_replaced(tmp_path, capsys):
    assert run(tmp_path, "transition-r32", "nodal", 2) == 0
    assert run(tmp_path, "corner-r12", "p1") == 0
    assert capsys.readouterr().out.splitlines()[-1].endswith("2 rows of this run; kept 2 rows of other runs")
    assert run(tmp_path, "transition-r32", "nodal", 1) == 0
    line = capsys.readouterr().out.splitlines()[-1]
    assert line == f"wrote {tmp_path / 'results.csv'}: 1 row of this run; replaced 1 earlier row (transition-r32 nodal); " \
                   f"kept 3 rows of other runs"
    frame = pd.read_csv(tmp_path / "results.csv")
    assert sorted(zip(frame.case, frame.method, frame.level)) == [
        ("corner-r12", "p1", 0), ("corner-r12", "p1", 1), ("transition-r32", "nodal", 0), ("transition-r32", "nodal", 1)]
    assert not (tmp_path / ".checkpoints").exists() and not (tmp_path / LOCK_NAME).exists()


def test_a_folder_in_use_is_refused_in_one_line_naming_its_owner_and_left_as_it_was(tmp_path, capsys):
    assert run(tmp_path, "transition-r32", "nodal") == 0
    before = (tmp_path / "results.csv").read_bytes()
    with owned(tmp_path, command="python -m harness run --case corner-r12"):
        assert run(tmp_path, "transition-r32", "p1") == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith(f"harness: error: {tmp_path} is in use by `python -m harness run --case corner-r12` "
                                                   f"(pid {os.getpid()}")
    assert (tmp_path / "results.csv").read_bytes() == before
    with owned(tmp_path):
        with pytest.raises(FolderBusy):
            with owned(tmp_path):
                pass


def test_the_python_api_refuses_a_folder_in_use_as_the_command_line_does(tmp_path):
    """`harness.run(out=...)` and `harness.store` take the folder as `run --out` does: another
    command's folder is refused before anything is computed or written."""
    import harness
    with owned(tmp_path, command="python -m harness run --case corner-r12"):
        with pytest.raises(FolderBusy, match="is in use by `python -m harness run --case corner-r12`"):
            harness.run("transition-r32", methods="nodal", levels=1, out=tmp_path, show_progress=False)
        rows = harness.run("transition-r32", methods="nodal", levels=1, show_progress=False)
        with pytest.raises(FolderBusy):
            harness.store(rows, tmp_path)
    assert sorted(p.name for p in tmp_path.iterdir()) == []
    assert harness.store(rows, tmp_path) == tmp_path / "results.csv" and len(pd.read_csv(tmp_path / "results.csv")) == 1


def test_two_runs_started_together_on_one_folder_keep_every_row_or_refuse_in_one_line(tmp_path):
    commands = [["transition-r32", "nodal", "5"], ["corner-r12", "p1", "4"]]
    started = [subprocess.Popen([sys.executable, "-m", "harness", "run", "--case", case, "--method", method, "--levels", levels,
                                 "--out", str(tmp_path), "--quiet"], cwd=ROOT, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                                text=True) for case, method, levels in commands]
    outcomes = [(p.wait(), p.stderr.read()) for p in started]
    frame = pd.read_csv(tmp_path / "results.csv")
    for (case, method, levels), (code, err) in zip(commands, outcomes):
        rows = frame[(frame.case == case) & (frame.method == method)]
        if code == 0:
            assert len(rows) == int(levels) + (method == "p1"), err
        else:
            assert code == 2 and err.count("\n") == 1 and "is in use by `" in err and rows.empty
    assert sum(code == 0 for code, _ in outcomes) >= 1


@pytest.mark.parametrize("mask", [0o002, 0o022, 0o077])
def test_results_get_the_mode_the_umask_gives(tmp_path, mask):
    previous = os.umask(mask)
    try:
        path = write_atomic(tmp_path / "results.csv", "case\n")
        with owned(tmp_path / "out"):
            lock_mode = stat.S_IMODE((tmp_path / "out" / LOCK_NAME).stat().st_mode)
    finally:
        os.umask(previous)
    assert stat.S_IMODE(path.stat().st_mode) == 0o666 & ~mask
    assert lock_mode == 0o666 & ~mask


def test_the_next_owner_removes_what_a_killed_write_left_and_keeps_the_checkpoints(tmp_path):
    orphans = [tmp_path / f".results.csv{TEMPORARY_MARK}-x1", tmp_path / "cases" / f".a.npz{TEMPORARY_MARK}-x2"]
    checkpoint = tmp_path / ".checkpoints" / "corner-r12" / "nodal-1.ckpt"
    for path in [*orphans, checkpoint]:
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text("partial")
    (tmp_path / LOCK_NAME).write_text('{"pid": 1}')      # a killed owner's lock file: no lock held
    with owned(tmp_path):
        assert not any(p.exists() for p in orphans)
        assert checkpoint.is_file()
    assert not (tmp_path / LOCK_NAME).exists()


def test_a_file_that_is_not_results_is_refused_before_the_study(tmp_path, capsys):
    (tmp_path / "results.csv").write_text("my notes\n\"unclosed")
    assert run(tmp_path, "transition-r32", "nodal") == 2
    assert "is not a results CSV" in capsys.readouterr().err
    assert (tmp_path / "results.csv").read_text() == "my notes\n\"unclosed"


def test_a_failed_run_leaves_only_the_checkpoints_its_resume_reuses(tmp_path, monkeypatch, capsys):
    from harness.study.chain import walk
    solved = []
    original = walk.keep

    def fail_on_the_second_level(on_level, phases, kept, case, method, level, problem, solve):
        if level == 1:
            raise RuntimeError("killed")
        solved.append(level)
        return original(on_level, phases, kept, case, method, level, problem, solve)
    monkeypatch.setattr(walk, "keep", fail_on_the_second_level)
    assert run(tmp_path, "transition-r32", "nodal", 3) == 3          # the study stopped on an error
    assert sorted(p.name for p in tmp_path.iterdir()) == [".checkpoints"]
    monkeypatch.setattr(walk, "keep", original)
    assert main(["run", "--case", "transition-r32", "--method", "nodal", "--levels", "3", "--out", str(tmp_path)]) == 0
    assert "transition-r32 nodal: resumed after level 0" in capsys.readouterr().out
    assert sorted(p.name for p in tmp_path.iterdir()) == ["results.csv"]


def test_merged_rows_are_keyed_by_case_method_parameters_mesh_and_level():
    earlier = pd.DataFrame({"case": ["a", "a", "a", "b"], "method": ["nitsche"] * 3 + ["p1"], "parameters": ["g=1", "g=2", "g=1", None],
                            "mesh": ["uniform", "uniform", "graded", "uniform"], "level": [0, 0, 0, 0], "err_h1": [1.0, 2, 3, 4]})
    rows = pd.DataFrame({"case": ["a", "b"], "method": ["nitsche", "p1"], "parameters": ["g=1", float("nan")],
                         "mesh": ["uniform"] * 2, "level": [0, 0], "err_h1": [10.0, 40]})
    merged = merge_rows(earlier, rows)
    assert merged.frame.err_h1.tolist() == [2, 3, 10, 40] and merged.kept == 2 and len(merged.replaced) == 2
    assert list(merged.frame.columns[:len(ROW_KEY)]) == ROW_KEY


def test_an_old_results_file_without_mesh_and_parameters_columns_merges(tmp_path):
    (tmp_path / "results.csv").write_text("case,method,level,err_h1\nx,nodal,0,1.0\n")
    earlier = read_rows(tmp_path / "results.csv")
    rows = pd.DataFrame({"case": ["x"], "method": ["nodal"], "parameters": [""], "mesh": ["uniform"], "level": [0], "err_h1": [2.0]})
    assert merge_rows(earlier, rows).frame.err_h1.tolist() == [2.0]


# --- threads (``study.execution.threads``)

@pytest.mark.parametrize("files, cores", [({"cpu.max": "150000 100000\n"}, 1.5), ({"cpu.max": "max 100000\n"}, None),
                                          ({"cpu/cpu.cfs_quota_us": "300000", "cpu/cpu.cfs_period_us": "100000"}, 3.0),
                                          ({"cpu/cpu.cfs_quota_us": "-1", "cpu/cpu.cfs_period_us": "100000"}, None), ({}, None)])
def test_the_cgroup_quota_is_read_from_v1_and_v2_files(tmp_path, files, cores):
    for name, text in files.items():
        (tmp_path / name).parent.mkdir(parents=True, exist_ok=True)
        (tmp_path / name).write_text(text)
    assert threads.cgroup_quota(tmp_path) == cores


def test_busy_ticks_count_only_the_cpus_this_process_may_use(tmp_path):
    (tmp_path / "stat").write_text("cpu  10 1 5 100 7 2 3 4 0 0\ncpu0 1 0 1 50 0 0 0 0 0 0\ncpu1 9 1 4 50 7 2 3 4 0 0\nintr 5\n")
    assert threads._busy_ticks(None, tmp_path / "stat") == 10 + 1 + 5 + 2 + 3 + 4
    assert threads._busy_ticks({0}, tmp_path / "stat") == 2
    assert threads._busy_ticks({1}, tmp_path / "stat") == 9 + 1 + 4 + 2 + 3 + 4


class Others:
    """A monitor that reads ``cores`` used by other processes."""
    def __init__(self, cores):
        self.cores = cores

    def others(self):
        return self.cores


@pytest.mark.parametrize("others, expected", [(0.0, 2), (0.2, 2), (0.5, 1), (0.7, 1), (1.0, 1), (2.0, 1), (None, 2)])
def test_a_large_level_gets_the_cores_the_other_processes_leave_free(monkeypatch, others, expected):
    monkeypatch.delenv(threads.ENVIRONMENT, raising=False)
    monkeypatch.setattr(threads, "usable_cpus", lambda: 2)
    policy = threads.Threads(monitor=Others(others))
    assert policy.for_level(10 * threads.SERIAL_BELOW) == expected
    assert policy.for_level(threads.SERIAL_BELOW - 1) == 1          # a small level: one thread, whatever is free


def test_fixed_threads_win_and_the_environment_fixes_them_where_none_are_given(monkeypatch):
    monkeypatch.setattr(threads, "usable_cpus", lambda: 2)
    assert threads.Threads(3, monitor=Others(1.0)).for_level(10) == 3
    monkeypatch.setenv(threads.ENVIRONMENT, "1")
    assert threads.Threads(monitor=Others(0.0)).for_level(10 * threads.SERIAL_BELOW) == 1
    monkeypatch.setenv(threads.ENVIRONMENT, "two")
    with pytest.raises(ValueError, match="HARNESS_THREADS must be a positive integer"):
        threads.Threads()


def _other_processes_cpu_seconds() -> float:
    """An independent count of what the monitor calls the others, on all CPUs: utime + stime of
    every process but this one (/proc/PID/stat), with the children they reaped (cutime + cstime:
    a process that ends leaves /proc), plus the time /proc/stat gives no process (irq, softirq,
    a hypervisor's steal)."""
    total, own = 0, os.getpid()
    for entry in Path("/proc").iterdir():
        if not entry.name.isdigit() or int(entry.name) == own:
            continue
        try:
            fields = (entry / "stat").read_text().rsplit(")", 1)[1].split()
        except OSError:
            continue                 # ended meanwhile
        total += sum(int(fields[k]) for k in (11, 12, 13, 14))
    cpu = Path("/proc/stat").read_text().splitlines()[0].split()
    total += int(cpu[6]) + int(cpu[7]) + int(cpu[8])
    return total / os.sysconf("SC_CLK_TCK")


@pytest.mark.skipif(not Path("/proc/stat").is_file() or threads.affinity() != set(range(os.cpu_count() or 1)),
                    reason="needs Linux's /proc and every CPU of the machine")
def test_the_monitor_does_not_count_this_process_as_another():
    # one busy core of our own, counted as another's, would read a full core above what the
    # other processes used, whatever else the machine runs meanwhile (the margin: half that
    # core, for what the two counts round differently)
    monitor = threads.CpuMonitor()
    monitor.others()
    before, start = _other_processes_cpu_seconds(), threads.time.monotonic()
    while threads.time.monotonic() < start + 0.5:
        pass
    others = monitor.others()
    independent = (_other_processes_cpu_seconds() - before) / (threads.time.monotonic() - start)
    assert others is not None and others <= independent + 0.5, (others, independent)


def test_a_level_inside_a_callers_task_manager_keeps_its_threads():
    import ngsolve as ngs
    with ngs.TaskManager():
        previous = ngs.GetNumThreads()
    ngs.SetNumThreads(2)
    try:
        with ngs.TaskManager():
            with threads.level(10 * threads.SERIAL_BELOW) as count:
                assert count is None and ngs.GetNumThreads() == 2
    finally:
        ngs.SetNumThreads(previous)


@pytest.mark.slow      # six runs and a busy loop that slows the other test worker: `make test-full`
def test_bench_load_times_every_thread_setting_idle_and_beside_a_busy_process():
    """`bench --only load` on a one-level run: each setting idle and beside a busy loop, and its goals."""
    from harness.bench.load import load_goals, run_load_bench
    frame = run_load_bench(runs=(("1 level", ["--case", "transition-r32", "--method", "nodal", "--levels", "1"]),),
                           progress=lambda line: None)
    assert sorted(zip(frame.threads, frame.load)) == sorted((t, load) for t in ("auto", "1", str(threads.usable_cpus()))
                                                             for load in ("idle", "one busy process"))
    assert (frame.seconds > 0).all()
    goals = load_goals(frame)
    assert len(goals) == 3 and all(figure[0].isdigit() for _, _, figure in goals)


def test_forgetting_a_cases_uniform_checkpoints_leaves_its_other_strategies_writing(tmp_path):
    """The report stores a case's uniform study (and forgets its checkpoints) while the same
    case's graded chain may still write its own in another worker: those must survive (a rename
    of a vanished temporary file failed a report in CI before)."""
    from types import SimpleNamespace

    from harness.study.storage.checkpoint import CheckpointStore
    case, method = SimpleNamespace(name="transition-r32"), SimpleNamespace(name="nodal")
    uniform, graded = CheckpointStore(tmp_path, 3), CheckpointStore(tmp_path, 3, mesh="graded")
    for store in (uniform, graded):
        store.path(case, method).parent.mkdir(parents=True, exist_ok=True)
        store.path(case, method).write_bytes(b"state")
    uniform.forget(case)
    assert not uniform.path(case, method).exists() and graded.path(case, method).read_bytes() == b"state"
    graded.forget(case)
    assert not (tmp_path / "transition-r32").exists()
    for store in (uniform, graded):
        store.path(case, method).parent.mkdir(parents=True, exist_ok=True)
        store.path(case, method).write_bytes(b"state")
    uniform.forget(case, every_mesh=True)          # `run`, once its whole study is written
    assert not (tmp_path / "transition-r32").exists()
