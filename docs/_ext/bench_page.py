"""The performance page's measured part: every benchmark table `python -m harness bench` wrote to
the results folder, each with the provenance and goals recorded beside it (``<name>.json``,
``harness.bench.common.write_bench``), so that no figure of the page is copied by hand."""
from __future__ import annotations

import hashlib
import json
from pathlib import Path

import pandas as pd
from tables import machine_stamp, markdown_table, wall_time

PLACEHOLDER = ("No benchmark tables were found when these pages were built: run `make bench` (or "
               "`python -m harness bench --only NAME` for one table), then `make docs`, and this page shows "
               "each table with the goals judged on it and what measured it.\n")

NOT_RECORDED = "provenance not recorded (written before `bench` recorded it beside its tables)"
NOT_MATCHING = "provenance not recorded for this CSV (the .json beside it is of another run of the table)"


def rounded(frame: pd.DataFrame) -> pd.DataFrame:
    """The floats of ``frame`` to 3 significant digits (as `bench` prints them); the rest as is."""
    shown = frame.astype(object)
    for column in frame.columns[[pd.api.types.is_float_dtype(t) for t in frame.dtypes]]:
        shown[column] = [None if pd.isna(v) else f"{v:.3g}" for v in frame[column]]
    return shown


def sidecar(csv: Path) -> tuple[dict | None, str]:
    """(the provenance beside ``csv``, or None; what to say where there is none or it is of
    another run of the table)."""
    path = csv.with_suffix(".json")
    if not path.is_file():
        return None, NOT_RECORDED
    meta = json.loads(path.read_text())
    if meta.get("csv_sha256") not in (None, hashlib.sha256(csv.read_bytes()).hexdigest()):
        return None, NOT_MATCHING
    return meta, ""


def table_section(csv: Path, title: str) -> list[str]:
    """A bench table's section: its title, the stamp of what measured it, its goals, the table."""
    meta, missing = sidecar(csv)
    heading = ((meta or {}).get("title") or title).rstrip(":")
    text = [f"### {heading}\n"]
    if meta is None:
        text.append(f"`{csv.name}`: {missing}.\n")
    else:
        load = meta.get("load_average")
        busy = f"; load average {load[0]:.2f} / {load[1]:.2f} / {load[2]:.2f} (1 / 5 / 15 min) when written" if load else ""
        text.append(f"`{csv.name}`, measured by {machine_stamp(meta)}; {wall_time(meta)}{busy}; "
                    f"`{meta.get('command') or '?'}`.\n")
        goals = meta.get("goals", [])
        if goals:
            text.append("\n".join(f"- {'met' if g['met'] else 'MISSED'}: {g['goal']}: {g['figure']}" for g in goals) + "\n")
    text.append(markdown_table(rounded(pd.read_csv(csv))))
    return text


def performance_page(results: Path) -> str:
    """Every bench table found in ``results`` (in the order of ``bench_names``), or what to run
    where there is none."""
    from harness.bench.command import bench_tables
    found = [(results / name, title) for _, name, title in bench_tables() if (results / name).is_file()]
    if not found:
        return PLACEHOLDER
    text = [f"Generated from the benchmark tables in `{results}` when these pages were built.\n"]
    for csv, title in found:
        text += table_section(csv, title)
    return "\n".join(text)
