"""Command line: python -m harness {run, sweep, cases, methods, rates, report, bench, export}.

Each command calls the Python API (``harness.api``) and adds only its
arguments and what it prints. Exit status: 0 done; 1 done, but a solve did not converge (each
named on stderr); 2 input refused before the study, nothing on disk touched; 3 the study
stopped on an error once started (one line; ``--debug`` shows the traceback); 130 interrupted.
"""
from __future__ import annotations

import argparse
import sys
import warnings
from pathlib import Path

# Each command imports the stages it needs, and the parser is built in full only for the
# command given: `cases`, `methods` and `--help` start without NGSolve, pandas or SciPy.

EXIT_NOT_CONVERGED, EXIT_BAD_INPUT, EXIT_STUDY_FAILED, EXIT_INTERRUPTED = 1, 2, 3, 130


class BadInput(Exception):
    pass


class _Parser(argparse.ArgumentParser):
    def error(self, message):  # one line instead of argparse's usage block
        raise BadInput(message)


def text_table(rows: list[dict], width: int = 60) -> str:
    """Rows as left-aligned columns, each cell cut to ``width`` characters (without pandas)."""
    if not rows:
        return ""
    cells = [[str(v) if len(str(v)) <= width else str(v)[:width - 3] + "..." for v in row.values()] for row in rows]
    widths = [max(len(text) for text in column) for column in zip(list(rows[0]), *cells)]
    return "\n".join("  ".join(t.ljust(w) for t, w in zip(line, widths)).rstrip() for line in [list(rows[0]), *cells])


def cmd_cases(args) -> int:
    from .api import case_rows
    from .problem.case import case_groups
    hidden = ("expected_rate", "expected_log_exponent")
    print(text_table([{k: v for k, v in row.items() if k not in hidden} for row in case_rows()], width=70))
    print("\ngroups (--case GROUP runs each of its cases):")
    print(text_table([{"group": group, "count": len(names), "cases": ", ".join(names)}
                      for group, names in case_groups().items()], width=100))
    return 0


def cmd_methods(args) -> int:
    from .api import method_rows
    print(text_table(method_rows(), width=80))
    return 0


def engine_of(args):
    """--workers N (local processes), --scheduler ADDRESS (Dask), or this process."""
    from .study import DaskEngine, InProcess, LocalProcesses
    if args.scheduler:
        return DaskEngine(scheduler=args.scheduler, threads=args.threads)
    if args.workers:
        return LocalProcesses(args.workers, threads=args.threads)
    return InProcess(threads=args.threads)


def _meshes(args) -> list:
    return [s for group in (args.mesh or []) for s in group] or ["uniform"]


def cmd_run(args) -> int:
    from .api import run
    engine = engine_of(args)
    try:
        frame = run(args.case, args.method or ["all"], args.levels, _meshes(args), out=args.out,
                    reference_levels=args.reference_levels, engine=engine, vtk=args.vtk, show_progress=not args.quiet,
                    check_memory=not args.skip_memory_check)
    finally:
        engine.close()
    if not args.quiet:
        _print_run(frame, Path(args.out))
    if args.vtk:
        _print_vtk(Path(args.out) / "vtk")
    print(frame.attrs["stored"])
    return _report_failures(frame)


def _print_run(frame, out: Path) -> None:
    """The run's rows as a table, the chains it resumed, and where reference errors come from."""
    import pandas as pd

    from .study.chain.outcome import reference_lines
    for (case, method), level in frame.attrs["resumed"].items():
        if level:
            print(f"{case} {method}: resumed after level {level - 1} from {out / '.checkpoints'}")
    columns = ["case", "method", "level", "h", "ndof", "err_h1", "max_penetration", "solver_iterations",
               "kkt_residual", "status"]
    if (frame["mesh"] != "uniform").any():
        columns[2:2], columns[-2:-2] = ["mesh"], ["effectivity"]
    with pd.option_context("display.width", 200, "display.max_columns", 30):
        print(frame[columns].to_string(index=False))
    print(*reference_lines(frame), sep="\n")


