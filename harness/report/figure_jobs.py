"""The report's figures, drawn in worker processes on the cores the study leaves free.

matplotlib draws on one core, and the report has dozens of figures (each in PNG and PDF);
each needs only its case's stored rows and snapshots, so two processes draw them side by side.
A case's figures are queued as soon as the case is stored (``study.planning.cache.compute``'s
listener), but drawn only on cores the study leaves idle (``cores_free``: the study's tail,
when fewer jobs are left than worker processes; on one process, once the study is done).
Drawing them beside the running study, on cores it uses, slows the study more than it saves,
at normal and at the lowest priority alike (``python -m harness bench --only report`` times
the report and where its time goes). Workers are spawned, not forked: the parent runs
NGSolve's threads. Every figure is drawn with the same colour per method in every process: the
parent assigns them (``plots.method_styles``, from the methods' declared roles) and sends them
to every figure.
"""
from __future__ import annotations

import multiprocessing
import sys
import threading
import time
from collections import deque
from concurrent.futures import Future, ProcessPoolExecutor, ThreadPoolExecutor
from pathlib import Path

import pandas as pd

from . import figure_cache

FIGURE_WORKERS = 2


def _timed(draw, styles, *args) -> tuple[dict, float]:
    from . import figures
    clock = time.perf_counter()
    figures.register_methods(styles)
    return draw(*args), time.perf_counter() - clock


def _case_figures(source: str, store: str, folder: str) -> dict:
    """The figures of one case from its stored rows (``report_cache``) and snapshots."""
    from ..measure.efficiency import efficiency_table
    from ..problem.case import load_case
    from ..study.chain.snapshots import load_snapshots
    from . import figures
    case, store, folder = load_case(source), Path(store), Path(folder)
    frame = pd.read_csv(store / f"{case.name}.csv")
    contact, domain = load_snapshots(store / f"{case.name}.npz")
    return {
        "convergence": figures.convergence(case, frame, folder),
        "contact": figures.contact(case, contact, folder),
        "solution": figures.domain(case, {k: v for k, v in domain.items() if k != "interface"}, folder),
        "interface": figures.interface(case, domain.get("interface"), folder),
        "efficiency": figures.efficiency(case, frame, efficiency_table(frame).target_err_h1.iloc[0], folder),
    }


def _mesh_figures(source: str, frame: pd.DataFrame, mesh_file: str, method: str, folder: str) -> dict:
    """The mesh study's figures of one case (``report.mesh_figures``)."""
    from ..problem.case import load_case
    from ..study.planning.mesh_study import load_finest_mesh
    from . import mesh_figures
    case, folder = load_case(source), Path(folder)
    finest = load_finest_mesh(Path(mesh_file))
    return {"errors": mesh_figures.error_against_ndof(case, frame, folder),
            "mesh": mesh_figures.adaptive_mesh(case, *finest, folder, method) if finest is not None else None}


def _degree_figures(source: str, frame: pd.DataFrame, folder: str) -> dict:
    """The degree study's figure of one case (``report.mesh_figures.degree_errors``)."""
    from ..problem.case import load_case
    from . import mesh_figures
    return {"errors": mesh_figures.degree_errors(load_case(source), frame, Path(folder))}


def _summary(rates: pd.DataFrame, folder: str) -> dict:
    from . import figures
    return figures.summary(rates, Path(folder))


def _sweep(source: str, frame: pd.DataFrame, folder: str) -> dict:
    from ..problem.case import load_case
    from . import figures
    return figures.sweep(load_case(source), frame, Path(folder))


def figure_executor(workers: int):
    """Where the figures are drawn: ``workers`` spawned processes; or one thread of this process
    when its main module is a script run by its path (``python my_study.py`` calling
    ``harness.report``), whose top level every spawned process would run again (Python's
    multiprocessing, "safe importing of main module"), the study included. A module run with
    ``-m`` (``python -m harness report``), a notebook or an interpreter spawns safely."""
    main = sys.modules.get("__main__")
    if getattr(main, "__file__", None) and getattr(main, "__spec__", None) is None:
        return ThreadPoolExecutor(1, thread_name_prefix="figures")
    return ProcessPoolExecutor(workers, mp_context=multiprocessing.get_context("spawn"))


