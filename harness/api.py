"""The Python API, for scripts and notebooks: what ``python -m harness`` does, as functions.

    >>> import harness
    >>> rows = harness.run(["transition-r32"], methods="paper", levels=4, out="results")
    >>> harness.rates(rows)             # fitted rates, each against its theorem, with a verdict
    >>> harness.quantities(rows)        # quantities of interest with Richardson/GCI bands
    >>> harness.efficiency(rows)        # cost at equal accuracy against the P1 baseline
    >>> harness.plot(rows)              # a Matplotlib figure: H^1 error against h
    >>> harness.report(cases=["transition-r32"], methods=["paper"], levels=3)
    >>> harness.export("transition-r32", levels=5, out="export")   # for another code to solve

Every function takes rows (a DataFrame of ``run``, or a results folder or file) and returns a
table, a figure or a path; ``out=`` writes what the command line writes, into a folder that one
command owns at a time. The command line calls these functions and adds only argument parsing
and printing.
"""
from __future__ import annotations

import warnings
from pathlib import Path
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    import pandas as pd

# Every stage is imported by the function that needs it: listing the cases must not cost
# pandas, SciPy or the methods' modules (``harness/__init__``).


class StudyWarning(UserWarning):
    """A case, method or mesh strategy a study leaves out, and why (the command line prints it as
    one ``harness:`` line)."""


def run(cases, methods="all", levels: int = 5, meshes="uniform", *, out=None, reference_levels: int | None = None,
        engine=None, checkpoints=None, vtk: bool = False, show_progress: bool = True, on_level=None,
        check_memory: bool = True) -> pd.DataFrame:
    """Run a convergence study: one row per case x method x mesh x level (the columns of
    ``docs/guide/results.md``).

    ``cases``: names, groups ('paper', 'all', '3d', ...: ``harness.problem.case.case_groups``),
    case files, modules or ``Case`` objects (or one of them), each case run once. ``methods``:
    names, groups ('paper', 'weak', ...), 'all', parameters (``nitsche:gamma0=0.1``), files or
    modules of your own, or ``Method`` objects. ``meshes``: "uniform", "graded", "adaptive"
    ("adaptive:theta=0.3"), "hp" ("hp:sigma=0.15,mu=1"), "all" (the first three), a strategy of
    your own or a list of them; each case runs on
    each strategy that meshes it. ``out``: a results folder, owned by this run while it lasts
    (another command's folder is refused before anything is computed); every finished level is
    made durable there (run again to resume), and the rows are merged by key into its
    results.csv, as ``python -m harness run --out`` does. ``reference_levels``: measure every
    method against one nodal P2 reference that many levels finer. ``engine``: where the jobs run
    (``harness.LocalProcesses(2)``, ``harness.DaskEngine(scheduler=...)``; default this
    process). ``checkpoints``: a folder for the durable levels when there is no ``out``.
    ``vtk``: write every level's solutions for ParaView under ``out``/vtk. Cases, methods and
    meshes a study leaves out are named in a ``StudyWarning``. Input is refused (ValueError,
    ``CaseError``, ``FolderBusy``) before anything is computed; an error once the study has
    started is a ``StudyFailed`` (``harness.study.storage.store``) whose cause is the error."""
    from .study import InProcess, run_study
    from .study.execution.engines import study_jobs
    loaded, chosen, strategies = _study_inputs(cases, methods, meshes, reference_levels)
    engine = engine or InProcess()
    if vtk and out is None:
        raise ValueError("vtk=True writes under the results folder: give out=")
    if vtk and on_level is not None:
        raise ValueError("vtk=True is an on_level hook of its own: give one of them")
    if out is not None and checkpoints is not None:
        raise ValueError("a run with out= keeps its checkpoints in out/.checkpoints: give out= or checkpoints=, not both")
    # refused before a folder is touched or a worker started
    study_jobs(loaded, chosen, levels, engine, on_level, check_memory=check_memory, meshes=strategies)
    _warn_left_out(loaded, chosen, strategies, methods)
    from .study.execution.into_folder import run_into
    from .study.storage.store import study_phase
    if out is None:
        with study_phase():
            frame = run_study(loaded, chosen, levels, show_progress=show_progress, on_level=on_level, engine=engine,
                              checkpoints=checkpoints, check_memory=False, meshes=strategies)
        return _summary(frame, loaded, chosen, strategies)
    if vtk:
        from .report.vtk import VtkWriter
        on_level = VtkWriter(Path(out) / "vtk")
    frame, stored = run_into(out, loaded, chosen, levels, engine=engine, meshes=strategies, show_progress=show_progress,
                             on_level=on_level)
    _summary(frame, loaded, chosen, strategies)
    frame.attrs["stored"] = stored.summary() + "".join(f"; left out: {line}" for line in frame.attrs["left_out"][:1]) + \
        (f" and {len(frame.attrs['left_out']) - 1} more (attrs['left_out'])" if len(frame.attrs["left_out"]) > 1 else "")
    return frame


