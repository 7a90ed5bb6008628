"""What a study's chains share, whichever walks them (one body: ``chain``; two bodies:
``two_body``): the columns of a row and how a row is made, the phases a chain is timed by,
what a chain returns, and how many levels a method runs."""
from __future__ import annotations

import time
from collections import defaultdict
from contextlib import contextmanager
from dataclasses import dataclass

from ..methods import Method

COLUMNS = [
    "case", "method", "order", "parameters", "mesh", "level", "h", "ndof", "n_contact_constraints", "err_h1", "err_h1_semi",
    "err_l2", "err_energy", "err_best_h1", "err_best_h1_semi", "err_best_energy", "err_h1_over_best", "err_trace_l2", "err_pressure_l2", "err_pressure_h12",
    # the residual a posteriori estimator eta (``measure.estimator``; NaN where it has no terms:
    # elasticity, 3D) and eta / err_energy on the exact cases
    "estimator", "effectivity",
    "max_penetration", "max_tension", "min_pressure", "active_constraints", "solver_iterations", "linear_iterations",
    "kkt_residual", "backward_error", "solve_seconds", "total_seconds", "status",
    # what the errors are measured against: "exact" (u), or "reference" (the solution of
    # reference_method, nodal, on level reference_level, with its KKT residual and status)
    "errors_against", "reference_level", "reference_ndof", "reference_kkt_residual", "reference_status",
    "reference_method",
    # what `rates` needs to fit a results file on its own: the case and the method's theories
    "nu", "expected_rate", "expected_log_exponent", "reference",
    "sharper_rate", "sharper_log_exponent", "sharper_reference", "case_source",
]

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


@dataclass
class ChainOutput:
    """What a chain of one case and some methods produced: its rows (level by level, methods in
    the order given), what ``on_level`` returned by (method name, level), the wall time of each
    phase, the level each method resumed from (0: it started afresh), and the contact solve
    seconds of the solves without a row (a reference chain's levels past the studied ones)."""

    rows: list[dict]
    kept: dict
    phases: dict
    resumed: dict
    reference_solve_seconds: float = 0.0


def level_row(case, method, mesh_label: str, level: int, h: float, ndof: int, fields: dict, total_seconds: float,
              estimator: float, expectation, sharper) -> dict:
    """A row of the study before its errors: what the case, the method and its solve say."""
    return {
        "case": case.name, "method": method.name, "order": method.order, "parameters": method.parameter_text,
        "mesh": mesh_label, "level": level, "h": h, "ndof": ndof, **fields, "estimator": estimator,
        "total_seconds": total_seconds, "nu": case.nu, "expected_rate": expectation.rate,
        "expected_log_exponent": expectation.log_exponent, "reference": expectation.reference, **_sharper(sharper),
        "case_source": case.source, "errors_against": "exact" if case.exact else "reference",
    }


def keep(on_level, phases, kept: dict, case, method, level: int, problem, solve) -> None:
    """``on_level``'s view of a studied solve, kept by (method, level) if it returns one."""
    if on_level is None:
        return
    with phases("hooks"):
        value = on_level(case, method, level, problem, solve)
    if value is not None:
        kept[(method.name, level)] = value


def _sharper(expectation) -> dict:
    """The row's second theory (``Method.sharper``), NaN where the method has none."""
    if expectation is None:
        return {"sharper_rate": float("nan"), "sharper_log_exponent": float("nan"), "sharper_reference": ""}
    return {"sharper_rate": expectation.rate, "sharper_log_exponent": expectation.log_exponent,
            "sharper_reference": expectation.reference}
