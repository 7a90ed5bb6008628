"""The benchmark tables' provenance (a .json beside each CSV `bench` writes) and the docs'
performance page generated from them (docs/_ext/bench_page.py)."""
import argparse
import json
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from harness.bench import command
from harness.bench.common import write_bench
from harness.study.planning.cache import provenance

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "docs" / "_ext"))

from bench_page import performance_page  # noqa: E402

TITLE = "elasticity (Remark 2.3): contact solve against one linear elastic solve, same matrix:"
GOALS = [("elastic 2D KKT residual <= 1e-10 at every size", np.True_, "max 3.1e-12"),
         ("elastic 2D contact solve <= 1.5x one linear solve at the largest size", False, "p2 1.73 at 2e+05 dofs")]


def tiny_frame() -> pd.DataFrame:
    return pd.DataFrame({"method": ["p2", "p1"], "ndof": [195489, 48961], "t_contact": [0.123456, 0.0456789],
                         "ratio_linear": [1.23456, np.nan]})


def test_write_bench_puts_the_title_provenance_and_goals_beside_the_csv(tmp_path):
    csv = write_bench(tiny_frame(), tmp_path / "bench_elastic.csv", TITLE, GOALS, 12.5, "python -m harness bench --only elastic")
    meta = json.loads((tmp_path / "bench_elastic.json").read_text())
    assert {"title", "harness_version", "git_commit", "ngsolve_version", "date", "machine", "command", "wall_seconds",
            "goals", "csv_sha256"} <= set(meta)
    assert {"cpus", "cpus_usable", "platform", "cpu_model"} <= set(meta["machine"])
    assert (meta["title"], meta["wall_seconds"], meta["command"]) == (TITLE, 12.5, "python -m harness bench --only elastic")
    assert meta["goals"] == [{"goal": goal, "met": bool(met), "figure": figure} for goal, met, figure in GOALS]
    pd.testing.assert_frame_equal(pd.read_csv(csv), tiny_frame())


def test_the_report_provenance_keeps_its_keys_after_sharing_the_environment_part():
    assert list(provenance({"profile": "default"})) == ["harness_version", "git_commit", "ngsolve_version", "date", "machine",
                                                        "settings", "solver_options"]
    assert set(provenance({})["machine"]) == {"node", "platform", "processor", "cpus", "python"}


def test_bench_only_one_table_rewrites_that_table_and_its_sidecar_alone(tmp_path, monkeypatch):
    def table(name):
        return (lambda: tiny_frame().assign(method=name), f"_{name}", f"{name} table:", lambda frame: [(name, True, "ok")])
    monkeypatch.setattr(command, "_tables", lambda: [table("study"), table("elastic"), table("3d")])
    args = argparse.Namespace(only="elastic", out=str(tmp_path / "bench.csv"), sizes=None, method=None, workers=None)
    (tmp_path / "bench_study.csv").write_text("old\n")
    (tmp_path / "bench_study.json").write_text("{}")
    assert command.run_bench_command(args) == 0
    assert sorted(p.name for p in tmp_path.iterdir()) == ["bench_elastic.csv", "bench_elastic.json", "bench_study.csv",
                                                          "bench_study.json"]
    assert (tmp_path / "bench_study.csv").read_text() == "old\n" and (tmp_path / "bench_study.json").read_text() == "{}"
    assert json.loads((tmp_path / "bench_elastic.json").read_text())["goals"] == [{"goal": "elastic", "met": True, "figure": "ok"}]


def test_the_page_shows_a_table_with_its_title_stamp_goals_and_three_digits(tmp_path):
    write_bench(tiny_frame(), tmp_path / "bench_elastic.csv", TITLE, GOALS, 12.5, "python -m harness bench --only elastic")
    meta = json.loads((tmp_path / "bench_elastic.json").read_text())
    page = performance_page(tmp_path)
    assert f"## {TITLE.rstrip(':')}\n" in page
    assert f"harness {meta['harness_version']}, commit `{meta['git_commit'][:12]}`, NGSolve {meta['ngsolve_version']}" in page
    assert meta["date"] in page and "wall time 12 s" in page and "`python -m harness bench --only elastic`" in page
    assert f"- met: {GOALS[0][0]}: {GOALS[0][2]}" in page and f"- MISSED: {GOALS[1][0]}: {GOALS[1][2]}" in page
    assert "| p2 | 195489 | 0.123 | 1.23 |" in page and "| p1 | 48961 | 0.0457 |  |" in page


def test_a_csv_without_its_sidecar_is_shown_as_provenance_not_recorded(tmp_path):
    tiny_frame().to_csv(tmp_path / "bench_3d.csv", index=False)
    page = performance_page(tmp_path)
    assert "## 3D (Section 6)" in page and "provenance not recorded" in page and "| p2 | 195489 | 0.123 |" in page


def test_a_sidecar_of_another_run_of_the_table_is_not_taken_for_its_provenance(tmp_path):
    write_bench(tiny_frame(), tmp_path / "bench_elastic.csv", TITLE, GOALS, 12.5, "bench")
    tiny_frame().head(1).to_csv(tmp_path / "bench_elastic.csv", index=False)      # rewritten without its sidecar
    page = performance_page(tmp_path)
    assert "provenance not recorded" in page and "MISSED" not in page


def test_the_tables_follow_the_order_of_bench_only(tmp_path):
    for name in ("bench.csv", "bench_study.csv", "bench_report.csv"):
        tiny_frame().to_csv(tmp_path / name, index=False)
    page = performance_page(tmp_path)
    headings = [line for line in page.splitlines() if line.startswith("### ")]
    assert [h.split()[1] for h in headings] == ["study", "solver", "make"]
    assert [name for name, _, _ in command.bench_tables()][:2] == command.bench_names()[:2]


@pytest.mark.parametrize("folder", ["empty", "missing"])
def test_without_bench_tables_the_page_says_what_to_run(tmp_path, folder):
    if folder == "empty":
        (tmp_path / folder).mkdir()
    page = performance_page(tmp_path / folder)
    assert "`make bench`" in page and "`python -m harness bench --only NAME`" in page and "`make docs`" in page
    assert "##" not in page
