"""The degree axis: X_h of order 3 and 4, the methods of degree k >= 3 (Nitsche, penalty, the
nodal cone at Gauss-Lobatto points), each solved exactly and checked against an independent
solver, and their rates on the cases that show them."""
import numpy as np
import pandas as pd
import pytest
import scipy.sparse as sp
from conftest import HIGH_ORDER_NAMES, clarabel_solution, problem_at, problem_with_hierarchy

from harness.fem.assembly import ContactTraceFunction, discretise
from harness.fem.contact_laws.system import law_system
from harness.fem.contact_quadrature import contact_quadrature
from harness.fem.edge_functionals import edge_functional_qp
from harness.fem.polynomials import lobatto_points
from harness.mesh.points import evaluate, in_elements
from harness.methods import METHODS
from harness.problem.case import load_case
from harness.solvers.general_constraints import GeneralConstraintSolver
from harness.solvers.newton import solve_semismooth_newton
from harness.study.chain import run_chain

slow = pytest.mark.slow


def fitted(rows: pd.DataFrame, last: int = 3) -> float:
    """The least-squares slope of log err_h1 against log h over the ``last`` levels."""
    tail = rows.sort_values("level").tail(last)
    return float(np.polyfit(np.log(tail.h), np.log(tail.err_h1), 1)[0])


@pytest.mark.parametrize("order", [3, 4])
@pytest.mark.parametrize("case_name", ["transition-r32", "elastic-transition-r32"])
def test_the_pk_trace_function_is_u_h_on_gamma_c_and_finds_its_least_value(case_name, order, rng):
    """``ContactTraceFunction`` of P_k: its values at any parameter of an edge are NGSolve's
    evaluation of the contact variable of u_h there, and ``minimum_parameters`` finds each edge's
    least value (no sample of 201 per edge lies below it)."""
    case, problem = load_case(case_name), problem_at(case_name, 1, order)
    u = rng.standard_normal(problem.ndof)
    trace_u = ContactTraceFunction.of(problem, u)
    t = np.array([0.1, 0.37, 0.5, 0.83])
    points = trace_u.a[:, None, :] + t[None, :, None] * (trace_u.b - trace_u.a)[:, None, :]
    in_elements(problem.mesh, points, np.broadcast_to(problem.trace.volumes[:, None], points.shape[:-1]))
    gfu = problem.gridfunction(u)
    value = evaluate(gfu, problem.mesh, points)
    if case.physics.elastic:
        value = -(value * problem.trace.normals[:, None, :]).sum(axis=-1)
    np.testing.assert_allclose(trace_u.at(t), value, atol=1e-11 * np.abs(value).max())
    edges = np.arange(len(trace_u.va))
    least = trace_u.value(edges, trace_u.minimum_parameters())
    dense = trace_u.at(np.linspace(0.0, 1.0, 201))
    assert (least <= dense.min(axis=1) + 1e-12 * np.abs(dense).max()).all()


@pytest.mark.parametrize("case_name", [pytest.param("transition-line-3d", marks=slow), "elastic-transition-3d"])
def test_the_3d_pk_trace_function_is_u_h_on_the_triangles_of_gamma_c(case_name, rng):
    """3D P3: ``ContactTraceFunction``'s values inside the triangles of Gamma_C (the Lagrange
    interpolant of its lattice values) and along their sides (Gauss-Lobatto values) are NGSolve's
    evaluation of the contact variable of a random u_h there."""
    case, problem = load_case(case_name), problem_at(case_name, 0, 3)
    u = rng.standard_normal(problem.ndof)
    trace_u = ContactTraceFunction.of(problem, u)
    gfu = problem.gridfunction(u)
    faces = problem.trace.faces
    lam = np.array([[0.2, 0.3, 0.5], [0.6, 0.1, 0.3], [1 / 3, 1 / 3, 1 / 3]])
    points, values = trace_u.on_faces(lam)
    in_elements(problem.mesh, points, np.broadcast_to(faces.volumes[:, None], points.shape[:-1]))
    exact = evaluate(gfu, problem.mesh, points)
    if case.physics.elastic:
        exact = -(exact * faces.normals[:, None, :]).sum(axis=-1)
    np.testing.assert_allclose(values, exact, atol=1e-10 * np.abs(exact).max())
    t = np.array([0.2, 0.7])
    along = trace_u.a[:, None, :] + t[None, :, None] * (trace_u.b - trace_u.a)[:, None, :]
    in_elements(problem.mesh, along, np.broadcast_to(trace_u.volumes[:, None], along.shape[:-1]))
    exact = evaluate(gfu, problem.mesh, along)
    if case.physics.elastic:
        exact = -(exact * problem.trace.normals[:, None, :]).sum(axis=-1)
    np.testing.assert_allclose(trace_u.at(t), exact, atol=1e-10 * np.abs(exact).max())


