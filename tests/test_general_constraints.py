"""The general-constraint QP solver (``solvers.general_constraints``, the machinery of the 3D
face-mean cone and of mortar conditions) returns the exact minimiser: against Clarabel on
random problems, with linearly dependent active rows, and against the bound solver where the
constraints are bounds."""
import numpy as np
import pytest
import scipy.sparse as sp
from conftest import problem_at
from qpsolvers import solve_qp

from harness.fem.cones import contact_qp
from harness.methods import METHODS
from harness.problem.case import load_case
from harness.solvers.bound_constraints import solve_contact_qp
from harness.solvers.general_constraints import GeneralConstraintSolver
from harness.solvers.options import SolverOptions


def _clarabel(K, b, B, g):
    """Clarabel's minimiser of 1/2 z'Kz - b'z subject to B z >= g (an interior point method: its
    z is as accurate as its gap tolerance lets it be, about 1e-6 relative on the 3D problem)."""
    return solve_qp(sp.csc_matrix(K), -b, G=sp.csc_matrix(-B), h=-g,
                    solver="clarabel", tol_gap_abs=1e-11, tol_gap_rel=1e-11, tol_feas=1e-11)


def _random_problem(seed: int, n: int = 40, m: int = 25):
    rng = np.random.default_rng(seed)
    M = rng.standard_normal((n, n))
    K = M @ M.T + 0.5 * np.eye(n)
    b = rng.standard_normal(n) * 3
    B = rng.standard_normal((m, n)) * (rng.random((m, n)) < 0.2)
    g = rng.standard_normal(m) * 0.3
    return K, b, B, g


@pytest.mark.parametrize("seed", range(6))
def test_random_general_constraints_match_clarabel(seed):
    K, b, B, g = _random_problem(seed)
    solution = GeneralConstraintSolver(K, b, np.ones(len(b), bool), B, g).solve()
    reference = _clarabel(K, b, B, g)
    assert solution.status == "converged" and solution.residual <= 1e-10
    assert np.abs(solution.z - reference).max() <= 1e-7 * max(1.0, np.abs(reference).max())
    assert (solution.multipliers >= -1e-10 * solution.multipliers.max(initial=1.0)).all()


@pytest.mark.parametrize("seed", range(3))
def test_linearly_dependent_active_rows_give_the_unique_minimiser(seed):
    """Rows repeated and a row that is the sum of two others (active together at the solution:
    the multipliers are not unique there, the minimiser is), pinned dofs beside them."""
    K, b, B, g = _random_problem(seed, n=30, m=10)
    free = np.ones(len(b), bool)
    free[:4] = False
    lift = np.linspace(-0.2, 0.3, len(b))
    unconstrained = lift.copy()
    unconstrained[free] = np.linalg.solve(K[free][:, free], (b - K @ np.where(free, 0.0, lift))[free])
    B[:5] = np.random.default_rng(seed + 100).standard_normal((5, len(b)))
    g[:5] = B[:5] @ unconstrained + 1.0          # the unconstrained minimiser violates rows 0-4
    B = np.vstack([B, B[:3], B[3] + B[4]])
    g = np.concatenate([g, g[:3], [g[3] + g[4]]])
    solution = GeneralConstraintSolver(K, b, free, B, g, lift=lift).solve(initial_active=np.ones(len(g), bool))
    pinned = np.where(free, 0.0, lift)
    reference = _clarabel(K[free][:, free], (b - K @ pinned)[free], B[:, free], g - B @ pinned)
    assert solution.status == "converged" and solution.residual <= 1e-10
    assert np.abs(solution.z[~free] - lift[~free]).max() == 0.0
    slack = B @ solution.z - g
    assert (np.abs(slack[[0, 1, 2, 3, 4]]) <= 1e-10).any()       # a row that is repeated or summed binds
    assert np.abs(solution.z[free] - reference).max() <= 1e-7 * max(1.0, np.abs(reference).max())


