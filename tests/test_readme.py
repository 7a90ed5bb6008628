"""README.md's code blocks run as written (issue 52): the Python block is executed, every
`python -m harness` line of the shell blocks is run (from a scratch folder, so that its
`results/` lands there), and every `make` target a block names exists (CI runs `make test`,
`make docs` and the suite; `make report` is the report's own test tier). Only `git clone`,
which needs the repository's address, is not run."""
import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
BLOCK = re.compile(r"```(\w+)\n(.*?)```", re.S)


def blocks(language: str) -> list[str]:
    return [body for lang, body in BLOCK.findall((ROOT / "README.md").read_text()) if lang == language]


def shell_lines() -> list[str]:
    return [line.split("#")[0].strip() for body in blocks("bash") for line in body.splitlines() if line.split("#")[0].strip()]


def test_the_readme_has_a_python_block_and_shell_blocks_and_stays_short():
    assert blocks("python") and blocks("bash")
    assert len((ROOT / "README.md").read_text().splitlines()) <= 120


def test_every_python_block_of_the_readme_runs(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    for body in blocks("python"):
        exec(compile(body, "README.md", "exec"), {})


def test_every_harness_command_of_the_readme_runs_in_order(tmp_path):
    for line in shell_lines():
        if " -m harness " in line:
            args = line.split(" -m harness ", 1)[1].split()
            done = subprocess.run([sys.executable, "-m", "harness", *args, *(["--quiet"] if args[0] == "run" else [])],
                                  cwd=tmp_path, capture_output=True, text=True)
            assert done.returncode == 0, (line, done.stderr)


@pytest.mark.parametrize("line", [line for line in shell_lines() if line.startswith("make ")])
def test_every_make_target_of_the_readme_exists(line):
    done = subprocess.run(["make", "-n", *line.split()[1:]], cwd=ROOT, capture_output=True, text=True)
    assert done.returncode == 0, done.stderr


def test_the_only_other_shell_line_is_the_clone():
    others = [line for line in shell_lines() if " -m harness " not in line and not line.startswith("make ")]
    assert [line.split()[:2] for line in others] == [["git", "clone"]]


def test_the_figure_caption_names_a_release_and_make_readme_figure_writes_the_reports_version(tmp_path):
    """The caption's version is a release of the CHANGELOG, written by ``make readme-figure``
    (docs/_ext/readme_figure.py) from the report's provenance.json, not typed by hand."""
    import json
    sys.path.insert(0, str(ROOT / "docs" / "_ext"))
    try:
        from readme_figure import CAPTION, update
    finally:
        sys.path.remove(str(ROOT / "docs" / "_ext"))
    readme = (ROOT / "README.md").read_text()
    version = CAPTION.search(readme).group(0).split()[3].rstrip(",")
    assert f"## {version} " in (ROOT / "CHANGELOG.md").read_text()
    (tmp_path / "results").mkdir()
    (tmp_path / "report" / "figures").mkdir(parents=True)
    (tmp_path / "docs" / "_static").mkdir(parents=True)
    (tmp_path / "report" / "figures" / "verdict_matrix.png").write_bytes(b"png")
    (tmp_path / "README.md").write_text(readme)
    meta = {"harness_version": "9.9.9", "git_commit": "abc", "settings": {"profile": "default"}}
    (tmp_path / "results" / "provenance.json").write_text(json.dumps(meta))
    assert update(tmp_path / "results", tmp_path / "report", tmp_path / "README.md") == "9.9.9"
    assert "computed by harness 9.9.9, default profile" in (tmp_path / "README.md").read_text()
    assert (tmp_path / "docs" / "_static" / "verdict_matrix.png").read_bytes() == b"png"
    (tmp_path / "results" / "provenance.json").write_text(json.dumps(meta | {"settings": {"profile": "fine"}}))
    with pytest.raises(SystemExit, match="fine report"):
        update(tmp_path / "results", tmp_path / "report", tmp_path / "README.md")