@pytest.mark.slow          # 2-3 s each
@pytest.mark.parametrize("case_name", ["smooth-3d", "elastic-transition-3d"])
def test_nitsche_p3_in_3d_is_solved_exactly_near_the_best_approximation(case_name):
    """Issue 63's "in 3D at least Nitsche": nitsche-p3 on a 3D scalar and a 3D elastic case, its
    Newton residual <= 1e-10, its error within 2% of the best approximation's (measured 1.006,
    0.993) and a third of P2's on the same mesh."""
    case = load_case(case_name)
    rows = pd.DataFrame(run_chain(case, [METHODS["nitsche"], METHODS["nitsche-p3"]], 1).rows).set_index("method")
    assert (rows.kkt_residual <= 1e-10).all() and (rows.status == "converged").all()
    assert rows.err_h1_over_best["nitsche-p3"] < 1.02
    assert rows.err_h1["nitsche-p3"] < rows.err_h1["nitsche"] / 3


@pytest.mark.parametrize("order", [3, 4])
def test_multigrid_newton_at_pk_equals_direct_newton(order):
    case = load_case("transition-r32")
    method = METHODS[f"nitsche-p{order}"]
    problem, multilevel = problem_with_hierarchy("transition-r32", 2, order)
    fast = solve_semismooth_newton(law_system(case, problem, method.law), multilevel=multilevel)
    direct = solve_semismooth_newton(law_system(case, problem_at("transition-r32", 2, order), method.law))
    assert fast.status == direct.status == "converged"
    assert np.abs(fast.u - direct.u).max() <= 1e-9 * np.abs(direct.u).max()


@pytest.mark.parametrize("cone", ["nodal", "mean"])
@pytest.mark.parametrize("order", [3, 4])
def test_the_pk_cones_are_solved_exactly_against_clarabel(order, cone):
    """nodal-p_k's and mean-p_k's QPs (vertex rows and k - 1 Gauss-Lobatto or sub-edge-mean rows
    per edge) by the harness's general-constraint active set method and by Clarabel, an
    interior-point solver: both feasible, the harness's energy J(z) = z K z / 2 - b z no higher
    than Clarabel's, and the two within 1e-5 of ||z||_K of each other in the energy norm (for the
    minimiser z over a convex set, ||z' - z||_K^2 <= 2 (J(z') - J(z)) for any feasible z'; P4's
    hierarchical basis makes the coefficients themselves ill-conditioned: mean-p4's differ by 1e-5
    relative, with Clarabel's J 3e-11 above the harness's)."""
    case = load_case("corner-r12")
    problem = problem_at("corner-r12", 1, order)
    qp = edge_functional_qp(case, problem, METHODS[f"{cone}-p{order}"].functionals)
    solution = GeneralConstraintSolver(qp.K, qp.b, qp.free, qp.B, qp.g, lift=qp.lift).solve()
    reference = solution.z.copy()
    reference[problem.free] = clarabel_solution(problem, qp)
    assert solution.status == "converged" and solution.residual <= 1e-10
    assert solution.active[qp.n_vertices:].any()                 # some edge row binds
    energy = lambda z: 0.5 * z @ (qp.K @ z) - qp.b @ z              # noqa: E731
    scale = solution.z @ (qp.K @ solution.z)
    assert (qp.B @ solution.z - qp.g).min() >= -1e-12 and (qp.B @ reference - qp.g).min() >= -1e-9
    assert energy(solution.z) <= energy(reference) + 1e-13 * scale
    difference = reference - solution.z
    assert difference @ (qp.K @ difference) <= 1e-10 * scale


