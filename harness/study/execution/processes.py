"""The study on local worker processes (``LocalProcesses``): N spawned processes of one NGSolve
thread each (cores / N), the jobs at ``engines.split_large``'s grain, the largest first.

Why processes and not threads: a chain spends much of its time where one thread works (the
multigrid's Gauss-Seidel smoothing, the Python of the active-set and Newton loops, numpy), so
NGSolve's threads in one process speed a 2D chain up little; two 1-thread processes keep both
cores busy and finish sooner than one process, though each job then costs more than in one
process (the two share what one process's two threads use;
``python -m harness bench --only report`` compares them). Why not Dask here: a Dask LocalCluster's nanny, scheduler and worker
event loops share the cores with the jobs, so the same study is slower on it than on local
processes; ``DaskEngine`` stays for clusters. Results are those of ``InProcess(threads=1)``, bit for bit.
"""
from __future__ import annotations

import multiprocessing
import queue as queues
from concurrent.futures import FIRST_COMPLETED, ProcessPoolExecutor, wait
from concurrent.futures.process import BrokenProcessPool

import cloudpickle

from . import budget
from .engines import Job, largest_first, run_job, split_large
from .progress import QueueProgress, replay
from .threads import usable_cpus

# how often the client looks at the progress queue while jobs run
POLL_SECONDS = 0.2

_QUEUE = None       # in a worker: where its progress messages go (``_start_worker``)


class WorkerDied(RuntimeError):
    """A worker process ended in the middle of a job (killed, out of memory)."""


def _start_worker(queue) -> None:
    global _QUEUE
    _QUEUE = queue


def _local_job(pickled: bytes, scope: str):
    # cloudpickle (Dask's): methods and hooks may hold closures, which pickle refuses
    source, reference_levels, methods, levels, on_level, threads, folder, mesh = cloudpickle.loads(pickled)
    return run_job(source, reference_levels, methods, levels, on_level, threads, folder, QueueProgress(_QUEUE, scope), mesh)


class LocalProcesses:
    """The study on ``workers`` local processes, ``threads`` NGSolve threads each (default:
    cores / workers). A worker that dies stops the study with one line (``WorkerDied``); what
    was finished is in the checkpoints, and the same command resumes there."""

    def __init__(self, workers: int, threads: int | None = None):
        if workers < 1:
            raise ValueError(f"local processes: workers must be a positive integer, got {workers}")
        self.workers = int(workers)
        self.threads = threads or max(1, usable_cpus() // self.workers)

    def split(self, jobs: list[Job]) -> list[Job]:
        return split_large(jobs, self.workers)

    def describe(self) -> str:
        return f"on {self.workers} local processes ({self.threads} thread{'s' if self.threads > 1 else ''} per job)"

    def memory(self) -> tuple[float, str]:
        return budget.machine_memory() / self.workers, f"one of {self.workers} local processes"

    def busy_cores(self, remaining: int) -> int:
        """The cores the study keeps busy while ``remaining`` jobs are left: one process of
        ``threads`` threads per job, at most ``workers`` at once (the study's tail leaves cores
        free, which the report fills with its figures: ``report.figure_jobs``)."""
        return min(remaining, self.workers) * self.threads

    def run(self, jobs: list[Job], progress=None):
        """(job, ``study.chain.rows.ChainOutput``) for each job, as they finish."""
        context = multiprocessing.get_context("spawn")
        messages = context.Queue()
        pool = ProcessPoolExecutor(min(self.workers, max(1, len(jobs))), mp_context=context,
                                   initializer=_start_worker, initargs=(messages,))
        finished = False
        try:
            pending = {}
            for job in largest_first(jobs):
                folder = str(job.checkpoints.resolve()) if job.checkpoints is not None else None
                args = (job.case.source, job.case.reference_levels, job.methods, job.levels, job.on_level, self.threads,
                        folder, job.mesh)
                pending[pool.submit(_local_job, cloudpickle.dumps(args), job.scope)] = job
            while pending:
                done, _ = wait(pending, timeout=POLL_SECONDS, return_when=FIRST_COMPLETED)
                _drain(messages, progress)
                for future in done:
                    job = pending.pop(future)
                    try:
                        output = future.result()
                    except BrokenProcessPool:
                        raise WorkerDied(f"a worker process died during {job.case.name} ({', '.join(m.name for m in job.methods)}): "
                                         f"killed or out of memory; run the same command again to resume from the checkpoints") from None
                    yield job, output
            _drain(messages, progress)
            finished = True
        finally:
            if not finished:
                # stopped early (a failed job, an interrupt, a caller that stops reading): the
                # running jobs end now, their finished levels are in the checkpoints
                for process in list(getattr(pool, "_processes", {}).values()):
                    process.terminate()
            pool.shutdown(wait=finished, cancel_futures=True)
            messages.close()

    def close(self) -> None:
        pass


def _drain(messages, progress) -> None:
    while True:
        try:
            message = messages.get_nowait()
        except queues.Empty:
            return
        if progress is not None:
            replay(progress, message)
