"""The report's computations and their cache: the 2D and 3D studies of a profile and the
parameter sweeps, run as one set of jobs on one engine (the largest first: no worker waits for
one study to end before the next begins), each case stored under ``results/cases`` (and each
sweep under ``results/sweeps``) as soon as its last job is done, and reused while the code, the
case file and the settings that produced it are unchanged (a hash of all three is stored
beside it); ``make clean`` forgets them.
"""
from __future__ import annotations

import datetime
import json
import os
import platform
import subprocess
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from functools import partial
from pathlib import Path

import ngsolve as ngs
import pandas as pd

from ... import __version__
from ...methods import ContactLawMethod, methods_named
from ...methods.method import EXTRA_LEVELS
from ...problem.case import Case
from ...problem.validate import validate_case
from ...solvers.options import SolverOptions
from ..chain.rows import PHASES
from ..chain.run import BothHooks
from ..chain.snapshots import SnapshotHook, save_snapshots
from ..execution.budget import SWEEP_SECONDS_PER_DOF, solve_weights
from ..execution.engines import InProcess, Job, chains, mesh_scope, plan, study_weights, tidy
from ..execution.progress import StudyProgress, scoped
from ..execution.refusals import check_methods
from ..execution.threads import usable_cpus
from ..storage.checkpoint import CheckpointStore
from ..storage.digest import code_hash
from ..storage.files import ensure_writable, write_atomic, write_csv
from . import degree_study
from .mesh_study import FinestMesh, mesh_config, mesh_jobs_plan, mesh_levels, read_mesh_results, save_finest_mesh
from .stored import store_name
from .sweep import REPORT_SWEEP, label_sweep, sweep_plan
from .timing import Timings

PACKAGE = Path(__file__).resolve().parents[1]
REPOSITORY = PACKAGE.parent
SWEEP_SCOPE = "sweep "      # the sweeps' solves on the progress bar, apart from the study's
DEGREE_SCOPE = "degree "    # the degree study's


def git_commit() -> str:
    try:
        commit = subprocess.run(["git", "rev-parse", "HEAD"], cwd=REPOSITORY, capture_output=True, text=True, check=True).stdout.strip()
        dirty = subprocess.run(["git", "status", "--porcelain", "--", "harness", "cases"], cwd=REPOSITORY,
                               capture_output=True, text=True).stdout.strip()
        return commit + ("+dirty" if dirty else "")
    except (OSError, subprocess.CalledProcessError):
        return "unknown"


def environment() -> dict:
    """What computed a result, now: the harness (version and commit), NGSolve, the date and the
    machine. Every stored result records it (``provenance``), and so does every benchmark table
    (``bench.common.write_bench``)."""
    return {
        "harness_version": __version__, "git_commit": git_commit(), "ngsolve_version": ngs.__version__,
        "date": datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds"),
        "machine": {"node": platform.node(), "platform": platform.platform(), "processor": platform.machine(),
                    "cpus": os.cpu_count(), "python": platform.python_version()},
    }


def provenance(settings: dict, methods=()) -> dict:
    """What a stored result was computed with: the harness, NGSolve, the machine (``environment``),
    the study's settings and the solver settings (``solvers.options.SolverOptions``: the defaults, and any
    of ``methods`` that solves with others, by name)."""
    solver = {"default": SolverOptions().as_dict()} | {m.name: m.solver.as_dict() for m in methods if m.solver != SolverOptions()}
    return environment() | {"settings": settings, "solver_options": solver}


def cache_key(case: Case, settings: dict) -> str:
    """Hash of the computing code and NGSolve's version (``study.storage.digest.code_hash``: not
    the report, nor this planning), the case file and the settings."""
    digest = code_hash()
    digest.update(Path(case.source).read_bytes())
    digest.update(json.dumps(settings, sort_keys=True).encode())
    return digest.hexdigest()


def _stored(meta_path: Path, files, key: str) -> bool:
    return all(path.is_file() for path in files) and meta_path.is_file() and \
        json.loads(meta_path.read_text()).get("cache_key") == key


