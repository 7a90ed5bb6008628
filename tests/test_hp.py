"""hp meshes: geometric layers toward the singular points, per-element degrees, the contact laws
on them solved exactly, and the exponential fit that judges their errors."""
import numpy as np
import pandas as pd
import pytest

from harness.fem.assembly import discretise
from harness.fem.contact_quadrature import contact_quadrature
from harness.measure.exponential import exponential_fit
from harness.measure.rates import rate_table
from harness.mesh.hp import HpRefinement, degrees_of
from harness.mesh.points import evaluate, in_elements
from harness.mesh.strategies import MeshStrategy, parse_mesh, singular_points
from harness.methods import METHODS
from harness.problem.case import load_case
from harness.study.chain import run_chain

slow = pytest.mark.slow


def hp_levels(case_name: str, count: int, order: int = 2):
    case = load_case(case_name)
    return case, list(HpRefinement(case, order, singular_points(case)).levels(count))


def test_each_layer_shrinks_the_elements_at_the_singular_points_by_sigma():
    """The elements at a singular point have diameter sigma^n times the coarse ones' (n layers),
    the mesh stays conforming (NGSolve builds it: every interior edge has two elements) and the
    degrees run from k at the singular points to k + mu (n + 1) away from them."""
    case, levels = hp_levels("transition-r32", 3)
    sizes = []
    for level in levels:
        mesh = level.mesh
        at_point = [el.nr for el in mesh.Elements() if any(np.allclose(mesh[v].point, (0.0, 0.0)) for v in el.vertices)]
        p = np.array([[mesh[v].point for v in el.vertices] for el in mesh.Elements()])
        diameters = np.linalg.norm(p - np.roll(p, 1, axis=1), axis=2).max(axis=1)
        sizes.append(diameters[at_point].max())
        assert all(len(e.elements) in (1, 2) for e in mesh.edges)
        assert level.degrees[at_point].max() == 2
        assert level.degrees.max() == 2 + round(1.0 * (level.index + 2))
    ratios = np.array(sizes[1:]) / np.array(sizes[:-1])
    assert np.allclose(ratios, 0.15, rtol=1e-6)


def test_degrees_grow_by_mu_per_layer_and_stay_within_bounds():
    depth = np.array([0, 1, 2, 3, 4])
    assert list(degrees_of(depth, 3, 2, 1.0, 24)) == [6, 5, 4, 3, 2]
    assert list(degrees_of(depth, 3, 2, 0.5, 24)) == [4, 4, 3, 2, 2]
    assert degrees_of(np.zeros(1, int), 40, 2, 1.0, 24)[0] == 24


def test_a_space_of_equal_degrees_is_the_uniform_space():
    """``discretise`` with every element's degree k gives P_k's stiffness, load and contact dofs."""
    case, (level,) = hp_levels("corner-r12", 1)
    plain = discretise(case, level.mesh, 3)
    hp = discretise(case, level.mesh, 3, degrees=np.full(level.mesh.ne, 3))
    assert plain.ndof == hp.ndof
    assert abs(plain.A - hp.A).max() == 0.0
    assert np.array_equal(plain.b, hp.b)
    assert np.array_equal(plain.edge_dofs, hp.edge_dofs)


def test_the_trace_rows_of_an_hp_space_are_ngsolves_evaluation(rng):
    """T and N at the Gamma_C points of a space of varying degrees: NGSolve's own values and normal
    derivatives of a random u_h."""
    case, (_, level) = hp_levels("transition-r32", 2)
    problem = discretise(case, level.mesh, 2, degrees=level.degrees)
    q = contact_quadrature(problem)
    u = rng.standard_normal(problem.ndof)
    gf = problem.gridfunction(u)
    in_elements(problem.mesh, q.points, problem.trace.volumes[q.edge])
    assert np.abs(q.T @ u - evaluate(gf, problem.mesh, q.points)).max() < 1e-10 * np.abs(u).max()
    grad = evaluate(pytest.importorskip("ngsolve").grad(gf), problem.mesh, q.points)
    scale = np.abs(grad).max()
    assert np.abs(q.N @ u - (grad * q.normals).sum(axis=1)).max() < 1e-10 * scale
    assert sorted(set(q.degree)) == sorted(set(problem.edge_degrees))


def test_per_element_degrees_are_refused_where_they_are_not_set():
    case = load_case("elastic-transition-r32")
    _, (level,) = hp_levels("transition-r32", 1)
    with pytest.raises(ValueError, match="scalar problem in 2D"):
        discretise(case, level.mesh, 2, degrees=level.degrees)
    with pytest.raises(ValueError, match="one per element"):
        discretise(load_case("transition-r32"), level.mesh, 2, degrees=np.full(3, 2))


