"""The study on Dask workers (``DaskEngine``): a LocalCluster of N worker processes, or an
existing cluster by its scheduler's address -- the engine for more than one machine. On one
machine ``processes.LocalProcesses`` runs the same jobs with less overhead (no nanny, scheduler
or worker event loops sharing the cores with them).
"""
from __future__ import annotations

import uuid

from . import budget
from .engines import Job, largest_first, run_job, split_large
from .progress import EventProgress, relay
from .threads import usable_cpus

# seconds to wait for an existing scheduler to answer before saying it is unreachable
SCHEDULER_TIMEOUT = 10


class SchedulerUnreachable(RuntimeError):
    """--scheduler names an address where no Dask scheduler answers."""


class DaskEngine:
    """The study on Dask workers, one job per case (split by order where large: ``split``), the
    largest first. A worker that
    dies mid-job (killed, out of memory) loses nothing durable: Dask reruns the job elsewhere and
    it resumes from its checkpoint (the checkpoint folder must then be on a file system the
    workers share, as on a cluster's home or scratch; otherwise the job starts again)."""

    def __init__(self, workers: int | None = None, scheduler: str | None = None, threads: int | None = None):
        if (workers is None) == (scheduler is None):
            raise ValueError("a Dask engine needs either a number of local workers or a scheduler address")
        self.workers, self.scheduler = workers, scheduler
        cores = usable_cpus()
        # N local workers share the cores: no more NGSolve threads than cores in all
        self.threads = threads or (max(1, cores // workers) if workers else 1)
        self._client = self._cluster = None

    @property
    def client(self):
        if self._client is None:
            import logging

            from distributed import Client, LocalCluster
            if self.workers:
                self._cluster = LocalCluster(n_workers=self.workers, threads_per_worker=1, processes=True,
                                             memory_limit=budget.machine_memory() / self.workers,
                                             dashboard_address=":0", silence_logs=logging.ERROR)
                self._client = Client(self._cluster)
            else:
                try:
                    self._client = Client(self.scheduler, timeout=f"{SCHEDULER_TIMEOUT}s")
                except (OSError, TimeoutError) as exc:
                    raise SchedulerUnreachable(
                        f"no Dask scheduler answered at {self.scheduler} within {SCHEDULER_TIMEOUT} s "
                        f"({type(exc).__name__}); start one with `dask scheduler` or drop --scheduler") from None
        return self._client

    def worker_count(self) -> int:
        if self.workers:
            return self.workers
        return max(1, len(self.client.scheduler_info()["workers"]))

    def split(self, jobs: list[Job]) -> list[Job]:
        """Jobs at the grain that pays: whole cases, and the largest split by order."""
        return split_large(jobs, self.worker_count())

    def describe(self) -> str:
        where = f"{self.workers} local Dask workers" if self.workers else f"the Dask cluster at {self.scheduler}"
        return f"on {where} ({self.threads} thread{'s' if self.threads > 1 else ''} per job)"

    def busy_cores(self, remaining: int) -> int:
        """The cores of this machine the study keeps busy while ``remaining`` jobs are left: a
        LocalCluster's workers' (one per job, at most ``workers``); none on a remote cluster."""
        return min(remaining, self.workers) * self.threads if self.workers else 0

    def memory(self) -> tuple[float, str]:
        """The memory of one worker (the largest, for an existing cluster)."""
        if self.workers:
            return budget.machine_memory() / self.workers, f"one of {self.workers} local Dask workers"
        limits = [w.get("memory_limit") or budget.machine_memory() for w in self.client.scheduler_info()["workers"].values()]
        if not limits:
            raise ValueError(f"the Dask cluster at {self.scheduler} has no workers")
        return max(limits), f"the largest Dask worker at {self.scheduler}"

    def run(self, jobs: list[Job], progress=None):
        from distributed import as_completed
        client = self.client
        topic = f"harness-progress-{uuid.uuid4().hex}"
        if progress is not None:
            client.subscribe_topic(topic, relay(progress))
        futures = {}
        for job in largest_first(jobs):
            folder = str(job.checkpoints.resolve()) if job.checkpoints is not None else None
            future = client.submit(run_job, job.case.source, job.case.reference_levels, job.methods, job.levels,
                                   job.on_level, self.threads, folder, EventProgress(topic, job.scope), job.mesh, pure=False,
                                   priority=int(job.seconds * 1000),
                                   key=f"{job.scope.strip().replace(' ', '-')}{job.case.name}-{'-'.join(m.name for m in job.methods)}-"
                                       f"{uuid.uuid4().hex[:8]}")
            futures[future] = job
        try:
            for future in as_completed(futures):
                yield futures[future], future.result()
        finally:
            for future in futures:
                future.cancel()
            if progress is not None:
                client.unsubscribe_topic(topic)

    def close(self) -> None:
        if self._client is not None:
            self._client.close()
        if self._cluster is not None:
            self._cluster.close()
        self._client = self._cluster = None


