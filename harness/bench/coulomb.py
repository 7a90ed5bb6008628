"""The Coulomb rows of `bench` (issue 76).

1. Cost: on elastic-coulomb-r32's uniform meshes, one load step of each P2 Coulomb method (its
   own ``solve``, nested from the coarser level as the study does: a contact law's semismooth
   Newton, GMRES with the multigrid V-cycle; a cone's fixed point over unilateral Tresca
   problems, each by the multigrid CG) against ONE linear multigrid CG solve of the
   Dirichlet/Neumann problem of the same space from the same nested start to the same tolerance
   (``ratio_nested``, the goal for Nitsche: at most ``COULOMB_GOAL``; the cones' shown), at
   >= 1e6 dofs; the Krylov iterations of both shown.
2. The friction coefficient as an axis (``study.planning.coulomb_axis.coefficient_axis``, the
   table ``_coulomb_axis``): Newton and the fixed point over Tresca problems as mu_F grows.
"""
from __future__ import annotations

from functools import partial

import pandas as pd

from .common import fresh_rows
from .friction import FRICTION_COLUMNS, _law_row, nitsche_laws

COULOMB_CASE = "elastic-coulomb-r32"
COULOMB_LEVEL = 6               # P2 plane strain: 1.2e6 dofs
COULOMB_GOAL = 3.0


def coulomb_methods() -> tuple:
    """The registered one-body P2 methods that declare "coulomb" (the bench's case has one body):
    the contact laws (Nitsche, penalty) and the cones (nodal, mean), each timed by
    ``friction._law_row`` (its own ``solve``)."""
    from ..methods import METHODS, BoundConstrained, ContactLawMethod
    return tuple(m.name for m in METHODS.values() if isinstance(m, (ContactLawMethod, BoundConstrained))
                 and m.order == 2 and "coulomb" in m.friction and 1 in m.bodies and ":" not in m.name)


def run_coulomb_bench(level: int = COULOMB_LEVEL, progress=print) -> pd.DataFrame:
    """Each Coulomb law's row, each in a fresh process."""
    frame = fresh_rows(partial(_law_row, case_name=COULOMB_CASE), "coulomb", "multigrid CG", (level,),
                       coulomb_methods(), progress, FRICTION_COLUMNS)
    return frame.rename(columns={"cg_iterations": "gmres_iterations"})


def coulomb_goals(frame: pd.DataFrame) -> list[tuple[str, bool, str]]:
    """The goals (issue 76): one load step of Nitsche-Coulomb within COULOMB_GOAL linear multigrid
    solves from the same nested start at >= 1e6 dofs, every row exact; the cones' ratios shown
    (their iterations: unilateral Tresca problems, their Krylov ones multigrid CG)."""
    laws = frame[frame.method.isin(nitsche_laws(frame.method))]
    ratios = ", ".join(f"{r.method} {r.ratio_nested:.2f} ({int(r.iterations)} Newton steps or Tresca problems, "
                       f"{int(r.gmres_iterations)} Krylov iterations against {int(r.nested_iterations)} CG) at {r.ndof:.2g} dofs"
                       for r in frame.itertuples())
    goals = [(f"coulomb one load step <= {COULOMB_GOAL:g}x one linear multigrid solve from the same start (Nitsche, >= 1e6 dofs)",
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