def stale_cases(cases: list[Case], settings: dict, results_dir: Path) -> list[Case]:
    """The cases whose stored results (``results_dir/cases``) are missing or were made by other
    code, case files or settings: those a report has to run."""
    store = Path(results_dir) / "cases"
    return [case for case in cases if not _stored(store / f"{case.name}.json",
                                                  [store / f"{case.name}.{ext}" for ext in ("csv", "npz")],
                                                  cache_key(case, settings))]


def sweep_config(levels: int) -> dict:
    """What the report sweeps (``sweep.REPORT_SWEEP``), at a level no finer than the study's
    finest P2 level (``report --levels 3`` sweeps level 2)."""
    config = {key: list(value) if isinstance(value, tuple) else value for key, value in REPORT_SWEEP.items()}
    config["level"] = min(REPORT_SWEEP["level"], levels - 1)
    return config


def stale_sweeps(cases: list[Case], config: dict, results_dir: Path) -> list[Case]:
    """Those of ``cases`` the report sweeps whose stored sweep is missing or was made otherwise."""
    store = Path(results_dir) / "sweeps"
    return [case for case in cases if case.name in config["cases"] and
            not _stored(store / f"{case.name}.json", [store / f"{case.name}.csv"], cache_key(case, {"sweep": config}))]


def case_settings(case: Case, settings: dict) -> dict:
    """The settings ``case``'s study runs with: a 3D case its own (smaller) number of levels (a
    3D level has 8 times the dofs), a two-body case at most the profile's ``levels_two_body``; a case that declares ``asymptotic_levels`` stops there when
    the profile says so (``stop_when_asymptotic``: the default profile, not ``--levels``), one that
    declares ``report_levels`` at its budget for the profile (not with ``--levels``); a 3D case
    without the weak methods where the profile says so (``weak_3d``)."""
    levels = settings["levels_3d"] if case.dimension == 3 else settings["levels"]
    if case.bodies == 2:
        # two bodies: about twice a one-body level's dofs, solved by sparse Cholesky
        levels = min(levels, settings.get("levels_two_body", levels))
    if settings.get("stop_when_asymptotic") and case.asymptotic_levels:
        levels = min(levels, case.asymptotic_levels)
    budget = dict(case.report_levels or ()).get(settings.get("profile"))
    if budget and not settings.get("levels_given"):
        levels = min(levels, budget)
    own = settings | {"levels": levels}
    if case.dimension == 3 and not settings.get("weak_3d", True):
        # the profile leaves the weak methods' 3D rows to a finer one (``chain.PROFILES``)
        own["methods"] = [m.name for m in methods_named(settings.get("methods", ["all"])) if not isinstance(m, ContactLawMethod)]
    if settings.get("stop_when_asymptotic") and case.asymptotic_levels_p1:
        # P1 stops with P2 (its fits asymptotic) or one level past it (P2's finest dofs)
        own["p1_extra_levels"] = min(max(case.asymptotic_levels_p1 - levels, 0), EXTRA_LEVELS[1])
    return own


def study_methods(settings: dict) -> list:
    """The methods of a study with ``settings`` (``case_settings``): P1 run past P2 by the
    case's own number of levels where it declares one."""
    methods = methods_named(settings["methods"])
    if "p1_extra_levels" not in settings:
        return methods
    return [m.with_extra_levels(settings["p1_extra_levels"]) if m.order == 1 else m for m in methods]


def study_groups(cases: list[Case], settings: dict) -> list[tuple[list[Case], dict]]:
    """The report's studies: the cases grouped by the settings they run with (``case_settings``),
    2D before 3D, in the order given."""
    groups: dict[str, tuple[list[Case], dict]] = {}
    for case in sorted(cases, key=lambda c: c.dimension):
        own = case_settings(case, settings)
        groups.setdefault(json.dumps(own, sort_keys=True), ([], own))[0].append(case)
    return list(groups.values())


