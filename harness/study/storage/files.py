"""Writing results: atomically, so that an interrupted or failed run never leaves a
truncated file or destroys results already computed."""
from __future__ import annotations

import os
import tempfile
from pathlib import Path

import pandas as pd

# in the name of every temporary file this harness writes: what a killed run may leave, and
# what the next owner of the folder deletes (``folder.remove_orphans``)
TEMPORARY_MARK = ".harness-tmp"


class OutputError(OSError):
    """The output folder cannot be created or written."""


def umask() -> int:
    """This process's umask (read from /proc where it can be, without changing it)."""
    try:
        for line in Path("/proc/self/status").read_text().splitlines():
            if line.startswith("Umask:"):
                return int(line.split()[1], 8)
    except (OSError, ValueError):
        pass
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


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


def write_atomic(path: Path, data: str | bytes) -> Path:
    """Write ``data`` to ``path`` so that a reader, or a run killed at any moment, sees the old
    file or the new one, never a part: a temporary file in the same folder, flushed to disk,
    then renamed over ``path`` (a rename is atomic within a file system). The file gets the mode
    the umask gives (``mkstemp`` alone makes it private)."""
    path = Path(path)
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}{TEMPORARY_MARK}-")
    try:
        os.fchmod(fd, 0o666 & ~umask())
        with os.fdopen(fd, "wb" if isinstance(data, bytes) else "w") as handle:
            handle.write(data)
            handle.flush()
            os.fsync(handle.fileno())
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
    return path


def write_csv(frame: pd.DataFrame, path: Path) -> Path:
    return write_atomic(path, frame.to_csv(index=False, float_format="%.10g"))
