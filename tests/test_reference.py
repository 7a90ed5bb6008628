"""Cases without a closed form: the exact prolongation, errors against a reference, the contract."""
import dataclasses
from pathlib import Path

import ngsolve as ngs
import numpy as np
import pytest
from conftest import CONE_NAMES, HIGH_ORDER_NAMES, WEAK_NAMES

from harness import run
from harness.measure.rates import rate_table
from harness.measure.reference import LevelNumbering, edge_dofs_of_sides, norm_matrices, prolongation, red_parents
from harness.mesh.levels import coarse_mesh, mesh_hierarchy
from harness.mesh.points import evaluate
from harness.methods import METHODS
from harness.problem.case import CaseError, load_case, registered_cases
from harness.problem.validate import validate_case

DATA = Path(__file__).parent / "data"

# a reference solution is nodal P2, into whose space P_k (k >= 3) does not embed: those methods
# refuse a case measured against one (``methods.method.Method.supports``;
# test_a_high_order_method_refuses_a_case_without_an_exact_solution)
REFERENCE_METHODS = CONE_NAMES + WEAK_NAMES
# hertz-line (elastic, its reference 2e5 dofs at four levels) in `make test-full`: the elastic
# reference path is test_elastic_reference's and test_hertz's
# (3D: hertz-sphere's levels cost 8 times the dofs each; its own tests are test_hertz's)
REFERENCE_CASES = [pytest.param(name, marks=pytest.mark.slow) if name == "hertz-line" else name
                   for name, case in registered_cases().items() if not case.exact and case.dimension == 2
                   and case.friction.name != "coulomb"]      # the Coulomb reference cases: tests/test_cattaneo.py


@pytest.mark.parametrize("order", [1, 2])
def test_prolongation_reproduces_the_coarse_function_exactly(order, rng):
    """Two red refinements: P u_h equals u_h at random points (evaluated on an untouched copy of
    the coarse mesh) and keeps its H^1-semi and L^2 norms, to round-off."""
    case = load_case("transition-r32")
    copy = coarse_mesh(case)
    numberings = []
    for level, mesh in mesh_hierarchy(case, 3):
        numberings.append(LevelNumbering.of(mesh))
        if level == 0:
            coarse_fes = ngs.H1(copy, order=order)
            u = rng.standard_normal(coarse_fes.ndof)
            coarse_norms = [u @ (M @ u) for M in norm_matrices(mesh, order)]
    fine = prolongation(numberings[1], numberings[2], order) @ (prolongation(numberings[0], numberings[1], order) @ u)
    fine_fes = ngs.H1(mesh, order=order)
    points = np.column_stack([rng.uniform(-1, 1, 200), rng.uniform(0, 1, 200)])
    coarse_gf, fine_gf = ngs.GridFunction(coarse_fes), ngs.GridFunction(fine_fes)
    coarse_gf.vec.FV().NumPy()[:] = u
    fine_gf.vec.FV().NumPy()[:] = fine
    assert np.abs(evaluate(coarse_gf, copy, points) - evaluate(fine_gf, mesh, points)).max() < 1e-12
    fine_norms = [fine @ (M @ fine) for M in norm_matrices(mesh, order)]
    assert np.allclose(fine_norms, coarse_norms, rtol=1e-12)


@pytest.mark.parametrize("order", [1, pytest.param(2, marks=pytest.mark.slow)])      # P2: 3 s
def test_prolongation_in_3d_reproduces_the_coarse_function_exactly(order, rng):
    """One red refinement of tetrahedra (eight children, the inner diagonal's bubble from the six
    coarse edges of its tetrahedron): P u_h equals u_h at random points, to round-off."""
    case = load_case("transition-line-3d")
    copy = coarse_mesh(case)
    coarse_fes = ngs.H1(copy, order=order)
    u = ngs.GridFunction(coarse_fes)
    u.vec.FV().NumPy()[:] = rng.standard_normal(coarse_fes.ndof)
    numberings = []
    for level, mesh in mesh_hierarchy(case, 2):
        numberings.append(LevelNumbering.of(mesh, coarse_nv=numberings[-1].nv if numberings else 0))
    fine = ngs.GridFunction(ngs.H1(mesh, order=order))
    fine.vec.FV().NumPy()[:] = prolongation(*numberings, order) @ u.vec.FV().NumPy()
    points = np.column_stack([rng.uniform(-1, 1, 300), rng.uniform(-1, 1, 300), rng.uniform(0, 1, 300)])
    assert np.abs(evaluate(u, copy, points) - evaluate(fine, mesh, points)).max() < 1e-12


