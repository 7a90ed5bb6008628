"""The Coulomb rows of `bench` (issue 76).

1. Cost: on elastic-coulomb-r32's uniform meshes, one load step of each Coulomb law (its own
   ``solve``: semismooth Newton, GMRES with the multigrid V-cycle, nested from the coarser
   level as the study does) against ONE linear multigrid CG solve of the Dirichlet/Neumann
   problem of the same space from the same nested start to the same tolerance (``ratio_nested``,
   the goal: at most ``COULOMB_GOAL``), at >= 1e6 dofs; the Krylov iterations of both shown.
2. The friction coefficient as an axis (``coefficient_axis``): for each mu_F of
   ``COEFFICIENTS`` the same case's data with Coulomb(mu_F), the nested Newton chain to
   ``AXIS_LEVEL`` and, on that level from the same start, the fixed point over Tresca problems
   (``solvers.coulomb_fixed_point``): their iterations, residuals, the stick/slip/separated
   points and the largest difference of the two solutions. Uniqueness is proven for small mu_F
   only (Khenous, Pommier & Renard 2006, abstract read): where the two disagree with both
   converged, the discrete problem has two solutions; where one fails, it says so.
"""
from __future__ import annotations

from dataclasses import replace
from functools import partial

import numpy as np
import pandas as pd

from .common import fresh_rows
from .friction import FRICTION_COLUMNS, _law_row

COULOMB_CASE = "elastic-coulomb-r32"
COULOMB_LEVEL = 6               # P2 plane strain: 1.2e6 dofs
COULOMB_GOAL = 3.0
COEFFICIENTS = (0.1, 0.3, 0.5, 1.0, 2.0, 5.0)
AXIS_LEVEL = 3                  # 1.8e4 dofs: the fixed point solves some 20 Tresca problems per mu_F
AXIS_COLUMNS = ["mu_F", "ndof", "newton_status", "newton_steps", "gmres_iterations", "newton_residual", "newton_seconds",
                "fixed_point_status", "tresca_problems", "fixed_point_steps", "fixed_point_residual", "fixed_point_seconds",
                "difference", "stick", "slip", "separated"]


def coulomb_law_methods() -> tuple:
    """The swept P2 contact laws (Nitsche, ``methods.method.SWEPT``) and the penalty that declare
    "coulomb", each timed by ``friction._law_row``."""
    from ..methods import METHODS, ContactLawMethod
    return tuple(m.name for m in METHODS.values() if isinstance(m, ContactLawMethod) and m.order == 2
                 and "coulomb" in m.friction and ":" not in m.name)


def run_coulomb_bench(level: int = COULOMB_LEVEL, progress=print) -> pd.DataFrame:
    """Each Coulomb law's row, each in a fresh process."""
    frame = fresh_rows(partial(_law_row, case_name=COULOMB_CASE), "coulomb", "multigrid CG", (level,),
                       coulomb_law_methods(), progress, FRICTION_COLUMNS)
    return frame.rename(columns={"cg_iterations": "gmres_iterations"})


def coefficient_axis(coefficients=COEFFICIENTS, level: int = AXIS_LEVEL, case_name: str = COULOMB_CASE,
                     method_name: str = "nitsche", progress=print) -> pd.DataFrame:
    """The solvers' behaviour as mu_F grows (the module's note 2), one row per coefficient."""
    rows = []
    for mu in coefficients:
        rows.append(_axis_row(mu, level, case_name, method_name))
        row = rows[-1]
        progress(f"coulomb mu_F {mu:g}: Newton {row['newton_status']} ({row['newton_steps']} steps), fixed point "
                 f"{row['fixed_point_status']} ({row['tresca_problems']} Tresca problems), difference {row['difference']:.1e}")
    return pd.DataFrame(rows, columns=AXIS_COLUMNS)


