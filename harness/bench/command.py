"""The `bench` command: runs the benchmark tables, writes each as CSV with its provenance and
goals beside it (``<name>.json``, read by the docs' performance page) and prints the goals."""
from __future__ import annotations

import os
from pathlib import Path

import pandas as pd

# tables of ``_tables`` that run only when `--only` names them: another code's environment and
# minutes of its solves (``codes``)
ASKED_ONLY = ("_codes",)
# the tables `bench --only NAME` runs besides these, each named by its CSV's suffix (``_tables``)
OTHER_BENCHES = ("solver", "report")


def _tables() -> list[tuple]:
    """(how to run it, the CSV's suffix, the title, its goals) of each table `bench` runs by
    default besides the solver table; `--only` names each by its suffix without the underscore."""
    from .adaptive import adaptive_goals, run_adaptive_bench
    from .codes import codes_goals, run_codes_bench
    from .coulomb import axis_goals, coefficient_axis, coulomb_goals, run_coulomb_bench
    from .degree import degree_goals, run_degree_bench
    from .elastic import elastic_goals, run_elastic_bench
    from .friction import friction_goals, run_friction_bench
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
            (run_degree_bench, "_degree",
             "degree k = 3, 4 (transition-r32): contact solve against one linear solve of the same stiffness:",
             degree_goals),
            (run_friction_bench, "_friction",
             "Tresca friction (tresca-r32): exact friction solve against one linear solve without friction rows, "
             "same start (multigrid CG):", friction_goals),
            (run_coulomb_bench, "_coulomb",
             "Coulomb friction (elastic-coulomb-r32): one load step (Newton, GMRES + multigrid) against one linear solve "
             "without contact rows, same start (multigrid CG):", coulomb_goals),
            (coefficient_axis, "_coulomb_axis",
             "Coulomb friction: the coupled Newton method and the fixed point over Tresca problems as mu_F grows "
             "(elastic-coulomb-r32's data, level 3):", axis_goals),
            (run_codes_bench, "_codes",
             "other codes (transition-r32): DOLFINx + PETSc SNES VI / Nitsche against the harness, same exported problem, "
             "one thread each:", codes_goals),
            (run_load_bench, "_load",
             "a study beside one busy process (`run`, wall seconds; threads: auto = the default policy):", load_goals)]


SOLVER_TITLE = ("solver (transition-r32): contact solve against one linear solve by three back ends, the textbook "
                "PDAS and Clarabel:")
# the report's tables (``--only report``), by the CSV's suffix
REPORT_TITLES = {"_report": "make report (default profile, empty results):",
                 "_report_profile": "where the report's time goes (first variant; study: work of each case's jobs):",
                 "_report_phases": "the study's seconds by case and phase:"}


def bench_names() -> list[str]:
    """What `bench --only` takes: the study row first, then the solver table and the rest."""
    names = [suffix.lstrip("_") for _, suffix, _, _ in _tables()]
    return [names[0], OTHER_BENCHES[0], *names[1:], OTHER_BENCHES[1]]


def bench_tables(stem: str = "bench") -> list[tuple[str, str, str]]:
    """(name `--only` takes, CSV file name, title) of every table `bench` writes beside
    ``stem``.csv, in the order of ``bench_names``."""
    suffixes = {suffix.lstrip("_"): [(suffix, title)] for _, suffix, title, _ in _tables()}
    suffixes[OTHER_BENCHES[0]] = [("", SOLVER_TITLE)]
    suffixes[OTHER_BENCHES[1]] = list(REPORT_TITLES.items())
    return [(name, f"{stem}{suffix}.csv", title) for name in bench_names() for suffix, title in suffixes[name]]


def command_line() -> str:
    """This process's command line, as typed: ``python -m harness ...`` when run as the module."""
    import shlex
    import sys
    program = Path(sys.argv[0])
    typed = "python -m harness" if program.name == "__main__.py" else program.name
    return " ".join([typed, shlex.join(sys.argv[1:])]).strip()


def run_bench_command(args) -> int:
    """`python -m harness bench`: the tables of ``args.only`` (all but the report's by default), each
    written beside ``args.out`` with its provenance (``common.write_bench``), then every goal with
    its measured figure."""
    from ..methods import PAPER, role_names
    from ..study.storage.files import ensure_writable
    from .common import timed
    from .solvers import DEFAULT_SIZES, goals, run_bench
    out = Path(args.out)
    ensure_writable(out.parent)
    command, lines = command_line(), []
    for run, suffix, title, judge in _tables():
        # `--only coulomb` runs its axis too (``_coulomb_axis``), `--only coulomb_axis` the axis alone
        if args.only in (suffix.lstrip("_"), suffix.lstrip("_").split("_")[0]) or (args.only is None and suffix not in ASKED_ONLY):
            seconds, frame = timed(run)
            lines += _publish(frame, _beside(out, suffix), title, judge(frame), seconds, command)
    if args.only in (None, OTHER_BENCHES[0]):
        seconds, frame = timed(run_bench, args.sizes or DEFAULT_SIZES, tuple(args.method or role_names(PAPER)))
        lines += _publish(frame, out, SOLVER_TITLE, goals(frame), seconds, command)
    if args.only == OTHER_BENCHES[1]:
        lines += _report_tables(args.workers or (0,), out, command)
    for goal, met, figure in lines:
        print(f"[{'met' if met else 'MISSED'}] {goal}: {figure}")
    return 0


def _beside(out: Path, suffix: str) -> Path:
    return out.with_name(out.stem + suffix + ".csv")


def _report_tables(workers, out: Path, command: str) -> list:
    """The report's three tables from one run of each variant; the goals are the first table's,
    and each table's wall time is that of the whole run."""
    from .common import timed
    from .report import profile_tables, report_goals, run_report_bench
    seconds, (frame, profile) = timed(run_report_bench, workers)
    sections, phases = profile_tables(profile)
    judged = report_goals(frame, os.cpu_count())
    for table, suffix, own in ((frame, "_report", judged), (sections, "_report_profile", []),
                               (phases.reset_index(), "_report_phases", [])):
        _publish(table, _beside(out, suffix), REPORT_TITLES[suffix], own, seconds, command)
    return judged


def _publish(frame: pd.DataFrame, path: Path, title: str, judged: list, seconds: float, command: str) -> list:
    """``frame`` written to ``path`` with its provenance and shown; its goals (``judged``) returned."""
    from .common import write_bench
    _show(frame, write_bench(frame, path, title, judged, seconds, command), title)
    return judged


def _show(frame: pd.DataFrame, path: Path, title: str) -> None:
    with pd.option_context("display.width", 220, "display.max_columns", 20):
        if title:
            print(title)
        print(frame.to_string(index=False, float_format=lambda v: f"{v:.3g}"))
    print(f"wrote {path}")
