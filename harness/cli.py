"""Command line: python -m harness {run, sweep, cases, methods, rates, report, bench}.

Bad input ends with one line on stderr and a non-zero exit status, before anything that
exists on disk is touched.
"""
from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    import pandas as pd

# Each command imports the stages it needs, and the parser is built in full only for the
# command given: `cases`, `methods` and `--help` start without NGSolve's solvers, pandas or
# SciPy (issue 61).

EXIT_BAD_INPUT = 2
EXIT_FAILED = 1


class BadInput(Exception):
    pass


class _Parser(argparse.ArgumentParser):
    def error(self, message):  # one line instead of argparse's usage block
        raise BadInput(message)


def _positive_int(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"must be a positive integer, got {text!r}")
    if value < 1:
        raise argparse.ArgumentTypeError(f"must be a positive integer, got {value}")
    return value


def text_table(rows: list[dict], width: int = 60) -> str:
    """Rows as left-aligned columns, each cell cut to ``width`` characters (the listing commands'
    tables, without pandas)."""
    if not rows:
        return ""
    cells = [[str(value) if len(str(value)) <= width else str(value)[:width - 3] + "..." for value in row.values()]
             for row in rows]
    header = list(rows[0])
    widths = [max(len(text) for text in column) for column in zip(header, *cells)]
    return "\n".join("  ".join(text.ljust(w) for text, w in zip(line, widths)).rstrip() for line in [header, *cells])


def cmd_cases(args) -> int:
    from .api import case_rows
    rows = [{key: value for key, value in row.items() if key not in ("expected_rate", "expected_log_exponent")}
            for row in case_rows()]
    print(text_table(rows, width=70))
    return 0


def cmd_methods(args) -> int:
    from .api import method_rows
    print(text_table(method_rows(), width=80))
    return 0


def selected_methods(args) -> list:
    """--method (repeatable: a name, a group or 'all'), or the old --model ('all' = the methods
    that declare the role PAPER)."""
    from .methods import PAPER, methods_named, role_names
    names = list(args.method or [])
    if args.model:
        names += role_names(PAPER) if args.model == "all" else [args.model]
    return methods_named(names or ["all"])


def named_methods(args) -> list:
    """The methods --method names one by one (not through a group such as 'all' or 'weak')."""
    from .methods import GROUPS, methods_named
    return methods_named([name for name in args.method or [] if name != "all" and name not in GROUPS])


def engine_of(args):
    """Where the jobs run: --workers N (N local processes), --scheduler ADDRESS (Dask), or this
    process."""
    from .study import DaskEngine, InProcess, LocalProcesses
    if args.scheduler:
        return DaskEngine(scheduler=args.scheduler, threads=args.threads)
    if args.workers:
        return LocalProcesses(args.workers, threads=args.threads)
    return InProcess(threads=args.threads)


def cmd_run(args) -> int:
    from .problem.case import load_case
    from .study.engines import skipped_meshes, skipped_methods, study_jobs
    from .study.folder import owned

    methods = selected_methods(args)
    args.mesh = selected_meshes(args)
    cases = [load_case(spec) for spec in args.case]
    if args.reference_levels:
        cases = [case.with_reference(args.reference_levels) for case in cases]
    engine = engine_of(args)
    try:
        # refused before the output folder is touched or a worker started
        study_jobs(cases, methods, args.levels, engine, check_memory=not args.skip_memory_check, meshes=args.mesh)
        for line in skipped_meshes(cases, args.mesh):
            print(f"harness: {line}", file=sys.stderr)
        with owned(Path(args.out)) as out:
            for line in skipped_methods(cases, named_methods(args)):
                print(f"harness: {line}", file=sys.stderr)
            frame, merged = _run_into(out, args, cases, methods, engine)
    finally:
        engine.close()
    if not args.quiet:
        _print_run(frame, out / ".checkpoints")
    print(merged.summary(out / "results.csv"))
    return report_failures(frame)


