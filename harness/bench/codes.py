"""The other-codes rows of `bench` (`bench --only codes`, issue 75): the harness's contact solve
against DOLFINx + PETSc (examples/codes/dolfinx_contact.py, in its own environment
``.venv-dolfinx``) on the same exported problem (``study.export``): transition-r32 at
CODES_LEVEL, one thread each, the nodal model (PETSc SNES VI against the harness's active set
method) and Nitsche (SNES newtonls against the harness's semismooth Newton), each DOLFINx run
with PETSc's linear-solver options as users write them ("default") and the best found ("best":
the driver's docstring says which). The ratio is DOLFINx's seconds over the harness's, each its
own solve of the finest level (assembly included; ). The two solutions are
compared at the nodes: the same discrete problem, so they agree to the solvers' tolerance."""
from __future__ import annotations

import json
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pandas as pd

CODES_CASE = "transition-r32"
CODES_LEVEL = 7                 # P2: 2.3e6 dofs
DRIVER = Path(__file__).resolve().parents[2] / "examples" / "codes" / "dolfinx_contact.py"
ENVIRONMENT = Path(__file__).resolve().parents[2] / ".venv-dolfinx" / "bin" / "python"
OPTIONS = ("default", "best")
CODES_COLUMNS = ["case", "model", "options", "ndof", "t_dolfinx", "t_harness", "ratio", "t_harness_total", "ratio_total",
                 "snes_iterations",
                 "ksp_iterations", "harness_iterations", "max_value_difference", "dolfinx_residual", "harness_residual"]


def run_codes_bench(level: int = CODES_LEVEL, folder: Path = Path("results/bench_codes"), progress=None) -> pd.DataFrame:
    """Export ``level`` of CODES_CASE, solve it by the harness and by DOLFINx (each model of
    ``methods.external.DRIVER_MODELS``, each of OPTIONS), one row per DOLFINx run."""
    if not ENVIRONMENT.exists():
        raise FileNotFoundError(f"bench --only codes runs DOLFINx from {ENVIRONMENT.parent.parent}: make .venv-dolfinx/.installed first")
    from ..methods.external import DRIVER_MODELS
    from ..problem.case import load_case
    progress = progress or (lambda line: print(line, flush=True))
    from ..study.export import export
    shutil.rmtree(folder, ignore_errors=True)
    export(load_case(CODES_CASE), level + 1, folder / "export", formats=("npz",))
    rows = []
    for model in DRIVER_MODELS:
        own = _harness_solution(model, level, folder / f"harness-{model}")
        for options in OPTIONS:
            progress(f"codes: DOLFINx {model} ({options} options) at level {level}")
            theirs = _dolfinx_solution(model, options, level, folder / f"dolfinx-{model}-{options}")
            rows.append(_row(model, options, own, theirs))
    return pd.DataFrame(rows, columns=CODES_COLUMNS)


def _harness_solution(model: str, level: int, folder: Path) -> dict:
    """The harness's solve of ``model`` on levels 0..level, one thread, its finest level written
    as point values (``study.export.solution_writer``)."""
    from ..methods import methods_named
    from ..problem.case import load_case
    from ..study import InProcess, run_study
    from ..study.export import solution_writer
    rows = run_study([load_case(CODES_CASE)], methods_named([model]), level + 1, show_progress=False,
                     engine=InProcess(threads=1), on_level=solution_writer(folder, CODES_CASE, model))
    found = _finest(folder)
    found["total_seconds"] = float(rows.sort_values("level").total_seconds.iloc[-1])
    return found


def _dolfinx_solution(model: str, options: str, level: int, folder: Path) -> dict:
    """DOLFINx's solve of the export's levels 0..level (the driver, one thread)."""
    command = [str(ENVIRONMENT), str(DRIVER), str(folder.parent / "export"), str(folder), "--model", model,
               "--options", options, "--levels", str(level + 1), "--threads", "1"]
    done = subprocess.run(command, capture_output=True, text=True)
    if done.returncode:
        raise RuntimeError(f"the DOLFINx driver failed ({' '.join(command)}): {done.stderr.strip().splitlines()[-1:]}")
    return _finest(folder)


def _finest(folder: Path) -> dict:
    files = sorted(folder.glob("level-*.npz"), key=lambda p: int(p.stem.split("-")[1]))
    with np.load(files[-1]) as data:
        found = {key: data[key] for key in data.files}
    found["manifest"] = json.loads((folder / "manifest.json").read_text())
    return found


def _row(model: str, options: str, own: dict, theirs: dict) -> dict:
    """One row: the seconds and their ratio, the iterations, and the largest difference of the
    two solutions at the nodes (matched by position) relative to the largest value."""
    from scipy.spatial import cKDTree
    _, at = cKDTree(own["points"]).query(theirs["points"])
    values = own["values"].reshape(len(own["values"]), -1)
    difference = np.abs(values[at] - theirs["values"].reshape(len(at), -1)).max() / np.abs(values).max()
    return {"case": CODES_CASE, "model": model, "options": options, "ndof": int(values.size),
            "t_dolfinx": float(theirs["seconds"]), "t_harness": float(own["seconds"]),
            "ratio": float(theirs["seconds"]) / float(own["seconds"]), "t_harness_total": own["total_seconds"],
            "ratio_total": float(theirs["seconds"]) / own["total_seconds"], "snes_iterations": int(theirs["iterations"]),
            "ksp_iterations": int(theirs.get("linear_iterations", -1)), "harness_iterations": int(own["iterations"]),
            "max_value_difference": float(difference), "dolfinx_residual": float(theirs.get("residual", np.nan)),
            "harness_residual": float(own["residual"])}


def codes_goals(frame: pd.DataFrame) -> list[tuple[str, bool, str]]:
    """What the table shows (issue 75): DOLFINx's time over the harness's per model at >= 1e6
    dofs, both options; the two solutions the same to 1e-6 of the largest value."""
    shown = "; ".join(f"{r.model} ({r.options}) {r.ratio:.1f}x: DOLFINx {r.t_dolfinx:.3g} s ({r.snes_iterations} SNES, "
                      f"{r.ksp_iterations} KSP) against {r.t_harness:.3g} s ({r.ratio_total:.1f}x the harness's whole level, "
                      f"{r.t_harness_total:.3g} s) at {r.ndof:.2g} dofs" for r in frame.itertuples())
    return [("codes DOLFINx/PETSc seconds over the harness's, one thread each, >= 1e6 dofs (shown)",
             bool((frame.ndof >= 1e6).all()), shown),
            ("codes the same discrete solution (nodes, relative max difference <= 1e-6)",
             bool((frame.max_value_difference <= 1e-6).all()), f"max {frame.max_value_difference.max():.1e}")]
