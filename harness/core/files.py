"""Files written atomically: an interrupted or failed run never leaves a truncated file or
destroys one written before."""
from __future__ import annotations

import os
import tempfile
from pathlib import Path

# in the name of every temporary file this harness writes: what a killed run may leave, and
# what the next owner of a results folder deletes
TEMPORARY_MARK = ".harness-tmp"


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