@pytest.mark.slow
@pytest.mark.parametrize("case_name", ["transition-line-3d", "elastic-transition-3d"])
def test_3d_errors_against_a_reference_miss_only_the_reference_error(case_name):
    """3D, scalar and elastic: the energy error of nodal P2 against the reference one level finer
    than the finest studied one is the exact error times sqrt(1 - (h_R/h)^{2p}), p = 3/2 (Galerkin
    orthogonality, the module docstring of ``measure.reference``), to 0.02; P1's, far larger at
    the same dofs, is the exact one to 1 %."""
    case = load_case(case_name)
    exact = run(case, methods=["nodal", "p1"], levels=2, show_progress=False).set_index(["method", "level"])
    against = run(case.with_reference(1), methods=["nodal", "p1"], levels=2, show_progress=False).set_index(["method", "level"])
    assert (against.errors_against == "reference").all() and (against.reference_level == 2).all()
    ratio = against.err_energy / exact.err_energy
    for level in (0, 1):
        assert ratio[("nodal", level)] == pytest.approx(np.sqrt(1 - 2.0 ** (-3 * (2 - level))), abs=0.02)
    np.testing.assert_allclose(ratio.loc["p1"], 1.0, atol=0.01)


@pytest.mark.parametrize("case_name", ["transition-r32", pytest.param("transition-circle-3d", marks=pytest.mark.slow)])
def test_parents_from_the_cells_are_netgens(case_name):
    """A red refinement's parents of its new vertices read from the cell table (2D, and 3D's
    tetrahedra; curved boundaries included) are those netgen gives one vertex at a time (netgen
    keeps older levels' parents for the coarse vertices; the prolongation reads new ones only)."""
    case, coarse_nv = load_case(case_name), 0
    for _, mesh in mesh_hierarchy(case, 3):
        netgen = np.sort(np.array([mesh.GetParentVertices(v) for v in range(mesh.nv)]).reshape(-1, 2), axis=1)
        parents = red_parents(mesh, coarse_nv)
        assert np.array_equal(np.sort(parents[coarse_nv:], axis=1), netgen[coarse_nv:])
        assert (parents[:coarse_nv] == -1).all() and (coarse_nv or (netgen == -1).all())
        coarse_nv = mesh.nv


def test_edge_dofs_read_at_midpoints_are_ngsolves_element_dofs():
    """Every triangle side's P2 edge dof, read from a numbered P2 function at the midpoints, is
    the one NGSolve lists for that element and edge (on a mesh refined twice)."""
    *_, (_, mesh) = mesh_hierarchy(load_case("transition-r32"), 3)
    fes = ngs.H1(mesh, order=2)
    pairs, edge_dofs = edge_dofs_of_sides(mesh, fes)
    listed = {}
    for element in fes.Elements(ngs.VOL):
        vertices, edges = element.dofs[:3], element.dofs[3:]
        for (a, b), dof in zip(((0, 2), (1, 2), (0, 1)), edges):
            listed[tuple(sorted((vertices[a], vertices[b])))] = dof
    assert len(pairs) == 3 * mesh.ne
    assert all(listed[tuple(sorted(pair))] == dof for pair, dof in zip(pairs.tolist(), edge_dofs.tolist()))


@pytest.fixture(scope="module")
def exact_and_reference():
    """transition-r32, 3 levels (P1: 4), every method: errors against u, and against k = 2."""
    case = registered_cases()["transition-r32"]
    exact = run(case, methods="all", levels=3, show_progress=False)
    reference = run(case.with_reference(2), methods="all", levels=3, show_progress=False)
    return exact, reference


VOLUME_AND_TRACE = ["err_h1", "err_h1_semi", "err_l2", "err_trace_l2"]
PRESSURE = ["err_pressure_l2", "err_pressure_h12"]


@pytest.mark.parametrize("method", REFERENCE_METHODS)
def test_errors_against_the_nodal_reference_agree_with_exact_errors_on_every_level(exact_and_reference, method):
    """One reference for every method, nodal P2 two levels finer: the H^1, L^2 and trace errors
    within 1% of the exact ones on every level, the last included (Galerkin orthogonality: at
    most the factor sqrt(1 - 4^-3) = 0.992 of a h^{3/2} method; measured 0.8% for nodal, 0.0%
    for P1, whose errors are larger at the same dofs); the pressure, which orthogonality does
    not cover, within 10% (measured 7.4%, Nitsche's finest level). Each method's own solution
    as the reference (harness 0.3.0) was off by up to 25% on penalty's finest level."""
    exact, reference = (frame[frame.method == method].sort_values("level") for frame in exact_and_reference)
    assert (reference.errors_against == "reference").all() and (exact.errors_against == "exact").all()
    assert (reference.reference_method == "nodal").all()
    assert np.all(np.abs(reference[VOLUME_AND_TRACE].values / exact[VOLUME_AND_TRACE].values - 1) <= 0.01)
    assert np.all(np.abs(reference[PRESSURE].values / exact[PRESSURE].values - 1) <= 0.10)
    # the reference solve is converged too, and a level's own columns do not depend on it
    assert (reference.reference_kkt_residual <= 1e-10).all() and (reference.reference_status == "converged").all()
    for column in ("active_constraints", "solver_iterations"):
        assert np.array_equal(reference[column].values, exact[column].values)


