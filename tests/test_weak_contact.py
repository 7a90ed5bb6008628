"""Penalty and Nitsche, the built-in contact laws (``fem.contact_laws.builtin``, ``fem.contact_laws``, ``newton``), in
every physics and dimension: the Gamma_C rows are NGSolve's basis (the contact variable and its
flux, d_n u or -sigma_n(u)), the semismooth Newton solution is the solution of NGSolve's own
assembly of the nonlinear form, the multigrid path equals the direct one, and parameters are
parsed and checked."""
import ngsolve as ngs
import numpy as np
import pytest
from conftest import WEAK_NAMES, problem_at, problem_with_hierarchy

from harness.fem.contact_laws.builtin import Nitsche, Penalty
from harness.fem.contact_laws.system import law_system
from harness.fem.contact_quadrature import contact_quadrature
from harness.mesh.points import evaluate
from harness.methods import METHODS, get_method, methods_named
from harness.problem.case import load_case
from harness.solvers.newton import solve_semismooth_newton
from harness.solvers.options import SolverOptions

# a straight horizontal Gamma_C; a slanted one with a gap; contact loads g_C
CASES = ["transition-r32", "tests/data/gap_case.py", "wedge-r23"]
VARIANTS = [pytest.param(0.0, 1.0, id="penalty"), pytest.param(1.0, 1.0, id="nitsche-theta1"),
            pytest.param(1.0, 0.0, id="nitsche-theta0"), pytest.param(1.0, -1.0, id="nitsche-theta-1")]


def weak_contact_system(case, problem, gamma0, theta, flux):
    """The system of Nitsche's law (``flux`` = 1) or the penalty law (0) with eps = gamma0 h."""
    return law_system(case, problem, Nitsche(gamma0, theta) if flux else Penalty(gamma0))


def method_system(case, problem, method):
    return law_system(case, problem, method.law)


# every physics and dimension: the 2D scalar cases, plane strain, the 3D scalar problem, 3D elasticity
# (the level of each: a few thousand dofs)
PHYSICS_CASES = [("elastic-transition-r32", 2), ("transition-line-3d", 0), ("elastic-transition-3d", 0)]


def contact_variable_and_flux(case, problem, u, points, normals):
    """c(u_h) and its flux at ``points`` by NGSolve's own evaluation of u_h and its gradient:
    u_h and d_n u_h, or -u_h . n and -n . sigma(u_h) n."""
    gfu, mesh = problem.gridfunction(u), problem.mesh
    if not case.physics.elastic:
        return evaluate(gfu, mesh, points), (evaluate(ngs.grad(gfu), mesh, points) * normals).sum(axis=1)
    d = mesh.dim
    sigma = case.physics.flux_array(evaluate(ngs.Grad(gfu), mesh, points).reshape(-1, d, d))
    return -(evaluate(gfu, mesh, points) * normals).sum(axis=1), -np.einsum("qi,qij,qj->q", normals, sigma, normals)


# the 3D rows of degree 3 and 4 (1.5-2.5 s each) in `make test-full`
ROW_CHECKS = [pytest.param(name, level, order, marks=pytest.mark.slow if name.endswith("-3d") and order > 2 else ())
              for name, level in [(name, 2) for name in CASES] + PHYSICS_CASES for order in (1, 2, 3, 4)]


@pytest.mark.parametrize("case_name, level, order", ROW_CHECKS)
def test_gamma_c_rows_give_ngsolve_contact_variable_and_flux(case_name, level, order, rng):
    case, problem = load_case(case_name), problem_at(case_name, level, order)
    quadrature = contact_quadrature(problem)
    u = rng.standard_normal(problem.ndof)
    value, flux = contact_variable_and_flux(case, problem, u, quadrature.points, quadrature.normals)
    np.testing.assert_allclose(quadrature.T @ u, value, atol=1e-12 * np.abs(value).max())
    np.testing.assert_allclose(quadrature.N @ u, flux, atol=1e-12 * np.abs(flux).max())
    area = problem.trace.lengths.sum() if problem.mesh.dim == 2 else ngs.Integrate(1, problem.mesh, definedon=problem.mesh.Boundaries("contact"))
    assert quadrature.weights.sum() == pytest.approx(area, rel=1e-13)


