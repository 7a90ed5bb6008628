"""How many threads NGSolve runs a level on: as many as the cores this process may use and
nobody else is using, and one where threads do not pay.

Why per level, and why it matters: NGSolve's task manager splits each parallel region (assembly,
Integrate, a sparse factorisation) among its threads and waits for the last of them. When
another process holds a core, one of the threads is descheduled in every region and every region
waits for it, so a study with a thread per core runs many times slower beside one busy process
than on an idle machine (``python -m harness bench --only load`` times it). One thread loses
nothing to that. So the study's default (``Threads()``, "auto") decides before every level,
from

- the cores this process may use (``usable_cpus``: its CPU affinity and its cgroup's CPU quota,
  which ``os.cpu_count`` ignores: a container limited to 2 CPUs on a 64-core host has 2);
- what the other processes used of them since the last decision (``CpuMonitor``: the busy
  time of those CPUs in ``/proc/stat`` less this process's own CPU time): a browser, a second
  study, the report's figure processes;
- the size of the level: below ``SERIAL_BELOW`` P2 dofs (vertices and edges of the mesh) a
  level costs less than the threads' start and synchronisation: it is as fast or faster on one
  thread.

``Threads(n)`` (``--threads n``, or the environment variable ``HARNESS_THREADS=n``) fixes n
threads for every level.
"""
from __future__ import annotations

import contextvars
import math
import os
import time
from contextlib import contextmanager, nullcontext
from dataclasses import dataclass, field
from pathlib import Path

# a level with fewer P2 dofs (vertices + edges of its mesh) runs on one thread
SERIAL_BELOW = 40_000
# a thread is kept while the other processes leave at least this share of its core free
# (one busy process measures 0.67-1.0 cores beside two threads of ours: one thread then)
SPARE_CORE = 0.75
# a measurement shorter than this (seconds) is too coarse for /proc/stat's 10 ms ticks: the
# previous decision stands
MIN_WINDOW = 0.05
# the environment variable that fixes the threads where no --threads is given (a CI runner, a
# test suite on one process per core), as OMP_NUM_THREADS does for OpenMP programs
ENVIRONMENT = "HARNESS_THREADS"


def cgroup_quota(root: Path = Path("/sys/fs/cgroup")) -> float | None:
    """The CPU quota of this process's cgroup in cores (v2 ``root/cpu.max``, v1 ``root/cpu/cpu.cfs_quota_us``),
    or None if it has none (or this is not Linux)."""
    try:
        quota, period = (root / "cpu.max").read_text().split()[:2]
        return None if quota == "max" else int(quota) / int(period)
    except (OSError, ValueError):
        pass
    try:
        quota = int((root / "cpu" / "cpu.cfs_quota_us").read_text())
        period = int((root / "cpu" / "cpu.cfs_period_us").read_text())
        return quota / period if quota > 0 else None
    except (OSError, ValueError):
        return None


def affinity() -> set[int] | None:
    """The CPUs this process may run on (None where the OS does not say: macOS, Windows)."""
    try:
        return set(os.sched_getaffinity(0))
    except (AttributeError, OSError):
        return None


def usable_cpus() -> int:
    """The cores this process may keep busy: its CPU affinity, capped by its cgroup's quota."""
    cpus = affinity()
    count = len(cpus) if cpus else (os.cpu_count() or 1)
    quota = cgroup_quota()
    return max(1, min(count, math.floor(quota + 0.5) if quota else count))


def _busy_ticks(cpus: set[int] | None, stat: Path = Path("/proc/stat")) -> int | None:
    """Busy clock ticks of ``cpus`` (all if None) since boot: user, nice, system, irq, softirq
    and steal (a hypervisor's other guests hold the core too); None if unreadable."""
    try:
        lines = stat.read_text().splitlines()
    except OSError:
        return None
    total = 0
    for line in lines:
        name, *values = line.split()
        if cpus is None and name == "cpu" or cpus is not None and name[3:].isdigit() and int(name[3:]) in cpus:
            ticks = [int(v) for v in values[:8]] + [0] * 8
            total += ticks[0] + ticks[1] + ticks[2] + ticks[5] + ticks[6] + ticks[7]
    return total


def _environment_threads() -> int:
    text = os.environ[ENVIRONMENT].strip()
    if not text.isdigit() or int(text) < 1:
        raise ValueError(f"{ENVIRONMENT} must be a positive integer, got {text!r}")
    return int(text)


