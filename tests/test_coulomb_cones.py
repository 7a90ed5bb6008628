"""Coulomb friction on the cones (``fem.coulomb_cones``): the unilateral Tresca solver
(``solvers.unilateral_friction``) against Clarabel, the fixed point's solution against the
discrete Coulomb conditions row by row (``solvers.coulomb_cones``), the H^1 rates of `nodal`
and `mean` on the exact case elastic-coulomb-r32, and a Cattaneo load history."""
from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp
from conftest import clarabel_unilateral_tresca, problem_with_hierarchy

import harness
from harness.fem.assembly import at_load_step
from harness.fem.coulomb_cones import coulomb_cone_qp
from harness.fem.sparse import ngsolve_matrix
from harness.measure.rates import fit_rate, verdict
from harness.methods import get_method
from harness.problem.case import load_case
from harness.solvers.bound_constraints import FactorisedSystem, MultigridSystem
from harness.solvers.coulomb_cones import solve_coulomb_history, solve_coulomb_step
from harness.solvers.unilateral_friction import solve_unilateral_friction

TOLERANCE = 1e-10


def _random_problem(seed: int, n: int = 36):
    """K SPD, 4 pinned dofs with a lift, 8 contact rows with an obstacle, 8 friction rows (two of
    weight 0) with a slip reference."""
    rng = np.random.default_rng(seed)
    M = rng.standard_normal((n, n))
    K = M @ M.T + 0.5 * np.eye(n)
    b = rng.standard_normal(n) * 3
    free = np.ones(n, bool)
    free[:4] = False
    lift = np.where(free, 0.0, rng.standard_normal(n) * 0.2)
    C, F = np.arange(4, 12), np.arange(12, 20)
    alpha = rng.standard_normal(len(C)) * 0.3
    c = rng.uniform(0.5, 4.0, len(F))
    c[[1, 5]] = 0.0
    zprev = rng.standard_normal(len(F)) * 0.2
    return K, b, free, lift, C, alpha, F, c, zprev


@pytest.mark.parametrize("seed", range(6))
def test_unilateral_tresca_solver_matches_clarabel_and_reaches_its_kkt_tolerance(seed):
    K, b, free, lift, C, alpha, F, c, zprev = _random_problem(seed)
    system = FactorisedSystem(sp.csr_matrix(K), ngsolve_matrix(sp.csr_matrix(K)), b)
    solution = solve_unilateral_friction(sp.csr_matrix(K), b, free, C, alpha, F, c, zprev, lift, system)
    reference = clarabel_unilateral_tresca(K, b, free, lift, C, alpha, F, c, zprev)
    assert solution.status == "converged" and solution.kkt.residual <= TOLERANCE
    assert np.abs(solution.z - reference).max() <= 1e-7 * max(1.0, np.abs(reference).max())
    m, k = len(C), len(F)
    contact, plus, minus = solution.active[:m], solution.active[m:m + k], solution.active[m + k:]
    lam_n, lam_t = solution.multipliers[:m], solution.multipliers[m:]
    assert np.all(solution.z[C[contact]] == alpha[contact]) and not (plus & minus).any()
    assert np.abs(lam_t[c == 0]).max() <= TOLERANCE * np.abs(b).max()      # weightless rows carry no force
    assert (lam_n >= -TOLERANCE * np.abs(b).max()).all()


def _coulomb_history(case_name: str, method: str, level: int):
    case = load_case(case_name)
    model = get_method(method).cone
    problem, multilevel = problem_with_hierarchy(case_name, level, get_method(method).order)
    qp = coulomb_cone_qp(case, problem, model)
    steps = [qp.at_step(at_load_step(case, problem, k)) for k in range(len(case.history))]
    history = solve_coulomb_history(qp, steps, case.friction.coefficient,
                                    lambda b: MultigridSystem(qp.K_ngs, b, multilevel, qp.edges),
                                    lambda k, solved: (solved[-1].solution.active, solved[-1].solution.z) if solved else (None, None))
    return case, qp, steps, history


def _coulomb_violations(qp, mu: float, step, data, zprev: np.ndarray) -> dict:
    """The discrete Coulomb conditions row by row, each violation over the force scale of the
    KKT residuals (``solvers.unilateral_friction.UnilateralFriction.load_scale``: the loads
    K lift - b, the forces holding the rows at alpha and zprev, and the multipliers) or over the
    displacement scale."""
    m, (b, lift), z, multipliers = len(qp.C), data, step.solution.z, step.solution.multipliers
    lam_n, lam_t, slip = multipliers[:m], multipliers[m:], z[qp.F] - zprev
    pins = np.zeros(len(z))
    pins[qp.C], pins[qp.F] = qp.alpha, zprev
    force = max(np.abs(lam_n).max(), np.abs(lam_t).max(), np.abs((qp.K @ lift - b)[qp.free]).max(),
                np.abs((qp.K @ pins)[qp.free]).max())
    gap, weighed = z[qp.C] - qp.alpha, qp.weights > 0
    bound = mu * np.maximum(lam_n, 0.0)
    slipping = np.abs(slip) > 0
    inside = weighed & (np.abs(lam_t) < bound - TOLERANCE * force)
    return {"unilateral": max(0.0, -gap.min()) / np.abs(z).max(),
            "pressure": max(0.0, -lam_n.min()) / force,
            "complementarity": np.abs(lam_n * gap).max() / (force * np.abs(z).max()),
            "cone": np.maximum(np.abs(lam_t) - bound, 0.0)[weighed].max() / force,
            "unweighed rows free": np.abs(lam_t[~weighed]).max(initial=0.0) / force,
            "slip at the bound": np.abs(np.abs(lam_t) - bound)[weighed & slipping].max(initial=0.0) / force,
            "slip against the force": np.maximum(-lam_t * np.sign(slip), 0.0)[slipping].max(initial=0.0) / force,
            "stick inside": np.abs(slip[inside]).max(initial=0.0) / np.abs(z).max(),
            "some stick, some slip": float(not (inside.any() and (weighed & slipping).any()))}