@pytest.mark.parametrize("method", REFERENCE_METHODS)
def test_rates_against_the_nodal_reference_are_the_exact_rates(exact_and_reference, method):
    """The fitted H^1 rate against the reference within 0.01 of the one against u (on the
    default report's 6 levels, measured within 0.006 for every method; against their own
    solutions penalty's was 0.16 too high and mean's and P1's 0.02-0.03: an inconsistent or
    different method's own reference shares part of its error)."""
    exact, reference = (rate_table(frame[frame.method == method]).fitted_rate.iloc[0] for frame in exact_and_reference)
    assert reference == pytest.approx(exact, abs=0.01)


def test_h1_error_against_a_reference_misses_only_the_reference_error(exact_and_reference):
    """Galerkin orthogonality with nested spaces: |u - u_h|^2 ~ |u_R - u_h|^2 + |u - u_R|^2, so on
    the finest level of a h^{3/2} method the ratio is about sqrt(1 - 4^{-3}) = 0.992."""
    exact, reference = (frame[frame.method == "nodal"].sort_values("level") for frame in exact_and_reference)
    assert reference.err_h1_semi.values[-1] / exact.err_h1_semi.values[-1] == pytest.approx(np.sqrt(1 - 4.0**-3), abs=0.01)


def test_a_reference_case_run_without_nodal_solves_nodal_for_its_reference_alone():
    """p1 alone on smooth-obstacle: the nodal chain runs to the reference level, and only p1's
    rows come out, measured against it."""
    frame = run("smooth-obstacle", methods="p1", levels=2, show_progress=False)
    assert list(frame.method.unique()) == ["p1"] and len(frame) == 3
    assert (frame.reference_method == "nodal").all() and (frame.reference_level == 1 + 2).all()
    assert frame.err_h1.notna().all() and (frame.reference_kkt_residual <= 1e-10).all()


def test_a_method_of_your_own_that_declares_the_reference_role_solves_the_reference():
    """A user's P2 method declaring REFERENCE (here `mean` renamed) takes the role from the
    registered one: its chain runs k levels further and every row is measured against it."""
    from harness.methods import METHODS, REFERENCE
    mine = dataclasses.replace(METHODS["mean"], name="my-reference", roles=frozenset({REFERENCE}))
    frame = run("smooth-obstacle", methods=["p1", mine], levels=2, show_progress=False)
    assert set(frame.method) == {"p1", "my-reference"}
    assert (frame.reference_method == "my-reference").all() and (frame.reference_level == 1 + 2).all()
    assert frame.err_h1.notna().all() and (frame.reference_kkt_residual <= 1e-10).all()


@pytest.mark.parametrize("case_name", REFERENCE_CASES)
def test_reference_case_rows_are_measured_against_a_converged_reference(case_name):
    frame = run(case_name, methods="paper", levels=4, show_progress=False)
    case = registered_cases()[case_name]
    assert (frame.errors_against == "reference").all()
    assert (frame.reference_level == 3 + case.reference_levels).all() and (frame.reference_method == "nodal").all()
    assert (frame.kkt_residual <= 1e-10).all() and (frame.reference_kkt_residual <= 1e-10).all()
    assert frame.err_best_h1.isna().all()
    rates = rate_table(frame)
    assert np.isfinite(rates.fitted_rate).all() and (rates.fitted_rate > 0).all()


def test_reference_case_without_boundary_data_is_refused():
    with pytest.raises(CaseError, match="must declare f, dirichlet and neumann; it lacks: neumann"):
        load_case(str(DATA / "reference_without_neumann.py"))


def test_case_with_u_and_boundary_data_is_refused():
    with pytest.raises(CaseError, match="declares u and dirichlet"):
        load_case(str(DATA / "exact_with_dirichlet.py"))


def test_reference_case_with_non_finite_data_is_refused():
    case = dataclasses.replace(registered_cases()["smooth-obstacle"], declared_f=ngs.log(ngs.x - ngs.x))
    with pytest.raises(CaseError, match="f is not finite"):
        validate_case(case)


@pytest.mark.parametrize("method", HIGH_ORDER_NAMES)
def test_a_high_order_method_refuses_a_case_without_an_exact_solution(method):
    exact, measured = load_case("transition-r32"), load_case("smooth-obstacle")
    assert not measured.exact and METHODS[method].supports(exact) and not METHODS[method].supports(measured)
