"""The mesh axis (issue 31): graded and adaptive level sequences, the residual estimator, the
multigrid on bisection hierarchies, the study's `mesh` column and the rates against N."""
import dataclasses
from pathlib import Path

import ngsolve as ngs
import numpy as np
import pandas as pd
import pytest
from conftest import assert_volume_and_jumps_are_ngsolves

from harness.cli import main
from harness.fem.assembly import discretise
from harness.measure.errors import error_norms
from harness.measure.estimator import ResidualEstimator, estimate
from harness.measure.rates import fit_ndof_rate, pairwise_rates, rate_table
from harness.mesh.bisection import (
    GRADED_START,
    AdaptiveRefinement,
    GradedRefinement,
    distance_to_segments,
    dorfler,
    element_sizes,
    grading_exponent,
)
from harness.mesh.levels import coarse_mesh
from harness.mesh.points import cells, coordinates
from harness.mesh.strategies import MeshStrategy, element_budget, parse_mesh, parse_meshes, singular_points
from harness.methods import get_method
from harness.problem.case import CaseError, load_case, registered_cases
from harness.problem.validate import validate_case
from harness.solvers.multigrid import Multilevel
from harness.study.chain import run_chain

DATA = Path(__file__).parent / "data"
TOLERANCE = 1e-10
STRATEGIES = ["uniform", "graded", "adaptive"]
METHODS = ["mean", "nodal", "p1", "nitsche", "penalty", "nitsche-p1", "penalty-p1"]


@pytest.fixture(scope="module")
def corner():
    return load_case("corner-r12")


def test_dorfler_marks_the_smallest_set_holding_theta_of_the_total():
    eta2 = np.array([1.0, 8.0, 0.5, 4.0, 2.0])
    marked = dorfler(eta2, 0.5)
    assert marked.tolist() == [False, True, False, False, False]       # 8 >= 0.5 * 15.5
    marked = dorfler(eta2, 0.8)
    assert marked.tolist() == [False, True, False, True, True]         # 14 >= 12.4, 12 < 12.4
    assert dorfler(eta2, 1.0).all()
    assert not dorfler(np.zeros(4), 0.5).any()


@pytest.mark.parametrize("lam, order, mu", [(0.5, 2, 0.225), (0.5, 1, 0.45), (1.5, 2, 0.675), (3.0, 2, 1.0)])
def test_the_grading_exponent_is_inside_apels_condition(lam, order, mu):
    assert grading_exponent(lam, order) == pytest.approx(mu)
    assert grading_exponent(lam, order) < lam / order or grading_exponent(lam, order) == 1.0


def test_a_graded_mesh_meets_its_size_function_and_nests(corner):
    sequence = GradedRefinement(corner, corner.nu - 1, 2, singular_points(corner))
    counts = []
    H = GRADED_START * corner.maxh
    for level in sequence.levels(4):
        sizes, centroids = element_sizes(level.mesh)
        assert (sizes <= sequence.target(H, centroids) * (1 + 1e-9)).all()
        counts.append(level.mesh.ne)
        H /= 2
    assert 3 < counts[3] / counts[2] < 5           # N grows by about 4 per level, as on uniform meshes
    # the smallest triangles touch the singular points, ~ H^(1/mu) across
    sizes, centroids = element_sizes(level.mesh)
    distance = np.linalg.norm(centroids[:, None] - singular_points(corner)[None], axis=2).min(axis=1)
    assert distance[np.argmin(sizes)] < 2 * sizes.min()