def _study_inputs(cases, methods, meshes, reference_levels):
    """(cases, methods, mesh strategies) of ``run``'s arguments, each parsed or loaded."""
    from .mesh.strategies import parse_meshes
    from .methods import methods_named
    from .problem.case import Case, expand_groups, load_case
    if isinstance(cases, (str, Path, Case)):
        cases = [cases]
    loaded = [c if isinstance(c, Case) else load_case(str(c)) for c in expand_groups(cases)]
    if reference_levels:
        loaded = [case.with_reference(reference_levels) for case in loaded]
    chosen = methods_named(methods)             # a name, a group, a Method, or a list of them
    strategies = parse_meshes(list(meshes) if isinstance(meshes, (list, tuple)) else [meshes])
    return loaded, chosen, strategies


def _warn_left_out(cases, methods, meshes, asked) -> None:
    """A ``StudyWarning`` per mesh strategy a case cannot have, and per method named one by one
    (not through a group) that discretises none of the cases or that a strategy's meshes cannot
    carry."""
    from .methods import GROUPS, Method
    from .study.execution.refusals import left_out
    asked = [asked] if isinstance(asked, (str, Method)) else list(asked)
    named = {a if isinstance(a, str) else a.name for a in asked if not (isinstance(a, str) and (a == "all" or a in GROUPS))}
    for line in left_out(cases, [m for m in methods if m.name in named], meshes):
        warnings.warn(line, StudyWarning, stacklevel=3)


def _summary(frame, cases, methods, meshes):
    """``frame`` with what the study left out and why (``attrs["left_out"]``: one line each)."""
    from .study.execution.refusals import left_out
    frame.attrs["left_out"] = left_out(cases, methods, meshes, partial=True)
    return frame


def rows_of(rows) -> pd.DataFrame:
    """A study's rows: a DataFrame as it is, or the results.csv of a folder or the file itself."""
    import pandas as pd
    if isinstance(rows, pd.DataFrame):
        return rows
    from .measure.results_file import read_results
    path = Path(rows)
    return read_results(path / "results.csv" if path.is_dir() else path)


def _written(table: pd.DataFrame, out, name: str) -> pd.DataFrame:
    """``table``, written as ``out``/``name`` (while this process owns the folder) if ``out``."""
    if out is not None:
        from .study.storage.files import write_csv
        from .study.storage.folder import owned
        with owned(Path(out)) as folder:
            table.attrs["path"] = str(write_csv(table, folder / name))
    return table


def rates(rows, fit_levels: int = 3, *, out=None) -> pd.DataFrame:
    """One row per (case, mesh, method): the H^1 rate fitted over the last ``fit_levels`` levels
    against the rate its theorem predicts, with a verdict (the columns of rates.csv); ``out``:
    also write rates.csv there."""
    from .measure.rates import rate_table
    return _written(rate_table(rows_of(rows), levels=fit_levels), out, "rates.csv")


def quantities(rows, *, out=None) -> pd.DataFrame:
    """One row per quantity of interest and chain of three levels or more: observed order,
    Richardson's extrapolation and the grid convergence index band (the columns of
    quantities.csv); ``out``: also write quantities.csv there."""
    from .measure.richardson import quantity_table
    frame = rows_of(rows)
    table = quantity_table(frame)
    if table.empty:
        raise ValueError("no chain with quantities of interest on three levels or more")
    return _written(table, out, "quantities.csv")


def efficiency(rows, mesh: str = "uniform", baseline: str | None = None, methods=()) -> pd.DataFrame:
    """One row per (case, method) on ``mesh``'s rows: the dofs and seconds that reach the case's
    target error, and the baseline's cost over each method's (by default the method with the
    role BASELINE, P1; ``methods``: Method objects of your own whose roles count)."""
    from .measure.efficiency import efficiency_table
    frame = rows_of(rows)
    if "mesh" in frame:
        frame = frame[frame["mesh"].fillna("uniform") == mesh]
    if frame.empty:
        raise ValueError(f"no rows on {mesh} meshes")
    return efficiency_table(frame, baseline, methods)