def test_the_sub_edge_mean_cone_of_degree_2_is_the_papers_mean():
    """``_mean_pk.sub_edge_means`` at k = 2 is the edge mean, and the cone of functionals it makes
    (general rows, the general-constraint active set method) solves `mean`'s problem (a bound
    cone after a change of variables, the projected active set method): the same u_h."""
    from harness.methods import FunctionalCone
    from harness.methods.cones import sub_edge_means
    rule, = sub_edge_means(2)
    assert sum(w for _, w in rule) == pytest.approx(1.0) and sum(w * t for t, w in rule) == pytest.approx(0.5)
    assert [len(r) for r in sub_edge_means(4)] == [3, 3, 3]
    case = load_case("transition-r32")
    cone = FunctionalCone(name="mean-as-functionals", order=2, contact="", reference="", expected=None,
                          functionals_of=sub_edge_means)
    ours = cone.solve(case, problem_at("transition-r32", 2, 2), None, None).u
    paper = METHODS["mean"].solve(case, problem_at("transition-r32", 2, 2), None, None).u
    np.testing.assert_allclose(ours, paper, atol=1e-9 * np.abs(paper).max())


def test_the_gauss_lobatto_points_are_the_midpoint_at_p2_and_symmetric():
    assert np.allclose(lobatto_points(2), [0.0, 0.5, 1.0])
    for k in (3, 4):
        t = lobatto_points(k)
        assert len(t) == k + 1 and np.allclose(t, 1.0 - t[::-1])


@pytest.mark.parametrize("order", [2, 3, 4])
def test_nitsche_gamma0_keeps_p2s_coercivity_margin_at_every_degree(order):
    """theta = 1 is coercive while gamma0 C_h < 1 (tests/test_weak_contact.py): C_h grows like
    k^2, and gamma0 = 0.05 (2/k)^2 keeps the factor 2.5 at P3 and P4 too."""
    import scipy.linalg
    name = "nitsche" if order == 2 else f"nitsche-p{order}"
    largest = 0.0
    for level in (0, 1):
        problem = problem_at("transition-r32", level, order)
        q = contact_quadrature(problem)
        B = (q.N.T @ sp.diags(q.weights * q.h / problem.physics.modulus) @ q.N).tocsr()
        free = problem.free
        A, Bf = problem.A[free][:, free].toarray(), B[free][:, free].toarray()
        largest = max(largest, scipy.linalg.eigh(Bf, A, eigvals_only=True, subset_by_index=[len(A) - 1, len(A) - 1])[0])
    assert 2.5 * METHODS[name].law.gamma0 * largest < 1, largest


@pytest.mark.parametrize("method_name", HIGH_ORDER_NAMES)
def test_every_high_order_method_solves_exactly_on_every_level(method_name):
    rows = pd.DataFrame(run_chain(load_case("transition-r32"), [METHODS[method_name]], 3).rows)
    assert (rows.status == "converged").all(), rows[["level", "status"]]
    residual = rows.kkt_residual
    assert (residual <= 1e-10).all(), residual


@pytest.mark.parametrize("case_name", ["transition-r32", "elastic-transition-r32", "smooth"])
def test_the_integrated_volume_and_jump_terms_of_p_k_are_the_p2_formulas_on_a_p2_function(case_name):
    """The estimator's P_k path (NGSolve's integration of the element residual and the flux
    jumps) and its P2 path (grad u_h at the vertices, exact for a linear flux) give the same
    terms, element by element, on a P2 function that is no solution: two independent
    implementations of the same integrals."""
    from harness.measure.estimator import ResidualEstimator
    case = load_case(case_name)
    problem = problem_at(case_name, 2, 2)
    u = np.where(problem.free, np.random.default_rng(3).standard_normal(problem.ndof), problem.lift)
    terms = ResidualEstimator(case, problem).terms
    gfu = problem.gridfunction(u)
    fast = terms.volume_and_jumps(gfu, 2, case.physics)
    integrated = terms.integrated_volume_and_jumps(gfu, 2, case.physics)
    np.testing.assert_allclose(integrated, fast, rtol=1e-8, atol=1e-12 * fast.max())


