"""What a study's chains share, whichever walks them (one body: ``chain``; two bodies:
``two_body``): the columns of a row and how a row is made, the phases a chain is timed by,
what a chain returns, and how many levels a method runs."""
from __future__ import annotations

import time
from collections import defaultdict
from contextlib import contextmanager
from dataclasses import dataclass

from ...methods import Method

COLUMNS = [
    "case", "method", "order", "parameters", "mesh", "dimension", "level", "h", "ndof", "n_contact_constraints", "err_h1", "err_h1_semi",
    "err_l2", "err_energy", "err_best_h1", "err_best_h1_semi", "err_best_energy", "err_h1_over_best", "err_trace_l2", "err_pressure_l2", "err_pressure_h12",
    # the residual a posteriori estimator eta (``measure.estimator``; NaN where it has no terms:
    # elasticity, 3D) and eta / err_energy on the exact cases
    "estimator", "effectivity",
    "max_penetration", "max_tension", "min_pressure",
    # quantities of interest (``measure.quantities``) and, on the cases with u, their exact values
    "qoi_force", "qoi_contact_measure", "qoi_peak_pressure", "qoi_energy",
    "qoi_force_exact", "qoi_contact_measure_exact", "qoi_peak_pressure_exact", "qoi_energy_exact",
    # ||u||_1 of a case with u: err_h1 / norm_h1_exact is the relative H^1 error
    "norm_h1_exact",
    "active_constraints", "solver_iterations", "linear_iterations", "kkt_residual", "backward_error", "solve_seconds", "total_seconds", "estimate_seconds", "measure_seconds", "status",
    # what the errors are measured against: "exact" (u), or "reference" (the solution of
    # reference_method, nodal, on level reference_level, with its KKT residual and status)
    "errors_against", "reference_level", "reference_ndof", "reference_kkt_residual", "reference_status",
    "reference_method",
    # what `rates` needs to fit a results file on its own: the case and the method's theories
    "nu", "expected_rate", "expected_log_exponent", "reference",
    "sharper_rate", "sharper_log_exponent", "sharper_reference", "case_source",
    # friction cases (``measure.quantities``, ``measure.errors.DiscreteTraction``)
    "qoi_slip_measure", "qoi_stick_slip_point", "qoi_slip_measure_exact", "qoi_stick_slip_point_exact", "err_friction_l2",
    # load histories (``problem.friction.LoadHistory``): the steps solved, each to the tolerance
    "load_steps",
    # Coulomb cases: Q, the stick zone, and (cases read against Cattaneo / Mindlin) the shear
    # traction's error against the closed form at the row's P and Q
    "qoi_tangential_force", "qoi_stick_measure", "err_traction_prediction",
]