PLOTS = ("convergence", "verdicts", "rates")


def plot(rows, case: str | None = None, kind: str = "convergence", ax=None):
    """A Matplotlib figure of the rows (a notebook shows it), or drawn into ``ax``. ``kind``:
    "convergence", the H^1 error of every method of ``case`` (needed when the rows hold several)
    against h on uniform meshes, with each theorem's bound dashed and a slope triangle;
    "verdicts", the matrix cases x methods of fitted / expected rates, coloured by verdict;
    "rates", the fitted rates against the expected ones."""
    from .report import plots
    frame = rows_of(rows)
    if kind == "convergence":
        return plots.convergence(frame, case, ax=ax)
    if kind == "verdicts":
        return plots.verdict_matrix(rates(frame), ax=ax)
    if kind == "rates":
        return plots.rate_summary(rates(frame), ax=ax)
    raise ValueError(f"unknown kind of plot {kind!r}: one of {', '.join(PLOTS)}")


def store(rows, folder) -> Path:
    """``rows`` merged into ``folder``/results.csv by key (case, method, parameters, mesh, level:
    a row computed again replaces the earlier one, every other is kept), while this process owns
    the folder (another command's folder is refused before anything is written); the file's
    path. ``harness.run(out=...)`` stores its rows so."""
    from .study.storage.store import store_rows
    return store_rows(rows_of(rows), folder).path


def sweep(case, methods, values=None, level: int = 4, *, reference=True, out=None, engine=None,
          show_progress: bool = True) -> pd.DataFrame:
    """A parameter sweep: each of ``methods`` (with a parameter: "penalty", "nitsche:theta=-1",
    ...) at every value of its first parameter (gamma0 or eps0; ``values``: default
    ``study.planning.sweep.SWEEP_VALUES``), on level ``level`` of ``case`` (P1 methods: their level
    with about the same dofs), beside a reference method (``reference``: True, the reference of
    ``measure.reference``; a method's name; None, none); one
    row per method and value, with its swept method, parameter and value (``sweep_*`` columns).
    ``out``: a folder, owned by this call while it lasts, where sweep_CASE.csv and its figure
    (sweep_CASE.png) are written, as ``python -m harness sweep`` does (their paths in
    ``attrs["path"]`` and ``attrs["figure"]``). A method without a parameter is refused
    (ValueError) before anything is computed or written."""
    from .measure.reference import REFERENCE_METHOD
    from .problem.case import Case, load_case
    from .study.planning.sweep import SWEEP_VALUES, run_sweep, swept
    from .study.storage.store import study_phase
    case = case if isinstance(case, Case) else load_case(str(case))
    methods = [methods] if isinstance(methods, str) else list(methods)
    values = list(SWEEP_VALUES if values is None else values)
    for spec in methods:
        swept(spec, values)
    references = [] if reference in (None, False, "none") else [REFERENCE_METHOD if reference is True else reference]
    if out is None:
        with study_phase():
            return run_sweep(case, methods, values, level, reference=references, show_progress=show_progress,
                             engine=engine)
    return _sweep_into(Path(out), case, methods, values, level, references, engine, show_progress)


def _sweep_into(out: Path, case, methods, values, level, references, engine, show_progress) -> pd.DataFrame:
    """``sweep`` with ``out``: the rows and their figure written there while this process owns it."""
    from .report import figures
    from .study.planning.sweep import run_sweep
    from .study.storage.files import write_csv
    from .study.storage.folder import owned
    from .study.storage.store import study_phase
    with owned(out) as folder:
        with study_phase():
            frame = run_sweep(case, methods, values, level, reference=references, show_progress=show_progress,
                              engine=engine)
        frame.attrs["path"] = write_csv(frame, folder / f"sweep_{case.name}.csv")
        frame.attrs["figure"] = figures.sweep(case, frame, folder)["png"]
    return frame


def export(case, levels: int = 5, out="export", *, order: int = 2, progress=None, formats=("npz", "vtu", "msh")) -> Path:
    """Write ``levels`` uniform levels of ``case`` (a name, a case file or a ``Case``) for another
    finite element code: per level the mesh, the P_``order`` Lagrange nodes, the data there, the
    right-hand side as moments against the Lagrange basis, the discrete Dirichlet values and the
    exact solution (docs/guide/measure-your-code.md); returns the manifest's path. ``progress(level,
    path)`` is called per level; ``formats``: .npz always, .vtu and .msh (meshio) if named. The
    other code's solutions come back as the method ``external:DIR`` (``external``)."""
    from .problem.case import Case, load_case
    from .study.export import export as write
    return write(case if isinstance(case, Case) else load_case(str(case)), levels, out, order=order, progress=progress,
                 formats=tuple(formats))


