"""The contact solver returns the exact solution of each discrete inequality (3.6), (5.1)."""
from dataclasses import replace

import numpy as np
import pytest
import scipy.sparse as sp
from conftest import CONE_NAMES, problem_at, problem_with_hierarchy
from qpsolvers import solve_qp

from harness.fem.cones import contact_qp
from harness.methods import METHODS
from harness.problem.case import load_case
from harness.solvers.bound_constraints import ActiveSetSolver, solve_contact_qp
from harness.solvers.options import SolverOptions

CROSS_CHECK_LEVELS = [0, 1, 2]   # 165, 609, 2337 dofs: all <= 3000


def hierarchical_qp(case, problem, model):
    """The same QP in NGSolve's own hierarchical variables, constraints as general rows G u >= alpha
    (P1: vertex rows only)."""
    free = np.flatnonzero(problem.free)
    A = problem.A[free][:, free]
    q = -(problem.b - problem.A @ problem.lift)[free]
    nv = len(problem.vertex_dofs)
    rows, cols, vals = [], [], []
    position = np.full(problem.ndof, -1)
    position[free] = np.arange(len(free))
    for k, dof in enumerate(problem.vertex_dofs):
        rows.append(k), cols.append(position[dof]), vals.append(1.0)
    for k, (edge, (a, b)) in enumerate(zip(problem.edge_dofs, problem.end_dofs)):
        for dof, val in ((a, 0.5), (b, 0.5), (edge, -0.5 / model.weight)):
            rows.append(nv + k), cols.append(position[dof]), vals.append(val)
    G = sp.csr_matrix((vals, (rows, cols)), shape=(nv + len(problem.edge_dofs), len(free)))
    alpha = contact_qp(case, problem, model).alpha
    return A, q, G, alpha, free


@pytest.mark.parametrize("level", CROSS_CHECK_LEVELS)
@pytest.mark.parametrize("method_name", CONE_NAMES)
def test_solution_equals_independent_qp_solver(method_name, level):
    """Clarabel (interior point), given the method's cone (K_h, K~_h, or the P1 vertex cone) as
    general linear rows in NGSolve's hierarchical variables, finds the same u_h to 1e-8."""
    case = load_case("transition-r32")
    method = METHODS[method_name]
    problem = problem_at("transition-r32", level, method.order)
    model = method.cone
    qp = contact_qp(case, problem, model)
    ours = qp.to_u(solve_contact_qp(qp).z)
    A, q, G, alpha, free = hierarchical_qp(case, problem, model)
    ref = solve_qp(sp.csc_matrix(A), q, G=-sp.csc_matrix(G), h=-alpha, solver="clarabel",
                   tol_gap_abs=1e-14, tol_gap_rel=1e-14, tol_feas=1e-14, tol_ktratio=1e-10, max_iter=400)
    assert ref is not None
    u_ref = problem.lift.copy()
    u_ref[free] = ref
    assert np.abs(ours - u_ref).max() <= 1e-8 * np.abs(u_ref).max()


@pytest.mark.parametrize("backend", ["multigrid", "cholesky"])
@pytest.mark.parametrize("method_name", CONE_NAMES)
@pytest.mark.parametrize("case_file", ["transition-r32", "tests/data/gap_case.py"])
def test_every_solution_satisfies_kkt_conditions(method_name, case_file, backend):
    case = load_case(case_file)
    method = METHODS[method_name]
    problem, multilevel = problem_with_hierarchy(case_file, 3, method.order)
    qp = contact_qp(case, problem, method.cone)
    solution = solve_contact_qp(qp, multilevel=multilevel if backend == "multigrid" else None)
    assert solution.status == "converged"
    # Recompute every KKT condition, in NGSolve's hierarchical variables, independently of the solver.
    u, lam, active = qp.to_u(solution.z), solution.multipliers, solution.active
    model = method.cone
    g = problem.A @ u - problem.b
    scale = np.abs((problem.b - problem.A @ problem.lift)[problem.free]).max()
    contact = model.constrained_dofs(problem)
    off_contact = problem.free.copy()
    off_contact[contact] = False
    G = model.constraint_matrix(problem)
    slack = G @ u - qp.alpha
    assert np.abs(g[off_contact]).max() <= 1e-10 * scale                         # stationarity
    np.testing.assert_allclose(G[:, contact].T @ lam, g[contact], atol=1e-10 * scale)
    assert np.abs(lam[~active]).max(initial=0) <= 1e-10 * scale                  # inactive: no force
    assert lam[active].min(initial=0) >= -1e-10 * scale                          # multiplier sign
    assert slack.min() >= -1e-10 * np.abs(u).max()                               # primal feasibility
    assert np.abs(lam * slack).max() <= 1e-10 * scale * np.abs(u).max()          # complementarity
    np.testing.assert_allclose(u[~problem.free], problem.lift[~problem.free], atol=1e-14)  # Dirichlet data


