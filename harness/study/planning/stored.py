"""The report's studies on other meshes than uniform (the mesh study, the degree study) keep one
file per (case, mesh strategy) in their store: its name (``store_name``) and the frames of a plan
read back (``read_stored``)."""
from __future__ import annotations

from pathlib import Path

import pandas as pd


def store_name(case, mesh) -> str:
    """The stem of ``case``'s files on ``mesh`` (a strategy's label, made a file name)."""
    return f"{case.name}-{mesh.label.replace(':', '_').replace('=', '')}"


def read_stored(store: Path, jobs) -> pd.DataFrame:
    """Every stored frame of ``jobs`` ((case, mesh, methods) of a plan) in ``store`` (empty if none)."""
    paths = [Path(store) / f"{store_name(case, mesh)}.csv" for case, mesh, _ in jobs]
    frames = [pd.read_csv(path) for path in paths if path.is_file()]
    return pd.concat(frames, ignore_index=True) if frames else pd.DataFrame()