def test_adaptive_refinement_concentrates_at_the_singular_point(corner):
    """corner-r12's junction (0, 0) is where u ~ r^1/2: the smallest triangle (by area) of the
    finest adaptive mesh of `nodal` has a vertex there. (By longest edge a bisection neighbour
    may be a little smaller: newest-vertex bisection makes two shapes of each triangle.)"""
    output = run_chain(corner, [get_method("nodal")], 3, mesh=MeshStrategy("adaptive"),
                       on_level=lambda case, method, level, problem, solve: (coordinates(problem.mesh), cells(problem.mesh)))
    points, triangles = output.kept[max(output.kept)]
    assert len(output.rows) > 5
    corners = points[triangles]
    sides = corners - np.roll(corners, 1, axis=1)
    areas = 0.5 * np.abs(sides[:, 0, 0] * sides[:, 1, 1] - sides[:, 0, 1] * sides[:, 1, 0])
    smallest = corners[np.argmin(areas)]
    assert np.linalg.norm(smallest - [0.0, 0.0], axis=1).min() < 1e-14
    assert areas.min() < 1e-6 * areas.max()


@pytest.mark.parametrize("data", ["quadratic_binding.py", "quadratic_binding_elastic.py"])
@pytest.mark.parametrize("method", ["mean", "nodal"])
def test_the_estimator_vanishes_where_u_h_is_u(method, data):
    """u in P2 and in both cones (scalar: x y + y^2; elastic: (x y + y^2, x y + y^2), frictionless
    by its contact traction): the solve gives u_h = u and every term of eta (the residuals, the
    flux against the discrete pressure, penetration, complementarity, and in elasticity the
    tangential traction) vanishes to round-off."""
    case = load_case(str(DATA / data))
    validate_case(case)             # u = gap on all of Gamma_C: validation allows its round-off
    mesh = ngs.Mesh(case.geometry.GenerateMesh(maxh=case.maxh))
    problem = discretise(case, mesh, 2)
    solve = get_method(method).solve(case, problem, None, None)
    assert solve.fields["kkt_residual"] <= TOLERANCE
    assert error_norms(case, [problem.gridfunction(solve.u)], _quadrature(case, mesh))[0]["err_h1"] < 1e-10
    eta2 = ResidualEstimator(case, problem).indicators(solve.u)
    assert eta2.shape == (mesh.ne,)
    assert estimate(eta2) < 1e-8


def test_the_elastic_estimator_sees_a_tangential_traction():
    """The frictionless condition is a term of its own: the same elastic P2 solution, with a
    contact traction whose tangential part no longer matches sigma_t(u), has eta > 0 on Gamma_C
    only through that term (the normal terms and the residuals still vanish)."""
    case = load_case(str(DATA / "quadratic_binding_elastic.py"))
    mesh = ngs.Mesh(case.geometry.GenerateMesh(maxh=case.maxh))
    problem = discretise(case, mesh, 2)
    u = get_method("nodal").solve(case, problem, None, None).u
    estimator = ResidualEstimator(case, problem)
    estimator.load = estimator.load + np.array([0.5, 0.0])         # g_t off by 1/2, g_n unchanged
    contact = estimator.contact_terms(u, problem.gridfunction(u))
    assert contact.sum() == pytest.approx(0.5**2 * (estimator.q.h * estimator.q.weights).sum(), rel=1e-10)


def test_the_estimator_sees_each_term_it_names(corner):
    """On a coarse corner-r12 solve each kind of term is nonzero somewhere: the estimator is the
    sum of the volume, jump, Neumann and contact parts."""
    mesh = ngs.Mesh(corner.geometry.GenerateMesh(maxh=corner.maxh))
    problem = discretise(corner, mesh, 2)
    solve = get_method("nodal").solve(corner, problem, None, None)
    estimator = ResidualEstimator(corner, problem)
    total = estimator.indicators(solve.u)
    contact = estimator.contact_terms(solve.u, problem.gridfunction(solve.u))
    assert contact.sum() > 0 and (total >= 0).all()
    assert total.sum() > contact.sum()
    # the contact part is added to the triangles on Gamma_C only
    on_contact = np.zeros(mesh.ne, bool)
    on_contact[problem.trace.volumes] = True
    assert total[on_contact].sum() >= contact.sum()