@pytest.mark.parametrize("method_name", ["nodal", "p1"])
def test_bounds_as_general_rows_equal_the_bound_solver(method_name):
    """The cones of 2D are bounds z_C >= alpha: as rows of B (a selection) the general solver
    finds the bound solver's solution."""
    case, method = load_case("transition-r32"), METHODS[method_name]
    qp = contact_qp(case, problem_at("transition-r32", 2, method.order), method.cone)
    bounds = solve_contact_qp(qp)
    B = sp.csr_matrix((np.ones(len(qp.C)), (np.arange(len(qp.C)), qp.C)), shape=(len(qp.C), len(qp.b)))
    general = GeneralConstraintSolver(qp.K, qp.b, qp.free, B, qp.alpha, lift=qp.lift).solve()
    assert bounds.status == general.status == "converged"
    assert general.residual <= 1e-10
    assert (general.active == bounds.active).all()
    assert np.abs(general.z - bounds.z).max() <= 1e-9 * np.abs(bounds.z).max()


def _contact_triangles(mesh, elements):
    import ngsolve as ngs
    corners = []
    for e in elements:
        element = mesh[ngs.ElementId(ngs.BND, int(e))]
        corners.append([mesh[v].point for v in element.vertices])
    return np.array(corners, dtype=float)


def test_a_p2_face_mean_is_the_average_of_its_three_midside_values():
    """docs/mathematics.md: on a triangle the P2 mean is the average of the three edge-midpoint
    values (the Lagrange vertex functions integrate to 0). Checked on every contact triangle of
    transition-line-3d for a quadratic that P2 represents exactly."""
    import ngsolve as ngs

    from harness.fem.face_means import face_mean_rows
    problem = problem_at("transition-line-3d", 1, 2)
    quadratic = lambda x, y, z: 1 + x - 2 * y + 3 * x * x - x * y + 2 * y * y + 0.5 * z   # noqa: E731
    gfu = ngs.GridFunction(problem.fes)
    gfu.Set(quadratic(ngs.x, ngs.y, ngs.z))
    B, g, elements = face_mean_rows(problem, ngs.CF(2.0))
    corners = _contact_triangles(problem.mesh, elements)
    midpoints = (corners + np.roll(corners, -1, axis=1)) / 2
    average = quadratic(*np.moveaxis(midpoints, -1, 0)).mean(axis=1)
    assert len(elements) > 0 and np.abs(B @ gfu.vec.FV().NumPy() - average).max() <= 1e-12 * np.abs(average).max()
    assert np.abs(g - 2.0).max() <= 1e-13
    vertex_average = quadratic(*np.moveaxis(corners, -1, 0)).mean(axis=1)
    assert np.abs(average - vertex_average).max() > 1e-3      # not the vertex average: the test can fail


def test_the_3d_face_mean_cone_is_solved_exactly_against_clarabel():
    """The 3D counterpart of K_h (vertex values >= alpha, face means >= the mean of alpha) on
    transition-line-3d's coarse mesh: the general-constraint solver and Clarabel agree, every
    KKT residual <= 1e-10."""
    from harness.fem.face_means import face_mean_rows
    case = load_case("transition-line-3d")
    problem = problem_at("transition-line-3d", 0, 2)
    B_faces, g_faces, _ = face_mean_rows(problem, case.obstacle)
    from harness.mesh.points import evaluate
    vertices = problem.vertex_dofs
    coordinates = np.array([problem.mesh[ngs_vertex].point for ngs_vertex in _vertex_ids(problem)])
    g_vertices = np.zeros(len(vertices)) if case.obstacle is None else evaluate(case.obstacle, problem.mesh, coordinates).ravel()
    B = sp.vstack([sp.csr_matrix((np.ones(len(vertices)), (np.arange(len(vertices)), vertices)),
                                 shape=(len(vertices), problem.ndof)), B_faces]).tocsr()
    g = np.concatenate([g_vertices, g_faces])
    A = problem.A
    solution = GeneralConstraintSolver(A, problem.b, problem.free, B, g, lift=problem.lift).solve()
    free = problem.free
    reduced = _clarabel(A[free][:, free].toarray(), (problem.b - A @ problem.lift)[free],
                        B[:, free].toarray(), g - B @ problem.lift)
    assert solution.status == "converged" and solution.residual <= 1e-10
    assert solution.active[len(vertices):].any()                 # some face constraint binds
    # the exact solver's objective is not above the interior point's, and the two minimisers
    # agree to the interior point's accuracy
    K_free, b_free = A[free][:, free], (problem.b - A @ problem.lift)[free]
    objective = lambda z: 0.5 * z @ (K_free @ z) - b_free @ z          # noqa: E731
    assert objective(solution.z[free]) <= objective(reduced) + 1e-12 * abs(objective(reduced))
    assert np.abs(solution.z[free] - reduced).max() <= 1e-5 * np.abs(reduced).max()


