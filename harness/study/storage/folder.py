"""A results folder that several people and processes share: one run owns it at a time
(``owned``), and what a run killed at any moment left behind is cleared by the next owner.

Ownership is an advisory lock (``flock``) on ``FOLDER/.harness.lock``, held while the command
runs: the kernel drops it when the process ends however it ends (SIGKILL, out of memory), so a
lock is never stale. A second command on the same folder is refused before it computes
anything, in one line naming the owner (its command line, process id, host and start) --
refused rather than made to wait: a study lasts minutes to hours, and a user who started a
second one into the same folder by mistake wants to know now, not after the first. (An NFS
mount without lock support refuses ``flock``: ``owned`` says so and names the folder.)

What a killed run leaves: its checkpoints (``.checkpoints``, which the same command resumes
from) and possibly temporary files of an atomic write that never completed
(``files.TEMPORARY_MARK``) and the lock file. The next owner deletes the temporary files on
taking the folder, and every owner deletes the lock file when it ends.
"""
from __future__ import annotations

import datetime
import errno
import json
import os
import platform
import sys
from contextlib import contextmanager
from pathlib import Path

from .files import TEMPORARY_MARK, OutputError, ensure_writable

LOCK_NAME = ".harness.lock"
# folders under an output folder never searched for orphans (a user's --out . in a repository)
SKIPPED = {".git", ".venv", "venv", "node_modules", "__pycache__"}


class FolderBusy(OutputError):
    """Another harness command owns the output folder."""


def command_line() -> str:
    """This process's command, as a user would type it."""
    argv = [Path(sys.argv[0]).name if sys.argv and sys.argv[0] else "python", *sys.argv[1:]]
    if argv[0] == "__main__.py":
        argv[0] = "python -m harness"
    return " ".join(argv)


def _owner_words(info: dict) -> str:
    started = info.get("started", "?")
    return f"`{info.get('command', 'another harness command')}` (pid {info.get('pid', '?')} on {info.get('host', '?')}, since {started})"


def _read_owner(path: Path) -> dict:
    try:
        return json.loads(path.read_text() or "{}")
    except (OSError, ValueError):
        return {}


def _lock(path: Path) -> int:
    """The descriptor of ``path``, locked by this process; FolderBusy if another holds it. The
    file is made with the mode the umask gives."""
    import fcntl
    while True:
        fd = os.open(path, os.O_RDWR | os.O_CREAT, 0o666)
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError as exc:
            os.close(fd)
            if exc.errno in (errno.EWOULDBLOCK, errno.EAGAIN, errno.EACCES):
                raise FolderBusy(f"{path.parent} is in use by {_owner_words(_read_owner(path))}: wait for it to end "
                                 f"or choose another output folder") from None
            raise OutputError(f"cannot lock {path.parent} ({exc.strerror}): its file system has no locks") from exc
        try:
            same = os.fstat(fd).st_ino == os.stat(path).st_ino
        except FileNotFoundError:
            same = False
        if same:
            return fd
        # the owner before us deleted the file between our open and our lock: try the new one
        os.close(fd)


def remove_orphans(folder: Path) -> list[Path]:
    """Delete the temporary files of atomic writes that never completed (a run killed in the
    middle of one) under ``folder``; only the owner of the folder may call this."""
    removed = []
    for root, dirs, files in os.walk(folder):
        dirs[:] = [d for d in dirs if d not in SKIPPED]
        for name in files:
            if TEMPORARY_MARK in name:
                path = Path(root) / name
                path.unlink(missing_ok=True)
                removed.append(path)
    return removed


@contextmanager
def owned(folder: Path, command: str | None = None):
    """``folder`` (made if needed, proven writable) owned by this process while the context
    lasts; FolderBusy, before anything in it is touched, if another harness command owns it."""
    folder = ensure_writable(Path(folder))
    path = folder / LOCK_NAME
    fd = _lock(path)
    try:
        info = {"command": command or command_line(), "pid": os.getpid(), "host": platform.node(),
                "started": datetime.datetime.now().astimezone().isoformat(timespec="seconds")}
        os.ftruncate(fd, 0)
        os.write(fd, json.dumps(info).encode())
        remove_orphans(folder)
        yield folder
    finally:
        # deleted while still locked: a process that opened it meanwhile sees a deleted file
        # (``_lock`` then opens the path again)
        path.unlink(missing_ok=True)
        os.close(fd)


@contextmanager
def all_owned(folders, command: str | None = None):
    """Each of ``folders`` owned (``owned``), in a fixed order (no two commands wait on each
    other's); the same folder named twice is owned once."""
    unique = sorted({Path(f).resolve() for f in folders})
    if not unique:
        yield
        return
    with owned(unique[0], command), all_owned(unique[1:], command):
        yield