def cell_sizes(problem):
    """eps's h on each facet of Gamma_C as NGSolve's FacetFESpace of order 0: the edge's length
    (2D), the triangle's diameter (3D), as ``contact_quadrature``'s h."""
    mesh = problem.mesh
    space = ngs.FacetFESpace(mesh, order=0)
    h = ngs.GridFunction(space)
    for element in mesh.Boundaries("contact").Elements():
        corners = np.array([mesh[v].point for v in element.vertices])
        diameter = max(np.linalg.norm(p - q) for p in corners for q in corners)
        (dof,) = space.GetDofNrs(element.edges[0] if mesh.dim == 2 else element.faces[0])
        h.vec[dof] = diameter
    return h


def ngsolve_reference(case, problem, gamma0, theta, flux):
    """The same method assembled by NGSolve from its symbolic form ((N)/(P) of ``fem.contact_laws.builtin``, in
    elasticity CHR 2015's eq. (10) with sigma_n(u) = n . sigma(u) n, written from the physics'
    own stress; the flux by a skeleton integral, the same Gauss rule) in NGSolve's Cartesian
    basis, and solved by a textbook Newton loop with NGSolve's linearisation and UMFPACK."""
    mesh, fes, physics = problem.mesh, problem.fes, case.physics
    eps = gamma0 / physics.modulus * cell_sizes(problem)
    u, v = fes.TnT()
    n = ngs.specialcf.normal(mesh.dim)
    if physics.elastic:
        def c(w):
            return -w * n

        def flux_of(w):
            return -(n * (physics.stress(ngs.Grad(w)) * n))
        load = -(case.contact_load * n) if case.contact_load is not None else ngs.CF(0)
        gap = -case.gap if case.gap is not None else ngs.CF(0)
    else:
        def c(w):
            return w

        def flux_of(w):
            return ngs.grad(w) * n
        load = case.contact_load if case.contact_load is not None else ngs.CF(0)
        gap = case.gap if case.gap is not None else ngs.CF(0)
    P = flux * eps * (flux_of(u) - load) + gap - c(u)
    P_theta_v = theta * flux * eps * flux_of(v) - c(v)
    degree = 2 * max(4, problem.order + 1) - 1            # the harness's Gamma_C rule (``contact_quadrature``)
    rule = {ngs.SEGM: ngs.IntegrationRule(ngs.SEGM, degree), ngs.TRIG: ngs.IntegrationRule(ngs.TRIG, degree)}
    gamma_c = ngs.ds(skeleton=True, definedon=mesh.Boundaries("contact"), intrules=rule)
    form = ngs.BilinearForm(fes)
    form += physics.form(u, v) * ngs.dx
    form += (-theta * flux * eps * (flux_of(u) - load) * flux_of(v)
             + (1 / eps) * ngs.IfPos(P, P, 0) * P_theta_v) * gamma_c
    gfu = ngs.GridFunction(fes)
    gfu.vec.FV().NumPy()[:] = problem.cartesian(problem.lift)
    b, r = gfu.vec.CreateVector(), gfu.vec.CreateVector()
    b.FV().NumPy()[:] = problem.cartesian(problem.b)
    for _ in range(50):
        form.Apply(gfu.vec, r)
        r.data -= b
        if np.abs(r.FV().NumPy()[problem.free]).max() < 1e-13 * np.abs(problem.b).max():
            break
        form.AssembleLinearization(gfu.vec)
        gfu.vec.data -= form.mat.Inverse(fes.FreeDofs(), inverse="umfpack") * r
    return gfu.vec.FV().NumPy().copy()