# What each column of results.csv means (the docs' table of results.csv is generated from this)
COLUMN_MEANINGS = {
    "case": "the case's name", "method": "the method's name (with its parameters: `nitsche:gamma0=0.1`)",
    "order": "the finite element order k", "parameters": "the method's parameter values, `name=value` separated by spaces",
    "mesh": "the mesh strategy (`uniform`, `graded`, `adaptive`, or a strategy of your own)",
    "dimension": "the space dimension d of the case (N-rates: the best P_k can do is N^{-k/d})",
    "level": "the level of the chain, from 0", "h": "the largest element diameter", "ndof": "the number of dofs of the level",
    "n_contact_constraints": "the number of contact constraints (cones; 0 for weak methods)",
    "err_h1": "‖u − u_h‖ in H¹ (against u, or against the reference: `errors_against`)",
    "err_h1_semi": "|u − u_h| in the H¹ seminorm", "err_l2": "‖u − u_h‖ in L²", "err_energy": "a(u − u_h, u − u_h)^{1/2}",
    "err_best_h1": "the H¹ error of the Ritz projection of u (the best approximation in the energy norm)",
    "err_best_h1_semi": "its seminorm error", "err_best_energy": "its energy error",
    "err_h1_over_best": "err_h1 / err_best_h1: what the contact condition costs over the best approximation",
    "err_trace_l2": "‖u − u_h‖ in L²(Γ_C)",
    "err_pressure_l2": "‖λ − λ_h‖ in L²(Γ_C), λ_h the Riesz representative of the residual a(u_h, ·) − L(·) on the trace space",
    "err_pressure_h12": "‖h^{1/2}(λ − λ_h)‖ in L²(Γ_C)",
    "estimator": "the residual a posteriori estimator η of u_h (NaN where it is not computed: uniform meshes in 3D)",
    "effectivity": "η / err_energy: against u, or against the reference (cases without u)",
    "max_penetration": "max over Γ_C of α − u_h, between nodes included",
    "max_tension": "max(−λ_h) on Γ_C: the flux counterpart of max_penetration",
    "min_pressure": "the smallest discrete contact pressure (an edge's mean)",
    "qoi_force": "the total contact force ∫_{Γ_C} λ_h", "qoi_contact_measure": "the length (3D: area) of the contact zone "
    "(trapezoidal rule of the binding vertices)", "qoi_peak_pressure": "the largest contact pressure max λ_h",
    "qoi_energy": "the strain energy a(u_h, u_h)/2",
    "qoi_force_exact": "the exact contact force (cases with u)", "qoi_contact_measure_exact": "the exact contact zone's "
    "measure (2D cases with u)", "qoi_peak_pressure_exact": "the exact largest pressure", "qoi_energy_exact": "the exact strain energy",
    "norm_h1_exact": "‖u‖₁ (cases with u): err_h1 / norm_h1_exact is the relative H¹ error",
    "active_constraints": "active constraints (cones) or active Gauss points (weak methods)",
    "solver_iterations": "active set or Newton iterations", "linear_iterations": "CG iterations, or LU factorisations",
    "kkt_residual": "the KKT residual (cones), the Newton residual (weak methods) or the method's own residual, relative to the loads",
    "backward_error": "the same forces over ‖K‖‖u_h‖ + ‖b‖ (normwise backward error)",
    "solve_seconds": "the contact solve's wall time",
    "total_seconds": "mesh (refinement and the multigrid's hierarchy), assembly, set-up and solve of the level for the "
                     "method; on adaptive meshes also ESTIMATE and MARK (`estimate_seconds`), steps of that algorithm",
    "estimate_seconds": "the residual estimator of the row's solve: its level's set-up and the indicators",
    "measure_seconds": "the harness's measurement of the row (errors, best approximation; a level's shared part split "
                       "over its rows): in no user's cost, so `total_seconds` leaves it out",
    "status": "`converged`, or why not", "errors_against": "`exact` (u) or `reference`",
    "reference_level": "the reference's level", "reference_ndof": "its dofs", "reference_kkt_residual": "its KKT residual",
    "reference_status": "its status", "reference_method": "the method that solved it (the role REFERENCE)",
    "nu": "the case's regularity ν (u ∈ H^ν)", "expected_rate": "the H¹ rate the method's theory gives for ν (NaN: no theory)",
    "expected_log_exponent": "the power of |log h| in that bound", "reference": "the theorem it comes from",
    "sharper_rate": "a second theory's rate", "sharper_log_exponent": "its log power", "sharper_reference": "its theorem",
    "case_source": "the case file",
    "qoi_slip_measure": "friction cases: the length (3D: area) of the slip zone, where |λ_h − (E/h) u_t,h| > s "
    "(Tresca's projection acts; Coulomb: s = μ_F λ_h, the slip that of the last load step, and only where in contact)", "qoi_stick_slip_point": "2D friction cases: the position along Γ_C (x of a horizontal Γ_C) "
    "of its first stick–slip point, to O(h); NaN where there is none",
    "qoi_slip_measure_exact": "the exact slip zone's measure (2D friction cases with u)",
    "qoi_stick_slip_point_exact": "the exact first stick–slip point (2D friction cases with u)",
    "err_friction_l2": "friction cases with u: ‖σ_t − σ_t,h‖ in L²(Γ_C), σ_t,h the Riesz representative of the residual's "
    "tangential part (scalar model: λ − λ_h, equal to err_pressure_l2)",
    "load_steps": "the load history's steps solved in order (1: a static case); kkt_residual and backward_error are "
    "the worst step's, the iterations and solve_seconds the sum over the steps",
    "qoi_tangential_force": "Coulomb cases: Q = ∫_{Γ_C} −σ_t,h, the friction force on the obstacle, positive in the sense of "
    "the applied shear (2D: signed along τ; 3D: the resultant's length); Q/(μ_F qoi_force) is the load ratio",
    "qoi_stick_measure": "Coulomb cases: the length (3D: area) of the stick zone, the contact zone less the slip zone "
    "(Cattaneo: 2c; Mindlin: π c²)",
    "err_traction_prediction": "Coulomb cases declaring `predicted_traction`: ‖−σ_t,h − q‖ / ‖q‖ in L²(Γ_C), q the "
    "closed-form shear traction (Cattaneo, Mindlin) at the row's computed P and Q, along Q's direction",
}

# The phases of a study, in the order of the data flow; ``Phases`` sums the wall time of each.
PHASES = ("mesh", "assembly", "best", "setup", "solve", "estimate", "errors", "hooks")


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
    ends at about the same number of dofs (``methods.method.EXTRA_LEVELS``), fewer for P4; at
    least one."""
    return max(levels + method.extra_levels, 1)


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
        "mesh": mesh_label, "dimension": case.dimension, "level": level, "h": h, "ndof": ndof, **fields, "estimator": estimator,
        "total_seconds": total_seconds, "estimate_seconds": float("nan"), "measure_seconds": float("nan"), "nu": case.nu, "expected_rate": expectation.rate,
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