def _print_vtk(folder: Path) -> None:
    """Where the ParaView files are, and how much they weigh."""
    files = list(folder.rglob("*.vtu"))
    print(f"wrote {len(files)} VTK files ({sum(f.stat().st_size for f in files) / 1e6:.3g} MB) under {folder}: "
          "open CASE/METHOD/omega.pvd and gamma_c.pvd in ParaView (the time slider steps through the levels)")


def _report_failures(frame) -> int:
    """Every failed solve on stderr, one line each, --quiet or not; 1 if any."""
    from .study.chain.outcome import failures
    lines = failures(frame)
    for line in lines:
        print(f"harness: {line}", file=sys.stderr)
    return EXIT_NOT_CONVERGED if lines else 0


def cmd_sweep(args) -> int:
    import pandas as pd

    from .api import sweep
    frame = sweep(args.case, args.method, args.values, args.level, reference=args.reference, out=args.out,
                  show_progress=not args.quiet)
    if not args.quiet:
        with pd.option_context("display.width", 200, "display.max_columns", 20):
            print(frame[["method", "level", "ndof", "err_h1", "max_penetration", "min_pressure", "solver_iterations",
                         "kkt_residual", "status"]].to_string(index=False))
    print(f"wrote {frame.attrs['path']} and {frame.attrs['figure']}")
    return 0 if (frame["status"] == "converged").all() else EXIT_NOT_CONVERGED


def cmd_rates(args) -> int:
    import pandas as pd

    from .api import quantities, rates
    folder = Path(args.results).parent
    if args.qoi:
        table = quantities(args.results, out=folder)
        from .measure.richardson import coverage
        with pd.option_context("display.width", 220, "display.max_rows", None):
            print(table.drop(columns=["order", "levels", "order_previous"]).to_string(index=False, float_format="{:.6g}".format))
        judged = coverage(table)
        if judged["judged"]:
            print(f"bands holding the exact value, in the asymptotic range: {judged['covered']} of {judged['judged']}")
        print(f"wrote {table.attrs['path']}")
        return 0
    table = rates(args.results, args.fit_levels, out=folder)
    if args.latex:
        from .api import latex_tables
        print(latex_tables(args.results, args.fit_levels))
    else:
        with pd.option_context("display.width", 200, "display.max_colwidth", 60):
            print(table.to_string(index=False, float_format=lambda v: f"{v:.3f}"))
    print(f"wrote {table.attrs['path']}", file=sys.stderr if args.latex else sys.stdout)
    return 0


def cmd_report(args) -> int:
    import pandas as pd

    from .api import report
    engine = engine_of(args)
    try:
        path = report(args.case, args.method or ["all"], args.levels, args.profile, args.results, args.report, engine,
                      show_progress=not args.quiet, vtk=args.vtk, check_memory=not args.skip_memory_check)
    finally:
        engine.close()
    if args.vtk:
        _print_vtk(Path(args.results) / "vtk")
    print(f"wrote {path}")
    return _report_failures(_report_rows(args, pd.read_csv(Path(args.results) / "results.csv")))


def _report_rows(args, rows):
    """The rows of results.csv that the report's study stands for: its cases and methods (rows
    of other runs kept in the folder are theirs to answer for)."""
    from .methods import methods_named
    from .problem.case import registered_cases
    from .report.build import in_profile
    cases = args.case or [case.name for case in in_profile(registered_cases().values(), args.profile)]
    methods = [method.name for method in methods_named(args.method or ["all"])]
    return rows[rows.case.isin(cases) & rows.method.isin(methods)]


def cmd_bench(args) -> int:
    from .bench.command import run_bench_command
    return run_bench_command(args)


def cmd_export(args) -> int:
    from .api import export
    report = None if args.quiet else (lambda level, path: print(f"level {level}: wrote {path}", flush=True))
    path = export(args.case, args.levels, args.out, order=args.order, progress=report)
    print(f"wrote {path}")
    return 0