@pytest.mark.parametrize("name, strategy", [("corner-r12", "uniform"), ("smooth", "uniform"), ("wedge-r23", "graded"),
                                            ("elastic-transition-r32", "uniform"), ("elastic-wedge", "graded")])
@pytest.mark.parametrize("order", [1, 2])
def test_the_estimators_volume_and_jump_terms_are_ngsolves_integrals(name, strategy, order):
    """The element residual and the flux jumps, made from grad u_h at the triangles' vertices
    (``MeshTerms``), agree with NGSolve's own integration of the same terms on each element,
    for a function that is no solution (every jump nonzero), on uniform and graded meshes, with
    and without a volume load, scalar and elastic (sigma(u_h) n jumps, div sigma(u_h))."""
    case = load_case(name)
    for level in MeshStrategy(strategy).sequence(case, order).levels(3):
        mesh = level.mesh
    assert_volume_and_jumps_are_ngsolves(case, mesh, order)


def _quadrature(case, mesh):
    from harness.fem.element_quadrature import ElementQuadrature
    return ElementQuadrature.of(case, mesh)


def test_multigrid_across_several_bisection_sweeps_matches_the_factorised_solve(corner):
    """A graded level is many bisection sweeps: the multigrid's prolongations chain them, and
    the solve agrees with the one that factorises."""
    sequence = GradedRefinement(corner, corner.nu - 1, 2, singular_points(corner))
    multilevel, method = None, get_method("nodal")
    for level in sequence.levels(4):
        multilevel = Multilevel(level.mesh) if multilevel is None else multilevel.refined(level.mesh, level.prolongation)
    # several bisection sweeps between the last two levels: the level's prolongation is their
    # product, with weights 1/4, 3/4, ... where a sweep halved an edge of the sweep before
    assert not np.isin(level.prolongation.data, [0.5, 1.0]).all()
    problem = discretise(corner, level.mesh, 2)
    with_multigrid = method.solve(corner, problem, None, multilevel)
    factorised = method.solve(corner, discretise(corner, level.mesh, 2), None, None)
    assert with_multigrid.fields["kkt_residual"] <= TOLERANCE and with_multigrid.fields["status"] == "converged"
    assert np.abs(with_multigrid.u - factorised.u).max() < 1e-8


@pytest.mark.parametrize("strategy", STRATEGIES)
@pytest.mark.parametrize("method", METHODS)
def test_every_method_runs_exactly_on_every_mesh_strategy(corner, method, strategy):
    output = run_chain(corner, [get_method(method)], 2, mesh=parse_mesh(strategy)[0])
    frame = pd.DataFrame(output.rows)
    assert (frame.mesh == strategy).all()
    assert (frame.status == "converged").all()
    assert (frame.kkt_residual <= TOLERANCE).all()
    assert np.isfinite(frame.estimator).all() and (frame.estimator > 0).all()
    assert np.allclose(frame.effectivity, frame.estimator / frame.err_energy)
    if strategy == "adaptive":         # the same budget of triangles as uniform level 1 (+ P1's extra level)
        assert len(frame) > 2
        assert (np.diff(frame.ndof) > 0).all()


@pytest.mark.parametrize("strategy", ["graded", "adaptive"])
@pytest.mark.parametrize("method", ["mean", "nodal", "p1"])
def test_every_cone_runs_exactly_on_elastic_graded_and_adaptive_meshes(method, strategy):
    """Issue 53: an elastic case on the mesh axis, its rows with the elastic estimator's
    effectivity against the energy error."""
    output = run_chain(load_case("elastic-wedge"), [get_method(method)], 2, mesh=parse_mesh(strategy)[0])
    frame = pd.DataFrame(output.rows)
    assert (frame.mesh == strategy).all() and (frame.status == "converged").all()
    assert (frame.kkt_residual <= TOLERANCE).all()
    assert (frame.estimator > 0).all() and np.allclose(frame.effectivity, frame.estimator / frame.err_energy)
    assert ((frame.effectivity > 0.5) & (frame.effectivity < 10)).all()


