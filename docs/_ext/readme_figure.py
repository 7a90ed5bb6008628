"""The README's figure: the verdict matrix of the last default report, copied to
docs/_static/verdict_matrix.png, its caption naming the harness version that computed the
report (``results/provenance.json``, written by every report). ``make readme-figure`` runs it
after ``make report``; nothing in the caption's version is typed by hand."""
from __future__ import annotations

import json
import re
import shutil
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
FIGURE = Path("docs/_static/verdict_matrix.png")
# the caption's words the version sits in, e.g. "computed by harness 0.10.3, default profile"
CAPTION = re.compile(r"computed by harness [0-9][0-9A-Za-z.+-]*, ([a-z]+) profile")


def update(results: Path = ROOT / "results", report: Path = ROOT / "report", readme: Path = ROOT / "README.md") -> str:
    """Copy the report's verdict matrix beside the README and write its version into the
    caption; the version. Refused (SystemExit) for a report of another profile than the caption's."""
    meta = json.loads((results / "provenance.json").read_text())
    text = readme.read_text()
    match = CAPTION.search(text)
    if match is None:
        raise SystemExit(f"{readme}: no caption 'computed by harness X.Y.Z, PROFILE profile' to update")
    profile = meta["settings"]["profile"]
    if profile != match.group(1):
        raise SystemExit(f"{results / 'provenance.json'} is a {profile} report; the README shows the {match.group(1)} one")
    version = meta["harness_version"] + ("+dirty" if meta.get("git_commit", "").endswith("+dirty") else "")
    shutil.copyfile(report / "figures" / "verdict_matrix.png", readme.parent / FIGURE)
    readme.write_text(CAPTION.sub(f"computed by harness {version}, {profile} profile", text, count=1))
    return version


if __name__ == "__main__":
    print(f"README.md: the verdict matrix of harness {update(*map(Path, sys.argv[1:]))}")
