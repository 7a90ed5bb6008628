"""One progress bar for a whole study, however many processes run it.

The bar's length is the estimated time of every solve of the study (``budget.solve_weights``:
a fixed cost per solve plus a cost per dof), so its ETA weighs the levels by their size: the
finest level of a chain is most of its time, and a rate per solve badly misjudges it. Levels a
resumed study restores from its checkpoints leave the bar (its length shrinks), so the rate and
the ETA count only work done now. Workers report through Dask's event log (``EventProgress``).
"""
from __future__ import annotations

from tqdm.auto import tqdm

BAR_FORMAT = "{desc}{percentage:3.0f}%|{bar}| {elapsed}<{remaining}"
# the description, then the percentage, the bar and the times (the bar takes what is left of a
# 100-column terminal: about 30 columns)
DESCRIPTION_WIDTH = 52


class StudyProgress:
    """The bar: ``solving``/``solved``/``restored`` come from the study (``chain.run_chain``),
    in this process or relayed from workers; a level counts once, even if a job is rerun.

    One bar may cover several studies (the report's 2D and 3D studies and its sweeps):
    ``add`` puts more weights on it, each study's keys under its own ``scope``
    (``scoped``). Its description is one line (``DESCRIPTION_WIDTH``): the case and level
    being solved, its dofs, how many of that level's methods are done, and how many other
    jobs run beside it (Dask workers)."""

    def __init__(self, weights: dict, show: bool = True):
        self.weights: dict = {}
        self.done: set = set()
        self.running: dict = {}
        self.total, self.count = 0, 0      # what the bar shows (also when hidden)
        self.bar = tqdm(total=0, disable=not show, bar_format=BAR_FORMAT, dynamic_ncols=True)
        self.add(weights)

    def add(self, weights: dict) -> None:
        # in whole milliseconds: the bar's count and length stay exact integers, however many
        # levels are added and restored
        for key, seconds in weights.items():
            if key not in self.weights:
                self.weights[key] = max(1, round(1000 * seconds))
                self.total += self.weights[key]
        self.bar.total = self.total
        self.bar.refresh()

    def solving(self, case: str, method: str, level: int, ndof: int, stage: str = "") -> None:
        self.running[(case, method)] = (level, ndof, stage)
        self._describe(case, level, ndof, stage)

    def _describe(self, case: str, level: int, ndof: int, stage: str) -> None:
        of_level = [key for key in self.weights if key[0] == case and key[2] == level]
        done = sum(key in self.done for key in of_level)
        others = len({c for c, _ in self.running} - {case})
        text = f"{case} L{level}{' ref' if stage else ''} {ndof:,} dofs"
        if of_level:        # an adaptive chain's levels are not known in advance: no count there
            text += f" {done}/{len(of_level)} methods"
        if others:
            text += f" +{others} jobs"
        if len(text) > DESCRIPTION_WIDTH - 1:
            text = text[: DESCRIPTION_WIDTH - 2] + "…"
        self.bar.set_description_str(text.ljust(DESCRIPTION_WIDTH), refresh=True)

    def solved(self, case: str, method: str, level: int) -> None:
        key = (case, method, level)
        self.running.pop((case, method), None)
        if key in self.done or key not in self.weights:
            return
        self.done.add(key)
        self.count += self.weights[key]
        self.bar.update(self.weights[key])

    def restored(self, case: str, method: str, levels: int) -> None:
        """Levels 0..levels-1 of a chain come from its checkpoint: not work of this run."""
        for level in range(levels):
            key = (case, method, level)
            if key not in self.done and key in self.weights:
                self.done.add(key)
                self.total -= self.weights[key]
        self.bar.total = self.total
        self.bar.refresh()

    def close(self) -> None:
        self.bar.close()


class Scoped:
    """A study's view of a shared bar: its case names prefixed by ``scope`` (``"sweep "``), so
    that two studies of one case (the report's study and its sweep) keep their levels apart."""

    def __init__(self, progress: StudyProgress, scope: str):
        self.progress, self.scope = progress, scope

    def solving(self, case, *args) -> None:
        self.progress.solving(self.scope + case, *args)

    def solved(self, case, *args) -> None:
        self.progress.solved(self.scope + case, *args)

    def restored(self, case, *args) -> None:
        self.progress.restored(self.scope + case, *args)


def scoped(weights: dict, scope: str) -> dict:
    """``weights`` with their case names under ``scope`` (see ``Scoped``)."""
    return {(scope + case, method, level): w for (case, method, level), w in weights.items()}


class RelayedProgress:
    """What a study running in another process says to the client's ``StudyProgress``: each
    call, its case under the job's ``scope``, goes to ``_send`` (one per kind of worker)."""

    def __init__(self, scope: str = ""):
        self.scope = scope

    def _send(self, message: tuple) -> None:
        raise NotImplementedError

    def solving(self, case, *args) -> None:
        self._send(("solving", self.scope + case, *args))

    def solved(self, case, *args) -> None:
        self._send(("solved", self.scope + case, *args))

    def restored(self, case, *args) -> None:
        self._send(("restored", self.scope + case, *args))


class EventProgress(RelayedProgress):
    """On a Dask worker: each call becomes an event on ``topic`` (``relay`` replays it on the
    client)."""

    def __init__(self, topic: str, scope: str = ""):
        super().__init__(scope)
        self.topic = topic

    def _send(self, message: tuple) -> None:
        from distributed import get_worker
        get_worker().log_event(self.topic, message)


def relay(progress: StudyProgress):
    """A ``distributed.Client.subscribe_topic`` handler replaying ``EventProgress`` events on ``progress``."""
    def handler(event) -> None:
        _timestamp, message = event
        replay(progress, message)
    return handler


class QueueProgress(RelayedProgress):
    """In a local worker process (``processes.LocalProcesses``): each call goes on a queue the
    client drains (``replay``)."""

    def __init__(self, queue, scope: str = ""):
        super().__init__(scope)
        self.queue = queue

    def _send(self, message: tuple) -> None:
        self.queue.put(message)


def replay(progress: StudyProgress, message: tuple) -> None:
    """One ``RelayedProgress`` message on ``progress``."""
    name, *args = message
    getattr(progress, name)(*args)