def compute(cases: list[Case], settings: dict, results_dir: Path, sweep_cases: list[Case], show_progress: bool = True,
            engine=None, check_memory: bool = True, timings: Timings | None = None,
            writer=None, listener=None) -> tuple[pd.DataFrame, dict, pd.DataFrame, pd.DataFrame]:
    """(the rows of every case, the sweep of every case in ``sweep_cases`` the report sweeps,
    the rows of the mesh study, ``mesh_study``, the rows of the degree study, ``degree_study``):
    reused where stored and unchanged, the rest run as one set of jobs on ``engine`` (default
    this process) under one progress bar, its ETA for all of it. Every finished level is
    checkpointed under ``cases/.checkpoints``: a report killed at any moment continues there.

    ``writer``: an ``on_level`` hook that writes files of the studies' solutions (``report
    --vtk``: ``report.vtk.VtkWriter``); a stored case is then reused only where
    ``writer.written(case, methods, levels)``, else it is run again to write them.

    ``listener``: told ``case_stored(case)`` as soon as a case's rows and snapshots are in the
    store (a reused case at once), and ``cores_free(n)`` whenever the number of this machine's
    cores the study leaves idle changes (``engine.busy_cores``; the report draws its figures
    there, ``report.figure_jobs``)."""
    stores = Stores.under(Path(results_dir))
    config, mconfig, dconfig = sweep_config(settings["levels"]), mesh_config(settings), degree_study.degree_config(settings)
    work, sweeps = Work(), {}
    plan_studies(work, cases, settings, stores, writer, listener)
    plan_sweeps(work, sweeps, sweep_cases, config, stores)
    plan_mesh_studies(work, cases, mconfig, stores)
    plan_degree_studies(work, cases, dconfig, stores)
    run_work(work, engine or InProcess(), check_memory, show_progress, timings, listener, stores.checkpoints)
    results = pd.concat([pd.read_csv(stores.cases / f"{case.name}.csv") for case in sorted(cases, key=lambda c: c.dimension)],
                        ignore_index=True)
    return (results, {name: sweeps[name] for name in config["cases"] if name in sweeps},
            read_mesh_results(stores.meshes, cases, mconfig), degree_study.read_degree_results(stores.degrees, cases, dconfig))


@dataclass(frozen=True)
class Stores:
    """The report's cache under ``root``: a folder per kind of computation, each proved
    writable before any of them starts, and the studies' checkpoints."""

    root: Path
    cases: Path
    sweeps: Path
    meshes: Path
    degrees: Path

    @classmethod
    def under(cls, root: Path) -> "Stores":
        return cls(root, *(ensure_writable(root / kind) for kind in ("cases", "sweeps", "meshes", "degree_study")))

    @property
    def checkpoints(self) -> Path:
        return self.cases / ".checkpoints"


@dataclass
class Pending:
    """The outputs of one stored name's jobs (scope + case) so far, and what stores them once
    all are in (``store(outputs)``); ``section``: where ``Timings`` counts their phases."""

    section: str
    store: Callable[[list], None]
    outputs: list = field(default_factory=list)


@dataclass
class Work:
    """What ``compute`` runs: the jobs, the progress bar's weights of their solves, and per
    stored name (scope + case) its ``Pending`` outputs."""

    jobs: list = field(default_factory=list)
    weights: dict = field(default_factory=dict)
    pending: dict[str, Pending] = field(default_factory=dict)


def plan_studies(work: Work, cases: list[Case], settings: dict, stores: Stores, writer, listener) -> None:
    """The study jobs of every case not stored (or whose ``writer`` files are missing); a
    stored case is reused, and ``listener`` hears so at once."""
    for group, group_settings in study_groups(cases, settings):
        methods, levels = study_methods(group_settings), group_settings["levels"]
        stale = stale_cases(group, group_settings, stores.root)
        todo = [c for c in group if c in stale or (writer is not None and not writer.written(c, methods, levels))]
        for case in group:
            if case not in todo:
                print(f"{case.name}: reusing results computed with the same code and settings")
                if listener is not None:
                    listener.case_stored(case)
        for case in todo:
            validate_case(case)
            check_methods(case, methods)
            work.pending[case.name] = Pending("study", partial(_finish_case, stores, case, methods=methods,
                                                                 settings=group_settings, listener=listener))
        hook = SnapshotHook(levels, methods) if writer is None else BothHooks(SnapshotHook(levels, methods), writer)
        work.jobs += chains(todo, methods, levels, hook, stores.checkpoints)
        work.weights |= study_weights(todo, methods, levels)