def cross_checks():
    """(case, level, order, flux, theta) of the NGSolve cross-check: every variant and order on the
    2D cases; in 3D (2-5 s each) one variant of the elastic case in `make test`, the rest in `make test-full`;
    P3 on the 2D cases, one level coarser (P4 in `make test-full`)."""
    quick_3d = {("elastic-transition-3d", 1, 0.0, 1.0)}
    out = []
    for name, level in [(name, 2) for name in CASES] + PHYSICS_CASES:
        two_d = load_case(name).dimension == 2
        for order in (1, 2, 3, 4) if two_d else (1, 2):
            at = 1 if order > 2 else level
            for variant in VARIANTS:
                flux, theta = variant.values
                slow = (not two_d and (name, order, flux, theta) not in quick_3d) or order == 4
                out.append(pytest.param(name, at, order, flux, theta, id=f"{name}-P{order}-{variant.id}",
                                        marks=pytest.mark.slow if slow else ()))
    return out


@pytest.mark.parametrize("case_name, level, order, flux, theta", cross_checks())
def test_newton_solution_equals_ngsolve_assembled_nonlinear_form(case_name, level, order, flux, theta):
    case, problem = load_case(case_name), problem_at(case_name, level, order)
    reference = ngsolve_reference(case, problem_at(case_name, level, order), 0.05, theta, flux)
    solution = solve_semismooth_newton(weak_contact_system(case, problem, 0.05, theta, flux))
    assert solution.status == "converged" and solution.residual <= 1e-10
    assert np.abs(problem.cartesian(solution.u) - reference).max() <= 1e-10 * np.abs(reference).max()


@pytest.mark.parametrize("method_name", WEAK_NAMES)
@pytest.mark.parametrize("case_name", ["transition-r32", "tests/data/gap_case.py"])
def test_multigrid_newton_equals_direct_newton(case_name, method_name):
    """The study's path (multigrid CG, coarse spaces truncated at the active Gamma_C vertices)
    and UMFPACK give the same u_h; the residual is recomputed from scratch."""
    case, method = load_case(case_name), METHODS[method_name]
    problem, multilevel = problem_with_hierarchy(case_name, 3, method.order)
    system = method_system(case, problem, method)
    fast = solve_semismooth_newton(system, multilevel=multilevel)
    direct = solve_semismooth_newton(method_system(case, problem_at(case_name, 3, method.order), method))
    assert fast.status == direct.status == "converged"
    assert fast.linear_iterations > direct.linear_iterations     # CG iterations against factorisations
    assert np.abs(fast.u - direct.u).max() <= 1e-9 * np.abs(direct.u).max()
    # F(u) from scratch: the law's terms at u, against A (not the Jacobian's memory)
    q = system.quadrature
    p, f = method.law.term(system.at(fast.u), method.law.branch(system.at(fast.u)))
    F = problem.A @ fast.u - problem.b - q.T.T @ (q.weights * p) + q.N.T @ (q.weights * f)
    scale = np.abs((problem.b - problem.A @ problem.lift)[problem.free]).max()
    assert np.abs(F[problem.free]).max() <= 1e-10 * scale


def test_pressure_is_the_bracket_over_eps_and_never_negative():
    case = load_case("transition-r32")
    problem = problem_at("transition-r32", 3)
    system = weak_contact_system(case, problem, 0.05, 1.0, 1.0)
    u = solve_semismooth_newton(system).u
    pressure = system.pressure(u)
    assert pressure.min() >= 0 and (pressure > 0).any()
    P, eps = system.law.bracket(system.at(u))
    np.testing.assert_allclose(pressure * eps, np.maximum(P, 0.0))


