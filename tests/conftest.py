import os

import numpy as np
import pytest
import scipy.sparse as sp

from harness.fem.assembly import discretise
from harness.mesh.levels import mesh_hierarchy
from harness.methods import METHODS, BoundConstrained, ContactLawMethod
from harness.problem.case import load_case
from harness.solvers.multigrid import Multilevel

if os.environ.get("PYTEST_XDIST_WORKER"):
    # `make test` runs one pytest-xdist worker per core: one NGSolve and BLAS thread each, as the
    # report's jobs (two task managers of two threads each on two cores spin against each other:
    # a 5-minute suite ran for 15 minutes and more)
    import ngsolve as ngs
    from threadpoolctl import threadpool_limits
    os.environ["HARNESS_THREADS"] = "1"         # the study's levels (``study.execution.threads``), here and in subprocesses
    ngs.SetNumThreads(1)
    _BLAS_THREADS = threadpool_limits(1)

# The paper's P2 cones by method name (the cone-level tests), the methods that solve a cone
# exactly (active set), the weak ones (penalty, Nitsche: semismooth Newton), and all.
# the cones of the 2D tests (`mean-edges`, 3D only, is test_three_d's)
CONE_NAMES = [name for name, m in METHODS.items() if isinstance(m, BoundConstrained) and 2 in m.dimensions]
CONE_NAMES_3D = [name for name, m in METHODS.items() if isinstance(m, BoundConstrained) and 3 in m.dimensions]
MODELS = {name: METHODS[name].cone for name in CONE_NAMES if METHODS[name].order == 2}
MODEL_NAMES = list(MODELS)
# the degree axis: methods of order k >= 3 (measured against exact solutions only; their solver
# paths are tests/test_degree.py's)
HIGH_ORDER_NAMES = [name for name, m in METHODS.items() if m.order > 2]
# the one-body weak methods of P1 and P2 (the two-body ones: tests/test_two_body_nitsche.py)
WEAK_NAMES = [name for name, m in METHODS.items() if isinstance(m, ContactLawMethod) and m.source is None
              and name not in HIGH_ORDER_NAMES and m.bodies == (1,)]
METHOD_NAMES = list(METHODS)


def problem_at(case_name: str, level: int, order: int = 2):
    for lev, mesh in mesh_hierarchy(load_case(case_name), level + 1):
        if lev == level:
            return discretise(load_case(case_name), mesh, order)


def problem_with_hierarchy(case_name: str, level: int, order: int = 2):
    """The problem of ``level`` and the multigrid's P1 hierarchy of levels 0..level (vector P1 in
    the rotated frame for an elastic case)."""
    case = load_case(case_name)
    multilevel = None
    for lev, mesh in mesh_hierarchy(case, level + 1):
        multilevel = Multilevel(mesh, case.physics) if multilevel is None else multilevel.refined(mesh)
    return discretise(case, mesh, order), multilevel


@pytest.fixture(scope="session")
def small_problem():
    """transition-r32 on level 1 (609 dofs)."""
    return problem_at("transition-r32", 1)


@pytest.fixture
def rng():
    return np.random.default_rng(20031)


def divergence_by_ngsolve(case, gfu, order: int):
    """div F(u_h) from NGSolve's Hessian (``physics.divergence``); zero for P1."""
    return 0 if order == 1 else case.physics.divergence(gfu)


def trace_values(problem, function):
    """The dofs of a polynomial of degree <= k on Gamma_C (y = 0) in the hierarchical trace basis:
    vertex values and, for P2, bubble coefficients c = 8 ((f(a) + f(b))/2 - f(mid))."""
    z = np.zeros(problem.ndof)
    trace = problem.trace
    z[problem.vertex_dofs] = function(trace.vertex_points[:, 0])
    if problem.order == 2:
        a, b = trace.a[:, 0], trace.b[:, 0]
        z[problem.edge_dofs] = 8.0 * (0.5 * (function(a) + function(b)) - function(0.5 * (a + b)))
    return z