def test_parse_mesh_reads_every_strategy_and_refuses_others():
    assert [s.label for s in parse_meshes(["all"])] == STRATEGIES
    assert parse_mesh("adaptive:theta=0.3")[0].theta == 0.3
    assert parse_mesh("adaptive:theta=0.3")[0].label == "adaptive:theta=0.3"
    assert parse_meshes(["uniform", "all", "graded"]) == [MeshStrategy(s) for s in STRATEGIES]
    for bad in ["refined", "graded:theta=0.3", "adaptive:theta=0", "adaptive:theta=2", "adaptive:beta=0.5", "adaptive:theta=x"]:
        with pytest.raises(ValueError):
            parse_mesh(bad)


def test_an_adaptive_theta_outside_0_1_is_refused():
    with pytest.raises(ValueError, match="theta"):
        AdaptiveRefinement(load_case("corner-r12"), theta=1.5)


def test_strategies_say_which_cases_they_mesh():
    assert MeshStrategy("graded").applies_to(load_case("transition-r32")) is None
    # 3D exact cases: adaptive meshes by the 3D estimator (tests/test_adaptive_3d.py)
    assert MeshStrategy("adaptive").applies_to(load_case("transition-line-3d")) is None
    assert MeshStrategy("adaptive").applies_to(load_case("elastic-transition-3d")) is None
    # issue 53: graded in 3D, scalar and elastic, toward declared singular lines
    # (the transition circles as polylines of chords)
    for name in ("transition-line-3d", "elastic-transition-3d", "elastic-junction-3d", "smooth-3d", "transition-circle-3d",
                 "elastic-transition-circle-3d"):
        assert MeshStrategy("graded").applies_to(load_case(name)) is None
    assert "singular_lines" in MeshStrategy("graded").applies_to(dataclasses.replace(load_case("transition-circle-3d"),
                                                                                     singular_lines=None))
    assert MeshStrategy("graded").applies_to(load_case("elastic-transition-r32")) is None
    assert MeshStrategy("adaptive").applies_to(load_case("elastic-wedge")) is None
    # a case without u: each level against its own reference (tests/test_adaptive_reference.py)
    reference = load_case("corner-r12").with_reference(1)
    assert MeshStrategy("adaptive").applies_to(reference) is None and MeshStrategy("graded").applies_to(reference) is None
    assert "2D" in MeshStrategy("adaptive").applies_to(load_case("transition-line-3d").with_reference(1))


def test_ndof_rates_are_the_h_rate_over_d_on_uniform_meshes():
    h = 0.5 ** np.arange(5)
    frame = pd.DataFrame({"case": "c", "mesh": "uniform", "method": "m", "order": 2, "level": range(5), "h": h,
                          "ndof": 100 * h ** -2.0, "err_h1": 0.3 * h ** 1.5, "expected_rate": 1.5,
                          "expected_log_exponent": 0.0, "reference": "r", "nu": 2.5})
    row = rate_table(frame).iloc[0]
    assert row.fitted_rate == pytest.approx(1.5)
    assert row.fitted_rate_ndof == pytest.approx(0.75)
    assert row.uniform_rate_ndof == pytest.approx(0.75) and row.optimal_rate_ndof == 1.0
    assert row.ndof_verdict == "below optimal"
    assert fit_ndof_rate([1e3, 4e3, 1.6e4], [1e-2, 2.5e-3, 6.25e-4]) == pytest.approx(1.0)


def test_a_case_file_given_by_path_runs_with_mesh_all(tmp_path, capsys):
    source = Path(__file__).parents[1] / "cases" / "corner_r12.py"
    code = main(["run", "--case", str(source), "--method", "nodal", "--mesh", "all", "--levels", "2",
                 "--out", str(tmp_path), "--quiet"])
    assert code == 0
    frame = pd.read_csv(tmp_path / "results.csv")
    assert list(dict.fromkeys(frame["mesh"])) == STRATEGIES
    assert (frame.kkt_residual <= TOLERANCE).all()
    rates = main(["rates", str(tmp_path / "results.csv")])
    assert rates == 0
    assert set(pd.read_csv(tmp_path / "rates.csv")["mesh"]) == set(STRATEGIES)