def coulomb_axis(case="elastic-coulomb-r32", coefficients=(0.1, 0.3, 0.5, 1.0, 2.0, 5.0), level: int = 3,
                 method: str | None = None, *, show_progress: bool = False) -> pd.DataFrame:
    """The friction coefficient as an axis of a Coulomb case (a Case, a registered name or a
    file): for each mu_F the case's data with ``Coulomb(mu_F)``, solved to ``level`` by
    ``method``'s coupled semismooth Newton method (nested, GMRES with multigrid) and, on that
    level from the same start, by the fixed point over Tresca problems (``method`` default: the
    first P2 contact law of the role reference, Nitsche's: ``study.planning.coulomb_axis.law_method``). One row per mu_F: each
    solver's status, iterations and residual, the stick/slip/separated Gauss points and the
    largest relative difference of the two solutions (two converged solvers that disagree: two
    discrete solutions)."""
    from .study.planning.coulomb_axis import coefficient_axis
    return coefficient_axis(tuple(coefficients), level, case, method, progress=print if show_progress else (lambda line: None))


def latex_tables(rows, fit_levels: int = 3) -> str:
    """The rates (``rates``) and each case's levels as booktabs LaTeX tables, one after the
    other, as ``python -m harness rates --latex`` prints them."""
    from .report import latex
    frame = rows_of(rows)
    table = rates(frame, fit_levels)
    return "\n".join([latex.summary_table(table), *(latex.convergence_table(frame, case) for case in frame.case.unique())])


def report(cases=None, methods=("all",), levels: int | None = None, profile: str = "default", results="results",
           out="report", engine=None, show_progress: bool = True, vtk: bool = False, check_memory: bool = True) -> Path:
    """The report of ``profile`` ("default" or "fine") into ``out``/report.html, its study's
    rows merged into ``results``/results.csv (rows already there and unchanged are reused).
    ``cases``: registered case names or groups (default: the profile's); ``methods``: as ``run`` takes
    them, your own objects included; ``levels``: instead of the profile's. Both folders are owned
    by this call while it runs. Returns the HTML's path.

        >>> harness.report(cases=["transition-r32"], methods=["paper", my_method], levels=3)
    """
    from .problem.case import expand_groups
    from .report.build import make_report
    cases = expand_groups(cases) if cases else cases        # a group ("paper"): its cases' names
    return make_report(profile, Path(results), Path(out), cases, show_progress=show_progress, levels=levels,
                       methods=methods, engine=engine, check_memory=check_memory, vtk=vtk)


def case_rows(cases=None) -> list[dict]:
    """One dict per case: regularity, theorem, the rate it predicts and its groups besides "all"
    (``case_table``'s rows)."""
    from .problem.case import fraction, registered_cases
    cases = list(registered_cases().values()) if cases is None else cases
    return [{
        "case": c.name, "nu": fraction(c.nu), "regime": c.regime, "theorem": c.theorem,
        "expected_rate": c.expected_rate, "expected_log_exponent": c.expected_log_exponent,
        "bound": c.expected_bound, "groups": " ".join(c.groups), "description": c.description,
    } for c in cases]


def method_rows() -> list[dict]:
    """One dict per registered method: order, how it imposes contact, where it comes from."""
    from .methods import METHODS
    return [{"method": m.name, "order": m.order, "contact condition": m.contact,
             "parameters": m.parameter_text, "reference": m.reference} for m in METHODS.values()]


def method_table() -> pd.DataFrame:
    """One row per method: order, how it imposes contact, where it comes from."""
    import pandas as pd
    return pd.DataFrame(method_rows())


def case_table(cases=None) -> pd.DataFrame:
    """One row per case: regularity, theorem, the rate it predicts and its groups (the columns of
    ``python -m harness cases``)."""
    import pandas as pd
    return pd.DataFrame(case_rows(cases))


def cases(cases=None) -> pd.DataFrame:
    """``case_table`` under a second name: deprecated (a DeprecationWarning), removed in 0.12."""
    warnings.warn("harness.cases() is harness.case_table() since 0.11.0", DeprecationWarning, stacklevel=2)
    return case_table(cases)