def _run_into(out: Path, args, cases, methods, engine):
    """The study of ``run`` into the folder ``out`` (which this process owns): its rows merged
    into ``out``/results.csv (``study.merge``), its checkpoints deleted once they are there."""
    from .report.vtk import VtkWriter
    from .study import run_study
    from .study.checkpoint import CheckpointStore
    from .study.files import write_csv
    from .study.merge import merge_rows, read_rows

    path = out / "results.csv"
    read_rows(path)             # a file that is not a results CSV is refused before the study
    checkpoints = out / ".checkpoints"
    writer = VtkWriter(out / "vtk") if args.vtk else None
    frame = run_study(cases, methods, args.levels, show_progress=not args.quiet, engine=engine,
                      checkpoints=checkpoints, check_memory=False, meshes=args.mesh, on_level=writer)
    merged = merge_rows(read_rows(path), frame)
    write_csv(merged.frame, path)
    store = CheckpointStore(checkpoints, args.levels)
    for case in cases:
        store.forget(case, every_mesh=True)
    if checkpoints.is_dir() and not any(checkpoints.iterdir()):
        checkpoints.rmdir()
    if args.vtk:
        _print_vtk(out / "vtk")
    return frame, merged


def _print_run(frame: pd.DataFrame, checkpoints: Path) -> None:
    """The run's rows as a table, and the chains it resumed."""
    import pandas as pd
    for (case, method), level in frame.attrs["resumed"].items():
        if level:
            print(f"{case} {method}: resumed after level {level - 1} from {checkpoints}")
    with pd.option_context("display.width", 200, "display.max_columns", 30):
        columns = ["case", "method", "level", "h", "ndof", "err_h1", "max_penetration", "solver_iterations",
                   "kkt_residual", "status"]
        if (frame["mesh"] != "uniform").any():
            columns[2:2] = ["mesh"]
            columns[-2:-2] = ["effectivity"]
        print(frame[columns].to_string(index=False))
        _print_references(frame)


def failures(frame: pd.DataFrame) -> list[str]:
    """One line per solve that did not converge: case, method, level and why; and per method
    whose reference solve did not (a case measured against a reference)."""
    lines = [f"case {r.case}, method {r.method}, {_mesh_words(getattr(r, 'mesh', None))}level {r.level}: {r.status}"
             for r in frame[frame["status"] != "converged"].itertuples()]
    measured = frame[(frame["errors_against"] == "reference") & (frame["reference_status"] != "converged")]
    for case, group in measured.groupby("case", sort=False):
        first = group.iloc[0]
        lines.append(f"case {case}, reference ({_reference_words(first)}) on level {int(first.reference_level)}: "
                     f"{first.reference_status}")
    return lines


def _reference_words(row) -> str:
    """Whose solution a reference is: the reference method's (a results file written before
    harness 0.3.1 has no ``reference_method``: each method was its own reference)."""
    method = getattr(row, "reference_method", None)
    return f"{method}'s solution" if isinstance(method, str) else "each method's own solution"


def _mesh_words(mesh) -> str:
    """'graded mesh, ' in a failure line; nothing for the uniform meshes (or an old file's NaN)."""
    return f"{mesh} mesh, " if isinstance(mesh, str) and mesh != "uniform" else ""


def _mesh_list(text: str) -> list:
    from .mesh.strategies import parse_mesh
    try:
        return parse_mesh(text)
    except ValueError as exc:
        raise argparse.ArgumentTypeError(str(exc))


def add_mesh_option(p) -> None:
    p.add_argument("--mesh", action="append", type=_mesh_list, metavar="STRATEGY",
                   help="uniform (the default), graded (Remark 4.4), adaptive (Dörfler, adaptive:theta=0.3), all, or a "
                        "strategy of your own (path/to/file.py[:name], package.module[:name], an installed one's label); "
                        "repeat for several")


def selected_meshes(args) -> list:
    from .mesh.strategies import parse_meshes
    return parse_meshes([s for group in (args.mesh or []) for s in group] or ["uniform"])


def report_failures(frame: pd.DataFrame) -> int:
    """Every failure on stderr, one line each, --quiet or not; the exit status: 1 if any."""
    lines = failures(frame)
    for line in lines:
        print(f"harness: {line}", file=sys.stderr)
    return 1 if lines else 0


