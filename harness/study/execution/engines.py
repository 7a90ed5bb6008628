"""Where a study's jobs run: in this process (``InProcess``, the default), on local worker
processes (``processes.LocalProcesses``: one NGSolve thread each, all cores busy), or on Dask
workers (``dask_engine.DaskEngine``: a LocalCluster, or an existing cluster by its scheduler's
address). A job (``Job``) is a level chain (``chain.run_chain``) of one case and some methods,
sharing each level's mesh, assembly, multigrid hierarchy and best approximation: one job per
case, except that on several workers a case whose estimated time is a large share of what each
worker gets is split by finite element order (``split_large``: its P2 and P1 chains share only
the mesh refinement, so the split repeats little), so that no single job outlasts the rest.
Jobs of different studies (the report's 2D and 3D studies, its sweeps and its mesh study) go to
the engine together (one call of its ``run``: ``InProcess.run``, ``processes.LocalProcesses.run``,
``dask_engine.DaskEngine.run``), the largest first, so that no worker waits for a study to end.
Every engine writes the same per-(case, method) checkpoints, so a study killed under one
engine resumes under any.

Every error column is computed level by level from the same data whichever job it runs in, so
the results do not depend on the engine or the number of workers -- bit for bit when NGSolve
runs one thread per process (``--threads 1``; a Dask worker's default). With more threads, the
task manager's parallel sums (sparse Cholesky, Integrate, the element colouring of a space made
under it) are not done in a fixed order, and two runs agree only to about 1e-14 relative.
"""
from __future__ import annotations

import time
from collections.abc import Iterator
from dataclasses import dataclass, field
from pathlib import Path
from typing import Protocol, runtime_checkable

import pandas as pd

from ...mesh.strategies import UNIFORM, MeshStrategy, refusal, serves
from ...methods import methods_for
from ...problem.case import load_case
from ...problem.validate import validate_case
from ..chain.rows import COLUMNS, Phases
from ..chain.run import run_chain
from ..storage.checkpoint import CheckpointStore
from . import budget
from . import threads as thread_policy
from .budget import check_fits, estimate, solve_weights
from .progress import Scoped, StudyProgress, scoped
from .refusals import check_hook, check_meshes, check_methods, check_runs
from .threads import usable_cpus


@dataclass(frozen=True)
class Job:
    """One level chain: ``methods`` on ``case`` over ``levels`` P2 levels, sharing each level.
    ``on_level``: the study's hook; ``checkpoints``: the folder of its checkpoints (or None);
    ``scope``: how its solves are named on a progress bar shared with other studies
    (``progress.Scoped``); ``tag``: what the caller makes of its output (the report: "study"
    or "sweep")."""

    case: object
    methods: tuple
    levels: int
    on_level: object = None
    checkpoints: Path | None = None
    scope: str = ""
    tag: str = field(default="study", compare=False)
    per_dof: float | None = None          # a solve's seconds per dof, if not its family's (``budget``)
    mesh: MeshStrategy = UNIFORM

    @property
    def seconds(self) -> float:
        """Estimated time (``budget.estimate``): the order in which jobs are submitted."""
        return estimate(self.case, self.methods, planned_levels(self), per_dof=self.per_dof).seconds

    def store(self) -> CheckpointStore | None:
        if self.checkpoints is None:
            return None
        return CheckpointStore(self.checkpoints, self.levels, self.on_level, self.mesh.label)


def mesh_scope(scope: str, mesh: MeshStrategy) -> str:
    """The progress bar's scope of a job on ``mesh`` (uniform: the study's own)."""
    return scope if mesh == UNIFORM else f"{scope}{mesh.label} "


def chains(cases, methods, levels: int, on_level=None, checkpoints=None, scope: str = "", tag: str = "study",
           meshes=(UNIFORM,)) -> list[Job]:
    """The jobs of a study as this process runs them: per case and mesh strategy, the methods
    that discretise the case, grouped by the level sequence they can share
    (``MeshStrategy.group_key``: all of them on uniform meshes)."""
    jobs = []
    for case in cases:
        for mesh in meshes:
            if refusal(mesh, case) is not None:
                continue
            groups: dict = {}
            for method in methods_for(case, methods):
                if serves(mesh, method):
                    groups.setdefault(mesh.group_key(method), []).append(method)
            jobs += [Job(case, tuple(group), levels, on_level, Path(checkpoints) if checkpoints else None,
                         mesh_scope(scope, mesh), tag, mesh=mesh) for group in groups.values()]
    return jobs


def by_order(job: Job) -> list[Job]:
    """A job split into one per finite element order (P2 methods, P1 methods)."""
    orders = sorted({m.order for m in job.methods}, reverse=True)
    return [Job(job.case, tuple(m for m in job.methods if m.order == order), job.levels, job.on_level, job.checkpoints,
                job.scope, job.tag, job.per_dof, job.mesh) for order in orders]