@pytest.mark.parametrize("argv, words", [
    (["--mesh", "refined"], "unknown mesh strategy"),
    (["--mesh", "adaptive:theta=3"], "theta"),
])
def test_a_bad_mesh_strategy_is_one_line_and_exit_2(tmp_path, capsys, argv, words):
    code = main(["run", "--case", "corner-r12", "--levels", "1", "--out", str(tmp_path / "out"), *argv])
    err = capsys.readouterr().err.strip()
    assert code == 2 and len(err.splitlines()) == 1 and words in err
    assert not (tmp_path / "out").exists()


def test_a_mesh_strategy_no_case_takes_is_refused_in_one_line(tmp_path, capsys):
    # a 3D case measured against a reference (no per-level reference in 3D: no adaptive meshes)
    code = main(["run", "--case", "transition-line-3d", "--reference-levels", "1", "--mesh", "adaptive", "--levels", "1",
                 "--out", str(tmp_path / "o")])
    err = capsys.readouterr().err.strip()
    assert code == 2 and len(err.splitlines()) == 1 and "2D only" in err
    assert not (tmp_path / "o").exists()


def _effectivities(case_name: str, method: str, levels: int) -> np.ndarray:
    frame = pd.DataFrame(run_chain(load_case(case_name), [get_method(method)], levels, mesh=MeshStrategy("adaptive")).rows)
    return frame.effectivity.to_numpy()


# every registered one-body 2D case with u, scalar and elastic (of the friction cases those of the
# default report: the others' estimator is tests/test_tresca_meshes.py's)
EXACT_2D = sorted(name for name, case in registered_cases(2).items() if case.bodies == 1 and case.exact
                  and (not case.frictional or case.report_profile == "default"))


# the cone methods, or on a Coulomb case Nitsche P2 and P1 (the cones' Coulomb solves not measured here): measured on
# elastic-coulomb-r32, 5 adaptive levels, 5.7-6.4 (P2) and 2.4-3.4 (P1)
EFFECTIVITY_RUNS = [(name, method) for name in EXACT_2D
                    for method in (("nitsche", "nitsche-p1") if registered_cases()[name].friction.name == "coulomb"
                                   else ("mean", "nodal", "p1"))]


@pytest.mark.slow
@pytest.mark.parametrize("case_name, method", EFFECTIVITY_RUNS)
def test_the_effectivity_is_bounded_and_steady_on_every_exact_case(case_name, method):
    """Issues 31 and 53: on every exact 2D case (scalar and elastic) x cone method (Nitsche on a
    Coulomb case) x adaptive level >= 2 the effectivity index lies in [0.5, 10], and over the last
    four levels max/min <= 2."""
    eff = _effectivities(case_name, method, 5)
    assert ((eff[2:] >= 0.5) & (eff[2:] <= 10)).all(), eff
    assert eff[-4:].max() / eff[-4:].min() <= 2, eff


def test_a_level_without_refinement_keeps_the_multigrid_hierarchy(corner):
    """A graded level may need no bisection (the coarse mesh already meets h(r)): the hierarchy
    gains no level, and the study goes on."""
    mesh = ngs.Mesh(corner.geometry.GenerateMesh(maxh=corner.maxh))
    multilevel = Multilevel(mesh)
    assert multilevel.refined(mesh) is multilevel and len(multilevel.matrices) == 1


