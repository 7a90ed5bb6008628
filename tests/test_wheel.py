"""The package installs (issue 51): a wheel built from the repository, installed with --no-deps
into a fresh venv over this environment's dependencies, lists the registered cases (shipped as
``signorini_cases``) and runs studies from a folder outside the repository: a registered case,
and a case and a method given by path. A minute of building and installing: `make test-full`."""
import shutil
import subprocess
import sys
import sysconfig
from pathlib import Path

import pandas as pd
import pytest

ROOT = Path(__file__).resolve().parent.parent
pytestmark = pytest.mark.slow


def check(*command, cwd=None):
    done = subprocess.run([str(c) for c in command], capture_output=True, text=True, cwd=cwd)
    assert done.returncode == 0, done.stderr[-2000:]
    return done.stdout


def test_the_wheel_installs_and_runs_studies_outside_the_repository(tmp_path):
    check(sys.executable, "-m", "pip", "wheel", "--quiet", "--no-deps", "-w", tmp_path / "dist", ROOT)
    wheel, = (tmp_path / "dist").glob("signorini_p2_harness-*.whl")
    venv = tmp_path / "venv"
    check(sys.executable, "-m", "venv", venv)
    python = venv / "bin" / "python"
    purelib = Path(check(python, "-c", "import sysconfig; print(sysconfig.get_paths()['purelib'])").strip())
    # this environment's dependencies beneath the new venv's own packages (its .pth files, the
    # editable harness among them, are not read from there)
    (purelib / "test-environment.pth").write_text(sysconfig.get_paths()["purelib"] + "\n")
    check(python, "-m", "pip", "install", "--quiet", "--no-deps", wheel)
    work = tmp_path / "work"
    work.mkdir()
    assert check(python, "-c", "import harness, signorini_cases; print(harness.__file__, signorini_cases.__file__)",
                 cwd=work).count(str(purelib)) == 2
    listed = check(python, "-m", "harness", "cases", cwd=work)
    assert all(name in listed for name in ("transition-r32", "corner-r12", "two-body-junction", "transition-line-3d"))
    check(python, "-m", "harness", "run", "--case", "transition-r32", "--method", "nodal", "--levels", "2", "--out", "registered",
          "--quiet", cwd=work)
    shutil.copy(ROOT / "cases" / "corner_r12.py", work / "my_case.py")
    shutil.copy(ROOT / "examples" / "methods" / "nitsche_small_gamma.py", work / "my_method.py")
    check(python, "-m", "harness", "run", "--case", "my_case.py", "--method", "my_method.py", "--levels", "2", "--out", "mine",
          "--quiet", cwd=work)
    for folder, methods in (("registered", {"nodal"}), ("mine", {"nitsche-g002"})):
        rows = pd.read_csv(work / folder / "results.csv")
        assert set(rows.method) == methods and len(rows) == 2 and (rows.status == "converged").all()