def _vertex_ids(problem):
    import ngsolve as ngs
    return [ngs.NodeId(ngs.VERTEX, int(v)) for v in problem.trace.vertices]


def test_row_projection_is_the_orthogonal_projector_even_with_dependent_rows():
    """P = I - B^T (B B^T)^+ B on rows with a repeated row and a sum of two (B B^T singular):
    P B^T = 0, P^2 = P, P symmetric, ``onto`` lands on {B z = t} for a consistent t."""
    from harness.solvers.row_projection import RowProjection
    rng = np.random.default_rng(5)
    B = rng.standard_normal((6, 30)) * (rng.random((6, 30)) < 0.4)
    B = sp.csr_matrix(np.vstack([B, B[1], B[2] + B[3]]))
    P = RowProjection(B)
    x, y = rng.standard_normal(30), rng.standard_normal(30)
    assert np.abs(P.apply(B.T @ rng.standard_normal(8))).max() <= 1e-12
    assert np.abs(P.apply(P.apply(x)) - P.apply(x)).max() <= 1e-12
    assert abs(P.apply(x) @ y - x @ P.apply(y)) <= 1e-12 * np.abs(x).max() * np.abs(y).max() * 30
    target = B @ rng.standard_normal(30)
    assert np.abs(B @ P.onto(x, target) - target).max() <= 1e-12


def _face_mean_solvers(case_name: str, level: int, options: SolverOptions = SolverOptions()):
    from conftest import problem_with_hierarchy

    from harness.fem.face_means import face_mean_qp
    from harness.fem.p1_embedding import ContactEdges
    from harness.solvers.projected_multigrid import ProjectedMultigridSystem
    problem, multilevel = problem_with_hierarchy(case_name, level)
    qp = face_mean_qp(load_case(case_name), problem)
    solver = lambda system=None: GeneralConstraintSolver(qp.K, qp.b, qp.free, qp.B, qp.g, lift=qp.lift,  # noqa: E731
                                                         system=system, options=options)
    return qp, solver, ProjectedMultigridSystem(qp.K_ngs, multilevel, ContactEdges.of(problem, model=False), options)


@pytest.mark.parametrize("case_name", ["transition-line-3d", "transition-circle-3d", "elastic-transition-3d"])
def test_constrained_multigrid_finds_the_saddle_systems_face_mean_solution(case_name):
    """The study's path for the 3D `mean` (projected CG, the constrained V-cycle) against the
    reference (SuperLU of each set's saddle matrix) on level 0: the same active set, u_h to
    1e-9, both KKT residuals <= 1e-10."""
    qp, solver, system = _face_mean_solvers(case_name, 0)
    reference = solver().solve()
    ours = solver(system).solve()
    assert reference.status == ours.status == "converged"
    assert reference.residual <= 1e-10 and ours.residual <= 1e-10
    assert (ours.active == reference.active).all() and ours.active[qp.n_vertices:].any()
    assert np.abs(ours.z - reference.z).max() <= 1e-9 * np.abs(reference.z).max()