@pytest.mark.parametrize("method", ["nodal", "mean", "p1"])
def test_the_fixed_point_solves_the_discrete_coulomb_conditions_row_by_row(method):
    """|lambda_t| <= mu_F lambda_n, stick (no slip) where strictly inside, |lambda_t| = mu_F
    lambda_n with the friction force (K z - b)_F = -lambda_t opposite the slip where it slips,
    and Signorini's conditions on the contact rows: every violation <= 1e-10 relative."""
    case, qp, steps, history = _coulomb_history("elastic-coulomb-r32", method, 2)
    step = history[-1]
    assert step.status == "converged" and step.iterations > 2 and step.change <= TOLERANCE
    violations = _coulomb_violations(qp, case.friction.coefficient, step, steps[-1], np.zeros(len(qp.F)))
    assert max(violations.values()) <= TOLERANCE, violations


def test_a_load_step_slips_from_the_previous_steps_state():
    """cattaneo-line-q07-nu47 (press, then shear), level 0: each step solves Coulomb with the slip
    measured from the step before (the first from 0), row by row to 1e-10."""
    case, qp, steps, history = _coulomb_history("cattaneo-line-q07-nu47", "nodal", 0)
    assert [step.status for step in history] == ["converged", "converged"]
    zprev = np.zeros(len(qp.F))
    for step, data in zip(history, steps):
        violations = _coulomb_violations(qp, case.friction.coefficient, step, data, zprev)
        assert max(violations.values()) <= TOLERANCE, violations
        zprev = step.solution.z[qp.F]


def test_a_fixed_point_cut_short_says_so_in_its_status():
    """Three Tresca problems do not reach the fixed point (about 19 do on elastic-coulomb-r32):
    the step's status says so, never "converged"."""
    case = load_case("elastic-coulomb-r32")
    problem, multilevel = problem_with_hierarchy("elastic-coulomb-r32", 1)
    qp = coulomb_cone_qp(case, problem, get_method("nodal").cone)
    b, lift = qp.at_step(problem)
    step = solve_coulomb_step(qp, b, lift, np.zeros(len(qp.F)), case.friction.coefficient,
                              lambda load: MultigridSystem(qp.K_ngs, load, multilevel, qp.edges), iterations=3)
    assert step.status.startswith("Coulomb fixed point: not converged in 3 Tresca problems") and step.iterations == 3
    assert step.change > TOLERANCE


@pytest.mark.slow
@pytest.mark.parametrize("method", ["nodal", "mean"])
def test_the_cones_converge_on_elastic_coulomb_at_the_expected_rate(method):
    """elastic-coulomb-r32, levels 0-3 (2e4 dofs): every level converged with its residual
    <= 1e-10, and the H^1 rate fitted over the last three levels meets the case's expectation
    h^{1.545} within the harness's tolerance (0.1). Measured pairwise in h: nodal 1.541, 1.544,
    1.545 (nitsche's, the case's docstring: 1.541, 1.544, 1.545), mean 1.560, 1.563, 1.556."""
    rows = harness.run("elastic-coulomb-r32", [method], levels=4, show_progress=False).sort_values("level")
    assert (rows.status == "converged").all() and (rows.kkt_residual <= TOLERANCE).all()
    assert (rows.solver_iterations > 2).all()             # the fixed point iterated on every level
    measured = rows[["err_h1", "qoi_force", "qoi_tangential_force", "qoi_slip_measure", "qoi_stick_slip_point"]]
    assert np.isfinite(measured.to_numpy(float)).all()    # the row's errors and quantities
    rate = fit_rate(rows.h.to_numpy(), rows.err_h1.to_numpy())[0]
    assert verdict(rate, load_case("elastic-coulomb-r32").expected_rate) == "meets", rate


@pytest.mark.slow
def test_nodal_runs_a_cattaneo_history_and_finds_nitsches_stick_zone():
    """cattaneo-line-q07-nu47, levels 0-1: `nodal` solves both load steps to 1e-10 and its stick
    zone (the quantities module's, from u_h and the previous step's u_h) is within 10% of
    Nitsche's on the same level (measured: equal to 1e-6 on level 1, 0.1079 both)."""
    rows = harness.run("cattaneo-line-q07-nu47", ["nodal", "nitsche"], levels=2, show_progress=False)
    last = rows[rows.level == 1].set_index("method")
    assert (rows.status == "converged").all() and (rows.kkt_residual <= TOLERANCE).all() and (rows.load_steps == 2).all()
    stick = last.qoi_stick_measure
    assert stick["nodal"] > 0 and abs(stick["nodal"] - stick["nitsche"]) <= 0.1 * stick["nitsche"]


def test_the_cones_discretise_coulomb_in_2d_only():
    flat, solid = load_case("elastic-coulomb-r32"), load_case("elastic-coulomb-3d")
    for name in ("nodal", "mean", "p1"):
        assert get_method(name).refusal(flat) is None
        assert "Coulomb" in get_method(name).refusal(solid)
    assert "not coulomb friction" in get_method("nodal-p3").refusal(flat)