@pytest.mark.parametrize("spec, label", [("hp", "hp"), ("hp:mu=0.5", "hp:mu=0.5"), ("hp:sigma=0.2,mu=2", "hp:sigma=0.2,mu=2"),
                                         ("hp:sigma=0.15", "hp")])
def test_hp_parameters_name_the_strategy(spec, label):
    assert parse_mesh(spec)[0].label == label


@pytest.mark.parametrize("spec, message", [("hp:sigma=1", "sigma must be a number in"), ("hp:mu=-1", "mu must be"),
                                           ("hp:theta=0.3", "has the parameters sigma, mu"),
                                           ("uniform:mu=1", "has no parameters")])
def test_bad_hp_parameters_are_refused_in_one_line(spec, message):
    with pytest.raises(ValueError, match=message):
        parse_mesh(spec)


def test_strategies_with_parameters_run_from_the_command_line(tmp_path):
    """``--mesh hp:mu=0.5`` and ``--mesh adaptive:theta=0.3`` (whose labels, with ':' and ',', the
    check of a strategy object refused before 0.10.0) run, each row labelled by its strategy."""
    from harness.cli import main
    code = main(["run", "--case", "transition-r32", "--method", "nitsche", "--mesh", "hp:sigma=0.2,mu=0.5",
                 "--mesh", "adaptive:theta=0.3", "--levels", "2", "--out", str(tmp_path), "--quiet"])
    assert code == 0
    rows = pd.read_csv(tmp_path / "results.csv")
    assert set(rows["mesh"]) == {"hp:sigma=0.2,mu=0.5", "adaptive:theta=0.3"}
    assert (rows.kkt_residual <= 1e-10).all()


def test_all_names_the_h_strategies_and_hp_serves_the_contact_laws_only():
    assert [s.label for s in parse_mesh("all")] == ["uniform", "graded", "adaptive"]
    hp = MeshStrategy("hp")
    assert hp.serves(METHODS["nitsche"]) and hp.serves(METHODS["nodal-p3"]) and not hp.serves(METHODS["nodal"])
    assert hp.applies_to(load_case("transition-r32")) is None
    for name in ("elastic-transition-r32", "transition-line-3d", "two-body-transition-r32", "smooth-obstacle"):
        assert hp.applies_to(load_case(name))


@pytest.mark.parametrize("case_name", ["corner-r12", "transition-r32"])
def test_nitsche_on_hp_meshes_is_solved_exactly_and_its_error_falls_every_level(case_name):
    """Every hp level's Newton residual is <= 1e-10, the H^1 error falls level by level and stays
    within 2% of the best approximation's (Falk's lemma: the contact costs nothing beyond the space)."""
    case = load_case(case_name)
    output = run_chain(case, [METHODS["nitsche"]], 4, mesh=MeshStrategy("hp"))
    rows = pd.DataFrame(output.rows)
    assert (rows.kkt_residual <= 1e-10).all() and (rows.status == "converged").all()
    assert (np.diff(rows.err_h1) < 0).all()
    assert (rows.err_h1_over_best < 1.02).all()
    assert (rows.norm_h1_exact > 0).all()


@pytest.mark.parametrize("case_name", ["corner-r12", "transition-r32"])
def test_nitsche_keeps_its_coercivity_margin_on_hp_meshes(case_name):
    """theta = 1 is coercive while gamma0 C_h < 1, C_h the largest ratio of int eps/gamma0
    flux(v)^2 over Gamma_C to a(v, v), with eps = gamma0 (2/p)^2 h at a point of degree p
    (``fem.contact_laws.builtin.degree_scale``). The trapezoid of each layer is split so that the child on Gamma_C
    keeps its parent's height (``mesh.hp.geometric_layer``); split the other way, C_h was 29 and
    theta = 1 Nitsche found spurious contact on transition-r32's free side. gamma0 = 0.05 keeps the
    factor 2.5 of uniform P2 meshes."""
    import scipy.linalg
    import scipy.sparse as sp
    case, levels = hp_levels(case_name, 3)
    for level in levels:
        problem = discretise(case, level.mesh, 2, degrees=level.degrees)
        q = contact_quadrature(problem)
        B = (q.N.T @ sp.diags(q.weights * q.h * (2.0 / q.degree) ** 2) @ q.N).tocsr()
        free = problem.free
        A, Bf = problem.A[free][:, free].toarray(), B[free][:, free].toarray()
        largest = scipy.linalg.eigh(Bf, A, eigvals_only=True, subset_by_index=[len(A) - 1, len(A) - 1])[0]
        assert 2.5 * METHODS["nitsche"].law.gamma0 * largest < 1, largest


