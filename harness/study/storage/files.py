"""Writing results: atomically, so that an interrupted or failed run never leaves a
truncated file or destroys results already computed."""
from __future__ import annotations

import tempfile
from pathlib import Path

import pandas as pd

from ...core.files import TEMPORARY_MARK, write_atomic


class OutputError(OSError):
    """The output folder cannot be created or written."""


def ensure_writable(folder: Path) -> Path:
    """Create folder if needed and prove it writable before any long computation starts."""
    folder = Path(folder)
    try:
        folder.mkdir(parents=True, exist_ok=True)
        with tempfile.NamedTemporaryFile(dir=folder, prefix=f"{TEMPORARY_MARK}-write-test-"):
            pass
    except OSError as exc:
        raise OutputError(f"output folder {folder} is not writable: {exc.strerror or exc}") from exc
    return folder


def write_csv(frame: pd.DataFrame, path: Path) -> Path:
    return write_atomic(path, frame.to_csv(index=False, float_format="%.10g"))
