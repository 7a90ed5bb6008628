"""scikit-fem, an external code in its own environment (examples/codes/skfem_contact.py), solves
the problem the harness exports: its P2 solution of transition-r32's nodal model, read back by
``external:DIR``, has the H^1 error of the harness's own ``nodal`` on every level (issue 75).

Skipped where the environment is not built (``make .venv-skfem/.installed``)."""
from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

REPOSITORY = Path(__file__).resolve().parents[1]
SKFEM_PYTHON = REPOSITORY / ".venv-skfem" / "bin" / "python"
DRIVER = REPOSITORY / "examples" / "codes" / "skfem_contact.py"
CASE = "transition-r32"
LEVELS = 3

pytestmark = pytest.mark.skipif(not SKFEM_PYTHON.exists(),
                                reason="no scikit-fem environment (.venv-skfem): build it with make .venv-skfem/.installed")


@pytest.fixture(scope="module")
def solved(tmp_path_factory) -> Path:
    """The export of CASE's first LEVELS levels and scikit-fem's solution of it (its folder)."""
    folder = tmp_path_factory.mktemp("skfem")
    export, solution = folder / "export", folder / "solution"
    harness_env = {**os.environ, "PYTHONPATH": str(REPOSITORY)}
    subprocess.run([sys.executable, "-m", "harness", "export", "--case", CASE, "--levels", str(LEVELS), "--out", str(export)],
                   check=True, cwd=REPOSITORY, env=harness_env, capture_output=True)
    # the driver is another program: no PYTHONPATH, so it could not import the harness if it tried
    code_env = {key: value for key, value in os.environ.items() if key != "PYTHONPATH"}
    subprocess.run([str(SKFEM_PYTHON), str(DRIVER), str(export), str(solution)], check=True, env=code_env,
                   capture_output=True)
    return solution


def test_the_driver_solves_every_level_to_the_kkt_tolerance_and_agrees_with_bvls(solved):
    manifest = json.loads((solved / "manifest.json").read_text())
    assert (manifest["format"], manifest["method"], manifest["like"]) == ("signorini-harness-solution", "skfem-nodal", "nodal")
    assert manifest["options"]["coarsest_level_vs_bvls"] <= 1e-6
    for level in range(LEVELS):
        data = np.load(solved / f"level-{level}.npz")
        assert data["residual"] <= 1e-10 and data["iterations"] >= 1 and data["seconds"] > 0
        assert np.isfinite(data["values"]).all() and data["points"].shape[0] == data["values"].shape[0]


@pytest.fixture(scope="module")
def rows(solved) -> dict:
    """The study's rows of CASE by (imported?, level): the harness's nodal and scikit-fem's."""
    import harness
    frame = harness.run(CASE, methods=["nodal", f"external:{solved}"], levels=LEVELS, show_progress=False)
    return {(row.method != "nodal", int(row.level)): row for row in frame.itertuples()}


@pytest.mark.parametrize("level", range(LEVELS))
def test_the_scikit_fem_h1_error_is_the_harness_nodal_one(rows, level):
    skfem, nodal = rows[True, level], rows[False, level]
    assert skfem.method == "skfem-nodal" and skfem.ndof == nodal.ndof
    assert abs(skfem.err_h1 - nodal.err_h1) <= 1e-6 * nodal.err_h1