def plan_sweeps(work: Work, sweeps: dict, sweep_cases: list[Case], config: dict, stores: Stores) -> None:
    """The sweep jobs of the cases the report sweeps whose sweep is not stored; a stored one
    is read into ``sweeps`` (a computed one joins it when stored)."""
    for case in [c for c in sweep_cases if c.name in config["cases"]]:
        if case not in stale_sweeps([case], config, stores.root):
            print(f"{case.name}: reusing the parameter sweep computed with the same code and settings")
            sweeps[case.name] = pd.read_csv(stores.sweeps / f"{case.name}.csv")
            continue
        validate_case(case)
        runs, methods = sweep_plan(config["methods"], config["values"], config["reference"])
        work.jobs.append(Job(case, tuple(methods), config["level"] + 1, scope=SWEEP_SCOPE, tag="sweep", per_dof=SWEEP_SECONDS_PER_DOF))
        work.weights |= scoped(solve_weights(case, methods, config["level"] + 1, per_dof=SWEEP_SECONDS_PER_DOF), SWEEP_SCOPE)
        work.pending[SWEEP_SCOPE + case.name] = Pending("sweeps", partial(_finish_sweep, sweeps, stores.sweeps, case,
                                                                          runs=runs, methods=methods, config=config))


def plan_mesh_studies(work: Work, cases: list[Case], config: dict, stores: Stores) -> None:
    """The jobs of the mesh study's (case, mesh strategy) chains not stored."""
    for case, mesh, methods in mesh_jobs_plan(cases, config):
        name, key = store_name(case, mesh), cache_key(case, {"meshes": config, "mesh": mesh.label})
        if _stored(stores.meshes / f"{name}.json", [stores.meshes / f"{name}.csv"], key):
            print(f"{case.name}: reusing the {mesh.label} meshes computed with the same code and settings")
            continue
        validate_case(case)
        hook = FinestMesh() if mesh.name == "adaptive" else None
        levels = mesh_levels(case, config)
        work.jobs += chains([case], methods, levels, hook, stores.checkpoints, tag="mesh", meshes=[mesh])
        work.weights |= study_weights([case], methods, levels, [mesh])
        work.pending[mesh_scope("", mesh) + case.name] = Pending("meshes", partial(_store_meshes, stores.meshes, case, mesh,
                                                                                   methods=methods, config=config))


def plan_degree_studies(work: Work, cases: list[Case], config: dict, stores: Stores) -> None:
    """The jobs of the degree study's (case, mesh strategy) chains not stored."""
    for case, mesh, methods in degree_study.degree_jobs_plan(cases, config):
        name = store_name(case, mesh)
        key = cache_key(case, {"degree_study": config, "mesh": mesh.label})
        if _stored(stores.degrees / f"{name}.json", [stores.degrees / f"{name}.csv"], key):
            print(f"{case.name}: reusing the degree study on {mesh.label} meshes computed with the same code and settings")
            continue
        validate_case(case)
        # checkpoints of their own: the main study's uniform chain of the same case and method
        # has other levels
        levels = degree_study.levels_of(mesh, config)
        work.jobs += chains([case], methods, levels, None, stores.degrees / ".checkpoints", tag="degree",
                            meshes=[mesh], scope=DEGREE_SCOPE)
        work.weights |= scoped(study_weights([case], methods, levels, [mesh]), DEGREE_SCOPE)
        work.pending[mesh_scope(DEGREE_SCOPE, mesh) + case.name] = Pending(
            "degree study", partial(_store_degrees, stores.degrees, case, mesh, methods=methods, config=config))


def _store_degrees(store: Path, case: Case, mesh, outputs: list, methods, config: dict) -> None:
    """One (case, mesh strategy)'s rows of the degree study in the report's cache."""
    name = store_name(case, mesh)
    write_csv(tidy(outputs, [case], methods, [mesh]), store / f"{name}.csv")
    CheckpointStore(store / ".checkpoints", degree_study.levels_of(mesh, config), None, mesh.label).forget(case)
    write_atomic(store / f"{name}.json", json.dumps(provenance({"degree_study": config}) | {
        "cache_key": cache_key(case, {"degree_study": config, "mesh": mesh.label}), "case": case.name, "mesh": mesh.label},
        indent=2))


