"""Reading a results file of this harness for `rates` (``harness.rates`` and the command line)."""
from __future__ import annotations

from pathlib import Path

import pandas as pd

# What `rates` needs of a results file: the errors, and each row's theory (the study writes it
# into every row)
RATE_INPUT = ["case", "method", "order", "level", "h", "err_h1", "expected_rate", "expected_log_exponent", "reference"]


def read_results(path: Path) -> pd.DataFrame:
    """The rows of results file ``path``; a one-line FileNotFoundError or ValueError if it is
    missing or not a results CSV of this harness."""
    if not path.is_file():
        raise FileNotFoundError(f"results file not found: {path}")
    try:
        frame = pd.read_csv(path)
    except (pd.errors.ParserError, pd.errors.EmptyDataError, UnicodeDecodeError) as exc:
        raise ValueError(f"{path} is not a results CSV: {exc}") from exc
    missing = [c for c in RATE_INPUT if c not in frame.columns]
    if missing:
        raise ValueError(f"{path} is not a results CSV: missing column(s) {', '.join(missing)}")
    if "mesh" not in frame.columns:         # rows written without a mesh column are on uniform meshes
        frame.insert(frame.columns.get_loc("method") + 1, "mesh", "uniform")
    return frame
