"""Durable level chains: after every finished level, each (case, method) chain's state
(``study.chain.walk.ChainState``) is written atomically to its own file, so that a study killed at any
moment -- the process, or a Dask worker mid-job -- continues from the last finished level.

A checkpoint is valid only for the code, the case file and the settings that wrote it (a
digest of all of them is stored in it); any other is ignored and overwritten. The files are
pickles written by this harness for itself: never load a checkpoint from a source you do not
trust.
"""
from __future__ import annotations

import hashlib
import pickle
import re
import shutil
from pathlib import Path

from .digest import code_hash
from .files import write_atomic


def chain_key(case, method, levels: int, hook=None, mesh: str = "uniform") -> str:
    """What a (case, method) chain's results depend on: the computing code and NGSolve's version
    (``digest.code_hash``), the case file and its reference setting, the method (and the file of
    one from outside the package) and its parameters, the number of levels, the hook, the mesh
    strategy."""
    digest = code_hash()
    digest.update(Path(case.source).read_bytes())
    if method.source:               # a method from outside the package: its file too
        digest.update(Path(method.source).read_bytes())
    settings = (case.name, case.reference_levels, method.name, method.parameter_text, levels, type(hook).__qualname__)
    digest.update(repr(settings if mesh == "uniform" else (*settings, mesh)).encode())
    return digest.hexdigest()


class CheckpointStore:
    """Checkpoints of the chains of one study, one file per (case, method) under ``folder``
    (per (case, mesh, method) for meshes other than uniform)."""

    def __init__(self, folder: Path, levels: int, hook=None, mesh: str = "uniform"):
        self.folder, self.levels, self.hook, self.mesh = Path(folder), levels, hook, mesh

    def path(self, case, method) -> Path:
        folder = self.folder / case.name
        if self.mesh != "uniform":
            folder = folder / _safe(self.mesh)
        return folder / f"{_safe(method.name)}-{hashlib.sha1(method.name.encode()).hexdigest()[:8]}.ckpt"

    def load(self, case, method):
        """The chain's saved ``ChainState``, or None (none saved, or saved by other code or
        settings, or unreadable)."""
        path = self.path(case, method)
        try:
            key, state = pickle.loads(path.read_bytes())
        except (OSError, EOFError, pickle.UnpicklingError, ValueError, TypeError, AttributeError, ImportError):
            return None
        return state if key == chain_key(case, method, self.levels, self.hook, self.mesh) else None

    def save(self, case, method, state) -> None:
        path = self.path(case, method)
        path.parent.mkdir(parents=True, exist_ok=True)
        write_atomic(path, pickle.dumps((chain_key(case, method, self.levels, self.hook, self.mesh), state),
                                        protocol=pickle.HIGHEST_PROTOCOL))

    def forget(self, case=None, every_mesh: bool = False) -> None:
        """Delete the checkpoints of ``case`` on this store's mesh strategy (on every strategy:
        ``every_mesh``; of every case: ``case`` None): their results are written elsewhere. Only
        this strategy's: the report stores a case's uniform study while the same case's graded and
        adaptive chains may still be writing theirs, in other workers, under the case's folder."""
        if case is None:
            shutil.rmtree(self.folder, ignore_errors=True)
            return
        folder = self.folder / case.name
        if every_mesh or self.mesh != "uniform":
            shutil.rmtree(folder if every_mesh else folder / _safe(self.mesh), ignore_errors=True)
        elif folder.is_dir():
            for path in folder.iterdir():
                if path.is_file():              # the uniform chains' files (and their temporaries)
                    path.unlink(missing_ok=True)
        try:
            folder.rmdir()                      # once no strategy's checkpoints are left in it
        except OSError:
            pass


def _safe(name: str) -> str:
    """``name`` as a file name (method names may carry parameters: nitsche:gamma0=0.1,theta=-1)."""
    return re.sub(r"[^A-Za-z0-9_.-]", "_", name)