@runtime_checkable
class Engine(Protocol):
    """Where a study's jobs run (``harness.run(engine=...)``, ``harness.report(engine=...)``): what
    ``InProcess``, ``processes.LocalProcesses`` and ``dask_engine.DaskEngine`` have in common. An
    engine of your own implements these six methods; a study calls ``split``, ``memory`` and
    ``describe`` before it starts, ``run`` once with all its jobs, ``busy_cores`` as they finish,
    and the caller ``close`` at the end."""

    threads: int | None

    def split(self, jobs: list[Job]) -> list[Job]:
        """The jobs at this engine's grain (a case's job split by order: ``split_large``)."""
        ...

    def describe(self) -> str:
        """Where the jobs run, in a few words ("in one process", "on 2 local processes")."""
        ...

    def memory(self) -> tuple[float, str]:
        """(bytes a job may use, what has them): the budget's check (``budget.check_fits``)."""
        ...

    def busy_cores(self, remaining: int) -> int:
        """The cores the study keeps busy while ``remaining`` jobs are left (``threads``)."""
        ...

    def run(self, jobs: list[Job], progress=None) -> Iterator[tuple[Job, object]]:
        """(job, ``study.chain.rows.ChainOutput``) for each job, as they finish."""
        ...

    def close(self) -> None:
        """Release the workers (nothing for this process)."""
        ...


class InProcess:
    """The study in this process: one job per case, its methods sharing each level. NGSolve's
    task manager runs assembly, integration and sparse factorisations on every core; the
    multigrid's Gauss-Seidel smoothing and the Python of the solvers and the errors run on one,
    so a chain gains little from a second thread, and 1-thread local processes
    (``processes.LocalProcesses``) run the default report faster
    (``python -m harness bench --only report`` compares them)."""

    def __init__(self, threads: int | None = None):
        self.threads = threads

    def split(self, jobs: list[Job]) -> list[Job]:
        return list(jobs)

    def describe(self) -> str:
        return "in one process" + ("" if self.threads is None else f" ({self.threads} thread{'s' if self.threads > 1 else ''})")

    def memory(self) -> tuple[float, str]:
        return budget.machine_memory(), "this machine"

    def busy_cores(self, remaining: int) -> int:
        """The cores of this machine the study keeps busy while ``remaining`` jobs are left:
        all of them (NGSolve's threads) until the last job ends."""
        return usable_cpus() if remaining else 0

    def run(self, jobs: list[Job], progress=None):
        """(job, ``study.chain.rows.ChainOutput``) for each job, as they finish."""
        for job in jobs:
            view = Scoped(progress, job.scope) if progress is not None and job.scope else progress
            with thread_policy.using(self.threads):
                output = run_chain(job.case, list(job.methods), job.levels, view, job.on_level, Phases(), job.store(),
                                   mesh=job.mesh)
            yield job, output

    def close(self) -> None:
        pass


def run_job(source: str, reference_levels, methods, levels: int, on_level, threads, folder, progress=None,
            mesh: MeshStrategy = UNIFORM):
    """A job in a worker process (local or Dask): the case is loaded there from its file (what a
    worker needs of it is its source, not NGSolve objects); ``progress`` relays the solves to the
    client's bar (``progress.EventProgress``, ``progress.QueueProgress``)."""
    case = load_case(source)
    if reference_levels != case.reference_levels:
        case = case.with_reference(reference_levels)
    store = CheckpointStore(folder, levels, on_level, mesh.label) if folder is not None else None
    with thread_policy.using(threads):
        return run_chain(case, list(methods), levels, progress, on_level, Phases(), store, mesh=mesh)


# a case is split by order when its estimated time exceeds this share of what each worker
# gets: then no job is much longer than the rest, and the split repeats only the coarser
# P2 job's mesh refinement
SPLIT_SHARE = 0.5


def split_large(jobs: list[Job], workers: int) -> list[Job]:
    """Jobs at the grain that pays on ``workers`` workers: whole cases (their methods share
    each level), and a case split by order where it alone would be more than ``SPLIT_SHARE``
    of one worker's share of the work -- an exact case only: the methods of a case measured
    against a reference wait for one reference solve (``chain.chain_methods``), which each
    part would repeat."""
    seconds = [job.seconds for job in jobs]
    share = SPLIT_SHARE * sum(seconds) / max(1, workers)
    return [part for job, t in zip(jobs, seconds)
            for part in (by_order(job) if t > share and job.case.exact else [job])]


def largest_first(jobs: list[Job]) -> list[Job]:
    """The order in which workers take jobs: the largest first, so that no worker is left with
    a long job at the end."""
    return sorted(jobs, key=lambda j: -j.seconds)


def plan(jobs: list[Job], engine, check_memory: bool = True) -> list[Job]:
    """The jobs at ``engine``'s grain, refused (``budget.BudgetError``, before anything is
    allocated) if the largest would not fit in the memory it would run in."""
    jobs = engine.split(jobs)
    if check_memory and jobs:
        check_fits([estimate(job.case, job.methods, planned_levels(job)) for job in jobs], *engine.memory())
    return jobs


