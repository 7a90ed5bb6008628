"""The command line's options, command by command: what each accepts and its help (``cli``
runs the commands). Only the command given has its options built: `run`'s import the methods,
which listing the cases does not need."""
from __future__ import annotations

import argparse


def _checked(convert, what: str):
    """An argparse type: ``convert(text)``, or argparse's one-line refusal saying ``what`` (a
    converter with words of its own raises ArgumentTypeError itself)."""
    def parse(text: str):
        try:
            return convert(text)
        except (ValueError, TypeError):
            raise argparse.ArgumentTypeError(f"{what}, got {text!r}") from None
    return parse


def _at_least(low: int):
    def convert(text):
        if int(text) < low:
            raise ValueError
        return int(text)
    return convert


def _values(text: str) -> list[float]:
    values = [float(v) for v in text.split(",") if v.strip()]
    if not values or any(not v > 0 for v in values):
        raise ValueError
    return values


def _sizes(text: str) -> list[tuple[float, int]]:
    sizes = [(float(h), int(level)) for h, level in (item.split(":") for item in text.split(","))]
    if not sizes or any(h <= 0 or level < 0 for h, level in sizes):
        raise ValueError
    return sizes


def _method_spec(text: str) -> str:
    from .methods import methods_named
    try:
        methods_named([text])
    except ValueError as exc:
        raise argparse.ArgumentTypeError(str(exc))
    return text


def _mesh_list(text: str) -> list:
    from .mesh.strategies import parse_mesh
    try:
        return parse_mesh(text)
    except ValueError as exc:
        raise argparse.ArgumentTypeError(str(exc))


POSITIVE = _checked(_at_least(1), "must be a positive integer")
LEVEL = _checked(_at_least(0), "level must be a non-negative integer")
VALUES = _checked(_values, "values must be positive comma-separated numbers")
SIZES = _checked(_sizes, "sizes must look like 0.25:3,0.25:4 (coarse maxh > 0 : level >= 0)")


def _parameter_example() -> str:
    """A registered method with parameters, as --method takes it (the one with the most
    parameters, a one-body method first: its first 0.1, the next -1)."""
    from .methods import METHODS
    with_parameters = [m for m in METHODS.values() if m.parameters]
    if not with_parameters:
        return "name:parameter=value"
    method = max(with_parameters, key=lambda m: (len(m.parameters), m.bodies == (1,)))
    return f"{method.name}:" + ",".join(f"{key}={value:g}" for key, value in zip(method.parameters, (0.1, -1.0)))


def _method_option(p, required: bool = False, help: str | None = None) -> None:
    from .methods import GROUPS, METHODS
    p.add_argument("--method", action="append", type=_checked(_method_spec, "not a method"), metavar="METHOD",
                   required=required,
                   help=help or f"a method ({', '.join(METHODS)}), a group ({', '.join(GROUPS)}) or 'all' (the default), "
                                f"a method with parameters, e.g. {_parameter_example()}, or one of your own: "
                                f"path/to/file.py[:name], package.module[:name] or an installed one's name; repeat for several")


def _engine_options(p) -> None:
    group = p.add_mutually_exclusive_group()
    group.add_argument("--workers", type=POSITIVE, metavar="N",
                       help="run the jobs (one per case, the largest split by order) on N local worker processes")
    group.add_argument("--scheduler", metavar="ADDRESS",
                       help="run the jobs on an existing Dask cluster, e.g. tcp://10.0.0.1:8786 (docs: Running studies)")
    p.add_argument("--threads", type=POSITIVE, metavar="T",
                   help="NGSolve and BLAS threads per process on every level (default: per level, 1 below 4e4 dofs, else "
                        "the usable cores other processes leave free; cores / N with --workers; 1 with --scheduler; "
                        "HARNESS_THREADS=T sets a default); with 1, results are reproducible bit for bit")
    p.add_argument("--skip-memory-check", action="store_true",
                   help="run even if the estimated peak memory exceeds the machine's (or a worker's)")


def add_run(p):
    p.add_argument("--case", action="append", required=True, metavar="NAME|GROUP|PATH",
                   help="a registered case name, a group of them ('paper', 'all', '3d', ...: see `cases`) "
                        "or a case file; repeat for several")
    _method_option(p)
    p.add_argument("--levels", type=POSITIVE, default=5, help="number of mesh levels (0..L-1)")
    p.add_argument("--reference-levels", type=POSITIVE, metavar="K",
                   help="measure every method's errors against one reference, the nodal P2 solution K levels finer "
                        "than P2's finest studied level (a case without u: default 2 or its own; a case with u: instead of u)")
    p.add_argument("--mesh", action="append", type=_checked(_mesh_list, "not a mesh strategy"), metavar="STRATEGY",
                   help="uniform (the default), graded (Remark 4.4), adaptive (Dörfler, adaptive:theta=0.3), hp (geometric layers "
                        "and degrees, hp:sigma=0.15,mu=1), all (uniform, graded, adaptive), or a "
                        "strategy of your own (path/to/file.py[:name], package.module[:name], an installed one's label); "
                        "repeat for several")
    p.add_argument("--out", default="results", metavar="DIR")
    p.add_argument("--quiet", action="store_true", help="no progress bar or table")
    p.add_argument("--vtk", action="store_true",
                   help="also write every level's u_h (Omega) and contact fields (Gamma_C) for ParaView under DIR/vtk")
    _engine_options(p)
    return p


