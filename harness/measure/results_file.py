"""Reading a results file for `rates`: a results.csv of this harness, or of harness 0.1 (a
`model` column and no theory in its rows, which the case files supply)."""
from __future__ import annotations

import sys
from pathlib import Path

import pandas as pd


def _known_cases(extra_specs) -> dict:
    from ..problem.case import load_case, registered_cases
    cases = registered_cases()
    for spec in extra_specs or []:
        case = load_case(spec)
        cases[case.name] = case
    return cases


# What `rates` needs of a results file: the errors, and each row's theory (written by the study
# since the method axis; older files, with a `model` column, get it from their case files).
RATE_INPUT = ["case", "method", "order", "level", "h", "err_h1", "expected_rate", "expected_log_exponent", "reference"]


def read_results(path: Path, extra_cases=None) -> pd.DataFrame:
    if not path.is_file():
        raise FileNotFoundError(f"results file not found: {path}")
    try:
        frame = pd.read_csv(path)
    except (pd.errors.ParserError, pd.errors.EmptyDataError, UnicodeDecodeError) as exc:
        raise ValueError(f"{path} is not a results CSV: {exc}") from exc
    if "model" in frame.columns and "method" not in frame.columns:
        frame = _from_model_column(frame, _known_cases(extra_cases), path)
    missing = [c for c in RATE_INPUT if c not in frame.columns]
    if missing:
        raise ValueError(f"{path} is not a results CSV: missing column(s) {', '.join(missing)}")
    if "mesh" not in frame.columns:         # before the mesh axis: every row on uniform meshes
        frame.insert(frame.columns.get_loc("method") + 1, "mesh", "uniform")
    return frame


def _from_model_column(frame: pd.DataFrame, cases: dict, path: Path) -> pd.DataFrame:
    """A results file of harness 0.1 (one `model` column, the P2 models only, no theory in the
    rows): read `model` as `method`, order 2, and the theory from the case files."""
    from ..methods import get_method
    unknown = sorted(set(frame.case) - set(cases))
    if unknown:
        raise ValueError(f"{path} has a `model` column (harness 0.1) and cases {', '.join(unknown)} that are not "
                         f"registered: pass their case files with --case")
    print(f"{path}: a `model` column (harness 0.1) read as `method`", file=sys.stderr)
    frame = frame.rename(columns={"model": "method"})
    frame.insert(frame.columns.get_loc("method") + 1, "order", 2)
    theory = {(c, m): get_method(m).expected(cases[c]) for c, m in frame[["case", "method"]].drop_duplicates().itertuples(index=False)}
    frame["expected_rate"] = [theory[k].rate for k in zip(frame.case, frame.method)]
    frame["expected_log_exponent"] = [theory[k].log_exponent for k in zip(frame.case, frame.method)]
    frame["reference"] = [theory[k].reference for k in zip(frame.case, frame.method)]
    return frame
