"""Reading a results file of this harness: the one reader of results.csv, for `rates`
(``harness.rates`` and the command line) and for the study's merge of new rows into a folder's
file (``study.storage.merge.read_rows``)."""
from __future__ import annotations

from pathlib import Path

import pandas as pd

# What `rates` needs of a results file: the errors, and each row's theory (the study writes it
# into every row)
RATE_INPUT = ["case", "method", "order", "level", "h", "err_h1", "expected_rate", "expected_log_exponent", "reference"]


class NotResults(ValueError):
    """A file that is not a results CSV of this harness; ``reason``: why, in a few words."""

    def __init__(self, path: Path, reason: str):
        super().__init__(f"{path} is not a results CSV: {reason}")
        self.path, self.reason = path, reason


def read_results(path: Path, columns=RATE_INPUT) -> pd.DataFrame:
    """The rows of results file ``path``, with a ``mesh`` column (rows written without one are on
    uniform meshes); a one-line FileNotFoundError if it is missing, ``NotResults`` (a ValueError)
    if it is not a results CSV of this harness with ``columns``."""
    path = Path(path)
    if not path.is_file():
        raise FileNotFoundError(f"results file not found: {path}")
    try:
        frame = pd.read_csv(path)
    except (pd.errors.ParserError, pd.errors.EmptyDataError, UnicodeDecodeError) as exc:
        raise NotResults(path, str(exc)) from exc
    missing = [c for c in columns if c not in frame.columns]
    if missing:
        raise NotResults(path, f"missing column(s) {', '.join(missing)}")
    if "mesh" not in frame.columns:         # rows written without a mesh column are on uniform meshes
        frame.insert(frame.columns.get_loc("method") + 1, "mesh", "uniform")
    return frame
