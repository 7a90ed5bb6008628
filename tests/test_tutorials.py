"""The tutorials of the documentation (docs/tutorials/*.py, executed by sphinx-gallery when
`make docs` builds the site) run as scripts, from a scratch folder. Slow tier, and left out of
.ci/run (`make test-full MARKERS='not tutorial and not scale'`), whose `make docs` executes them."""
import os
import subprocess
import sys
from pathlib import Path

import pytest

TUTORIALS = sorted((Path(__file__).resolve().parent.parent / "docs" / "tutorials").glob("plot_*.py"))
pytestmark = pytest.mark.slow


def test_there_is_a_tutorial_for_each_topic_the_docs_promise():
    assert [p.stem.split("_", 2)[2] for p in TUTORIALS] == [
        "first_study", "your_own_case", "your_own_method", "graded_and_adaptive", "paraview", "dask_and_resume",
        "beside_the_paper", "tresca", "other_codes", "coulomb"]


@pytest.mark.tutorial
@pytest.mark.parametrize("script", TUTORIALS, ids=lambda p: p.stem)
def test_the_tutorial_runs_as_a_script(script, tmp_path):
    done = subprocess.run([sys.executable, str(script)], cwd=tmp_path, capture_output=True, text=True,
                          env={**os.environ, "MPLBACKEND": "Agg"})
    assert done.returncode == 0, done.stderr[-2000:]