def _print_references(frame: pd.DataFrame) -> None:
    """One line per reference solve, or per chain of references (graded and adaptive meshes: one
    per level, ``measure.level_reference``): where the errors of a case without u come from."""
    measured = frame[frame["errors_against"] == "reference"]
    for (case, mesh), group in measured.groupby(["case", "mesh"], sort=False, dropna=False):
        first = group.iloc[0]
        if group["reference_level"].nunique() == 1:
            print(f"{case}: {_mesh_words(mesh)}errors of every method against {_reference_words(first)} on level "
                  f"{int(first.reference_level)} ({int(first.reference_ndof)} dofs, KKT residual "
                  f"{first.reference_kkt_residual:.1e}, {first.reference_status})")
            continue
        refinements = int(first.reference_level - first.level)
        statuses = ", ".join(sorted(set(group["reference_status"])))
        print(f"{case}: {_mesh_words(mesh)}errors of each level against {_reference_words(first)} on that level's mesh "
              f"refined uniformly {refinements} times ({int(group.reference_ndof.min())} to {int(group.reference_ndof.max())} "
              f"dofs, KKT residual <= {group.reference_kkt_residual.max():.1e}, {statuses})")


def cmd_sweep(args) -> int:
    import pandas as pd

    from .problem.case import load_case
    from .report import figures
    from .study.files import write_csv
    from .study.folder import owned
    from .study.sweep import run_sweep, swept

    case = load_case(args.case)
    for spec in args.method:
        swept(spec, args.values)        # refuses a method without a parameter before anything is written
    with owned(Path(args.out)) as out:
        frame = run_sweep(case, args.method, args.values, args.level, reference=[] if args.reference == "none" else [args.reference],
                          show_progress=not args.quiet)
        path = write_csv(frame, out / f"sweep_{case.name}.csv")
        figure = figures.sweep(case, frame, out)
    if not args.quiet:
        with pd.option_context("display.width", 200, "display.max_columns", 20):
            print(frame[["method", "level", "ndof", "err_h1", "max_penetration", "min_pressure", "solver_iterations",
                         "kkt_residual", "status"]].to_string(index=False))
    print(f"wrote {path} and {figure['png']}")
    return 0 if (frame["status"] == "converged").all() else 1


def _values(text: str) -> list[float]:
    try:
        values = [float(v) for v in text.split(",") if v.strip()]
    except ValueError:
        raise argparse.ArgumentTypeError(f"values must be comma-separated numbers, got {text!r}")
    if not values or any(not v > 0 for v in values):
        raise argparse.ArgumentTypeError(f"values must be positive numbers, got {text!r}")
    return values


