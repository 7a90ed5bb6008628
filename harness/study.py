"""A convergence study: case -> mesh hierarchy -> discrete problem -> contact model -> solve
-> errors -> one tidy row per (case, model, level)."""
from __future__ import annotations

import time
from collections import defaultdict
from contextlib import contextmanager

import ngsolve as ngs
import pandas as pd
from tqdm import tqdm

from .case import Case
from .discrete import discretise
from .errors import error_norms, max_penetration
from .mesh import mesh_hierarchy, mesh_size
from .models import ContactModel, contact_qp
from .multigrid import Multilevel, nested_start
from .solver import solve_contact_qp
from .validate import validate_case

COLUMNS = [
    "case", "model", "level", "h", "ndof", "n_contact_constraints", "err_h1", "err_h1_semi",
    "err_l2", "max_penetration", "active_constraints", "solver_iterations", "kkt_residual",
    "solve_seconds", "status",
]

ngs.ngsglobals.msg_level = 0

PROFILES = {
    # finest levels: about 5.8e5 dofs (transition geometry), well inside 10 minutes on 2 cores
    "default": {"levels": 7},
    # finest levels: about 2.3e6 dofs
    "fine": {"levels": 8},
}

# The phases of a study, in the order of the data flow; ``Phases`` sums the wall time of each.
PHASES = ("mesh", "assembly", "setup", "solve", "errors", "hooks")


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



def solve_level(case: Case, problem, model: ContactModel, previous=None, multilevel=None, coarse_vertex_values=None,
                phases: Phases | None = None, last: bool = False):
    """Solve one model on one level; return the row's solver fields, u_h, its trace on Gamma_C
    and the solution (the errors of all models of a level come after, in one pass: ``run_case``).

    Nested iteration: ``previous`` (the coarser level's trace on Gamma_C) predicts the active
    set, ``coarse_vertex_values`` (its u_h at the vertices) gives the multigrid its start.
    ``last``: the level's last model, which takes the stiffness matrix's memory for its own.
    """
    phases = phases or Phases()
    with phases("setup"):
        qp = contact_qp(case, problem, model, take_stiffness=last)
        start = None
        if multilevel is not None and coarse_vertex_values is not None:
            start = nested_start(multilevel, coarse_vertex_values, problem)
        predicted = qp.predicted_active(previous)
    with phases("solve"):
        solution = solve_contact_qp(qp, predicted, multilevel=multilevel, start=start)
    with phases("errors"):
        u = qp.to_u(solution.z)
        trace_u = qp.trace_function(u, solution.active)
        row = {
            "n_contact_constraints": len(qp.C),
            "max_penetration": max_penetration(case, problem.mesh, trace_u),
            "active_constraints": int(solution.active.sum()),
            "solver_iterations": solution.iterations,
            "kkt_residual": solution.kkt.residual,
            "solve_seconds": solution.seconds,
            "status": solution.status,
        }
    return row, u, trace_u, solution


def run_case(case: Case, models: list[ContactModel], levels: int, progress=None, on_level=None,
             phases: Phases | None = None) -> list[dict]:
    """Rows of one case; ``on_level(case, model, level, problem, u, solution, trace_u)`` sees
    every solve (the report uses it to keep the finest solutions)."""
    phases = phases or Phases()
    previous = {model.name: (None, None) for model in models}
    rows = []
    multilevel = None
    with ngs.TaskManager():
        hierarchy = mesh_hierarchy(case, levels)
        for level in range(levels):
            with phases("mesh"):
                _, mesh = next(hierarchy)
                multilevel = Multilevel(mesh) if multilevel is None else multilevel.refined()
                h = mesh_size(mesh)
            with phases("assembly"):
                problem = discretise(case, mesh)
            level_rows, solutions = [], []
            for model in models:
                if progress is not None:
                    progress.set_postfix_str(f"{case.name} {model.name} level {level} ndof {problem.ndof}")
                fields, u, trace_u, solution = solve_level(case, problem, model, previous[model.name][0], multilevel,
                                                           previous[model.name][1], phases, last=model is models[-1])
                previous[model.name] = (trace_u, u[: multilevel.nvertices].copy())
                level_rows.append({"case": case.name, "model": model.name, "level": level, "h": h,
                                   "ndof": problem.ndof, **fields})
                solutions.append(problem.gridfunction(u))
                if on_level is not None:
                    with phases("hooks"):
                        on_level(case, model, level, problem, u, solution, trace_u)
                if progress is not None:
                    progress.update(1)
            with phases("errors"):
                errors = error_norms(case, solutions, problem.quadrature)
            rows += [row | norms for row, norms in zip(level_rows, errors)]
    return rows


def progress_bar(total: int, show: bool = True):
    """Progress of a study: case, model, level and ndof of the running solve, elapsed time."""
    return tqdm(total=total, disable=not show, unit="solve", dynamic_ncols=True)


def run_study(cases: list[Case], models: list[ContactModel], levels: int, show_progress: bool = True,
              on_level=None, progress=None) -> pd.DataFrame:
    """Every case x model x level; one tidy row each (columns ``COLUMNS``). ``progress``: a
    bar shared with a larger run (else one is made)."""
    if levels < 1:
        raise ValueError(f"levels must be a positive integer, got {levels}")
    for case in cases:
        validate_case(case)
    rows = []
    start = time.perf_counter()
    phases = Phases()
    own = progress is None
    progress = progress_bar(len(cases) * len(models) * levels, show_progress) if own else progress
    try:
        for case in cases:
            rows += run_case(case, models, levels, progress, on_level, phases)
    finally:
        if own:
            progress.close()
    frame = pd.DataFrame(rows, columns=COLUMNS)
    frame.attrs["wall_seconds"] = time.perf_counter() - start
    frame.attrs["phase_seconds"] = phases.as_dict()
    return frame
