"""Two-body Coulomb friction by the dual mortar method (docs: the design note's steps 2-4): the
tangential jump's dual projection as QP variables (``fem.two_body.dual_bound_qp(...,
tangential=True)``), the frozen-threshold problem against Clarabel, the Coulomb fixed point of the
one-body cones (``solvers.coulomb_cones``) on the two-body QP row by row, mu_F -> 0, the coupled
multigrid against Cholesky, the mirror pair's symmetry (no slip on matching meshes, vanishing
friction on non-matching ones) and the entry point ``methods.mortar.Mortar.solve_coulomb``.

The data: two-body-elastic-transition's pair refined once (non-matching, 2:3 on Gamma_C); step 1
the case's own data (frictionless in the limit), step 2 the upper body's Dirichlet values moved by
XI along x (the lower body's kept), which shears the interface: a mirror pair with equal data
never slips. At XI = 1 (the case's displacements reach 3) the contact nodes both stick and slip."""
from __future__ import annotations

import dataclasses
from types import SimpleNamespace

import ngsolve as ngs
import numpy as np
import pytest
import scipy.sparse as sp
from conftest import clarabel_unilateral_tresca, trace_values

import harness
from harness.fem.assembly import discretise
from harness.fem.mortar import mortar_coupling
from harness.fem.sparse import ngsolve_matrix
from harness.fem.two_body import TwoBodyProblem, dual_bound_qp
from harness.mesh.levels import UniformRefinement, coarse_mesh
from harness.mesh.strategies import parse_mesh
from harness.mesh.strategies import refusal as mesh_refusal
from harness.methods import get_method
from harness.methods.mortar import bound_system, coulomb_guess, two_body_steps
from harness.problem.bodies import MirrorBody, lower_body
from harness.problem.case import CaseError, registered_cases
from harness.problem.contract import check_friction, check_second_body
from harness.problem.friction import Coulomb, LoadHistory, LoadStep
from harness.solvers.bound_constraints import ActiveSetSolver, FactorisedSystem
from harness.solvers.coulomb_cones import solve_coulomb_history
from harness.solvers.multigrid import Multilevel
from harness.solvers.options import SolverOptions
from harness.solvers.two_body_multigrid import JointMultilevel, mortar_coupling_matrix, mortar_injection
from harness.solvers.unilateral_friction import solve_unilateral_friction

TOLERANCE = 1e-10
MU = 0.3
XI = 1.0


@pytest.fixture(scope="module", params=[1, 2], ids=["P1", "P2"])
def pair(request):
    """(problem, frictionless QP, QP with the tangential rows, the two steps' (b, lift))."""
    case = registered_cases()["two-body-elastic-transition"]
    meshes = [coarse_mesh(body) for body in (case, lower_body(case))]
    for mesh in meshes:
        mesh.Refine()
    return _qps(case, meshes, request.param)