@pytest.mark.slow          # 3 s: four P3 levels
def test_the_p3_estimator_is_steady_and_the_complementarity_it_leaves_out_is_of_lower_order():
    """On smooth-quintic (uniform meshes, nitsche-p3) eta / ||u - u_h||_a stays within a factor
    1.5 of itself over the levels; the complementarity term int (lambda_h)_+ (c(u_h) - alpha)_+,
    which the P_k estimator leaves out (``ResidualEstimator.gap_density``), falls like h^3 only,
    against the squared error's h^6: kept, it would dominate eta."""
    from harness.measure.errors import error_norms
    from harness.measure.estimator import ResidualEstimator
    from harness.mesh.levels import mesh_hierarchy
    case, method = load_case("smooth-quintic"), METHODS["nitsche-p3"]
    ratios, complementarity = [], []
    for _, mesh in mesh_hierarchy(case, 4):
        problem = discretise(case, mesh, 3)
        estimator = ResidualEstimator(case, problem)
        u = method.solve(case, problem, None, None).u
        error = error_norms(case, [problem.gridfunction(u)], problem.quadrature)[0]["err_energy"]
        lam_h = estimator.T_contact @ estimator.pressure.coefficients(u)
        q = estimator.q
        gap = q.T @ u - estimator.obstacle
        complementarity.append((q.weights * np.maximum(lam_h, 0.0) * np.maximum(gap, 0.0)).sum())
        ratios.append(estimator.indicators(u).sum() / error**2)
    assert max(ratios) <= 1.5 * min(ratios), ratios
    assert abs(np.log2(complementarity[-2] / complementarity[-1]) - 3.0) <= 0.3, complementarity


@slow
@pytest.mark.parametrize("case_name", ["corner-r12", "transition-r32"])
@pytest.mark.parametrize("order", [3, 4])
def test_adaptive_nitsche_of_degree_k_converges_at_k_over_2_in_the_dofs(case_name, order):
    """Adaptive meshes recover the optimal N^{-k/2} where uniform ones saturate (issue: N-rate
    >= 0.9 k/2), fitted over the last five levels."""
    import harness
    rows = harness.run([case_name], methods=[f"nitsche-p{order}"], levels=6, meshes="adaptive", show_progress=False)
    tail = rows.sort_values("level").tail(5)
    rate = -np.polyfit(np.log(tail.ndof), np.log(tail.err_h1), 1)[0]
    assert rate >= 0.9 * order / 2, tail[["level", "ndof", "err_h1"]]
    assert (rows.kkt_residual <= 1e-10).all()


# Measured, against a conjecture (no theorem covers the cones of degree k >= 3): mean-p4, the means
# over 3 sub-edges, fits 2.45 on smooth-quintic (pairwise 2.32 2.36 2.43 2.47 on 6 levels, its
# error 2.2 to 186 times R_h u's), where nodal-p4 and its declared min(nu - 1, k) are 4; mean-p3
# meets 3 (within 1.003 of R_h u)
MEAN_P4 = pytest.mark.xfail(strict=True, reason="measured 2.45 against the conjectured 4")


@slow
@pytest.mark.parametrize("method_name, order", [("nitsche-p3", 3), ("nodal-p3", 3), ("mean-p3", 3), ("nitsche-p4", 4),
                                                ("nodal-p4", 4), pytest.param("mean-p4", 4, marks=MEAN_P4)])
def test_smooth_quintic_shows_the_optimal_rate_of_each_degree(method_name, order):
    """nu = 11/2: Nitsche's min(nu - 1, k) = k, and the cones at the best approximation's rate
    (their declared conjecture)."""
    rows = pd.DataFrame(run_chain(load_case("smooth-quintic"), [METHODS[method_name]], 5).rows)
    assert fitted(rows) >= order - 0.1, rows[["level", "err_h1"]]


@slow
@pytest.mark.parametrize("method_name", ["nitsche-p3", "nodal-p3", "nitsche-p4", "mean-p3", "mean-p4"])
def test_p3_and_p4_saturate_at_one_and_a_half_on_transition_r32(method_name):
    """The transition singularity r^{3/2} caps every degree at h^{3/2} on uniform meshes."""
    rows = pd.DataFrame(run_chain(load_case("transition-r32"), [METHODS[method_name]], 6).rows)
    assert abs(fitted(rows) - 1.5) <= 0.1, rows[["level", "err_h1"]]


@slow
def test_penalty_stays_at_rate_one_whatever_the_degree():
    """Its consistency error eps lambda = eps0 h lambda caps the rate at h (Gustafsson & Stenberg
    2025, abstract: "an optimal convergence rate cannot be achieved")."""
    rows = pd.DataFrame(run_chain(load_case("smooth-quintic"), [METHODS["penalty-p3"]], 5).rows)
    assert abs(fitted(rows) - 1.0) <= 0.1, rows[["level", "err_h1"]]
