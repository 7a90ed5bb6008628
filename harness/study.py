"""A convergence study: case -> mesh hierarchy -> discrete problems -> methods -> solve ->
errors -> one tidy row per (case, method, level)."""
from __future__ import annotations

import time
from collections import defaultdict
from contextlib import contextmanager

import ngsolve as ngs
import pandas as pd
from tqdm import tqdm

from .case import Case
from .discrete import discretise
from .errors import ExactErrors
from .mesh import mesh_hierarchy, mesh_size
from .methods import Method
from .multigrid import Multilevel
from .quadrature import ElementQuadrature
from .reference import ReferenceErrors
from .validate import validate_case

COLUMNS = [
    "case", "method", "order", "parameters", "level", "h", "ndof", "n_contact_constraints", "err_h1", "err_h1_semi",
    "err_l2", "err_best_h1", "err_best_h1_semi", "err_h1_over_best", "err_trace_l2", "err_pressure_l2", "err_pressure_h12",
    "max_penetration", "max_tension", "min_pressure", "active_constraints", "solver_iterations", "linear_iterations",
    "kkt_residual", "solve_seconds", "total_seconds", "status",
    # what the errors are measured against: "exact" (u), or "reference" (the method's solution
    # on level reference_level, with its KKT residual and status)
    "errors_against", "reference_level", "reference_ndof", "reference_kkt_residual", "reference_status",
    # what `rates` needs to fit a results file on its own: the case and the method's theories
    "nu", "expected_rate", "expected_log_exponent", "reference",
    "sharper_rate", "sharper_log_exponent", "sharper_reference", "case_source",
]

ngs.ngsglobals.msg_level = 0

PROFILES = {
    # finest levels: about 5.8e5 dofs (transition geometry), well inside 10 minutes on 2 cores
    "default": {"levels": 7},
    # finest levels: about 2.3e6 dofs
    "fine": {"levels": 8},
}

# The phases of a study, in the order of the data flow; ``Phases`` sums the wall time of each.
PHASES = ("mesh", "assembly", "best", "setup", "solve", "errors", "hooks")


class Phases:
    """Wall seconds per phase of a study (``PHASES``): where a study spends its time."""

    def __init__(self):
        self.seconds: dict[str, float] = defaultdict(float)

    @contextmanager
    def __call__(self, phase: str):
        start = time.perf_counter()
        try:
            yield
        finally:
            self.seconds[phase] += time.perf_counter() - start

    def as_dict(self) -> dict[str, float]:
        return {phase: self.seconds.get(phase, 0.0) for phase in PHASES}



def study_levels(method: Method, levels: int) -> int:
    """Levels a method runs in a study of ``levels`` levels: more for P1, so that every method
    ends at about the same number of dofs (``methods.base.EXTRA_LEVELS``)."""
    return levels + method.extra_levels


def chain_levels(case: Case, method: Method, levels: int) -> int:
    """Levels a method solves for a case: its studied levels, then, for a case measured against
    a reference, k more (nested iteration all the way; the last is the reference)."""
    return study_levels(method, levels) + (0 if case.exact else case.reference_levels)


