"""The `bench` command: runs the benchmark tables, writes each as CSV and prints the goals."""
from __future__ import annotations

import os
from pathlib import Path

import pandas as pd

# the tables `bench --only NAME` runs besides these, each named by its CSV's suffix (``_tables``)
OTHER_BENCHES = ("solver", "report")


def _tables() -> list[tuple]:
    """(how to run it, the CSV's suffix, the title, its goals) of each table `bench` runs by
    default besides the solver table; `--only` names each by its suffix without the underscore."""
    from .adaptive import adaptive_goals, run_adaptive_bench
    from .elastic import elastic_goals, run_elastic_bench
    from .load import load_goals, run_load_bench
    from .mortar import mortar_goals, run_mortar_bench
    from .study import measure_study, study_goals
    from .three_d import run_3d_bench, three_d_goals
    return [(measure_study, "_study", "study (default profile, every case; the paper's methods, then every method):",
             study_goals),
            (run_elastic_bench, "_elastic",
             "elasticity (Remark 2.3): contact solve against one linear elastic solve, same matrix:", elastic_goals),
            (run_3d_bench, "_3d",
             "3D (Section 6): contact solve against one linear solve of the same matrix (multigrid CG):", three_d_goals),
            (run_adaptive_bench, "_adaptive",
             "adaptive meshes (corner-r12): contact solve on the finest against one linear solve (multigrid CG):",
             adaptive_goals),
            (run_mortar_bench, "_mortar",
             "two bodies, non-matching meshes (Section 6): mortar contact solve against one linear solve of both bodies:",
             mortar_goals),
            (run_load_bench, "_load",
             "a study beside one busy process (`run`, wall seconds; threads: auto = the default policy):", load_goals)]


def bench_names() -> list[str]:
    """What `bench --only` takes: the study row first, then the solver table and the rest."""
    names = [suffix.lstrip("_") for _, suffix, _, _ in _tables()]
    return [names[0], OTHER_BENCHES[0], *names[1:], OTHER_BENCHES[1]]


def run_bench_command(args) -> int:
    """`python -m harness bench`: the tables of ``args.only`` (all but the report's by default), each
    written beside ``args.out``, then every goal with its measured figure."""
    from ..methods import PAPER, role_names
    from ..study.files import ensure_writable
    from .common import write_bench
    from .solvers import DEFAULT_SIZES, goals, run_bench
    out = Path(args.out)
    ensure_writable(out.parent)
    lines = []
    for run, suffix, title, judge in _tables():
        if args.only in (None, suffix.lstrip("_")):
            frame = run()
            _show(frame, write_bench(frame, out.with_name(out.stem + suffix + ".csv")), title)
            lines += judge(frame)
    if args.only in (None, OTHER_BENCHES[0]):
        frame = run_bench(args.sizes or DEFAULT_SIZES, tuple(args.method or role_names(PAPER)))
        _show(frame, write_bench(frame, out), "")
        lines += goals(frame)
    if args.only == OTHER_BENCHES[1]:
        from .report import profile_tables, report_goals, run_report_bench
        frame, profile = run_report_bench(args.workers or (0,))
        _show(frame, write_bench(frame, out.with_name(out.stem + "_report.csv")), "make report (default profile, empty results):")
        sections, phases = profile_tables(profile)
        _show(sections, write_bench(sections, out.with_name(out.stem + "_report_profile.csv")),
              "where the report's time goes (first variant; study: work of each case's jobs):")
        _show(phases.reset_index(), write_bench(phases.reset_index(), out.with_name(out.stem + "_report_phases.csv")),
              "the study's seconds by case and phase:")
        lines += report_goals(frame, os.cpu_count())
    for goal, met, figure in lines:
        print(f"[{'met' if met else 'MISSED'}] {goal}: {figure}")
    return 0


def _show(frame: pd.DataFrame, path: Path, title: str) -> None:
    with pd.option_context("display.width", 220, "display.max_columns", 20):
        if title:
            print(title)
        print(frame.to_string(index=False, float_format=lambda v: f"{v:.3g}"))
    print(f"wrote {path}")