def _non_negative_int(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        value = -1
    if value < 0:
        raise argparse.ArgumentTypeError(f"level must be a non-negative integer, got {text!r}")
    return value


def _method_spec(text: str) -> str:
    """A method name, a group, 'all', or a method with parameters (nitsche:gamma0=0.1,theta=-1)."""
    from .methods import methods_named
    try:
        methods_named([text])
    except ValueError as exc:
        raise argparse.ArgumentTypeError(str(exc))
    return text


def cmd_rates(args) -> int:
    import pandas as pd

    from .measure.rates import rate_table
    from .measure.results_file import read_results
    from .study.files import write_csv
    from .study.folder import owned
    path = Path(args.results)
    frame = read_results(path, args.case)
    if args.qoi:
        return print_quantities(frame, path)
    table = rate_table(frame, levels=args.fit_levels)
    with owned(path.parent):
        out = write_csv(table, path.parent / "rates.csv")
    if args.latex:
        from .report import latex
        print(latex.summary_table(table))
        for case in frame.case.unique():
            print(latex.convergence_table(frame, case))
    else:
        with pd.option_context("display.width", 200, "display.max_colwidth", 60):
            print(table.to_string(index=False, float_format=lambda v: f"{v:.3f}"))
    print(f"wrote {out}", file=sys.stderr if args.latex else sys.stdout)
    return 0


def print_quantities(frame: pd.DataFrame, path: Path) -> int:
    """``rates --qoi``: the quantities of interest with their Richardson bands."""
    import pandas as pd

    from .measure.richardson import coverage, quantity_table
    from .study.files import write_csv
    from .study.folder import owned
    table = quantity_table(frame)
    if table.empty:
        raise ValueError(f"{path}: no chain with quantities of interest on three levels or more (results of harness < 0.5?)")
    with owned(path.parent):
        out = write_csv(table, path.parent / "quantities.csv")
    shown = table.drop(columns=["order", "levels", "order_previous"])
    with pd.option_context("display.width", 220, "display.max_rows", None):
        print(shown.to_string(index=False, float_format=lambda v: f"{v:.6g}"))
    judged = coverage(table)
    if judged["judged"]:
        print(f"bands holding the exact value, in the asymptotic range: {judged['covered']} of {judged['judged']}")
    print(f"wrote {out}")
    return 0


def cmd_report(args) -> int:
    import pandas as pd

    from .report.build import make_report
    engine = engine_of(args)
    try:
        path = make_report(args.profile, Path(args.results), Path(args.report), args.case,
                           show_progress=not args.quiet, levels=args.levels, methods=selected_methods(args),
                           engine=engine, check_memory=not args.skip_memory_check, vtk=args.vtk)
    finally:
        engine.close()
    if args.vtk:
        _print_vtk(Path(args.results) / "vtk")
    print(f"wrote {path}")
    return report_failures(pd.read_csv(Path(args.results) / "results.csv"))


def _print_vtk(folder: Path) -> None:
    """Where the ParaView files are, and how much they weigh."""
    files = list(folder.rglob("*.vtu"))
    size = sum(f.stat().st_size for f in files) / 1e6
    print(f"wrote {len(files)} VTK files ({size:.3g} MB) under {folder}: open CASE/METHOD/omega.pvd "
          "and gamma_c.pvd in ParaView (the time slider steps through the levels)")


def cmd_bench(args) -> int:
    from .bench.command import run_bench_command
    return run_bench_command(args)


def _sizes(text: str) -> list[tuple[float, int]]:
    try:
        sizes = [(float(h), int(level)) for h, level in (item.split(":") for item in text.split(","))]
    except ValueError:
        raise argparse.ArgumentTypeError(f"sizes must look like 0.25:3,0.25:4 (coarse maxh:level), got {text!r}")
    if not sizes or any(h <= 0 or level < 0 for h, level in sizes):
        raise argparse.ArgumentTypeError(f"sizes need maxh > 0 and level >= 0, got {text!r}")
    return sizes


def _method_names() -> list[str]:
    from .methods import METHODS
    return list(METHODS)


def _parameter_example() -> str:
    """A registered method with parameters, as --method takes it (the one with the most
    parameters: its first 0.1, the next -1)."""
    from .methods import METHODS
    with_parameters = [m for m in METHODS.values() if m.parameters]
    if not with_parameters:
        return "name:parameter=value"
    method = max(with_parameters, key=lambda m: len(m.parameters))
    return f"{method.name}:" + ",".join(f"{key}={value:g}" for key, value in zip(method.parameters, (0.1, -1.0)))


def add_method_options(p) -> None:
    from .methods import GROUPS, METHODS, PAPER, role_names
    p.add_argument("--method", action="append", type=_method_spec, metavar="METHOD",
                   help=f"a method ({', '.join(METHODS)}), a group ({', '.join(GROUPS)}) or 'all' (the default), a "
                        f"method with parameters, e.g. {_parameter_example()}, or one of your own: path/to/file.py[:name], "
                        f"package.module[:name] or an installed one's name; repeat for several")
    p.add_argument("--model", choices=[*role_names(PAPER), "all"],
                   help="the paper's models, as before the method axis ('all' = both)")


def add_engine_options(p) -> None:
    group = p.add_mutually_exclusive_group()
    group.add_argument("--workers", type=_positive_int, metavar="N",
                       help="run the jobs (one per case, the largest split by order) on N local worker processes "
                            "(until 0.3 a Dask LocalCluster: harness.study.DaskEngine(workers=N) in Python)")
    group.add_argument("--scheduler", metavar="ADDRESS",
                       help="run the jobs on an existing Dask cluster, e.g. tcp://10.0.0.1:8786 (docs: Running studies)")
    p.add_argument("--threads", type=_positive_int, metavar="T",
                   help="NGSolve and BLAS threads per process on every level (default: per level, 1 below 4e4 dofs, else "
                        "the usable cores other processes leave free; cores / N with --workers; 1 with --scheduler; "
                        "HARNESS_THREADS=T sets a default); with 1, results are reproducible bit for bit")
    p.add_argument("--skip-memory-check", action="store_true",
                   help="run even if the estimated peak memory exceeds the machine's (or a worker's)")


def _add_cases(sub) -> None:
    sub.add_parser("cases", help=COMMANDS["cases"]).set_defaults(func=cmd_cases)


def _add_methods(sub) -> None:
    sub.add_parser("methods", help=COMMANDS["methods"]).set_defaults(func=cmd_methods)


COMMANDS = {
    "cases": "list the registered cases with regularity and expected rate",
    "methods": "list the discretisations: order, contact condition, reference",
    "run": "run a convergence study and write DIR/results.csv",
    "sweep": "a penalty/Nitsche method over values of its parameter, at one level of one case",
    "rates": "fit rates of a results CSV; writes rates.csv beside it (--qoi: quantities.csv)",
    "report": "run the study (reusing unchanged results) and render the report",
    "bench": "contact solve vs one linear solve, textbook PDAS and Clarabel",
}


def build_parser(argv=None) -> argparse.ArgumentParser:
    """The parser; with ``argv``, only the command it names gets its options (the others their
    one-line help): building `run`'s or `bench`'s options imports the methods, which listing
    the cases does not need."""
    parser = _Parser(prog="python -m harness", description=__doc__.splitlines()[0])
    parser.add_argument("--debug", action="store_true",
                        help="let an error through with its traceback (accepted anywhere on the line)")
    sub = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)
    given = next((arg for arg in argv if not arg.startswith("-")), None) if argv is not None else None
    adders = {"cases": _add_cases, "methods": _add_methods, "run": _add_run, "sweep": _add_sweep,
              "rates": _add_rates, "report": _add_report, "bench": _add_bench}
    for name, add in adders.items():
        if given is None or given == name or given not in adders:
            add(sub)
        else:
            sub.add_parser(name, help=COMMANDS[name])
    return parser