@pytest.mark.slow          # 7 s: every strategy on every kind of case
def test_mesh_all_runs_every_strategy_on_every_kind_of_case(tmp_path, capsys):
    """A one-body 2D, a two-body and a 3D case on every strategy: each on all three, no line
    skipped (what a strategy refuses is refused before any solve: the test above)."""
    from harness.cli import main
    cases = ["transition-r32", "two-body-transition-r32", "transition-line-3d"]
    code = main(["run", *(a for c in cases for a in ("--case", c)), "--mesh", "all", "--method", "nodal", "--method", "mortar-nodal",
                 "--levels", "1", "--out", str(tmp_path), "--quiet"])
    assert code == 0 and capsys.readouterr().err == ""
    rows = pd.read_csv(tmp_path / "results.csv")
    assert sorted(set(zip(rows.case, rows["mesh"]))) == sorted((case, mesh) for case in cases for mesh in ("uniform", "graded", "adaptive"))


# 3D (issue 53, item 2): graded meshes toward singular lines, the multigrid on tetrahedral
# bisection hierarchies. Sizes: transition-line-3d's graded levels 0, 1, 2 have 1.4e3, 4.2e3 and
# 7.4e4 tetrahedra (2.5e3, 6.5e3, 1.0e5 P2 dofs).

@pytest.fixture(scope="module")
def line3d():
    return load_case("transition-line-3d")


def test_the_distance_to_a_segment_is_to_its_nearest_point():
    segment = np.array([[[0.0, -1.0, 0.0], [0.0, 1.0, 0.0]]])
    points = np.array([[0.3, 0.5, 0.4],      # beside it: across, 0.5
                       [0.0, 3.0, 0.0],      # beyond an end, on its line: to the end, 2
                       [0.0, 0.2, 0.0],      # on it
                       [1.0, -2.0, 0.0]])    # beyond the other end, off its line: sqrt(2)
    assert distance_to_segments(points, segment) == pytest.approx([0.5, 2.0, 0.0, np.sqrt(2)])
    # a point is a segment of length 0; the nearest of several; none: infinitely far; 2D too
    two = np.concatenate([np.array([[[1.0, 1.0, 1.0], [1.0, 1.0, 1.0]]]), segment])
    assert distance_to_segments(np.array([[1.0, 1.0, 0.5], [0.0, 0.0, 0.25]]), two) == pytest.approx([0.5, 0.25])
    assert np.isinf(distance_to_segments(points, np.zeros((0, 2, 3)))).all()
    assert distance_to_segments(np.array([[0.5, 1.0]]), np.array([[[0.0, 0.0], [1.0, 0.0]]])) == pytest.approx([1.0])


@pytest.mark.slow          # 3 s: 3D graded levels
def test_a_3d_graded_mesh_meets_its_size_function_nests_and_keeps_the_budget(line3d):
    """h_T <= H min(1, r/R)^(1 - mu) on every tetrahedron, r the distance to the declared line
    {x = 0, z = 0}; each level keeps the previous one's vertices (refined in place); the
    tetrahedra at the line are the small ones; the chain stays within the uniform chain's
    elements."""
    sequence = MeshStrategy("graded").sequence(line3d, 2)
    assert sequence.mu == pytest.approx(0.675)              # 0.9 lambda / k, lambda = 3/2, k = 2
    H, previous = GRADED_START * line3d.maxh, None
    for level in sequence.levels(3):
        sizes, centroids = element_sizes(level.mesh)
        assert (sizes <= sequence.target(H, centroids) * (1 + 1e-9)).all()
        vertices = coordinates(level.mesh)
        if previous is not None:
            assert len(vertices) > len(previous) and np.array_equal(vertices[:len(previous)], previous)
        previous = vertices
        H /= 2
    assert level.mesh.ne <= element_budget(line3d, 3) == coarse_mesh(line3d).ne * 8**2     # 8 tetrahedra per red refinement
    # the grading: near the line the tetrahedra are several times smaller than away from it
    r = np.hypot(centroids[:, 0], centroids[:, 2])
    assert np.median(sizes[r < 0.05]) < 0.5 * np.median(sizes[r > 0.5])