def _qps(case, meshes, order):
    problem = TwoBodyProblem(*(discretise(body, mesh, order) for body, mesh in zip((case, lower_body(case)), meshes)))
    coupling = mortar_coupling(problem.upper, problem.lower, case.obstacle, "dual", "midpoint")
    weight = 4.0 if order == 2 else None
    plain, qp = (dual_bound_qp(problem, coupling, weight, tangential=flag) for flag in (False, True))
    sheared = qp.lift.copy()
    upper_x = np.flatnonzero(~problem.upper.free[: problem.upper.ndof // 2])
    sheared[upper_x] += XI
    return problem, plain, qp, [(qp.b, qp.lift), (qp.b, sheared)]


def _system(qp):
    return lambda b: FactorisedSystem(qp.K, ngsolve_matrix(qp.K), b)


def _history(qp, steps, mu):
    guess = lambda k, solved: (solved[-1].solution.active, solved[-1].solution.z) if solved else (None, None)  # noqa: E731
    return solve_coulomb_history(qp, steps, mu, _system(qp), guess)


def _frictionless(plain, lift):
    solution = ActiveSetSolver(plain.K, plain.b, plain.free, plain.C, plain.alpha, lift=lift,
                               system=_system(plain)(plain.b)).solve()
    assert solution.status == "converged"
    return plain.to_u(solution.z)


def _with_tangential_trace(problem, u_n, u_t):
    """Body-wise vectors holding u_n's normal trace and u_t's trace values in the tangential block."""
    parts = []
    for body, normal, tangential in zip(problem.bodies, u_n, u_t):
        part, dofs = normal.copy(), np.concatenate([body.vertex_dofs, body.edge_dofs])
        part[dofs - body.ndof // 2] = tangential[dofs]
        parts.append(part)
    return np.concatenate(parts)


def test_tangential_rows_are_the_slave_node_values_of_the_jump_for_polynomials(pair):
    """For traces in the slave's space on non-matching meshes, z[C] = c_1 + c_2 and
    z[T] = t_1 - t_2 at the slave's nodes (biorthogonality, exact intersection integrals);
    to_z inverts to_u; K = S^T diag(A_1, A_2) S (dense, level 1); the normal channel is the
    frictionless QP's."""
    problem, plain, qp, _ = pair
    order = problem.order
    p, q = (lambda x: 0.3 + x - 0.7 * x ** order), (lambda x: -1.1 + 0.5 * x + 0.2 * x ** order)
    r, s = (lambda x: 0.2 - 0.4 * x + 0.9 * x ** order), (lambda x: 0.7 + 0.3 * x - 0.5 * x ** order)
    u = _with_tangential_trace(problem, [trace_values(problem.upper, p), trace_values(problem.lower, q)],
                               [trace_values(problem.upper, r), trace_values(problem.lower, s)])
    z = qp.to_z(u)
    trace = problem.upper.trace
    nodes = trace.vertex_points[:, 0] if order == 1 else np.concatenate([trace.vertex_points[:, 0], trace.midpoints[:, 0]])
    np.testing.assert_allclose(z[qp.C], p(nodes) + q(nodes), rtol=0, atol=1e-13)
    np.testing.assert_allclose(z[qp.T], r(nodes) - s(nodes), rtol=0, atol=1e-13)
    np.testing.assert_allclose(qp.to_u(z), u, rtol=0, atol=1e-13)
    A = sp.block_diag(qp.blocks).toarray()
    S = qp.S.toarray()
    assert np.abs(qp.K.toarray() - S.T @ A @ S).max() <= 1e-14 * np.abs(A).max()
    assert (np.abs(qp.R[qp.C] - plain.R[plain.C]).max() == 0) and np.array_equal(qp.alpha, plain.alpha)
    assert qp.free[qp.T].all() and len(qp.T) == len(qp.C)


def test_the_tangential_rows_are_refused_where_they_do_not_apply(pair):
    """Edge means (w = 6, `mortar-mean`) and standard multipliers (rows, not bounds): one line
    each, also when a method's refusal is bypassed."""
    problem, _, _, _ = pair
    coupling = mortar_coupling(problem.upper, problem.lower, None, "dual", "midpoint")
    case = _pressed_then_held(registered_cases()["two-body-elastic-transition"])
    if problem.order == 2:
        with pytest.raises(ValueError, match="nodal edge variables"):
            dual_bound_qp(problem, coupling, 6.0, tangential=True)
        with pytest.raises(ValueError, match="nodal edge variables"):
            get_method("mortar-mean").solve(case, problem, None, None)
        with pytest.raises(ValueError, match="not dual"):
            get_method("mortar-standard").solve(case, problem, None, None)


@pytest.mark.parametrize("name, reason", [("mortar-nodal", None), ("mortar-p1", None),
                                          ("mortar-mean", "O(h^2) of either sign"), ("mortar-standard", "not dual")])
def test_the_dual_nodal_mortars_discretise_two_body_coulomb_and_the_others_refuse_it_in_one_line(name, reason):
    refusal = get_method(name).refusal(_pressed_then_held(registered_cases()["two-body-elastic-transition"]))
    assert refusal is None if reason is None else (reason in refusal and "\n" not in refusal)


@pytest.mark.parametrize("physics, solid, refused", [("elasticity", False, None), ("scalar", False, "needs a normal stress"),
                                                     ("elasticity", True, "2D only")])
def test_the_contract_allows_coulomb_between_two_bodies_in_2d_elasticity_only(physics, solid, refused):
    """``problem.contract.check_friction``: two elastic bodies in 2D pass; the scalar model and
    a 3D geometry are refused in one line each."""
    geometry = registered_cases()["elastic-coulomb-3d" if solid else "two-body-elastic-transition"].geometry
    module = SimpleNamespace(friction=Coulomb(MU), physics=physics, second_body=object(), geometry=geometry)
    if refused is None:
        check_friction(module, "probe")
        return
    with pytest.raises(CaseError, match=r"^case probe: Coulomb friction [^\n]*" + refused + r"[^\n]*$"):
        check_friction(module, "probe")


def test_the_frozen_threshold_problem_matches_clarabel(pair):
    """Unilateral contact with Tresca rows of weights c = mu_F p (the frictionless forces of
    step 1) on the sheared step, the slip measured from step 1's z[T]: the active set solver of
    the one-body cones (``solvers.unilateral_friction``) on the two-body QP = Clarabel (epigraph
    form), z to 1e-7 relative, its KKT residual <= 1e-10, contact nodes in stick and in slip."""
    problem, plain, qp, steps = pair
    first = _history(qp, steps[:1], 0.0)[0].solution
    m = len(qp.C)
    c, reference = MU * np.maximum(first.multipliers[:m], 0.0), first.z[qp.T]
    b, lift = steps[1]
    solution = solve_unilateral_friction(qp.K, b, qp.free, qp.C, qp.alpha, qp.T, c, reference, lift, _system(qp)(b))
    clarabel = clarabel_unilateral_tresca(qp.K.toarray(), b, qp.free, lift, qp.C, qp.alpha, qp.T, c, reference)
    assert solution.status == "converged" and solution.kkt.residual <= TOLERANCE
    assert np.abs(solution.z - clarabel).max() <= 1e-7 * np.abs(clarabel).max()
    contact, slip = solution.active[:m], solution.active[m:2 * m] | solution.active[2 * m:]
    assert (contact & (c > 0) & slip).any() and (contact & (c > 0) & ~slip).any()


def _coulomb_violations(qp, mu, step, zprev) -> dict:
    """The discrete Coulomb law at the slave's nodes (the design note, Section 2.1) in the forces
    p = (K z - b)_C = D lambda_n and tau = (b - K z)_T = D lambda_t, each violation over the
    largest force or over max |z|."""
    m, z, multipliers = len(qp.C), step.solution.z, step.solution.multipliers
    p, tau, slip = multipliers[:m], multipliers[m:], z[qp.T] - zprev
    force, size = max(np.abs(p).max(), np.abs(tau).max()), np.abs(z).max()
    gap, bound = z[qp.C] - qp.alpha, mu * np.maximum(p, 0.0)
    slipping = np.abs(slip) > 0
    inside = np.abs(tau) < bound - TOLERANCE * force
    return {"unilateral": max(0.0, -gap.min()) / size,
            "pressure": max(0.0, -p.min()) / force,
            "complementarity": np.abs(p * gap).max() / (force * size),
            "cone": np.maximum(np.abs(tau) - bound, 0.0).max() / force,
            "slip at the bound": np.abs(np.abs(tau) - bound)[slipping].max(initial=0.0) / force,
            "slip against the force": np.maximum(-tau * np.sign(slip), 0.0)[slipping].max(initial=0.0) / force,
            "stick inside": np.abs(slip[inside]).max(initial=0.0) / size}


def test_the_fixed_point_solves_the_discrete_coulomb_conditions_row_by_row(pair):
    """Both steps (the second slipping from the first's z[T]): c = mu_F p reached (change
    <= 1e-10) and every condition holds to 1e-10; on the sheared step some contact nodes stick
    strictly inside the cone and some slip."""
    problem, plain, qp, steps = pair
    history = _history(qp, steps, MU)
    assert [step.status for step in history] == ["converged", "converged"] and history[1].iterations > 2
    zprev = np.zeros(len(qp.T))
    for step in history:
        violations = _coulomb_violations(qp, MU, step, zprev)
        assert max(violations.values()) <= TOLERANCE, violations
        zprev = step.solution.z[qp.T]
    m, last = len(qp.C), history[1].solution
    tau, bound = last.multipliers[m:], MU * np.maximum(last.multipliers[:m], 0.0)
    slip = np.abs(last.z[qp.T] - history[0].solution.z[qp.T]) > 0
    assert (slip & (bound > 0)).any() and ((np.abs(tau) < 0.9 * bound) & ~slip).any()


def test_mu_to_zero_reproduces_the_frictionless_two_body_solution(pair):
    """mu_F = 0: u = S z of both steps equals the frictionless mortar solution (no tangential
    rows) to 1e-10 relative (the tangential variables are free: the same minimiser in other
    variables); mu_F > 0 moves it by O(mu_F)."""
    problem, plain, qp, steps = pair
    frictionless = [_frictionless(plain, lift) for _, lift in steps]
    for step, u in zip(_history(qp, steps, 0.0), frictionless):
        assert step.iterations == 1
        assert np.abs(qp.to_u(step.solution.z) - u).max() <= TOLERANCE * np.abs(u).max()
    moved = [np.abs(qp.to_u(_history(qp, steps, mu)[1].solution.z) - frictionless[1]).max() for mu in (1e-3, 1e-4)]
    assert 0 < moved[1] <= 0.11 * moved[0], moved


def _pair_on_hierarchy(levels: int, order: int):
    """The pair's QPs on the finest of ``levels`` uniform levels and the joint P1 hierarchy."""
    case = registered_cases()["two-body-elastic-transition"]
    walks = [UniformRefinement(body).levels(levels) for body in (case, lower_body(case))]
    multilevel = None
    for _ in range(levels):
        meshes = [next(walk).mesh for walk in walks]
        multilevel = JointMultilevel(*(Multilevel(mesh, case.physics) for mesh in meshes)) if multilevel is None \
            else multilevel.refined(meshes)
    return _qps(case, meshes, order), multilevel


@pytest.mark.parametrize("order", [1, 2])
def test_coulomb_on_the_coupled_multigrid_solves_what_it_solves_on_cholesky(order):
    """Level 2: the finest matrix of the P1 hierarchy with the tangential rows in the coupling
    (``solvers.two_body_multigrid.mortar_coupling_matrix`` on C and T) is E^T K E, and both
    Coulomb steps on the coupled multigrid (``methods.mortar.bound_system``, threshold 0) give
    Cholesky's z to 1e-8 relative (measured 1e-10), each converged. (The tangential edge
    variables' injection, the mean of their ends, only speeds CG: 349 iterations against 375
    without it, P2, measured.)"""
    (problem, _, qp, steps), multilevel = _pair_on_hierarchy(3, order)
    E = mortar_injection(problem, tangential=True)
    top = multilevel.coupled(mortar_coupling_matrix(problem, qp.S_rows(qp.changed), qp.changed, E)).matrices[-1].scipy()
    assert abs(E.T @ qp.K @ E - top).max() <= 1e-13 * abs(top).max()
    _, multigrid, _ = bound_system(qp, problem, None, multilevel, SolverOptions(mortar_multigrid_from=0))
    guess = lambda k, solved: (solved[-1].solution.active, solved[-1].solution.z) if solved else (None, None)  # noqa: E731
    on_multigrid = solve_coulomb_history(qp, steps, MU, lambda b: multigrid, guess)
    on_cholesky = _history(qp, steps, MU)
    for mine, reference in zip(on_multigrid, on_cholesky):
        assert mine.status == reference.status == "converged"
        z = reference.solution.z
        assert np.abs(mine.solution.z - z).max() <= 1e-8 * np.abs(z).max()
    assert multigrid.work()["cg_iterations"] > 0


@pytest.mark.parametrize("order", [1, 2])
def test_a_matching_mirror_pair_with_equal_data_never_slips(order):
    """The design note's Section 1: on matching meshes (the lower body meshed as the upper) the
    case's mirror data give a zero tangential jump and zero friction force (each <= 1e-13
    relative, measured 3e-16 and 2e-15) under mu_F = 0.3: Coulomb = frictionless to 1e-10."""
    case = registered_cases()["two-body-elastic-transition"]
    case = dataclasses.replace(case, second_body=MirrorBody(case.geometry, case.maxh))
    meshes = [coarse_mesh(body) for body in (case, lower_body(case))]
    for mesh in meshes:
        mesh.Refine()
    problem, plain, qp, steps = _qps(case, meshes, order)
    step = _history(qp, steps[:1], MU)[0]
    u = _frictionless(plain, steps[0][1])
    m, z = len(qp.C), step.solution.z
    assert step.status == "converged" and (step.c > 0).any()
    assert np.abs(z[qp.T]).max() <= 1e-13 * np.abs(z).max()
    assert np.abs(step.solution.multipliers[m:]).max() <= 1e-13 * step.solution.multipliers[:m].max()
    assert np.abs(qp.to_u(z) - u).max() <= TOLERANCE * np.abs(u).max()


def _pressed_then_held(case):
    """The case as a reference Coulomb case (no u: its u as the Dirichlet data) with a two-step
    history, half the data first (the entry point's test: a two-body case loaded from a file
    needs its u, ``problem.case.case_from_module``)."""
    traction = case.physics.flux(case.grad_u, ngs.specialcf.normal(2))
    return dataclasses.replace(case, u=None, dirichlet=case.u, neumann=traction, friction=Coulomb(MU),
                               history=LoadHistory((LoadStep("normal", dirichlet=0.5 * case.u, neumann=0.5 * traction),
                                                    LoadStep("final"))))


@pytest.mark.parametrize("method_name", ["mortar-p1", "mortar-nodal"])
def test_mortar_solve_coulomb_runs_the_load_history_on_cholesky_and_on_multigrid(method_name):
    """``Mortar.solve_coulomb`` on level 2 of a two-step history: both steps converged (fields:
    KKT <= 1e-10, two load steps, the first step's u kept), the last step's data the problem's
    own, the first's half of them, u the fixed point's on these steps to 1e-10; on the coupled
    multigrid (threshold 0, nested from level 1's carry) the same u to 1e-8 relative."""
    method = get_method(method_name)
    (problem, _, qp, _), multilevel = _pair_on_hierarchy(3, method.order)
    case = _pressed_then_held(registered_cases()["two-body-elastic-transition"])
    steps = two_body_steps(case, problem, qp)
    assert np.array_equal(steps[1][0], qp.b) and np.array_equal(steps[1][1], qp.lift)
    np.testing.assert_allclose(steps[0][1], 0.5 * qp.lift, rtol=0, atol=1e-12 * np.abs(qp.lift).max())
    np.testing.assert_allclose(steps[0][0], 0.5 * qp.b, rtol=0, atol=1e-12 * np.abs(qp.b).max())
    on_cholesky = method.solve(case, problem, None, None)
    fields = on_cholesky.fields
    assert fields.status == "converged" and fields.kkt_residual <= TOLERANCE and fields.load_steps == 2
    assert on_cholesky.previous is not None and fields.active_constraints > 0
    # the fixed point of every step on its own system (a factorised system kept across steps would
    # hold the first step's pinned values: the same pin set at the second step's lift returned the
    # first step's solution, measured 1.5 max |u| off)
    direct = qp.to_u(_history(qp, steps, MU)[-1].solution.z)
    assert np.abs(on_cholesky.u - direct).max() <= TOLERANCE * np.abs(direct).max()
    (coarse, *_), _ = _pair_on_hierarchy(2, method.order)
    carry = method.solve(case, coarse, None, None).carry
    assert len(carry.steps) == 1 and len(carry.slip) == 2 * len(carry.active) == 2 * len(carry.steps[0].active)
    multigrid = dataclasses.replace(method, solver=dataclasses.replace(method.solver, mortar_multigrid_from=0))
    on_multigrid = multigrid.solve(case, problem, carry, multilevel)
    assert on_multigrid.fields.status == "converged" and on_multigrid.fields.kkt_residual <= TOLERANCE
    assert np.abs(on_multigrid.u - on_cholesky.u).max() <= 1e-8 * np.abs(on_cholesky.u).max()
    # each step nested from level 1's same step (``methods.mortar.coulomb_guess``): both steps'
    # rows predicted and started from it
    guesses = [coulomb_guess(qp, problem, carry, multilevel, k, []) for k in range(2)]
    assert all(predicted is not None and start is not None for predicted, start in guesses)
    assert len(guesses[0][0]) == 3 * len(qp.C) and guesses[1][0][:len(qp.C)].any()


@pytest.mark.parametrize("order", [1, 2])
def test_on_non_matching_meshes_the_friction_of_mirror_data_vanishes_under_refinement(order):
    """The design note's Section 1 and 3, seen discretely: mirror data drive no slip, so the
    friction force of the case's own step (mu_F = 0.3) comes from the non-matching meshes only,
    and max |tau| / (mu_F max p) falls on levels 1-3 (measured: P1 0.042, 0.017, 0.012; P2 0.023,
    0.016, 0.011; on to 0.0088 and 0.0079 on level 4, about h^{1/2})."""
    ratios = []
    for levels in (2, 3, 4):
        (problem, _, qp, steps), _ = _pair_on_hierarchy(levels, order)
        step = _history(qp, steps[:1], MU)[0]
        assert step.status == "converged"
        m = len(qp.C)
        ratios.append(np.abs(step.solution.multipliers[m:]).max() / (MU * step.solution.multipliers[:m].max()))
    assert ratios[0] > ratios[1] > ratios[2] and ratios[0] < 0.05, ratios


def _sheared(case, xi: float = XI):
    """The exact case with Coulomb friction and the design note's two-step history: step 1 the
    case's own data on both bodies, step 2 the upper body's Dirichlet values moved by ``xi``
    along x while the lower body holds the mirror data (its own, ``MirrorBody.dirichlet``)."""
    body = case.second_body
    return dataclasses.replace(case, friction=Coulomb(MU), dirichlet=case.u + ngs.CF((xi, 0.0)),
                               second_body=MirrorBody(body.geometry, body.maxh, dirichlet=case.u),
                               history=LoadHistory((LoadStep("normal", dirichlet=case.u), LoadStep("tangential"))))


def test_the_lower_body_holds_its_own_dirichlet_data_at_every_step():
    """``problem.bodies.lower_body`` with ``MirrorBody.dirichlet``: the lower body's lift is the
    mirror data's at both steps (the history's Dirichlet values are the upper's), the upper's
    moves by XI along x at its Dirichlet vertices between the steps, and nothing else moves; without it the lower body is
    the case's (the same history, no data of its own)."""
    case = registered_cases()["two-body-elastic-transition"]
    assert lower_body(case).dirichlet is None and lower_body(case).history is case.history
    sheared = _sheared(case)
    meshes = [coarse_mesh(body) for body in (case, lower_body(case))]
    problem, _, qp, _ = _qps(case, meshes, 2)
    steps = two_body_steps(sheared, TwoBodyProblem(*(discretise(body, mesh, 2) for body, mesh in
                                                     zip((sheared, lower_body(sheared)), meshes))), qp)
    n1, (lift_1, lift_2) = problem.upper.ndof, (lift for _, lift in steps)
    np.testing.assert_allclose(lift_1, qp.lift, rtol=0, atol=1e-13)
    np.testing.assert_allclose(lift_2[n1:], qp.lift[n1:], rtol=0, atol=1e-13)
    # the x-components' Dirichlet vertex dofs (NGSolve's P2 basis is hierarchical: a constant
    # has no edge coefficients)
    moved = np.flatnonzero(np.abs(lift_2 - lift_1) > 1e-13)
    assert len(moved) > 0 and (moved < n1 // 2).all() and not problem.upper.free[moved].any()
    np.testing.assert_allclose((lift_2 - lift_1)[moved], XI, rtol=0, atol=1e-13)


def test_the_contract_refuses_a_lower_bodys_own_data_beside_the_mirror_solution():
    case = registered_cases()["two-body-elastic-transition"]
    with pytest.raises(CaseError, match=r"^case probe: second_body declares its own dirichlet[^\n]*$"):
        check_second_body(_sheared(case), "probe")
    with pytest.raises(ValueError, match="dirichlet must be a CoefficientFunction or a number"):
        MirrorBody(case.geometry, case.maxh, dirichlet="u")


def _conditions_of_the_solve(case, method, level, problem, solve) -> dict:
    """``harness.run``'s on_level hook: the discrete Coulomb law of the last load step at the
    slave's nodes (``_coulomb_violations``), from the level's u_h and the previous step's."""
    coupling = mortar_coupling(problem.upper, problem.lower, case.obstacle, "dual", "midpoint")
    qp = dual_bound_qp(problem, coupling, method.contact_weight(problem.order), tangential=True)
    z, m = qp.to_z(solve.u), len(qp.C)
    multipliers = np.concatenate([(qp.K @ z - qp.b)[qp.C], (qp.b - qp.K @ z)[qp.T]])
    step = SimpleNamespace(solution=SimpleNamespace(z=z, multipliers=multipliers))
    # S^{-1} (u_h) rounds the stick nodes' pinned values: a slip below 1e-12 max |z| is a stick
    reference = qp.to_z(solve.previous)[qp.T]
    reference = np.where(np.abs(z[qp.T] - reference) <= 1e-12 * np.abs(z).max(), z[qp.T], reference)
    violations = _coulomb_violations(qp, case.friction.coefficient, step, reference)
    slip = np.abs(z[qp.T] - reference) > 0
    bound = case.friction.coefficient * np.maximum(multipliers[:m], 0.0)
    return violations | {"slipping": int((slip & (bound > 0)).sum()),
                         "sticking": int(((np.abs(multipliers[m:]) < 0.9 * bound) & ~slip).sum())}


@pytest.mark.parametrize("multigrid_from", [None, 0], ids=["cholesky", "multigrid"])
def test_harness_run_shears_an_exact_two_body_case_under_coulomb_with_mortar_nodal(multigrid_from):
    """two-body-elastic-transition with Coulomb friction (mu_F = 0.3) and a two-step history,
    step 2 shearing the upper body by XI against the lower (which holds the mirror data,
    ``MirrorBody.dirichlet``), through ``harness.run`` with `mortar-nodal`, levels 0-2, on
    Cholesky and on the coupled multigrid (every step nested from the coarser level's same
    step, ``methods.mortar.coulomb_guess``): every row converged, both load steps, KKT residual
    <= 1e-10, and the discrete Coulomb law of the last step holds at every slave node of every
    level to 1e-10, with nodes in slip and in stick (measured on levels 0-2, `mortar-nodal` and
    `mortar-p1`: KKT 2e-12 to 5e-11, the law to 1.3e-11; KKT <= 8e-11 on levels 0-3, and 0-4 of
    `mortar-p1`). The slip and stick zones are measured from the jump, their exact values and
    the estimator are NaN; the error
    columns are measured against the case's u, not this problem's solution."""
    kept, method = {}, get_method("mortar-nodal")
    if multigrid_from is not None:
        method = dataclasses.replace(method, solver=dataclasses.replace(method.solver, mortar_multigrid_from=multigrid_from))
    rows = harness.run(_sheared(registered_cases()["two-body-elastic-transition"]), [method], levels=3,
                       show_progress=False, on_level=lambda *args: kept.setdefault(args[2], _conditions_of_the_solve(*args)))
    assert len(rows) == 3 and (rows.status == "converged").all() and (rows.load_steps == 2).all()
    assert (rows.kkt_residual <= TOLERANCE).all(), rows.kkt_residual.tolist()
    # the slip between the bodies is the jump of u_t (``measure.two_body_quantities``,
    # tests/test_two_body_quantities.py); a mirror pair has no exact slip zone
    assert rows[["qoi_slip_measure", "qoi_stick_measure"]].notna().all().all()
    assert rows[["qoi_slip_measure_exact", "estimator"]].isna().all().all()
    for level, conditions in kept.items():
        assert max(v for k, v in conditions.items() if k not in ("slipping", "sticking")) <= TOLERANCE, (level, conditions)
        assert conditions["slipping"] > 0 and conditions["sticking"] > 0, (level, conditions)


def test_adaptive_meshes_refuse_a_two_body_load_history_in_one_line():
    """The two-body estimator has no friction terms for a load step's slip (NaN indicators):
    no adaptive pair; uniform and graded meshes serve the case."""
    case = _sheared(registered_cases()["two-body-elastic-transition"])
    reasons = {strategy.name: mesh_refusal(strategy, case) for strategy in parse_mesh("all")}
    assert reasons["uniform"] is None and reasons["graded"] is None
    assert "estimator" in reasons["adaptive"] and "\n" not in reasons["adaptive"]