def test_the_hp_nodal_cone_has_each_edges_own_gauss_lobatto_rows_and_clarabel_agrees(rng):
    """nodal-p3 on an hp mesh: an edge of degree p has p - 1 rows, the values of v_h at its interior
    Gauss-Lobatto points (NGSolve's evaluation of a random u_h there), and the QP's solution by the
    general-constraint active set method is Clarabel's."""
    from conftest import clarabel_solution

    from harness.fem.edge_functionals import edge_functional_qp, edge_functional_rows
    from harness.fem.polynomials import lobatto_points
    from harness.solvers.general_constraints import GeneralConstraintSolver
    case, (_, level) = hp_levels("corner-r12", 2, order=3)
    problem = discretise(case, level.mesh, 3, degrees=level.degrees)
    method = METHODS["nodal-p3"]
    rows = edge_functional_rows(problem, method.functionals_of)
    degrees = problem.edge_degrees
    assert len(set(degrees)) > 1 and rows.shape[0] == (degrees - 1).sum()
    u = rng.standard_normal(problem.ndof)
    gf = problem.gridfunction(u)
    trace = problem.trace
    expected = []
    for e, p in enumerate(degrees):
        t = lobatto_points(int(p))[1:-1]
        points = trace.a[e] + t[:, None] * (trace.b[e] - trace.a[e])
        in_elements(problem.mesh, points, np.full(len(t), trace.volumes[e]))
        expected.append(evaluate(gf, problem.mesh, points))
    np.testing.assert_allclose(rows @ u, np.concatenate(expected), atol=1e-10 * np.abs(u).max())
    qp = edge_functional_qp(case, problem, method.functionals_of)
    solution = GeneralConstraintSolver(qp.K, qp.b, qp.free, qp.B, qp.g, lift=qp.lift).solve()
    reference = clarabel_solution(problem, qp)
    assert solution.status == "converged" and solution.residual <= 1e-10
    np.testing.assert_allclose(solution.z[problem.free], reference, atol=1e-6 * np.abs(reference).max())


def test_the_nodal_cone_on_hp_meshes_is_exact_and_near_the_best_approximation():
    """nodal-p3 on 4 hp levels of transition-r32: KKT <= 1e-10, the error falls every level, within
    5% of R_h u's (measured 1.01-1.03)."""
    rows = pd.DataFrame(run_chain(load_case("transition-r32"), [METHODS["nodal-p3"]], 4, mesh=MeshStrategy("hp")).rows)
    assert (rows.kkt_residual <= 1e-10).all() and (rows.status == "converged").all()
    assert (np.diff(rows.err_h1) < 0).all() and (rows.err_h1_over_best < 1.05).all()


def test_the_exponential_fit_recovers_b_and_tells_an_algebraic_law_apart():
    N = np.array([600, 1000, 1500, 2200, 3000, 4000, 5000])
    exponential = exponential_fit(N, 3.0 * np.exp(-1.7 * N ** (1 / 3)))
    assert exponential["exponential_verdict"] == "exponential"
    assert exponential["exponential_b"] == pytest.approx(1.7)
    assert exponential["exponential_r2"] == pytest.approx(1.0)
    algebraic = exponential_fit(N, 2.0 * N ** -1.0)
    assert algebraic["exponential_verdict"] == "algebraic"
    assert exponential_fit(N[:4], N[:4] ** -1.0)["exponential_verdict"] == "too few levels"


@slow
@pytest.mark.parametrize("case_name, levels", [("corner-r12", 14), ("transition-r32", 14)])
def test_hp_nitsche_converges_exponentially_to_a_relative_error_of_1e_6(case_name, levels):
    """Issue 63: on hp meshes Nitsche's relative H^1 error reaches 1e-6 at <= 1e5 dofs, and
    ln(err) is linear in N^{1/3} (R^2 >= 0.98) over the levels, within 2% of R_h u's error."""
    case = load_case(case_name)
    rows = pd.DataFrame(run_chain(case, [METHODS["nitsche"]], levels, mesh=MeshStrategy("hp")).rows)
    rates = rate_table(rows.assign(mesh="hp")).iloc[0]
    assert (rows.kkt_residual <= 1e-10).all()
    assert rates.exponential_verdict == "exponential" and rates.exponential_r2 >= 0.98
    assert rates.finest_relative_error <= 1e-6 and rows.ndof.iloc[-1] <= 1e5
    assert (rows.err_h1_over_best < 1.02).all()


def test_hp_levels_below_round_off_are_refused_before_the_first_level():
    """corner-r12's layers (sigma = 0.15) keep their smallest edge above 1e-13 of the coordinates
    for 14 levels (``mesh.hp.SMALLEST_RELATIVE_EDGE``); 30 are refused before any level is made."""
    from harness.mesh.strategies import MeshStrategy
    levels = MeshStrategy("hp").sequence(load_case("corner-r12"), 2).levels
    with pytest.raises(ValueError, match="at most 14 levels"):
        next(levels(30))
    assert next(levels(14)).index == 0
