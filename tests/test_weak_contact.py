"""Penalty and Nitsche (``weak_contact``, ``newton``): the Gamma_C operators are NGSolve's basis,
the semismooth Newton solution is the solution of NGSolve's own assembly of the nonlinear form,
the multigrid path equals the direct one, and parameters are parsed and checked."""
import ngsolve as ngs
import numpy as np
import pytest
from conftest import WEAK_NAMES, problem_at, problem_with_hierarchy

from harness.fem.contact_quadrature import contact_quadrature
from harness.fem.weak_contact import weak_contact_system
from harness.mesh.points import evaluate
from harness.methods import METHODS, get_method, methods_named
from harness.problem.case import load_case
from harness.solvers.newton import solve_semismooth_newton
from harness.solvers.options import SolverOptions

# a straight horizontal Gamma_C; a slanted one with a gap; contact loads g_C
CASES = ["transition-r32", "tests/data/gap_case.py", "wedge-r23"]
VARIANTS = [pytest.param(0.0, 1.0, id="penalty"), pytest.param(1.0, 1.0, id="nitsche-theta1"),
            pytest.param(1.0, 0.0, id="nitsche-theta0"), pytest.param(1.0, -1.0, id="nitsche-theta-1")]


@pytest.mark.parametrize("order", [1, 2])
@pytest.mark.parametrize("case_name", CASES)
def test_gamma_c_operators_give_ngsolve_trace_and_normal_derivative(case_name, order, rng):
    problem = problem_at(case_name, 2, order)
    quadrature = contact_quadrature(problem)
    u = rng.standard_normal(problem.ndof)
    gfu = problem.gridfunction(u)
    normals = problem.trace.normals[quadrature.edge]
    dn = (evaluate(ngs.grad(gfu), problem.mesh, quadrature.points) * normals).sum(axis=1)
    np.testing.assert_allclose(quadrature.T @ u, evaluate(gfu, problem.mesh, quadrature.points), atol=1e-12)
    np.testing.assert_allclose(quadrature.N @ u, dn, atol=1e-12 * np.abs(dn).max())
    assert quadrature.weights.sum() == pytest.approx(problem.trace.lengths.sum(), rel=1e-14)


def ngsolve_reference(case, problem, gamma0, theta, flux):
    """The same method assembled by NGSolve from its symbolic form ((N)/(P) of ``weak_contact``,
    d_n u by a skeleton integral, the same 4-point Gauss rule) and solved by a textbook Newton
    loop with NGSolve's linearisation and UMFPACK."""
    mesh, fes = problem.mesh, problem.fes
    eps_space = ngs.FacetFESpace(mesh, order=0)
    eps = ngs.GridFunction(eps_space)
    for edge, length in zip(problem.trace.edges, problem.trace.lengths):
        (dof,) = eps_space.GetDofNrs(ngs.NodeId(ngs.EDGE, int(edge)))
        eps.vec[dof] = gamma0 * length
    u, v = fes.TnT()
    n = ngs.specialcf.normal(2)
    load = case.contact_load if case.contact_load is not None else ngs.CF(0)
    gap = case.gap if case.gap is not None else ngs.CF(0)
    P = flux * eps * (ngs.grad(u) * n - load) + gap - u
    P_theta_v = theta * flux * eps * (ngs.grad(v) * n) - v
    gamma_c = ngs.ds(skeleton=True, definedon=mesh.Boundaries("contact"),
                     intrules={ngs.SEGM: ngs.IntegrationRule(ngs.SEGM, 7)})
    form = ngs.BilinearForm(fes)
    form += ngs.grad(u) * ngs.grad(v) * ngs.dx
    form += (-theta * flux * eps * (ngs.grad(u) * n - load) * (ngs.grad(v) * n)
             + (1 / eps) * ngs.IfPos(P, P, 0) * P_theta_v) * gamma_c
    gfu = ngs.GridFunction(fes)
    gfu.vec.FV().NumPy()[:] = problem.lift
    b, r = gfu.vec.CreateVector(), gfu.vec.CreateVector()
    b.FV().NumPy()[:] = problem.b
    for _ in range(50):
        form.Apply(gfu.vec, r)
        r.data -= b
        if np.abs(r.FV().NumPy()[problem.free]).max() < 1e-13 * np.abs(problem.b).max():
            break
        form.AssembleLinearization(gfu.vec)
        gfu.vec.data -= form.mat.Inverse(fes.FreeDofs(), inverse="umfpack") * r
    return gfu.vec.FV().NumPy().copy()


