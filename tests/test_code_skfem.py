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


def external_available(folder: Path) -> bool:
    """Whether this harness reads solution folders as a method (``external:DIR``)."""
    from harness.methods import methods_named
    try:
        methods_named([f"external:{folder}"])
    except ValueError as error:      # only "unknown method" means absent; a refused folder is a failure
        if "unknown method 'external'" in str(error):
            return False
        raise
    return True


def h1_distances(solved: Path) -> dict:
    """Per level, (||u_skfem - u_nodal||_H1, the harness's err_h1 of nodal): the imported values
    made the harness's P2 function (``fem.lagrange.LagrangeNodes``) beside its own nodal solve.
    |err_h1(skfem) - err_h1(nodal)| <= ||u_skfem - u_nodal||_H1 (the triangle inequality)."""
    import ngsolve as ngs

    import harness
    from harness.fem.lagrange import LagrangeNodes
    distance = {}

    def measure(case, method, level, problem, solve):
        nodes = LagrangeNodes.of(problem.fes)
        data = np.load(solved / f"level-{level}.npz")
        node = nodes.match(data["points"], 1e-9 * np.ptp(nodes.points, axis=0).max())
        values = np.empty((nodes.count, 1))
        values[node] = data["values"]
        gf = ngs.GridFunction(problem.fes)
        gf.vec.FV().NumPy()[:] = nodes.coefficients(values - nodes.values(problem.cartesian(solve.u), 1))
        # P2: the integrand is a polynomial of degree 4, integrated exactly
        distance[level] = np.sqrt(ngs.Integrate(ngs.InnerProduct(ngs.grad(gf), ngs.grad(gf)) + gf * gf, problem.mesh, order=4))

    frame = harness.run(CASE, methods=["nodal"], levels=LEVELS, on_level=measure, show_progress=False)
    return {int(row.level): (distance[int(row.level)], row.err_h1) for row in frame.itertuples()}


@pytest.fixture(scope="module")
def errors(solved) -> dict:
    """Per level, (scikit-fem's err_h1 or a bound of its distance to nodal's, nodal's err_h1):
    through ``external:DIR`` where the harness has it, else the H^1 distance of the solutions."""
    if not external_available(solved):
        return {level: (nodal + distance, nodal) for level, (distance, nodal) in h1_distances(solved).items()}
    import harness
    frame = harness.run(CASE, methods=["nodal", f"external:{solved}"], levels=LEVELS, show_progress=False)
    err = {(row.method == "nodal", int(row.level)): row.err_h1 for row in frame.itertuples()}
    return {level: (err[False, level], err[True, level]) for level in range(LEVELS)}


@pytest.mark.parametrize("level", range(LEVELS))
def test_the_scikit_fem_h1_error_is_the_harness_nodal_one(errors, level):
    skfem_error, nodal_error = errors[level]
    assert abs(skfem_error - nodal_error) <= 1e-6 * nodal_error