@pytest.mark.parametrize("case_name, sweeps", [("transition-line-3d", 2), ("elastic-transition-3d", 1)])
def test_multigrid_on_a_3d_bisection_hierarchy_matches_the_factorised_solve(case_name, sweeps):
    """A graded 3D level is bisection sweeps of tetrahedra (level 1: two of transition-line-3d,
    one of elastic-transition-3d's coarser mesh): the multigrid's prolongations chain them
    (scalar, and vector P1 in the rotated frame), and the solve agrees with the one that
    factorises."""
    case = load_case(case_name)
    multilevel, method = None, get_method("nodal")
    for level in MeshStrategy("graded").sequence(case, 2).levels(2):
        multilevel = Multilevel(level.mesh, case.physics) if multilevel is None else multilevel.refined(level.mesh)
    assert multilevel.mesh_levels[-1] - multilevel.mesh_levels[-2] == sweeps
    with_multigrid = method.solve(case, discretise(case, level.mesh, 2), None, multilevel)
    factorised = method.solve(case, discretise(case, level.mesh, 2), None, None)
    assert with_multigrid.fields["kkt_residual"] <= TOLERANCE and with_multigrid.fields["status"] == "converged"
    assert np.abs(with_multigrid.u - factorised.u).max() < 1e-8


@pytest.mark.slow     # 20 s; make test grades 3D meshes in test_a_3d_graded_mesh_meets_its_size_function...
def test_run_grades_a_3d_case(tmp_path):
    """`run --case transition-line-3d --mesh graded --levels 2`: every 3D method of order 1 and 2,
    the cones and the contact laws, converges exactly on the graded levels (P3 and P4 in 3D, one
    minute more here: tests/test_degree.py on uniform levels, whose solver paths the graded
    levels share)."""
    code = main(["run", "--case", "transition-line-3d", "--mesh", "graded", "--levels", "2", "--method", "cones",
                 "--method", "mean-edges", "--method", "weak", "--out", str(tmp_path), "--quiet"])
    frame = pd.read_csv(tmp_path / "results.csv")
    assert code == 0 and (frame["mesh"] == "graded").all()
    assert set(frame.method) == {"mean", "mean-edges", "nodal", "p1", "nitsche", "nitsche-p1", "penalty", "penalty-p1"}
    assert (frame.status == "converged").all() and (frame.kkt_residual <= TOLERANCE).all()


LINE = "singular_lines = [((0.0, -1.0, 0.0), (0.0, 1.0, 0.0))]"


@pytest.mark.parametrize("declaration, words", [
    ("singular_lines = [((0.0, -1.0, 0.0), (0.0, -1.0, 0.0))]", "distinct ends"),
    ("singular_lines = [((0.0, -1.0), (0.0, 1.0))]", "((x, y, z), (x, y, z))"),
    ("singular_lines = [(0.0, 0.0, 0.0)]", "segments"),
    ("singular_lines = 5", "segments"),
    ("singular_lines = [((0.0, -1.0, 0.0), (0.0, float('nan'), 0.0))]", "finite"),
    ("singular_points = [(0.0, 0.0)]", "(x, y, z) triples"),
])
def test_a_malformed_3d_singular_set_is_refused_in_one_line(tmp_path, declaration, words):
    source = (Path(__file__).parents[1] / "cases" / "transition_line_3d.py").read_text()
    path = tmp_path / "line.py"
    path.write_text(source.replace(LINE, declaration) if "lines" in declaration else source + declaration + "\n")
    with pytest.raises(CaseError) as refused:
        load_case(str(path))
    assert words in str(refused.value) and "\n" not in str(refused.value)


