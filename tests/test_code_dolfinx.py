"""DOLFINx as an external code (examples/codes/dolfinx_contact.py, run in its own environment
.venv-dolfinx): on the harness's exported problems its nodal model (PETSc SNES VI) and its Nitsche
law (UFL) solve the harness's discrete problems, so ``external:DIR`` measures the errors of the
harness's own ``nodal`` and ``nitsche``. Skipped where the environment is not built
(``make .venv-dolfinx/.installed``)."""
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest

import harness

ROOT = Path(__file__).resolve().parents[1]
PYTHON = ROOT / ".venv-dolfinx" / "bin" / "python"
DRIVER = ROOT / "examples" / "codes" / "dolfinx_contact.py"
pytestmark = pytest.mark.skipif(not PYTHON.exists(), reason="no DOLFINx environment: build it with `make .venv-dolfinx/.installed`")
LEVELS = 3


@pytest.fixture(scope="module")
def exports(tmp_path_factory):
    """case -> its exported folder (made once per case)."""
    made = {}

    def folder(case: str) -> Path:
        if case not in made:
            made[case] = tmp_path_factory.mktemp("export") / case
            harness.export(case, levels=LEVELS, out=made[case])
        return made[case]
    return folder


def _dolfinx(export: Path, out: Path, *options: str) -> Path:
    done = subprocess.run([str(PYTHON), str(DRIVER), str(export), str(out), *options],
                          capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr[-2000:]
    assert len(done.stdout.splitlines()) == LEVELS        # one progress line per level
    return out


def _errors(case: str, methods: list[str]) -> dict:
    rows = harness.run(case, methods=methods, levels=LEVELS, show_progress=False)
    return {name: group.sort_values("level").err_h1.to_numpy() for name, group in rows.groupby("method")}


def _check_matches(case: str, like: str, solutions: Path, method: str) -> None:
    errors = _errors(case, [like, f"external:{solutions}"])
    assert len(errors[method]) == LEVELS
    np.testing.assert_allclose(errors[method], errors[like], rtol=1e-6, atol=0)


@pytest.mark.parametrize("case", ["transition-r32", "elastic-transition-r32"])
@pytest.mark.parametrize("model", ["nodal", "nitsche"])
def test_dolfinx_solves_the_harness_discrete_problem(exports, tmp_path, case, model):
    """err_h1 of DOLFINx's solution equals the harness's same method's on every level (1e-6 relative;
    measured: ~1e-13)."""
    out = _dolfinx(exports(case), tmp_path / "sol", "--model", model, "--options", "best")
    _check_matches(case, model, out, f"dolfinx-{model}")


@pytest.mark.slow
@pytest.mark.parametrize("case, model, options", [("corner-r12", "nitsche", "best"), ("corner-r12", "nodal", "default"),
                                                  ("elastic-transition-r32", "nitsche", "default")])
def test_dolfinx_matches_with_either_options_and_nonpolynomial_data(exports, tmp_path, case, model, options):
    """corner-r12's contact load jumps and is singular (Nitsche takes it at the harness's Gauss
    points); the Krylov options (CG + GAMG) reach the same solution as the direct ones."""
    out = _dolfinx(exports(case), tmp_path / "sol", "--model", model, "--options", options)
    _check_matches(case, model, out, f"dolfinx-{model}")


@pytest.mark.slow
@pytest.mark.parametrize("theta", [0, -1])
def test_dolfinx_nitsche_theta_variants_match_the_harness(exports, tmp_path, theta):
    out = _dolfinx(exports("transition-r32"), tmp_path / "sol", "--model", "nitsche", "--theta", str(theta))
    _check_matches("transition-r32", f"nitsche:theta={theta}", out, f"dolfinx-nitsche-theta{theta}")


def test_dolfinx_refuses_the_nodal_model_off_an_axis_normal(exports, tmp_path):
    """A bound per component needs Gamma_C's normal along an axis (the registered cases' Gamma_C are
    flat): an export whose contact normals are tilted is refused in one line."""
    export = tmp_path / "tilted"
    shutil.copytree(exports("elastic-transition-r32"), export)
    with np.load(export / "level-0.npz") as data:
        arrays = {key: data[key] for key in data.files}
    arrays["normal"][arrays["on_contact"]] = (0.6, -0.8)
    np.savez(export / "level-0.npz", **arrays)
    done = subprocess.run([str(PYTHON), str(DRIVER), str(export), str(tmp_path / "s"), "--model", "nodal", "--levels", "1"],
                          capture_output=True, text=True, timeout=300)
    assert done.returncode != 0 and "normal +-e_i" in done.stderr and len(done.stderr.strip().splitlines()) == 1


@pytest.mark.slow
@pytest.mark.parametrize("case", ["transition-r32", "corner-r12"])
def test_dolfinx_nodal_on_five_levels_meets_the_theorem_and_the_harness_on_every_level(tmp_path, case):
    """Issue 75's measure: five levels of DOLFINx's SNES VI solution, imported: the fitted H1 rate
    within 0.1 of the theorem's (Thm 4.1 ii: 3/2; 4.1 i: 1/2) and err_h1 within 1e-6 of `nodal`'s."""
    export = tmp_path / "export"
    harness.export(case, levels=5, out=export, formats=("npz",))
    done = subprocess.run([str(PYTHON), str(DRIVER), str(export), str(tmp_path / "sol"), "--model", "nodal"],
                          capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stderr[-2000:]
    rows = harness.run(case, methods=["nodal", f"external:{tmp_path / 'sol'}"], levels=5, show_progress=False)
    errors = {name: group.sort_values("level").err_h1.to_numpy() for name, group in rows.groupby("method")}
    np.testing.assert_allclose(errors["dolfinx-nodal"], errors["nodal"], rtol=1e-6, atol=0)
    rate = harness.rates(rows).set_index("method").loc["dolfinx-nodal"]
    assert abs(rate.fitted_rate - harness.load_case(case).expected_rate) <= 0.1