def _add_run(sub) -> None:
    p = sub.add_parser("run", help=COMMANDS["run"])
    p.add_argument("--case", action="append", required=True, metavar="NAME|PATH",
                   help="a registered case name or a case file; repeat for several")
    add_method_options(p)
    p.add_argument("--levels", type=_positive_int, default=5, help="number of mesh levels (0..L-1)")
    p.add_argument("--reference-levels", type=_positive_int, metavar="K",
                   help="measure every method's errors against one reference, the nodal P2 solution K "
                        "levels finer than P2's finest studied level (a case without u: default 2 or its "
                        "own; a case with u: instead of u)")
    add_mesh_option(p)
    p.add_argument("--out", default="results", metavar="DIR")
    p.add_argument("--quiet", action="store_true", help="no progress bar or table")
    p.add_argument("--vtk", action="store_true",
                   help="also write every level's u_h (Omega) and contact fields (Gamma_C) for ParaView under DIR/vtk")
    add_engine_options(p)
    p.set_defaults(func=cmd_run)


def _add_sweep(sub) -> None:
    from .measure.reference import REFERENCE_METHOD as reference
    from .study.sweep import REPORT_SWEEP, SWEEP_VALUES
    p = sub.add_parser("sweep", help=COMMANDS["sweep"])
    p.add_argument("--case", required=True, metavar="NAME|PATH")
    p.add_argument("--method", action="append", type=_method_spec, required=True, metavar="METHOD",
                   help=f"a method with a parameter (penalty, Nitsche), e.g. {', '.join(REPORT_SWEEP['methods'])}; "
                        "repeat for several")
    p.add_argument("--values", type=_values, default=list(SWEEP_VALUES), metavar="V1,V2,...",
                   help="values of its first parameter (gamma0 or epsilon0; default: %(default)s)")
    p.add_argument("--level", type=_non_negative_int, default=4, help="the P2 level (P1: the level with as many dofs)")
    p.add_argument("--reference", default=reference, type=lambda t: t if t == "none" else _method_spec(t),
                   help="a method drawn as the reference line (default %(default)s), or 'none'")
    p.add_argument("--out", default="results/sweep", metavar="DIR")
    p.add_argument("--quiet", action="store_true")
    p.set_defaults(func=cmd_sweep)