def run_work(work: Work, engine, check_memory: bool, show_progress: bool, timings: Timings | None, listener,
             checkpoints: Path) -> None:
    """``work``'s jobs on ``engine`` under one progress bar, each name's outputs stored as soon
    as its last job is done; then the checkpoints no store needed are forgotten."""
    jobs = plan(work.jobs, engine, check_memory)
    remaining = {name: sum(1 for job in jobs if job.scope + job.case.name == name) for name in work.pending}
    progress = StudyProgress(work.weights, show_progress and bool(jobs))
    clock = time.perf_counter()
    cores = usable_cpus()
    if listener is not None:
        listener.cores_free(max(0, cores - engine.busy_cores(len(jobs))))
    try:
        for finished, (job, output) in enumerate(engine.run(jobs, progress), start=1):
            if listener is not None:
                listener.cores_free(max(0, cores - engine.busy_cores(len(jobs) - finished)))
            name = job.scope + job.case.name
            work.pending[name].outputs.append(output)
            remaining[name] -= 1
            if not remaining[name]:
                _store_pending(work.pending[name], job.case.name, timings)
    finally:
        progress.close()
    # every job is stored: what is left are the checkpoints of chains no store needed
    CheckpointStore(checkpoints, 0).forget()
    if timings is not None:
        timings.add("jobs (wall)", engine.describe(), "", time.perf_counter() - clock)


def _store_pending(pending: Pending, case_name: str, timings: Timings | None) -> None:
    """A name's outputs, all in: their phases counted, then stored."""
    if timings is not None:
        for phase in PHASES:
            timings.add(pending.section, case_name, phase, sum(o.phases.get(phase, 0.0) for o in pending.outputs))
    pending.store(pending.outputs)


def _finish_case(stores: Stores, case: Case, outputs: list, methods, settings: dict, listener) -> None:
    """A case's study, all in: stored, its checkpoints forgotten, ``listener`` told."""
    _store_case(stores.cases, case, outputs, methods, settings)
    CheckpointStore(stores.checkpoints, settings["levels"]).forget(case)
    if listener is not None:
        listener.case_stored(case)


def _finish_sweep(sweeps: dict, store: Path, case: Case, outputs: list, runs, methods, config: dict) -> None:
    sweeps[case.name] = _store_sweep(store, case, outputs, runs, methods, config)


def _store_meshes(store: Path, case: Case, mesh, outputs: list, methods, config: dict) -> None:
    """One (case, mesh strategy)'s rows (and its finest adaptive mesh) in the report's cache."""
    name = store_name(case, mesh)
    write_csv(tidy(outputs, [case], methods, [mesh]), store / f"{name}.csv")
    save_finest_mesh({k: v for output in outputs for k, v in output.kept.items()}, store / f"{name}.npz")
    write_atomic(store / f"{name}.json", json.dumps(provenance({"meshes": config}) | {
        "cache_key": cache_key(case, {"meshes": config, "mesh": mesh.label}), "case": case.name, "mesh": mesh.label},
        indent=2))


def _store_case(store: Path, case: Case, outputs: list, methods, settings: dict) -> None:
    """One case's rows, snapshots and provenance in the report's cache (the .json last: it
    marks the case complete). ``work_seconds``: the seconds its jobs spent, summed (they may
    have run side by side on workers, and a resumed job counts only what it redid)."""
    frame = tidy(outputs, [case], methods)
    write_csv(frame, store / f"{case.name}.csv")
    save_snapshots({k: v for output in outputs for k, v in output.kept.items()}, store / f"{case.name}.npz")
    work = sum(sum(output.phases.values()) for output in outputs)
    meta = provenance(settings) | {"cache_key": cache_key(case, settings), "case": case.name, "work_seconds": work}
    write_atomic(store / f"{case.name}.json", json.dumps(meta, indent=2))


def _store_sweep(store: Path, case: Case, outputs: list, runs, methods, config: dict) -> pd.DataFrame:
    frame = label_sweep(tidy(outputs, [case], methods), runs, methods, config["level"])
    write_csv(frame, store / f"{case.name}.csv")
    write_atomic(store / f"{case.name}.json", json.dumps(provenance({"sweep": config}) |
                                                         {"cache_key": cache_key(case, {"sweep": config}), "case": case.name},
                                                         indent=2))
    return frame