@pytest.mark.parametrize("method_name", CONE_NAMES)
def test_factorised_solver_equals_textbook_pdas(method_name):
    """The single-mesh solver (one factorisation, bordered updates, warm-started) and the textbook
    PDAS (cold, refactorised) agree to 1e-10."""
    case = load_case("transition-r32")
    method = METHODS[method_name]
    problem = problem_at("transition-r32", 3, method.order)
    qp = contact_qp(case, problem, method.cone)
    textbook = solve_contact_qp(qp, textbook=True)
    assert textbook.work["factorizations"] == textbook.iterations
    # A deliberately poor warm start: every constraint active.
    fast = solve_contact_qp(qp, initial_active=np.ones(len(qp.C), bool))
    assert textbook.status == fast.status == "converged"
    assert fast.work["factorizations"] < textbook.work["factorizations"]
    assert np.abs(fast.z - textbook.z).max() <= 1e-10 * np.abs(textbook.z).max()


@pytest.mark.parametrize("case_file", ["transition-r32", "tests/data/gap_case.py"])
@pytest.mark.parametrize("method_name", CONE_NAMES)
def test_multigrid_solver_equals_textbook_pdas(method_name, case_file):
    """The study's solver (truncated-multigrid CG, from a poor start: every constraint active)
    and the textbook PDAS (cold, refactorised) agree to 1e-10; for P1 the V-cycle starts at
    the finest P1 level itself."""
    case = load_case(case_file)
    method = METHODS[method_name]
    problem, multilevel = problem_with_hierarchy(case_file, 3, method.order)
    qp = contact_qp(case, problem, method.cone)
    textbook = solve_contact_qp(qp, textbook=True)
    fast = solve_contact_qp(qp, initial_active=np.ones(len(qp.C), bool), multilevel=multilevel)
    assert textbook.status == fast.status == "converged"
    assert fast.kkt.residual <= 1e-10
    assert np.abs(fast.z - textbook.z).max() <= 1e-10 * np.abs(textbook.z).max()


@pytest.mark.parametrize("seed", range(6))
def test_random_bound_qps_match_clarabel(seed):
    """Dense SPD matrices that are far from M-matrices exercise the cycling safeguard."""
    rng = np.random.default_rng(seed)
    n, m = 40, 25
    B = rng.standard_normal((n, n))
    K = B @ B.T + 0.5 * np.eye(n)
    r = rng.standard_normal(n) * 3
    C = np.sort(rng.choice(n, m, replace=False))
    alpha = rng.standard_normal(m) * 0.3
    sol = ActiveSetSolver(sp.csr_matrix(K), r, np.ones(n, bool), C, alpha).solve()
    G = np.zeros((m, n))
    G[np.arange(m), C] = -1
    ref = solve_qp(sp.csc_matrix(K), -r, G=sp.csc_matrix(G), h=-alpha, solver="clarabel", tol_gap_abs=1e-13, tol_gap_rel=1e-13, tol_feas=1e-13)
    assert sol.status == "converged"
    assert np.abs(sol.z - ref).max() <= 1e-7 * max(1, np.abs(ref).max())


def _p1_qp(case_file: str, level: int):
    case, method = load_case(case_file), METHODS["p1"]
    problem, multilevel = problem_with_hierarchy(case_file, level, method.order)
    return contact_qp(case, problem, method.cone, take_stiffness=True), multilevel


def test_a_tolerance_below_the_round_off_floor_ends_converged_at_round_off_not_stalled():
    """The floor of the relative KKT residual grows like eps cond(K); asking 1e-14 on 1.2e4 P1
    dofs (floor about 5e-12) is the stall of a 7.9e5-dof reference, small. The solve ends
    converged, the normwise backward error of its forces at round-off, primal feasibility exact."""
    qp, multilevel = _p1_qp("tests/data/square_sine.py", 5)
    solution = solve_contact_qp(qp, multilevel=multilevel, options=SolverOptions(tolerance=1e-14))
    assert solution.status == "converged"
    assert solution.kkt.residual > 1e-14                      # the relative residual cannot get there
    assert solution.kkt.backward <= SolverOptions().roundoff_backward_error
    assert solution.kkt.primal <= 1e-14
    # the same active set as at the usual tolerance
    assert (solution.active == solve_contact_qp(qp, multilevel=multilevel).active).all()