def pair_traces(problem, normal, tangential):
    """Body-wise vectors of a two-body problem with the polynomial traces ``normal`` (c_k) and
    ``tangential`` (t_k, elasticity) on Gamma_C, each a pair of functions of x."""
    parts = []
    for body, c, t in zip(problem.bodies, normal, tangential):
        part = trace_values(body, c)
        dofs = np.concatenate([body.vertex_dofs, body.edge_dofs])
        part[dofs - body.ndof // 2] = trace_values(body, t)[dofs]
        parts.append(part)
    return np.concatenate(parts)


def volume_and_jumps_by_ngsolve(case, problem, u):
    """The residual estimator's element residual and flux jumps as NGSolve integrates them on
    each element's boundary (``Other()``: the neighbour's trace), with NGSolve's mesh size as the
    weight, on every facet but those of the boundary (in 3D the faces labelled 'interior' glue
    two boxes: boundary elements of the mesh, interior faces of Omega); ``divergence(case, gfu,
    order)``: div F(u_h) from NGSolve's Hessian (``divergence_by_ngsolve``)."""
    import ngsolve as ngs

    from harness.measure.estimator import VOLUME_ORDER
    mesh, gfu, physics = problem.mesh, problem.gridfunction(u), case.physics
    h, n = ngs.specialcf.mesh_size, ngs.specialcf.normal(mesh.dim)
    interior = ngs.GridFunction(ngs.FacetFESpace(mesh, order=0))
    interior.vec[:] = 1.0
    for element in mesh.Elements(ngs.BND):
        if element.mat != "interior":
            interior.vec[interior.space.GetDofNrs(element)[0]] = 0.0
    f = physics.constant(0) if case.f_vanishes else case.f
    residual = f + divergence_by_ngsolve(case, gfu, problem.order)
    # the estimator's rules (Gauss, graded on the elements at singular points): then its split of
    # this term (f's oscillation plus the mean's residual) is the same sum, to round-off
    volume = sum(ngs.Integrate(h * h * ngs.InnerProduct(residual, residual) * dx, mesh, element_wise=True).NumPy()
                 for dx in problem.quadrature.measures(VOLUME_ORDER))
    jump = physics.flux(ngs.Grad(gfu), n) - physics.flux(ngs.Grad(gfu).Other(), n)
    jumps = ngs.Integrate(0.5 * h * interior * ngs.InnerProduct(jump, jump) * ngs.dx(element_boundary=True), mesh,
                          element_wise=True).NumPy()
    return volume + jumps


def assert_volume_and_jumps_are_ngsolves(case, mesh, order: int) -> None:
    """The estimator's volume and jump terms of a function that is no solution (every jump
    nonzero) on ``mesh``, against ``volume_and_jumps_by_ngsolve``, element by element."""
    from harness.measure.estimator import ResidualEstimator
    problem = discretise(case, mesh, order)
    u = np.where(problem.free, np.random.default_rng(1).standard_normal(problem.ndof), problem.lift)
    ours = ResidualEstimator(case, problem).terms.volume_and_jumps(problem.gridfunction(u), order, case.physics)
    theirs = volume_and_jumps_by_ngsolve(case, problem, u)
    assert np.abs(ours - theirs).max() <= 1e-10 * np.abs(theirs).max()


def clarabel_solution(problem, qp):
    """The free dofs of the solution of a general-rows cone's QP (``qp.B z >= qp.g``) by Clarabel,
    an interior-point solver independent of the harness's active set methods."""
    import scipy.sparse as sp
    from qpsolvers import solve_qp
    free, A = problem.free, problem.A
    K_free, b_free = A[free][:, free], (problem.b - A @ problem.lift)[free]
    return solve_qp(sp.csc_matrix(K_free), -b_free, G=sp.csc_matrix(-qp.B[:, free]), h=-(qp.g - qp.B @ problem.lift),
                    solver="clarabel", tol_gap_abs=1e-11, tol_gap_rel=1e-11, tol_feas=1e-11)


def clarabel_unilateral_tresca(K, b, free, lift, C, alpha, F, c, zprev):
    """Clarabel's minimiser with the |.| terms as epigraphs: variables (z, t), t_i >= |z_F_i -
    zprev_i|, minimise 1/2 z'Kz - b'z + c't (an interior point method, independent of the active
    set iteration)."""
    from qpsolvers import solve_qp
    n, k = len(b), len(F)
    P = sp.block_diag([sp.csc_matrix(K), sp.csc_matrix((k, k))]).tocsc()
    q = np.concatenate([-b, c])
    select_F = sp.csr_matrix((np.ones(k), (np.arange(k), F)), shape=(k, n))
    select_C = sp.csr_matrix((np.ones(len(C)), (np.arange(len(C)), C)), shape=(len(C), n))
    eye = sp.identity(k)
    G = sp.vstack([sp.hstack([-select_C, sp.csr_matrix((len(C), k))]),     # z_C >= alpha
                   sp.hstack([select_F, -eye]), sp.hstack([-select_F, -eye])]).tocsc()
    h = np.concatenate([-alpha, zprev, -zprev])
    pinned = np.flatnonzero(~free)
    A = sp.csr_matrix((np.ones(len(pinned)), (np.arange(len(pinned)), pinned)), shape=(len(pinned), n + k))
    x = solve_qp(P, q, G=G, h=h, A=A.tocsc(), b=lift[pinned], solver="clarabel",
                 tol_gap_abs=1e-12, tol_gap_rel=1e-12, tol_feas=1e-12)
    return x[:n]