def _axis_row(mu: float, level: int, case_name: str, method_name: str) -> dict:
    import ngsolve as ngs

    from ..fem.assembly import discretise
    from ..mesh.levels import UniformRefinement
    from ..methods import get_method
    from ..methods.protocol import nested_guess
    from ..problem import Coulomb
    from ..problem.case import load_case
    from ..solvers.coulomb_fixed_point import solve_fixed_point
    from ..solvers.multigrid import Multilevel

    ngs.ngsglobals.msg_level = 0
    case, method = replace(load_case(case_name), friction=Coulomb(mu)), get_method(method_name)
    multilevel, carry, previous = None, None, None
    with ngs.TaskManager():
        for step in UniformRefinement(case).levels(level + 1):
            multilevel = Multilevel(step.mesh, case.physics) if multilevel is None else multilevel.refined(step.mesh)
            problem = discretise(case, step.mesh, method.order)
            previous, solve = carry, method.solve(case, problem, carry, multilevel)
            carry = solve.carry
        system = method.system(case, problem)
        start, _ = nested_guess(system, previous, multilevel)
        fixed = solve_fixed_point(system, start, multilevel, method.solver)
    fields, codes = solve.fields, np.bincount(np.asarray(carry.active, np.int64), minlength=4)
    return {"mu_F": mu, "ndof": problem.ndof, "newton_status": fields.status, "newton_steps": fields.solver_iterations,
            "gmres_iterations": fields.linear_iterations, "newton_residual": fields.kkt_residual,
            "newton_seconds": fields.solve_seconds, "fixed_point_status": fixed.status, "tresca_problems": fixed.iterations,
            "fixed_point_steps": fixed.newton_steps, "fixed_point_residual": fixed.residual,
            "fixed_point_seconds": fixed.seconds,
            "difference": float(np.abs(fixed.u - solve.u).max() / max(np.abs(solve.u).max(), np.finfo(float).tiny)),
            "stick": int(codes[0]), "slip": int(codes[1] + codes[2]), "separated": int(codes[3])}


def coulomb_goals(frame: pd.DataFrame) -> list[tuple[str, bool, str]]:
    """The goals (issue 76): one load step of Nitsche-Coulomb within COULOMB_GOAL linear multigrid
    solves from the same nested start at >= 1e6 dofs, every row exact."""
    laws = frame[frame.method == "nitsche"]
    ratios = ", ".join(f"{r.method} {r.ratio_nested:.2f} ({int(r.iterations)} Newton steps, {int(r.gmres_iterations)} GMRES "
                       f"iterations against {int(r.nested_iterations)} CG) at {r.ndof:.2g} dofs" for r in frame.itertuples())
    goals = [(f"coulomb one load step <= {COULOMB_GOAL:g}x one linear multigrid solve from the same start (nitsche, >= 1e6 dofs)",
              bool(len(laws)) and bool((laws.ratio_nested <= COULOMB_GOAL).all()) and bool((laws.ndof >= 1e6).all()), ratios),
             ("coulomb residual <= 1e-10 in every row", bool((frame.kkt_residual <= 1e-10).all()),
              f"max {frame.kkt_residual.max():.1e}")]
    return goals


def axis_goals(axis: pd.DataFrame) -> list[tuple[str, bool, str]]:
    """The mu_F axis: shown, not judged (no theorem says where uniqueness ends), but every
    converged solution's residual <= 1e-10."""
    shown = "; ".join(f"mu_F {r.mu_F:g}: Newton {r.newton_status} in {r.newton_steps}, fixed point {r.fixed_point_status} "
                      f"in {r.tresca_problems}, difference {r.difference:.1e}" for r in axis.itertuples())
    converged = axis[axis.newton_status == "converged"]
    return [("coulomb mu_F axis (shown)", True, shown),
            ("coulomb mu_F axis: residual <= 1e-10 wherever Newton converged", bool((converged.newton_residual <= 1e-10).all()),
             f"max {converged.newton_residual.max():.1e}")]