COMMANDS = {
    "cases": "list the registered cases with regularity and expected rate",
    "methods": "list the discretisations: order, contact condition, reference",
    "run": "run a convergence study and write DIR/results.csv",
    "sweep": "a penalty/Nitsche method over values of its parameter, at one level of one case",
    "rates": "fit rates of a results CSV; writes rates.csv beside it (--qoi: quantities.csv)",
    "report": "run the study (reusing unchanged results) and render the report",
    "bench": "contact solve vs one linear solve, textbook PDAS and Clarabel",
    "export": "write a case's discrete problems (mesh, nodes, data, load moments) for another code to solve",
}


def build_parser(argv=None) -> argparse.ArgumentParser:
    """The parser; with ``argv``, only the command it names gets its options (the others their
    one-line help): `run`'s options import the methods, which listing the cases does not need."""
    from .cli_options import ADDERS
    parser = _Parser(prog="python -m harness", description=__doc__.splitlines()[0])
    parser.add_argument("--debug", action="store_true",
                        help="let an error through with its traceback (accepted anywhere on the line)")
    sub = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)
    given = next((arg for arg in argv if not arg.startswith("-")), None) if argv is not None else None
    for name, add in ADDERS.items():
        if given is None or given == name or given not in ADDERS:
            add(sub.add_parser(name, help=COMMANDS[name])).set_defaults(func=globals()[f"cmd_{name}"])
        else:
            sub.add_parser(name, help=COMMANDS[name])
    return parser


# An except clause's classes are looked up only when an exception reaches it: the study's
# modules are imported then, not at start-up.
def _bad_input() -> tuple:
    from .study.storage.files import OutputError
    return (BadInput, ValueError, FileNotFoundError, OutputError)       # CaseError is a ValueError


def _study_failed() -> tuple:
    from .study.execution.dask_engine import SchedulerUnreachable
    from .study.execution.processes import WorkerDied
    from .study.storage.store import StudyFailed
    return (StudyFailed, SchedulerUnreachable, WorkerDied)


def _show_warning(message, category, filename, lineno, file=None, line=None):
    """A ``StudyWarning`` as one ``harness:`` line; any other warning as Python shows it."""
    from .api import StudyWarning
    if issubclass(category, StudyWarning):
        print(f"harness: {message}", file=sys.stderr)
    else:
        warnings._showwarnmsg_impl(warnings.WarningMessage(message, category, filename, lineno, file, line))


def main(argv=None) -> int:
    """Every failure ends as one line on stderr and the exit status of the module docstring;
    ``--debug`` (anywhere on the line) lets the exception through with its traceback."""
    argv = list(sys.argv[1:] if argv is None else argv)
    debug = "--debug" in argv
    argv = [arg for arg in argv if arg != "--debug"]
    with warnings.catch_warnings():
        warnings.showwarning = _show_warning
        try:
            args = build_parser(argv).parse_args(argv)
            return args.func(args)
        except KeyboardInterrupt:
            print("harness: interrupted; no results file was written (run and report continue from their last "
                  "finished level when started again)", file=sys.stderr)
            return EXIT_INTERRUPTED
        except Exception as exc:
            if debug:
                raise
            return _one_line(exc)


def _one_line(exc: Exception) -> int:
    """``exc`` as one stderr line, and its exit status."""
    if isinstance(exc, _study_failed()):
        print(f"harness: error: {exc} (run with --debug for the traceback)", file=sys.stderr)
        return EXIT_STUDY_FAILED
    if isinstance(exc, _bad_input()):
        print(f"harness: error: {exc}", file=sys.stderr)
        return EXIT_BAD_INPUT
    print(f"harness: error: {type(exc).__name__}: {exc} (run with --debug for the traceback)", file=sys.stderr)
    return EXIT_STUDY_FAILED