def planned_levels(job: Job) -> int:
    """The uniform levels a job costs about as much as (``budget`` is written for them): its own,
    or for an hp job the uniform levels of about its finest dofs (``mesh.hp.uniform_equivalent``)."""
    mesh = job.mesh
    if getattr(mesh, "name", None) != "hp":
        return job.levels
    from ...mesh.hp import uniform_equivalent
    from ...mesh.levels import coarse_mesh
    return uniform_equivalent(coarse_mesh(job.case).ne, max(m.order for m in job.methods), job.levels, mesh.mu)


def study_weights(cases, methods, levels: int, meshes=(UNIFORM,)) -> dict:
    """The progress bar's weights of every solve of a study (``budget.solve_weights``); a graded
    or adaptive chain is weighed as the uniform one of the same budget of dofs, under its scope
    (with each level's own reference for a case without u)."""
    weights = {}
    for case in cases:
        if methods_for(case, methods):
            for mesh in meshes:
                if refusal(mesh, case) is None:
                    # a case without u: off uniform meshes each level has its own reference
                    own = solve_weights(case, methods_for(case, methods), levels,
                                        per_level_reference=not case.exact and mesh.label != UNIFORM.label)
                    weights |= scoped(own, mesh_scope("", mesh))
    return weights


def study_progress(cases, methods, levels: int, show: bool, meshes=(UNIFORM,)) -> StudyProgress:
    return StudyProgress(study_weights(cases, methods, levels, meshes), show)


def tidy(outputs, cases, methods, meshes=(UNIFORM,)) -> pd.DataFrame:
    """One frame of the rows of all jobs: by case, then mesh strategy, level, method, as given
    (the same order whichever engine ran them)."""
    case_order = {c.name: k for k, c in enumerate(cases)}
    method_order = {m.name: k for k, m in enumerate(methods)}
    mesh_order = {m.label: k for k, m in enumerate(meshes)}
    rows = sorted((row for output in outputs for row in output.rows),
                  key=lambda r: (case_order[r["case"]], mesh_order.get(r["mesh"], 0), r["level"], method_order[r["method"]]))
    return pd.DataFrame(rows, columns=COLUMNS)


def run_study(cases, methods, levels: int, show_progress: bool = True, on_level=None, progress=None,
              engine=None, checkpoints: Path | None = None, check_memory: bool = True, meshes=(UNIFORM,)) -> pd.DataFrame:
    """Every case x method x level; one tidy row each (columns ``study.chain.rows.COLUMNS``). ``levels``
    counts the P2 levels (P1 runs one more: ``study.chain.rows.study_levels``). ``engine``: where the jobs
    run (default ``InProcess()``). ``checkpoints``: a folder that makes every finished level
    durable; a study started again with the same folder continues where it stopped.
    ``progress``: a bar shared with a larger run (else one is made). The frame's attrs: wall
    seconds, seconds per phase (summed over jobs), and the level each (case, method) chain
    resumed from (0: it started afresh), the contact solve seconds of the reference chains'
    solves (no row holds them). ``meshes``: the mesh strategies
    (``mesh.strategies``), each case on each that applies to it."""
    start = time.perf_counter()
    own = progress is None
    progress = study_progress(cases, methods, levels, show_progress, meshes) if own else progress
    try:
        done = list(run_jobs(cases, methods, levels, engine, progress, on_level, checkpoints, check_memory, meshes))
    finally:
        if own:
            progress.close()
    outputs = [output for _job, output in done]
    frame = tidy(outputs, cases, methods, meshes)
    frame.attrs["wall_seconds"] = time.perf_counter() - start
    frame.attrs["phase_seconds"] = {phase: sum(o.phases.get(phase, 0.0) for o in outputs) for phase in Phases().as_dict()}
    frame.attrs["reference_solve_seconds"] = sum(o.reference_solve_seconds for o in outputs)
    frame.attrs["resumed"] = {(job.case.name, name): level for job, output in done for name, level in output.resumed.items()}
    return frame


def study_jobs(cases, methods, levels: int, engine, on_level=None, checkpoints: Path | None = None,
               check_memory: bool = True, meshes=(UNIFORM,)) -> list[Job]:
    """The jobs of a study at ``engine``'s grain: every case validated, discretised by at least
    one of ``methods``, meshed by at least one strategy, and its largest job within the memory
    (``plan``); refused otherwise."""
    if levels < 1:
        raise ValueError(f"levels must be a positive integer, got {levels}")
    for case in cases:
        validate_case(case)
    for case in cases:
        check_methods(case, methods)
    check_meshes(cases, meshes, levels)
    check_runs(cases, methods, meshes)
    check_hook(on_level)
    return plan(chains(cases, methods, levels, on_level, checkpoints, meshes=meshes), engine, check_memory)


def run_jobs(cases, methods, levels: int, engine=None, progress=None, on_level=None, checkpoints: Path | None = None,
             check_memory: bool = True, meshes=(UNIFORM,)):
    """(job, ``study.chain.rows.ChainOutput``) of every job of a study, as they finish: validated and
    checked against the memory first (``study_jobs``), then run on ``engine`` (default: this process)."""
    engine = engine or InProcess()
    yield from engine.run(study_jobs(cases, methods, levels, engine, on_level, checkpoints, check_memory, meshes), progress)