def run_case(case: Case, methods: list[Method], levels: int, progress=None, on_level=None,
             phases: Phases | None = None) -> list[dict]:
    """Rows of one case; ``on_level(case, method, level, problem, solve)`` sees every studied
    solve (``solve``: a ``methods.LevelSolve``; the report keeps the finest solutions).

    Per level: one mesh, one discrete problem per finite element order shared by the methods
    of that order (the last of them takes its stiffness matrix), one error measurement for all:
    ``errors.ExactErrors`` against u, or ``reference.ReferenceErrors`` against each method's
    solution k levels finer (the rows of a method get their errors when it gets there).
    ``total_seconds`` of a row: what the level costs a user of that method alone -- the
    refinement, its order's assembly, its own set-up and solve; not the error measurement.
    """
    phases = phases or Phases()
    carry: dict[str, tuple | None] = {m.name: None for m in methods}
    studied = {m.name: study_levels(m, levels) for m in methods}
    chain = {m.name: chain_levels(case, m, levels) for m in methods}
    measure = ExactErrors(case, phases) if case.exact else ReferenceErrors(studied, {m.name: m.order for m in methods}, case.reference_levels)
    rows, method_rows = [], {m.name: [] for m in methods}
    multilevel = None
    expectations = {m.name: m.expected(case) for m in methods}
    sharper = {m.name: m.sharper(case) for m in methods}
    h = None
    with ngs.TaskManager():
        hierarchy = mesh_hierarchy(case, max(chain.values()))
        for level in range(max(chain.values())):
            clock = time.perf_counter()
            with phases("mesh"):
                _, mesh = next(hierarchy)
                multilevel = Multilevel(mesh) if multilevel is None else multilevel.refined()
                # red refinement halves every edge, so h halves exactly: measured once
                h = mesh_size(mesh) if level == 0 else h / 2
                quadrature = ElementQuadrature.of(case, mesh)
            mesh_seconds = time.perf_counter() - clock
            active = [m for m in methods if level < chain[m.name]]
            problems, assembly_seconds = {}, {}
            for order in sorted({m.order for m in active}, reverse=True):
                clock = time.perf_counter()
                with phases("assembly"):
                    problems[order] = discretise(case, mesh, order, quadrature)
                assembly_seconds[order] = time.perf_counter() - clock
            # before a method takes the stiffness matrix (the best approximation needs it)
            measure.begin_level(level, mesh, problems, quadrature, multilevel)
            level_rows = []
            for method in active:
                problem = problems[method.order]
                stage = "" if level < studied[method.name] else " (reference chain)"
                if progress is not None:
                    progress.set_postfix_str(f"{case.name} {method.name} level {level}{stage} ndof {problem.ndof}")
                last = method is [m for m in active if m.order == method.order][-1]
                clock = time.perf_counter()
                solve = method.solve(case, problem, carry[method.name], multilevel, take_stiffness=last, phases=phases)
                own_seconds = time.perf_counter() - clock
                carry[method.name] = solve.carry
                row = None
                if level < studied[method.name]:
                    expectation = expectations[method.name]
                    row = {
                        "case": case.name, "method": method.name, "order": method.order,
                        "parameters": method.parameter_text, "level": level, "h": h,
                        "ndof": problem.ndof, **solve.fields,
                        "total_seconds": mesh_seconds + assembly_seconds[method.order] + own_seconds,
                        "nu": case.nu, "expected_rate": expectation.rate, "expected_log_exponent": expectation.log_exponent,
                        "reference": expectation.reference, **_sharper(sharper[method.name]), "case_source": case.source,
                        "errors_against": "exact" if case.exact else "reference",
                    }
                    level_rows.append(row)
                    method_rows[method.name].append(row)
                elif level == chain[method.name] - 1:
                    _reference_fields(method_rows[method.name], level, problem.ndof, solve.fields)
                with phases("errors"):
                    columns = measure.solved(method, level, problem, solve.u, row)
                if row is not None:
                    row.update(columns)
                    if on_level is not None:
                        with phases("hooks"):
                            on_level(case, method, level, problem, solve)
                if progress is not None:
                    progress.update(1)
            with phases("errors"):
                measure.end_level()
            rows += level_rows
    return rows


def _reference_fields(rows: list[dict], level: int, ndof: int, fields: dict) -> None:
    """What the rows of a method say about the reference they were measured against."""
    for row in rows:
        row.update({"reference_level": level, "reference_ndof": ndof,
                    "reference_kkt_residual": fields["kkt_residual"], "reference_status": fields["status"]})


def _sharper(expectation) -> dict:
    """The row's second theory (``Method.sharper``), NaN where the method has none."""
    if expectation is None:
        return {"sharper_rate": float("nan"), "sharper_log_exponent": float("nan"), "sharper_reference": ""}
    return {"sharper_rate": expectation.rate, "sharper_log_exponent": expectation.log_exponent,
            "sharper_reference": expectation.reference}


def total_solves(cases: list[Case], methods: list[Method], levels: int) -> int:
    """Solves of a study, reference chains included: the length of its progress bar."""
    return sum(chain_levels(case, m, levels) for case in cases for m in methods)


def progress_bar(total: int, show: bool = True):
    """Progress of a study: case, model, level and ndof of the running solve, elapsed time."""
    return tqdm(total=total, disable=not show, unit="solve", dynamic_ncols=True)


def run_study(cases: list[Case], methods: list[Method], levels: int, show_progress: bool = True,
              on_level=None, progress=None) -> pd.DataFrame:
    """Every case x method x level; one tidy row each (columns ``COLUMNS``). ``levels`` counts
    the P2 levels (P1 runs one more: ``study_levels``). ``progress``: a bar shared with a
    larger run (else one is made)."""
    if levels < 1:
        raise ValueError(f"levels must be a positive integer, got {levels}")
    for case in cases:
        validate_case(case)
    rows = []
    start = time.perf_counter()
    phases = Phases()
    own = progress is None
    progress = progress_bar(total_solves(cases, methods, levels), show_progress) if own else progress
    try:
        for case in cases:
            rows += run_case(case, methods, levels, progress, on_level, phases)
    finally:
        if own:
            progress.close()
    frame = pd.DataFrame(rows, columns=COLUMNS)
    frame.attrs["wall_seconds"] = time.perf_counter() - start
    frame.attrs["phase_seconds"] = phases.as_dict()
    return frame