@pytest.mark.slow
@pytest.mark.scale      # 7.9e5 dofs: `make test-scale`
def test_the_issue_30_reference_solve_converges():
    """P1 on 7.9e5 dofs of the square case: stalled at KKT 1.3e-10 before; now converged with
    backward error ~3e-16 (KKT residual 1.5e-10, the floor)."""
    qp, multilevel = _p1_qp("tests/data/square_sine.py", 8)
    solution = solve_contact_qp(qp, multilevel=multilevel)
    assert solution.status == "converged" and solution.kkt.backward <= 1e-13


@pytest.mark.parametrize("chunk", [1, 7, 1 << 22])
def test_row_norm_is_the_infinity_norm_of_the_chosen_rows(chunk, rng):
    from harness.solvers.bound_constraints import row_norm
    K = sp.random(60, 45, density=0.15, format="csr", random_state=3)
    K = sp.vstack([K[:10], sp.csr_matrix((2, 45)), K[10:]]).tocsr()         # empty rows too
    rows = rng.random(K.shape[0]) < 0.6
    expected = np.asarray(abs(K).sum(axis=1)).ravel()[rows].max()
    assert row_norm(K, rows, chunk) == pytest.approx(expected, rel=1e-13)


@pytest.mark.parametrize("method_name", CONE_NAMES)
def test_loose_solves_of_new_active_sets_reach_the_same_kkt_point_with_fewer_cg_iterations(method_name):
    """Inexact active-set steps (``loose_depth``): from a poor prediction (every constraint
    active) the sets that are to change are solved to 1e-3 of the residual only; the answer is
    the KKT point of the all-full-depth run, to the tolerance, in fewer CG iterations."""
    case = load_case("transition-r32")
    method = METHODS[method_name]
    problem, multilevel = problem_with_hierarchy("transition-r32", 3, method.order)
    qp = contact_qp(case, problem, method.cone)
    everything = np.ones(len(qp.C), bool)
    loose = solve_contact_qp(qp, initial_active=everything, multilevel=multilevel)
    full = solve_contact_qp(qp, initial_active=everything, multilevel=multilevel,
                            options=SolverOptions(forcing=0.0))        # every solve to the full depth
    assert loose.status == full.status == "converged"
    assert loose.kkt.residual <= 1e-10
    assert (loose.active == full.active).all()
    assert np.abs(loose.z - full.z).max() <= 1e-10 * np.abs(full.z).max()
    assert loose.work["cg_iterations"] < full.work["cg_iterations"]


def test_solver_options_are_plain_data_with_the_harness_defaults():
    """``SolverOptions``: today's constants as defaults, plain numbers for provenance, a frozen
    value equal to itself rebuilt from its dict, and nonsense refused in one line."""
    values = SolverOptions().as_dict()
    assert (values["tolerance"], values["forcing"], values["loose_gain"], values["stall_steps"]) == (1e-10, 1e-3, 1e3, 12)
    assert all(type(value) in (float, int) for value in values.values())
    assert SolverOptions(**values) == SolverOptions() and SolverOptions(forcing=0) == SolverOptions(forcing=0.0)
    with pytest.raises(ValueError, match="active_set_iterations"):
        SolverOptions(active_set_iterations=0)
    with pytest.raises(ValueError, match="forcing"):
        SolverOptions(forcing=-1.0)


def test_a_methods_solver_options_reach_its_solver():
    """``Method.solver`` is part of the method (compared) and is what its solve uses: one active
    set allowed from a cold start ends "not converged" after that set."""
    case, method = load_case("transition-r32"), METHODS["nodal"]
    problem, multilevel = problem_with_hierarchy("transition-r32", 2, method.order)
    capped = replace(method, solver=SolverOptions(active_set_iterations=1))
    assert capped != method and capped.solver.active_set_iterations == 1
    fields = capped.solve(case, problem, None, multilevel).fields
    assert fields["status"] == "not converged in 1 iterations" and fields["solver_iterations"] == 1
    assert method.solve(case, problem, None, multilevel).fields["status"] == "converged"