def test_method_parameters_are_parsed_named_and_checked():
    method = get_method("nitsche:theta=-1,gamma0=0.5")
    assert (method.name, method.law) == ("nitsche:gamma0=0.5,theta=-1", Nitsche(0.5, -1.0))
    assert method.roles == frozenset() and METHODS["nitsche"].roles     # a variant takes no role
    assert get_method("penalty:epsilon0=1e-3").parameters == {"epsilon0": 1e-3}
    assert [m.name for m in methods_named(["paper", "penalty:epsilon0=0.1"])] == ["mean", "nodal", "penalty:epsilon0=0.1"]
    for bad in ["nitsche:gamma=1", "nitsche:theta", "penalty:theta=1", "nodal:gamma0=1", "nitsche:theta=0.5",
                "nitsche:gamma0=0", "penalty:epsilon0=-1"]:
        with pytest.raises(ValueError):
            get_method(bad)
    with pytest.raises(ValueError, match="positive"):
        Nitsche(0.0, 1.0)


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
    system = method_system(case, problem, method)
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
        return solve_semismooth_newton(method_system(case, problem, method), multilevel=multilevel, options=options)
    loose = solve()
    full = solve(SolverOptions(forcing=0.0))        # every step to the full depth
    assert loose.status == full.status == "converged"
    assert loose.residual <= 1e-10
    assert np.abs(loose.u - full.u).max() <= 1e-9 * np.abs(full.u).max()
    assert loose.linear_iterations < full.linear_iterations


def test_the_weak_method_forms_of_0_6_are_gone_as_their_deprecation_said():
    """0.7 deprecated ``replace(method, gamma0=...)`` and ``WeakContact`` for removal in 0.8.0:
    a weak method is a ``ContactLawMethod`` whose law holds its parameters (``with_parameters``)."""
    from dataclasses import replace

    import harness.methods
    with pytest.raises(TypeError, match="gamma0"):
        replace(METHODS["nitsche"], name="nitsche-g002", gamma0=0.02)
    assert not hasattr(harness.methods, "WeakContact")
    assert METHODS["nitsche"].with_parameters(gamma0=0.02, theta=-1).law == Nitsche(0.02, -1.0)


@pytest.mark.parametrize("case_name", ["elastic-transition-r32", pytest.param("elastic-transition-3d", marks=pytest.mark.slow)])
def test_elastic_multigrid_newton_equals_direct_newton(case_name):
    """Plane strain and 3D elasticity: the vector V-cycle in the rotated frame, truncated at the
    active Gamma_C vertices' contact component, gives the factorisation's u_h."""
    case, method = load_case(case_name), METHODS["nitsche"]
    level = 3 if case.dimension == 2 else 1
    problem, multilevel = problem_with_hierarchy(case_name, level)
    fast = solve_semismooth_newton(method_system(case, problem, method), multilevel=multilevel)
    direct = solve_semismooth_newton(method_system(case, problem_at(case_name, level), method))
    assert fast.status == direct.status == "converged" and fast.linear_iterations > direct.linear_iterations
    assert np.abs(fast.u - direct.u).max() <= 1e-9 * np.abs(direct.u).max()


@pytest.mark.parametrize("order", [1, 2])
@pytest.mark.parametrize("case_name", ["transition-r32", "elastic-transition-r32", "elastic-transition-incompressible"])
def test_the_default_gamma0_lies_below_theta_one_coercivity_bound_whatever_the_material(case_name, order):
    """theta = 1 is coercive while gamma0 C_h < 1, C_h the largest eigenvalue of
    int (h/M) flux(v)^2 against a(v, v) on X_h (``fem.contact_laws.builtin``): with eps = gamma0 h / M,
    M = lambda + 2 mu, C_h is about the same for lambda/mu = 1.5 and 49, and the default
    gamma0 = 0.05 keeps a factor 2.5 on levels 0-1."""
    import scipy.linalg
    import scipy.sparse as sp
    largest = 0.0
    for level in (0, 1):
        problem = problem_at(case_name, level, order)
        q = contact_quadrature(problem)
        B = (q.N.T @ sp.diags(q.weights * q.h / problem.physics.modulus) @ q.N).tocsr()
        free = problem.free
        A, Bf = problem.A[free][:, free].toarray(), B[free][:, free].toarray()
        largest = max(largest, scipy.linalg.eigh(Bf, A, eigvals_only=True, subset_by_index=[len(A) - 1, len(A) - 1])[0])
    assert 2.5 * METHODS["nitsche"].law.gamma0 * largest < 1, largest
