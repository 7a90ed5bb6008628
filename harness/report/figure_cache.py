"""Figures kept from the last report while what they are drawn from is unchanged.

A figure is a function of its inputs (a case's stored rows and snapshots, a frame of rows, the
methods' styles) and of the drawing code; when a report is written again over a stored study
(``study.planning.cache``: every case reused), drawing its figures again would be most of its time.
Each job of ``figure_jobs.FigurePool`` therefore leaves a key beside its figures: the
SHA-256 of the drawing function's name, its arguments (files by their bytes, frames by their
values), the styles, and the code of the report (``study.storage.digest.code_hash``: its syntax, so
that an edited comment draws nothing again) with the harness's, NGSolve's and Matplotlib's versions. A job whose key is stored, with every figure it names on disk, is not
drawn again.
"""
from __future__ import annotations

import json
from pathlib import Path

import matplotlib
import pandas as pd

from ..study.storage.digest import code_hash
from ..study.storage.files import write_atomic

KEYS = ".keys"           # the folder of keys, inside the figures' folder
DRAWING_CODE = ("report",)        # what draws a figure: the report package


def _feed(digest, value) -> None:
    """Hash ``value``: a frame by its values, an existing file by its bytes, the rest by repr."""
    if isinstance(value, pd.DataFrame):
        digest.update(pd.util.hash_pandas_object(value, index=True).values.tobytes())
        digest.update(repr(list(value.columns)).encode())
    elif isinstance(value, str) and value not in ("", "-") and Path(value).is_file():
        digest.update(Path(value).read_bytes())
    elif isinstance(value, str) and Path(value).is_dir():
        digest.update(b"folder")                  # the store: its case files are hashed by name below
    else:
        digest.update(repr(value).encode())


def job_key(draw, styles: dict, args: tuple, inputs: tuple = ()) -> str:
    """The key of one figure job: ``draw(styles, *args)``, reading also the files ``inputs``."""
    digest = code_hash(DRAWING_CODE, harness_version=True, versions=(f"matplotlib {matplotlib.__version__}",))
    digest.update(draw.__name__.encode())
    digest.update(json.dumps(styles, sort_keys=True, default=repr).encode())
    for value in (*args, *map(str, inputs)):
        _feed(digest, value)
    return digest.hexdigest()


def _encode(value):
    if isinstance(value, Path):
        return {"path": str(value)}
    if isinstance(value, dict):
        return {"dict": {k: _encode(v) for k, v in value.items()}}
    return {"value": value}


def _decode(value):
    if "path" in value:
        return Path(value["path"])
    if "dict" in value:
        return {k: _decode(v) for k, v in value["dict"].items()}
    return value["value"]


def _paths(value) -> list[Path]:
    if isinstance(value, Path):
        return [value]
    if isinstance(value, dict):
        return [p for v in value.values() for p in _paths(v)]
    return []


def stored(folder: Path, name: str, key: str):
    """The figures the job ``name`` drew with ``key``, if its key is stored and they all exist; else None."""
    path = Path(folder) / KEYS / f"{name}.json"
    try:
        entry = json.loads(path.read_text())
    except (OSError, ValueError):
        return None
    if entry.get("key") != key:
        return None
    result = _decode(entry["result"])
    return result if all(p.is_file() for p in _paths(result)) else None


def store(folder: Path, name: str, key: str, result) -> None:
    """Keep ``result`` (the job's figures by name) under ``key`` (after they are written)."""
    keys = Path(folder) / KEYS
    keys.mkdir(parents=True, exist_ok=True)
    write_atomic(keys / f"{name}.json", json.dumps({"key": key, "result": _encode(result)}).encode())
