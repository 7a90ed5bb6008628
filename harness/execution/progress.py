"""One progress bar for a whole study, however many processes run it.

The bar's length is the estimated time of every solve of the study (``budget.solve_weights``:
a fixed cost per solve plus a cost per dof), so its ETA weighs the levels by their size: the
finest level of a chain is most of its time, and a rate per solve badly misjudges it. Levels a
resumed study restores from its checkpoints leave the bar (its length shrinks), so the rate and
the ETA count only work done now. Workers report through Dask's event log (``EventProgress``).
"""
from __future__ import annotations

from tqdm import tqdm

BAR_FORMAT = "{percentage:3.0f}%|{bar}| [{elapsed}<{remaining}]{postfix}"


class StudyProgress:
    """The bar: ``solving``/``solved``/``restored`` come from the study (``study.run_chain``),
    in this process or relayed from workers; a level counts once, even if a job is rerun."""

    def __init__(self, weights: dict, show: bool = True):
        # in whole milliseconds: the bar's count and length stay exact integers, however many
        # levels are added and restored
        self.weights = {key: max(1, round(1000 * seconds)) for key, seconds in weights.items()}
        self.done: set = set()
        self.running: dict = {}
        self.total, self.count = sum(self.weights.values()), 0      # what the bar shows (also when hidden)
        self.bar = tqdm(total=self.total, disable=not show, bar_format=BAR_FORMAT, dynamic_ncols=True)

    def solving(self, case: str, method: str, level: int, ndof: int, stage: str = "") -> None:
        self.running[(case, method)] = f"{case} {method} level {level}{' ' + stage if stage else ''} ({ndof} dofs)"
        self.bar.set_postfix_str("; ".join(self.running.values()), refresh=True)

    def solved(self, case: str, method: str, level: int) -> None:
        key = (case, method, level)
        if key in self.done or key not in self.weights:
            return
        self.done.add(key)
        self.count += self.weights[key]
        self.running.pop((case, method), None)
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


class EventProgress:
    """What a study running on a Dask worker says to the client's ``StudyProgress``: each call
    becomes an event on ``topic`` (``relay`` replays it on the client)."""

    def __init__(self, topic: str):
        self.topic = topic

    def _send(self, *message) -> None:
        from distributed import get_worker
        get_worker().log_event(self.topic, message)

    def solving(self, *args) -> None:
        self._send("solving", *args)

    def solved(self, *args) -> None:
        self._send("solved", *args)

    def restored(self, *args) -> None:
        self._send("restored", *args)


def relay(progress: StudyProgress):
    """A ``Client.subscribe_topic`` handler replaying ``EventProgress`` events on ``progress``."""
    calls = {"solving": progress.solving, "solved": progress.solved, "restored": progress.restored}

    def handler(event) -> None:
        _timestamp, (name, *args) = event
        calls[name](*args)
    return handler
