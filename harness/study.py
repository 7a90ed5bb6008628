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
from .best import ritz_projection
from .errors import ContactErrors, error_norms
from .mesh import mesh_hierarchy, mesh_size
from .methods import Method
from .multigrid import Multilevel
from .quadrature import ElementQuadrature
from .validate import validate_case

COLUMNS = [
    "case", "method", "order", "parameters", "level", "h", "ndof", "n_contact_constraints", "err_h1", "err_h1_semi",
    "err_l2", "err_best_h1", "err_best_h1_semi", "err_h1_over_best", "err_trace_l2", "err_pressure_l2", "err_pressure_h12",
    "max_penetration", "max_tension", "min_pressure", "active_constraints", "solver_iterations", "linear_iterations",
    "kkt_residual", "solve_seconds", "total_seconds", "status",
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


def run_case(case: Case, methods: list[Method], levels: int, progress=None, on_level=None,
             phases: Phases | None = None) -> list[dict]:
    """Rows of one case; ``on_level(case, method, level, problem, solve)`` sees every solve
    (``solve``: a ``methods.LevelSolve``; the report keeps the finest solutions).

    Per level: one mesh, one discrete problem per finite element order shared by the methods
    of that order (the last of them takes its stiffness matrix), one error integration for all.
    ``total_seconds`` of a row: what the level costs a user of that method alone -- the
    refinement, its order's assembly, its own set-up and solve; not the error measurement.
    """
    phases = phases or Phases()
    carry: dict[str, tuple | None] = {m.name: None for m in methods}
    rows = []
    multilevel = None
    expectations = {m.name: m.expected(case) for m in methods}
    sharper = {m.name: m.sharper(case) for m in methods}
    total_levels = max(study_levels(m, levels) for m in methods)
    h = None
    with ngs.TaskManager():
        hierarchy = mesh_hierarchy(case, total_levels)
        for level in range(total_levels):
            clock = time.perf_counter()
            with phases("mesh"):
                _, mesh = next(hierarchy)
                multilevel = Multilevel(mesh) if multilevel is None else multilevel.refined()
                # red refinement halves every edge, so h halves exactly: measured once
                h = mesh_size(mesh) if level == 0 else h / 2
                quadrature = ElementQuadrature.of(case, mesh)
            mesh_seconds = time.perf_counter() - clock
            active = [m for m in methods if level < study_levels(m, levels)]
            problems, assembly_seconds, best, on_contact = {}, {}, {}, {}
            for order in sorted({m.order for m in active}, reverse=True):
                clock = time.perf_counter()
                with phases("assembly"):
                    problems[order] = discretise(case, mesh, order, quadrature)
                assembly_seconds[order] = time.perf_counter() - clock
                # the best approximation, before a method takes the stiffness matrix
                with phases("best"):
                    best[order] = ritz_projection(case, problems[order], multilevel)
                    on_contact[order] = ContactErrors(case, problems[order])
            level_rows, solutions = [], []
            for method in active:
                problem = problems[method.order]
                if progress is not None:
                    progress.set_postfix_str(f"{case.name} {method.name} level {level} ndof {problem.ndof}")
                last = method is [m for m in active if m.order == method.order][-1]
                clock = time.perf_counter()
                solve = method.solve(case, problem, carry[method.name], multilevel, take_stiffness=last, phases=phases)
                own_seconds = time.perf_counter() - clock
                carry[method.name] = solve.carry
                expectation = expectations[method.name]
                level_rows.append({
                    "case": case.name, "method": method.name, "order": method.order,
                    "parameters": method.parameter_text, "level": level, "h": h,
                    "ndof": problem.ndof, **solve.fields,
                    "total_seconds": mesh_seconds + assembly_seconds[method.order] + own_seconds,
                    "nu": case.nu, "expected_rate": expectation.rate, "expected_log_exponent": expectation.log_exponent,
                    "reference": expectation.reference, **_sharper(sharper[method.name]), "case_source": case.source,
                })
                with phases("errors"):
                    level_rows[-1] |= on_contact[method.order](solve.u)
                solutions.append(problem.gridfunction(solve.u))
                if on_level is not None:
                    with phases("hooks"):
                        on_level(case, method, level, problem, solve)
                if progress is not None:
                    progress.update(1)
            with phases("errors"):
                orders = list(best)
                errors = error_norms(case, solutions + [problems[k].gridfunction(best[k]) for k in orders], quadrature)
                best_errors = dict(zip(orders, errors[len(solutions):]))
            for row, norms in zip(level_rows, errors):
                best_norms = best_errors[row["order"]]
                rows.append(row | norms | {"err_best_h1": best_norms["err_h1"], "err_best_h1_semi": best_norms["err_h1_semi"],
                                           "err_h1_over_best": norms["err_h1"] / best_norms["err_h1"]})
    return rows


def _sharper(expectation) -> dict:
    """The row's second theory (``Method.sharper``), NaN where the method has none."""
    if expectation is None:
        return {"sharper_rate": float("nan"), "sharper_log_exponent": float("nan"), "sharper_reference": ""}
    return {"sharper_rate": expectation.rate, "sharper_log_exponent": expectation.log_exponent,
            "sharper_reference": expectation.reference}


def total_solves(methods: list[Method], levels: int) -> int:
    return sum(study_levels(m, levels) for m in methods)


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
    progress = progress_bar(len(cases) * total_solves(methods, levels), show_progress) if own else progress
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