class FigurePool:
    """Figures drawn in ``workers`` processes, at most ``cores_free(n)`` at once (none until told:
    the study may still use every core); ``collect`` lets all workers draw, waits, and gives them
    by name (a case's name, "summary", "sweeps") with the seconds each took in its worker. It is
    the listener of ``study.planning.cache.compute``: a stored case's figures are queued at once.
    ``methods``: the study's methods (Method objects or names), or their styles
    (``plots.method_styles``)."""

    def __init__(self, methods, folder: Path, workers: int = FIGURE_WORKERS, store: Path | None = None):
        from .plots import method_styles
        self.styles = dict(methods) if isinstance(methods, dict) else method_styles(methods)
        self.folder, self.workers, self.store = str(folder), workers, store
        self.pool = figure_executor(workers)
        self.futures: dict[str, Future] = {}
        self.sweeps: dict[str, Future] = {}
        self.meshes: dict[str, Future] = {}
        self.degrees: dict[str, Future] = {}
        # the queue of figures not yet handed to the pool; a dispatcher thread hands them over
        # while fewer than ``slots`` are drawing (a done-callback must not submit: it runs in the
        # pool's own management thread)
        self._queue: deque = deque()
        self._slots, self._drawing, self._closed = 0, 0, False
        self._changed = threading.Condition()
        self._dispatcher = threading.Thread(target=self._dispatch, name="figure dispatcher", daemon=True)
        self._dispatcher.start()

    def __enter__(self) -> "FigurePool":
        return self

    def __exit__(self, *exc) -> None:
        with self._changed:
            self._closed, self._slots = True, self.workers
            if exc[0] is not None:
                self._queue.clear()
            self._changed.notify_all()
        self._dispatcher.join()
        self.pool.shutdown(wait=exc[0] is None, cancel_futures=exc[0] is not None)

    def cores_free(self, cores: int) -> None:
        """Draw at most ``cores`` figures at once from now on (up to ``workers``)."""
        with self._changed:
            self._slots = max(0, min(int(cores), self.workers))
            self._changed.notify_all()

    def case_stored(self, case) -> None:
        """``study.planning.cache.compute``'s listener: the case is in ``store``, its figures can be drawn."""
        self.case(case, self.store)

    def _dispatch(self) -> None:
        while True:
            with self._changed:
                self._changed.wait_for(lambda: (self._queue and self._drawing < self._slots) or
                                       (self._closed and not self._queue))
                if not self._queue:
                    return
                outer, args = self._queue.popleft()
                self._drawing += 1
            inner = self.pool.submit(_timed, *args)
            inner.add_done_callback(lambda done, outer=outer: self._finished(done, outer))

    def _finished(self, done: Future, outer: Future) -> None:
        with self._changed:
            self._drawing -= 1
            self._changed.notify_all()
        if done.exception() is not None:
            outer.set_exception(done.exception())
        else:
            outer.set_result(done.result())

    def _submit(self, name: str, draw, *args, inputs: tuple = ()) -> Future:
        """Queue ``draw``'s job ``name``, or give the figures it left with the same inputs
        (``figure_cache``: ``inputs`` are the files it reads besides its arguments)."""
        outer: Future = Future()
        key = figure_cache.job_key(draw, self.styles, args, inputs)
        kept = figure_cache.stored(Path(self.folder), name, key)
        if kept is not None:
            outer.set_result((kept, 0.0))
            return outer
        outer.add_done_callback(lambda done: done.exception() is None and
                                figure_cache.store(Path(self.folder), name, key, done.result()[0]))
        with self._changed:
            self._queue.append((outer, (draw, self.styles, *args, self.folder)))
            self._changed.notify_all()
        return outer

    def case(self, case, store: Path) -> None:
        stored = tuple(Path(store) / f"{case.name}.{kind}" for kind in ("csv", "npz"))
        self.futures[case.name] = self._submit(case.name, _case_figures, str(case.source), str(store), inputs=stored)

    def summary(self, rates: pd.DataFrame) -> None:
        self.futures["summary"] = self._submit("summary", _summary, rates)

    def sweep(self, case, frame: pd.DataFrame) -> None:
        self.sweeps[case.name] = self._submit(f"sweep-{case.name}", _sweep, str(case.source), frame)

    def meshes_of(self, case, frame: pd.DataFrame, mesh_file: Path, method: str) -> None:
        self.meshes[case.name] = self._submit(f"meshes-{case.name}", _mesh_figures, str(case.source), frame, str(mesh_file), method)

    def degrees_of(self, case, frame: pd.DataFrame) -> None:
        self.degrees[case.name] = self._submit(f"degrees-{case.name}", _degree_figures, str(case.source), frame)

    def collect(self) -> tuple[dict, dict]:
        """(figures by name, the sweeps' under "sweeps"; worker seconds by name), every worker
        drawing from now on."""
        self.cores_free(self.workers)
        figs, seconds = {}, {}
        for name, future in self.futures.items():
            figs[name], seconds[name] = future.result()
        done = {name: future.result() for name, future in self.sweeps.items()}
        figs["sweeps"] = {name: paths for name, (paths, _) in done.items()}
        seconds["sweeps"] = sum(s for _, s in done.values())
        drawn = {name: future.result() for name, future in self.meshes.items()}
        figs["meshes"] = {name: paths for name, (paths, _) in drawn.items()}
        seconds["meshes"] = sum(s for _, s in drawn.values())
        by_degree = {name: future.result() for name, future in self.degrees.items()}
        figs["degree_study"] = {name: paths for name, (paths, _) in by_degree.items()}
        seconds["degree_study"] = sum(s for _, s in by_degree.values())
        return figs, seconds
