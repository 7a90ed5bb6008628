"""The friction coefficient as an axis of a Coulomb case (``problem.friction.Coulomb``): for each
mu_F the same case's data with Coulomb(mu_F), the study's nested Newton chain to ``level`` (a
method's own ``solve``, GMRES with multigrid) and, on that level from the same nested start, the
fixed point over Tresca problems (``solvers.coulomb_fixed_point``): their status, iterations,
residuals, the stick/slip/separated Gauss points and the largest difference of the two solutions.

Uniqueness of the discrete solution is proven for small mu_F only (H. B. Khenous, J. Pommier &
Y. Renard, Appl. Numer. Math. 56 (2006) 163-192, abstract read): where the two disagree with both
converged, the discrete problem has two solutions; where one fails, the row says so.
"""
from __future__ import annotations

from dataclasses import replace

import numpy as np
import pandas as pd

COEFFICIENTS = (0.1, 0.3, 0.5, 1.0, 2.0, 5.0)
AXIS_LEVEL = 3                  # elastic-coulomb-r32: 1.8e4 dofs; the fixed point solves some 20 Tresca problems per mu_F
AXIS_COLUMNS = ["case", "method", "mu_F", "level", "ndof", "newton_status", "newton_steps", "gmres_iterations",
                "newton_residual", "newton_seconds", "fixed_point_status", "tresca_problems", "fixed_point_steps",
                "fixed_point_residual", "fixed_point_seconds", "difference", "stick", "slip", "separated"]


def coefficient_axis(coefficients=COEFFICIENTS, level: int = AXIS_LEVEL, case="elastic-coulomb-r32",
                     method_name: str | None = None, progress=print) -> pd.DataFrame:
    """The solvers' behaviour as mu_F grows (the module's note), one row per coefficient, on
    ``case`` (a Case, or a registered name or file) with the method ``method_name`` (default:
    ``law_method``)."""
    from ...problem.case import Case, load_case
    case = case if isinstance(case, Case) else load_case(case)
    method_name = method_name or law_method(case).name
    rows = []
    for mu in coefficients:
        rows.append(_axis_row(mu, level, case, method_name))
        row = rows[-1]
        progress(f"coulomb mu_F {mu:g}: Newton {row['newton_status']} ({row['newton_steps']} steps), fixed point "
                 f"{row['fixed_point_status']} ({row['tresca_problems']} Tresca problems), difference {row['difference']:.1e}")
    return pd.DataFrame(rows, columns=AXIS_COLUMNS)


def law_method(case):
    """The first method of the role REFERENCE that discretises ``case`` in P2 by a contact law
    (one with a ``system``: its Newton method's, which the fixed point reuses): Nitsche's."""
    from ...methods import METHODS, ContactLawMethod
    from ...methods.method import REFERENCE
    from ...methods.registry import with_role
    for method in with_role(REFERENCE, list(METHODS.values())):
        if isinstance(method, ContactLawMethod) and method.order == 2 and method.supports(case):
            return method
    raise ValueError(f"no P2 contact law of the role {REFERENCE!r} discretises {case.name}")


def _axis_row(mu: float, level: int, case, method_name: str) -> dict:
    import ngsolve as ngs

    from ...fem.assembly import discretise
    from ...mesh.levels import UniformRefinement
    from ...methods import get_method
    from ...methods.protocol import nested_guess
    from ...problem import Coulomb
    from ...solvers.coulomb_fixed_point import solve_fixed_point
    from ...solvers.multigrid import Multilevel

    ngs.ngsglobals.msg_level = 0
    case, method = replace(case, friction=Coulomb(mu)), get_method(method_name)
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
    return {"case": case.name, "method": method_name, "mu_F": mu, "level": level, "ndof": problem.ndof, "newton_status": fields.status, "newton_steps": fields.solver_iterations,
            "gmres_iterations": fields.linear_iterations, "newton_residual": fields.kkt_residual,
            "newton_seconds": fields.solve_seconds, "fixed_point_status": fixed.status, "tresca_problems": fixed.iterations,
            "fixed_point_steps": fixed.newton_steps, "fixed_point_residual": fixed.residual,
            "fixed_point_seconds": fixed.seconds,
            "difference": float(np.abs(fixed.u - solve.u).max() / max(np.abs(solve.u).max(), np.finfo(float).tiny)),
            "stick": int(codes[0]), "slip": int(codes[1] + codes[2]), "separated": int(codes[3])}