def _add_rates(sub) -> None:
    p = sub.add_parser("rates", help=COMMANDS["rates"])
    p.add_argument("results", metavar="RESULTS.csv")
    p.add_argument("--fit-levels", type=_positive_int, default=3, help="levels in the asymptotic fit (>= 3)")
    p.add_argument("--case", action="append", metavar="PATH",
                   help="case file, for results of harness 0.1 (a `model` column) of unregistered cases")
    p.add_argument("--latex", action="store_true",
                   help="print booktabs LaTeX tables (the rates, then each case's levels) instead of text")
    p.add_argument("--qoi", action="store_true",
                   help="the quantities of interest instead: observed order, Richardson's extrapolation and the grid "
                        "convergence index of each; writes quantities.csv")
    p.set_defaults(func=cmd_rates)


def _add_report(sub) -> None:
    p = sub.add_parser("report", help=COMMANDS["report"])
    p.add_argument("--profile", default="default", choices=["default", "fine"])
    p.add_argument("--levels", type=_positive_int, help="override the profile's number of levels")
    p.add_argument("--case", action="append", metavar="NAME", help="only these registered cases")
    add_method_options(p)
    p.add_argument("--results", default="results", metavar="DIR")
    p.add_argument("--report", default="report", metavar="DIR")
    p.add_argument("--quiet", action="store_true")
    p.add_argument("--vtk", action="store_true",
                   help="also write every level's solutions for ParaView under RESULTS/vtk (reruns stored cases without them)")
    add_engine_options(p)
    p.set_defaults(func=cmd_report)


def _add_bench(sub) -> None:
    from .bench.command import bench_names
    from .measure.reference import REFERENCE_METHOD as reference
    from .methods import PAPER, role_names
    p = sub.add_parser("bench", help=COMMANDS["bench"])
    p.add_argument("--sizes", type=_sizes, default=None, metavar="MAXH:LEVEL,...",
                   help="coarse mesh size and level of each problem (default: 9e3 to 4.2e6 dofs)")
    p.add_argument("--method", action="append", choices=_method_names(),
                   help=f"default: {' and '.join(role_names(PAPER))} (the paper's); a penalty or Nitsche method adds its rows (one "
                        f"solve against one {reference} solve)")
    p.add_argument("--only", choices=bench_names(),
                   help="only the study row, only the solver table, only the elastic rows, only the 3D rows, only the "
                        "adaptive rows, only the two-body (mortar) rows, only the runs beside a busy process (load), or "
                        "only the report's profile (not part of the default run: a whole `make report` per variant)")
    p.add_argument("--workers", type=_non_negative_int, action="append", metavar="N",
                   help="with --only report: the variants, 0 = in this process, N = N local worker processes "
                        "(repeatable; default 0; ratios against the first)")
    p.add_argument("--out", default="results/bench.csv", metavar="CSV",
                   help="the solver table; the study row goes beside it, as <name>_study.csv")
    p.set_defaults(func=cmd_bench)


# An except clause's classes are looked up only when an exception reaches it: the study's
# modules are imported then, not at start-up.
def _bad_input() -> tuple:
    from .study.files import OutputError
    return (BadInput, ValueError, FileNotFoundError, OutputError)       # CaseError is a ValueError


def _engine_errors() -> tuple:
    from .study.dask_engine import SchedulerUnreachable
    from .study.processes import WorkerDied
    return (SchedulerUnreachable, WorkerDied)


def main(argv=None) -> int:
    """Every failure ends as one line on stderr and a non-zero exit: 2 for bad input (before
    anything on disk is touched), 1 for a run that failed; ``--debug`` (anywhere on the line)
    lets the exception through with its traceback."""
    argv = list(sys.argv[1:] if argv is None else argv)
    debug = "--debug" in argv
    argv = [arg for arg in argv if arg != "--debug"]
    try:
        args = build_parser(argv).parse_args(argv)
        return args.func(args)
    except _bad_input() as exc:
        if debug:
            raise
        print(f"harness: error: {exc}", file=sys.stderr)
        return EXIT_BAD_INPUT
    except _engine_errors() as exc:
        if debug:
            raise
        print(f"harness: error: {exc}", file=sys.stderr)
        return EXIT_FAILED
    except KeyboardInterrupt:
        print("harness: interrupted; no results file was written (run and report continue from their last finished level when started again)", file=sys.stderr)
        return 130
    except Exception as exc:
        if debug:
            raise
        print(f"harness: error: {type(exc).__name__}: {exc} (run with --debug for the traceback)", file=sys.stderr)
        return EXIT_FAILED