@pytest.mark.parametrize("flux, theta", VARIANTS)
@pytest.mark.parametrize("order", [1, 2])
@pytest.mark.parametrize("case_name", CASES)
def test_newton_solution_equals_ngsolve_assembled_nonlinear_form(case_name, order, flux, theta):
    case = load_case(case_name)
    reference = ngsolve_reference(case, problem_at(case_name, 2, order), 0.05, theta, flux)
    solution = solve_semismooth_newton(weak_contact_system(case, problem_at(case_name, 2, order), 0.05, theta, flux))
    assert solution.status == "converged" and solution.residual <= 1e-10
    assert np.abs(solution.u - reference).max() <= 1e-10 * np.abs(reference).max()


@pytest.mark.parametrize("method_name", WEAK_NAMES)
@pytest.mark.parametrize("case_name", ["transition-r32", "tests/data/gap_case.py"])
def test_multigrid_newton_equals_direct_newton(case_name, method_name):
    """The study's path (multigrid CG, coarse spaces truncated at the active Gamma_C vertices)
    and UMFPACK give the same u_h; the residual is recomputed from scratch."""
    case, method = load_case(case_name), METHODS[method_name]
    problem, multilevel = problem_with_hierarchy(case_name, 3, method.order)
    system = weak_contact_system(case, problem, method.gamma0, method.theta, method.flux)
    fast = solve_semismooth_newton(system, multilevel=multilevel)
    direct = solve_semismooth_newton(weak_contact_system(case, problem_at(case_name, 3, method.order), method.gamma0,
                                                         method.theta, method.flux))
    assert fast.status == direct.status == "converged"
    assert fast.linear_iterations > direct.linear_iterations     # CG iterations against factorisations
    assert np.abs(fast.u - direct.u).max() <= 1e-9 * np.abs(direct.u).max()
    F = problem.A @ fast.u - system.rhs + system.Btheta.T @ (system.quadrature.weights * system.pressure(fast.u))
    if method.flux and method.theta:
        N = system.quadrature.N
        F -= method.theta * (N.T @ (system.quadrature.weights * system.eps * (N @ fast.u)))
    scale = np.abs((problem.b - problem.A @ problem.lift)[problem.free]).max()
    assert np.abs(F[problem.free]).max() <= 1e-10 * scale


def test_pressure_is_the_bracket_over_eps_and_never_negative():
    case = load_case("transition-r32")
    problem = problem_at("transition-r32", 3)
    system = weak_contact_system(case, problem, 0.05, 1.0, 1.0)
    u = solve_semismooth_newton(system).u
    pressure = system.pressure(u)
    assert pressure.min() >= 0 and (pressure > 0).any()
    np.testing.assert_allclose(pressure * system.eps, np.maximum(system.bracket(u), 0.0))


def test_method_parameters_are_parsed_named_and_checked():
    method = get_method("nitsche:theta=-1,gamma0=0.5")
    assert (method.name, method.theta, method.gamma0) == ("nitsche:gamma0=0.5,theta=-1", -1.0, 0.5)
    assert get_method("penalty:epsilon0=1e-3").parameters == {"epsilon0": 1e-3}
    assert [m.name for m in methods_named(["paper", "penalty:epsilon0=0.1"])] == ["mean", "nodal", "penalty:epsilon0=0.1"]
    for bad in ["nitsche:gamma=1", "nitsche:theta", "penalty:theta=1", "nodal:gamma0=1"]:
        with pytest.raises(ValueError):
            get_method(bad)
    with pytest.raises(ValueError, match="positive"):
        weak_contact_system(load_case("transition-r32"), problem_at("transition-r32", 0), 0.0, 1.0, 1.0)


