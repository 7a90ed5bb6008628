"""The report's figures, drawn in worker processes on the cores the study leaves free (what each
section draws, its jobs, is the section's: ``report.sections``).

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

from . import figure_cache

FIGURE_WORKERS = 2


def _timed(draw, styles, *args) -> tuple[dict, float]:
    from . import figures
    clock = time.perf_counter()
    figures.register_methods(styles)
    return draw(*args), time.perf_counter() - clock


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
    by name (a case's name, "summary") or by group and name (``groups``: "sweeps", "meshes", ...,
    each given even when empty) with the seconds each took in its worker. What is drawn, each
    job's function and arguments, the report's sections declare (``report.sections``: ``job``).
    It is the listener of ``study.planning.cache.compute``: a stored case's figures are queued at
    once (``on_stored(pool, case, store)``). ``methods``: the study's methods (Method objects or
    names), or their styles (``plots.method_styles``)."""

    def __init__(self, methods, folder: Path, workers: int = FIGURE_WORKERS, store: Path | None = None,
                 groups=(), on_stored=None):
        from .plots import method_styles
        self.styles = dict(methods) if isinstance(methods, dict) else method_styles(methods)
        self.folder, self.workers, self.store = str(folder), workers, store
        self.on_stored = on_stored
        self.pool = figure_executor(workers)
        self.futures: dict[str, Future] = {}
        self.groups: dict[str, dict[str, Future]] = {group: {} for group in groups}
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
        """``study.planning.cache.compute``'s listener: the case is in ``store``, its figures can be
        drawn (``on_stored(pool, case, store)`` queues them)."""
        if self.on_stored is not None:
            self.on_stored(self, case, self.store)

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

    def job(self, name: str, draw, *args, group: str | None = None, key: str | None = None, inputs: tuple = ()) -> None:
        """Queue ``draw(*args, folder)`` (a module-level function: it is sent to a worker), the
        figures it returns to be collected under ``key`` (default ``name``), in ``group`` if
        given; ``name``: its key's name in ``figure_cache``, ``inputs``: the files it reads."""
        future = self._submit(name, draw, *args, inputs=inputs)
        (self.futures if group is None else self.groups.setdefault(group, {}))[key or name] = future

    def collect(self) -> tuple[dict, dict]:
        """(figures by name, those of a group under its name, by name; worker seconds by name and
        by group), every worker drawing from now on."""
        self.cores_free(self.workers)
        figs, seconds = {}, {}
        for name, future in self.futures.items():
            figs[name], seconds[name] = future.result()
        for group, futures in self.groups.items():
            done = {name: future.result() for name, future in futures.items()}
            figs[group] = {name: paths for name, (paths, _) in done.items()}
            seconds[group] = sum(s for _, s in done.values())
        return figs, seconds