@dataclass
class CpuMonitor:
    """The cores the other processes kept busy, on the CPUs this process may use, since the
    last reading (``others``): their busy time in ``/proc/stat`` less this process's CPU time
    (all its threads). Reads 0 where there is no ``/proc/stat``."""

    cpus: set[int] | None = field(default_factory=affinity)
    _last: tuple | None = None

    def _now(self) -> tuple:
        return time.monotonic(), _busy_ticks(self.cpus), time.process_time()

    def others(self) -> float | None:
        """Cores used by other processes since the last reading; None if the window was too
        short to tell (or this is the first reading, which starts the window)."""
        now = self._now()
        last, self._last = self._last, now
        if last is None or now[1] is None or last[1] is None or now[0] - last[0] < MIN_WINDOW:
            if last is not None and now[0] - last[0] < MIN_WINDOW:
                self._last = last            # keep the window open
            return None
        wall = now[0] - last[0]
        busy = (now[1] - last[1]) / os.sysconf("SC_CLK_TCK")
        return max(0.0, busy - (now[2] - last[2])) / wall


@dataclass
class Threads:
    """The thread policy of a study: ``fixed`` threads on every level (``--threads``), or None:
    per level, those of ``usable_cpus`` the other processes leave free, one on a small level
    (see the module's docstring). Data: an engine passes it to its jobs (``using``)."""

    fixed: int | None = None
    monitor: CpuMonitor = field(default_factory=CpuMonitor, repr=False, compare=False)
    _last: int | None = field(default=None, repr=False, compare=False)

    def __post_init__(self):
        if self.fixed is None and os.environ.get(ENVIRONMENT, "").strip():
            self.fixed = _environment_threads()
        self.monitor.others()           # opens the first window

    def for_level(self, p2_dofs: int) -> int:
        """The threads of a level of about ``p2_dofs`` scalar P2 dofs."""
        if self.fixed is not None:
            return self.fixed
        others = self.monitor.others()
        cores = usable_cpus()
        if others is None:
            free = self._last if self._last is not None else cores
        else:
            free = max(1, min(cores, math.floor(cores - others + (1 - SPARE_CORE))))
        self._last = free
        return 1 if p2_dofs < SERIAL_BELOW else free


_POLICY: contextvars.ContextVar[Threads | None] = contextvars.ContextVar("threads", default=None)


@contextmanager
def using(threads: int | None):
    """A job's threads: ``threads`` on every level (and for the BLAS throughout), or None: the
    auto policy decides per level (``level``), and between levels the BLAS runs on one thread
    (its dense work there is small, and OpenBLAS's threads spin against a busy neighbour as
    NGSolve's wait for one). NGSolve's thread count is restored after."""
    import ngsolve as ngs
    from threadpoolctl import threadpool_limits
    with ngs.TaskManager():
        previous = ngs.GetNumThreads()      # outside a task manager it reads 1
    token = _POLICY.set(Threads(threads))
    try:
        with threadpool_limits(threads or 1):
            yield
    finally:
        _POLICY.reset(token)
        ngs.SetNumThreads(previous)


def _caller_task_manager() -> bool:
    """True inside a task manager someone else opened (a test, a user's script): its threads
    stand. Outside one, NGSolve reports 1 thread."""
    import ngsolve as ngs
    return ngs.GetNumThreads() > 1


def p2_size(*meshes) -> int:
    """About the scalar P2 dofs of ``meshes``: their vertices and edges."""
    return sum(mesh.nv + mesh.nedge for mesh in meshes)


@contextmanager
def level(size: int):
    """NGSolve's task manager (and the BLAS) for one level's work of ``size`` scalar P2 dofs
    (``p2_size``), with the threads the current policy (``using``; default: auto) gives it; one
    thread: no task manager at all."""
    import ngsolve as ngs
    from threadpoolctl import threadpool_limits
    if _caller_task_manager():
        yield
        return
    policy = _POLICY.get()
    if policy is None:
        policy = Threads()
        _POLICY.set(policy)
    count = policy.for_level(size)
    ngs.SetNumThreads(count)
    with threadpool_limits(count), (ngs.TaskManager() if count > 1 else nullcontext()):
        yield count