def test_nitsche_past_its_coercivity_bound_leaves_cg_at_once_and_matches_ngsolve():
    """theta = 1 with gamma0 = 0.3 (past the bound 0.145, ``methods/nitsche.py``): J is
    indefinite, CG stops at its first non-positive curvature and the steps go to the updated
    LDL^T factorisation; the solution is the one NGSolve's own Newton (a fresh UMFPACK
    factorisation per step) finds."""
    case, level = load_case("corner-r12"), 3
    problem, multilevel = problem_with_hierarchy("corner-r12", level, 2)
    fast = solve_semismooth_newton(weak_contact_system(case, problem, 0.3, 1.0, 1.0), multilevel=multilevel)
    reference = ngsolve_reference(case, problem_at("corner-r12", level, 2), 0.3, 1.0, 1.0)
    assert fast.status == "converged" and fast.residual <= 1e-10
    assert fast.linear_iterations < 2 * fast.iterations + 20       # not 500 CG steps before the switch
    assert np.abs(fast.u - reference).max() <= 1e-10 * np.abs(reference).max()


@pytest.mark.parametrize("method_name", ["nitsche", "penalty"])
def test_newton_below_the_round_off_floor_ends_converged_at_round_off(method_name):
    """tol = 1e-17 lies below the floor of the relative residual (eps cond(J); 1e-15 did too until
    the CG of a repeated set went on from where it stopped, which reached 9.7e-16 once): once the
    set of active Gauss points repeats, Newton stops with the backward error of J u = r at
    round-off instead of running its 60 steps."""
    case, method = load_case("transition-r32"), METHODS[method_name]
    problem, multilevel = problem_with_hierarchy("transition-r32", 4, method.order)
    system = weak_contact_system(case, problem, method.gamma0, method.theta, method.flux)
    solution = solve_semismooth_newton(system, multilevel=multilevel, options=SolverOptions(tolerance=1e-17))
    assert solution.status == "converged" and solution.residual > 1e-17
    assert solution.backward <= SolverOptions().roundoff_backward_error and solution.iterations < 20


def test_nitsche_without_a_solution_stops_as_stalled_where_sixty_steps_would_not_converge():
    """theta = 1, gamma0 = 3 (far past the coercivity bound): max |F| stops falling; Newton stops
    ``stall_steps`` after its best residual, and running on to 60 steps would not have converged."""
    case = load_case("corner-r12")
    problem, multilevel = problem_with_hierarchy("corner-r12", 2, 2)
    stalled = solve_semismooth_newton(weak_contact_system(case, problem, 3.0, 1.0, 1.0), multilevel=multilevel)
    assert stalled.status.startswith("stalled: max |F| not below its best") and stalled.iterations < 30
    assert stalled.residual > 1e-10
    wandering = solve_semismooth_newton(weak_contact_system(case, problem, 3.0, 1.0, 1.0), multilevel=multilevel,
                                        options=SolverOptions(stall_steps=1000))
    assert wandering.status == "not converged in 60 iterations"


@pytest.mark.parametrize("method_name", WEAK_NAMES)
def test_loose_newton_steps_on_new_sets_reach_the_same_solution_with_fewer_cg_iterations(method_name):
    """Inexact semismooth Newton (``pdas.loose_depth``): from the zero start, the steps
    whose set is new are solved to 1e-3 of the residual; the solution is the all-full-depth
    run's, to the tolerance, in fewer CG iterations."""
    case, method = load_case("transition-r32"), METHODS[method_name]
    problem, multilevel = problem_with_hierarchy("transition-r32", 3, method.order)

    def solve(options=SolverOptions()):
        return solve_semismooth_newton(weak_contact_system(case, problem, method.gamma0, method.theta, method.flux),
                                       multilevel=multilevel, options=options)
    loose = solve()
    full = solve(SolverOptions(forcing=0.0))        # every step to the full depth
    assert loose.status == full.status == "converged"
    assert loose.residual <= 1e-10
    assert np.abs(loose.u - full.u).max() <= 1e-9 * np.abs(full.u).max()
    assert loose.linear_iterations < full.linear_iterations