def add_sweep(p):
    from .measure.reference import REFERENCE_METHOD as reference
    from .study.planning.sweep import REPORT_SWEEP, SWEEP_VALUES
    p.add_argument("--case", required=True, metavar="NAME|PATH")
    _method_option(p, required=True, help=f"a method with a parameter (penalty, Nitsche), e.g. "
                                          f"{', '.join(REPORT_SWEEP['methods'])}; repeat for several")
    p.add_argument("--values", type=VALUES, default=list(SWEEP_VALUES), metavar="V1,V2,...",
                   help="values of its first parameter (gamma0 or epsilon0; default: %(default)s)")
    p.add_argument("--level", type=LEVEL, default=4, help="the P2 level (P1: the level with as many dofs)")
    p.add_argument("--reference", default=reference, metavar="METHOD",
                   type=lambda t: t if t == "none" else _checked(_method_spec, "not a method")(t),
                   help="a method drawn as the reference line (default %(default)s), or 'none'")
    p.add_argument("--out", default="results/sweep", metavar="DIR")
    p.add_argument("--quiet", action="store_true")
    return p


def add_rates(p):
    p.add_argument("results", metavar="RESULTS.csv")
    p.add_argument("--fit-levels", type=POSITIVE, default=3, help="levels in the asymptotic fit (>= 3)")
    p.add_argument("--latex", action="store_true",
                   help="print booktabs LaTeX tables (the rates, then each case's levels) instead of text")
    p.add_argument("--qoi", action="store_true",
                   help="the quantities of interest instead: observed order, Richardson's extrapolation and the grid "
                        "convergence index of each; writes quantities.csv")
    return p


def add_report(p):
    from .study.chain import PROFILES
    p.add_argument("--profile", default="default", choices=list(PROFILES))
    p.add_argument("--levels", type=POSITIVE, help="override the profile's number of levels")
    p.add_argument("--case", action="append", metavar="NAME|GROUP",
                   help="only these registered cases (a group: its cases; see `cases`)")
    _method_option(p)
    p.add_argument("--results", default="results", metavar="DIR")
    p.add_argument("--report", default="report", metavar="DIR")
    p.add_argument("--quiet", action="store_true")
    p.add_argument("--vtk", action="store_true",
                   help="also write every level's solutions for ParaView under RESULTS/vtk (reruns stored cases without them)")
    _engine_options(p)
    return p


def add_bench(p):
    from .bench.command import bench_names
    from .measure.reference import REFERENCE_METHOD as reference
    from .methods import METHODS, PAPER, role_names
    p.add_argument("--sizes", type=SIZES, default=None, metavar="MAXH:LEVEL,...",
                   help="coarse mesh size and level of each problem (default: 9e3 to 4.2e6 dofs)")
    p.add_argument("--method", action="append", choices=list(METHODS),
                   help=f"default: {' and '.join(role_names(PAPER))} (the paper's); a penalty or Nitsche method adds its "
                        f"rows (one solve against one {reference} solve)")
    p.add_argument("--only", choices=bench_names(),
                   help="only the study row, only the solver table, only the elastic rows, only the 3D rows, only the "
                        "adaptive rows, only the two-body (mortar) rows, only the degree or friction rows, only the runs beside "
                        "a busy process (load), only DOLFINx + PETSc against the harness on one exported problem (codes; "
                        "not part of the default run: it needs make .venv-dolfinx/.installed), or only the report's "
                        "profile (not part of the default run: a whole `make report` per variant)")
    p.add_argument("--workers", type=LEVEL, action="append", metavar="N",
                   help="with --only report: the variants, 0 = in this process, N = N local worker processes "
                        "(repeatable; default 0; ratios against the first)")
    p.add_argument("--out", default="results/bench.csv", metavar="CSV",
                   help="the solver table; the study row goes beside it, as <name>_study.csv")
    return p


def add_export(p):
    p.add_argument("--case", required=True, metavar="NAME|PATH", help="a registered case name or a case file (one body)")
    p.add_argument("--levels", type=POSITIVE, default=5, help="number of mesh levels (0..L-1)")
    p.add_argument("--order", type=int, choices=(1, 2), default=2, help="k of the P_k Lagrange nodes (default 2)")
    p.add_argument("--out", required=True, metavar="DIR",
                   help="a new or empty folder, or an earlier export (its files are replaced; any other folder is refused)")
    p.add_argument("--quiet", action="store_true", help="no line per level")
    return p


ADDERS = {"cases": lambda p: p, "methods": lambda p: p, "run": add_run, "sweep": add_sweep, "rates": add_rates,
          "report": add_report, "bench": add_bench, "export": add_export}