def test_singular_lines_are_3d_only_and_3d_points_grade_too(tmp_path):
    path = tmp_path / "corner.py"
    path.write_text((Path(__file__).parents[1] / "cases" / "corner_r12.py").read_text() + LINE + "\n")
    with pytest.raises(CaseError, match="singular_lines are 3D only"):
        load_case(str(path))
    # a 3D point: no mesh vertex needed (no graded quadrature in 3D), the mesh graded toward it
    source = (Path(__file__).parents[1] / "cases" / "transition_line_3d.py").read_text()
    path = tmp_path / "point.py"
    path.write_text(source.replace(LINE, "singular_points = [(0.1, 0.2, 0.0)]"))
    case = load_case(str(path))
    assert case.singular_lines is None and MeshStrategy("graded").applies_to(case) is None
    sequence = MeshStrategy("graded").sequence(case, 2)
    centroids = np.array([[0.1, 0.2, 0.5], [0.0, 0.9, 0.0]])
    assert sequence.distance(centroids) == pytest.approx([0.5, np.sqrt(0.5)])


@pytest.mark.slow       # 100 s (nodal alone; 9e5 dofs on the finest level): `make test-scale`
@pytest.mark.scale
def test_graded_meshes_beat_uniform_ones_in_n_on_transition_line_3d():
    """Issue 53, item 2: `nodal` on transition-line-3d's graded meshes within the uniform 4-level
    chain's budget of tetrahedra: the finest level has >= 5e5 dofs, and the rate in N is above
    uniform meshes' 1/2 toward the optimal 2/3. Measured: N = 2.5e3, 6.5e3, 1.0e5, 9.0e5,
    pairwise rates 0.764, 0.551, 0.632; the fit over the last three levels 0.585 (its first
    pair is pre-asymptotic: the coarse mesh's elements, 0.2 to 0.55 across, first meet H = 0.25
    there, N grows 16-fold)."""
    frame = pd.DataFrame(run_chain(load_case("transition-line-3d"), [get_method("nodal")], 4, mesh=MeshStrategy("graded")).rows)
    assert len(frame) == 4 and frame.ndof.iloc[-1] >= 5e5
    assert (frame.status == "converged").all() and (frame.kkt_residual <= TOLERANCE).all()
    # the goal on the finest pair; over all levels, above what uniform meshes can do (1/2)
    assert -pairwise_rates(frame.ndof, frame.err_h1)[-1] >= 0.6
    assert fit_ndof_rate(frame.ndof, frame.err_h1) > 0.5


def test_the_nested_prediction_keeps_the_status_of_an_edge_that_bisection_leaves_whole(corner):
    """An adaptive level bisects the marked triangles only: a Gamma_C edge left whole inherits its
    own edge constraint's status, whatever its ends' (`mean`'s vertex constraints are degenerate
    in binding zones; predicting from them set hundreds of such edges free and cost 18 active
    sets on adaptive corner-r12's finest level, 4 since)."""
    from harness.fem.cones import contact_qp
    from harness.solvers.bound_constraints import solve_contact_qp

    def edges(trace):
        return [tuple(np.round(np.r_[a, b], 12)) for a, b in zip(trace.a, trace.b)]

    method = get_method("mean")
    sequence = MeshStrategy("adaptive").sequence(corner, method.order)
    previous, coarse_status = None, {}
    for level in sequence.levels(3):
        problem = discretise(corner, level.mesh, 2)
        qp, nv = contact_qp(corner, problem, method.cone), len(problem.vertex_dofs)
        if previous is not None:
            predicted = qp.predicted_active(previous)[nv:]
            kept = [i for i, edge in enumerate(edges(problem.trace)) if edge in coarse_status]
            assert 0 < len(kept) < len(predicted)         # some edges bisected, some left whole
            assert [bool(predicted[i]) for i in kept] == [coarse_status[edges(problem.trace)[i]] for i in kept]
        solution = solve_contact_qp(qp)
        u = qp.to_u(solution.z)
        previous = qp.trace_function(u, solution.active)
        coarse_status = dict(zip(edges(problem.trace), map(bool, solution.active[nv:])))
        sequence.observe(ResidualEstimator(corner, problem).indicators(u))