def test_constrained_vcycle_keeps_the_face_rows_and_costs_about_a_pinned_solve():
    """On transition-line-3d's level 1 and the active set of its solution: the V-cycle maps into
    the kernel of the active face rows and is symmetric; projected CG with it needs at most 1.5x
    the CG iterations of the same vertex pins without the face rows (measured 35 and 32), where
    P M P with a pointwise smoother needed 223 (the rows are nearly dependent: module docstring
    of ``solvers.projected_multigrid``)."""
    from harness.solvers.projected_multigrid import ConstrainedVCycle
    qp, solver, system = _face_mean_solvers("transition-line-3d", 1)
    general_solver = solver(system)
    solution = general_solver.solve()
    rows = np.flatnonzero(solution.active)
    bounds, faces = system.split(general_solver.B, rows)
    assert len(faces) > 0
    vcycle, _ = system._preconditioner(general_solver, ~_pins(qp, general_solver, bounds), faces)
    assert isinstance(vcycle, ConstrainedVCycle)
    rng = np.random.default_rng(2)
    free = ~_pins(qp, general_solver, bounds)

    def M(v):
        r, out = qp.K_ngs.CreateColVector(), qp.K_ngs.CreateColVector()
        r.FV().NumPy()[:] = v * free
        vcycle.apply(r, out)
        return out.FV().NumPy().copy()
    a, b = rng.standard_normal(len(qp.b)), rng.standard_normal(len(qp.b))
    Ma, Mb = M(a), M(b)
    assert np.abs(general_solver.B[faces] @ Ma).max() <= 1e-12 * np.abs(Ma).max()
    assert abs(a @ Mb - b @ Ma) <= 1e-12 * abs(a @ Mb) and a @ Ma > 0
    iterations = {}
    for name, chosen in (("faces", rows), ("pins", bounds)):
        system.cg_iterations, system._last = 0, None
        system.solve(general_solver, chosen, None, 0.1 * general_solver.options.tolerance * general_solver.load_scale)
        iterations[name] = system.cg_iterations
    assert iterations["faces"] <= 1.5 * iterations["pins"], iterations


def _pins(qp, general_solver, bounds):
    pinned = ~qp.free.copy()
    pinned[general_solver.B.indices[general_solver.B.indptr[bounds]]] = True
    return pinned


@pytest.mark.slow          # 3 s
def test_inexact_face_mean_steps_reach_the_exact_steps_solution():
    """The general-constraint active set method with loose solves of new sets (``forcing``) and
    with every set solved to the full depth (forcing = 0) find the same KKT point on
    transition-line-3d's level 1, the loose one with no more CG iterations."""
    found = {}
    for name, options in (("loose", SolverOptions()), ("exact", SolverOptions(forcing=0.0))):
        qp, solver, system = _face_mean_solvers("transition-line-3d", 1, options)
        found[name] = solver(system).solve()
    loose, exact = found["loose"], found["exact"]
    assert loose.status == exact.status == "converged" and max(loose.residual, exact.residual) <= 1e-10
    assert (loose.active == exact.active).all()
    assert np.abs(loose.z - exact.z).max() <= 1e-8 * np.abs(exact.z).max()
    assert loose.work["cg_iterations"] <= exact.work["cg_iterations"], (loose.work, exact.work)


@pytest.mark.parametrize("method_name", ["mean", "mean-edges", "nodal"])
def test_every_3d_p2_cone_converges_where_u_and_alpha_vanish_on_all_of_gamma_c(method_name):
    """u = x z + z^2 binds on all of Gamma_C with u = alpha = 0: the constraint values are
    round-off (~1e-21), and a relative primal residual against a scale of that size read 1
    ("stalled"). Values double precision cannot tell from 0 count as 0 (``pdas.resolved``):
    every P2 cone converges to a KKT residual <= 1e-10; the face means and the nodal cone
    reproduce u. (The edge means cannot: B'lambda > 0 at every vertex of Gamma_C, where the
    pressure's consistent load on P2 triangles is 0.)"""
    from harness.study.chain import run_chain
    case = load_case(str(__import__("pathlib").Path(__file__).parent / "data" / "quadratic_binding_3d.py"))
    rows = run_chain(case, [METHODS[method_name]], 2).rows
    for row in rows:
        assert row["status"] == "converged" and row["kkt_residual"] <= 1e-10, row
        assert row["err_h1"] <= 1e-9 or method_name == "mean-edges"


def test_a_constraint_value_within_its_rounding_bound_is_zero_and_one_past_it_is_kept():
    from harness.solvers.pdas import resolved
    slack, bound = np.array([-2.6e-21, 3e-17, -1e-12, 0.5]), np.array([4.4e-16, 4.4e-16, 4.4e-16, 1.0])
    assert resolved(slack, bound).tolist() == [0.0, 0.0, -1e-12, 0.0]
    # a violation of 1e-12 stays one (the solver must see it)
    assert resolved(np.array([-1e-12]), np.array([4.4e-16]))[0] == -1e-12
