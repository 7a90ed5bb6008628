"""The two discrete cones are exactly the paper's K_h (Section 3) and K~_h (Section 5)."""
from pathlib import Path

import ngsolve as ngs
import numpy as np
import pytest
from conftest import MODEL_NAMES, MODELS

from harness.fem.assembly import ContactTraceFunction, discretise
from harness.fem.cones import contact_qp
from harness.mesh.levels import coarse_mesh
from harness.mesh.points import evaluate
from harness.problem.case import load_case

DATA = Path(__file__).parent / "data"

GAUSS_T, GAUSS_W = np.polynomial.legendre.leggauss(6)
GAUSS_T, GAUSS_W = 0.5 * (GAUSS_T + 1), 0.5 * GAUSS_W


def random_gridfunction(problem, rng):
    u = rng.standard_normal(problem.ndof)
    return u, problem.gridfunction(u)


def test_vertex_constraints_are_point_values(small_problem, rng):
    u, gf = random_gridfunction(small_problem, rng)
    direct = evaluate(gf, small_problem.mesh, small_problem.trace.vertex_points)
    for model in MODELS.values():
        values = model.constraint_values(small_problem, u)[: len(small_problem.vertex_dofs)]
        np.testing.assert_allclose(values, direct, rtol=0, atol=1e-12)


def test_nodal_edge_constraints_are_midpoint_values(small_problem, rng):
    u, gf = random_gridfunction(small_problem, rng)
    direct = evaluate(gf, small_problem.mesh, small_problem.trace.midpoints)
    np.testing.assert_allclose(MODELS["nodal"].edge_values(small_problem, u), direct, atol=1e-12)


def test_mean_edge_constraints_are_edge_means(small_problem, rng):
    u, gf = random_gridfunction(small_problem, rng)
    means = evaluate(gf, small_problem.mesh, small_problem.trace.points(GAUSS_T)) @ GAUSS_W
    np.testing.assert_allclose(MODELS["mean"].edge_values(small_problem, u), means, atol=1e-12)


def test_edge_mean_equals_ngsolve_boundary_integral(small_problem, rng):
    """Sum over Gamma_C of |t_i| * mean_i equals NGSolve's own integral of u_h over Gamma_C."""
    u, gf = random_gridfunction(small_problem, rng)
    means = MODELS["mean"].edge_values(small_problem, u)
    total = ngs.Integrate(gf, small_problem.mesh, definedon=small_problem.mesh.Boundaries("contact"))
    assert abs((means * small_problem.trace.lengths).sum() - total) < 1e-12 * max(1, abs(total))


def test_trace_function_matches_ngsolve_on_contact_edges(small_problem, rng):
    u, gf = random_gridfunction(small_problem, rng)
    trace_u = ContactTraceFunction.of(small_problem, u)
    t = rng.uniform(size=7)
    np.testing.assert_allclose(trace_u.at(t), evaluate(gf, small_problem.mesh, small_problem.trace.points(t)), atol=1e-12)


@pytest.mark.parametrize("model_name", MODEL_NAMES)
def test_change_of_variables_builds_p2_function_with_chosen_constraint_values(small_problem, rng, model_name):
    """u = S z has exactly the chosen vertex values and edge functionals z on Gamma_C."""
    model = MODELS[model_name]
    z = rng.standard_normal(small_problem.ndof)
    u = model.transform(small_problem) @ z
    np.testing.assert_allclose(model.constraint_values(small_problem, u), z[model.constrained_dofs(small_problem)], atol=1e-12)


@pytest.mark.parametrize("model_name", MODEL_NAMES)
def test_membership_of_functions_built_from_chosen_values(small_problem, rng, model_name):
    model = MODELS[model_name]
    C = model.constrained_dofs(small_problem)
    z = rng.standard_normal(small_problem.ndof)
    z[C] = np.abs(z[C])
    inside = model.transform(small_problem) @ z
    assert (model.constraint_values(small_problem, inside) >= 0).all()
    z[C[len(C) // 2]] = -1e-3
    outside = model.transform(small_problem) @ z
    assert (model.constraint_values(small_problem, outside) < 0).sum() == 1


def test_nodal_cone_lies_in_mean_cone(small_problem, rng):
    """K~_h subset K_h (Simpson's rule, Section 5); the converse fails."""
    S = MODELS["nodal"].transform(small_problem)
    C = MODELS["nodal"].constrained_dofs(small_problem)
    for _ in range(200):
        z = rng.standard_normal(small_problem.ndof)
        z[C] = rng.exponential(size=len(C)) * rng.integers(0, 2, size=len(C))  # many exact zeros
        u = S @ z
        assert (MODELS["mean"].constraint_values(small_problem, u) >= -1e-14).all()
    # Functions of K_h outside K~_h exist: a bubble with positive mean and negative midpoint.
    Sm = MODELS["mean"].transform(small_problem)
    zm = np.zeros(small_problem.ndof)
    Cm = MODELS["mean"].constrained_dofs(small_problem)
    zm[Cm] = 1e-3
    edge = small_problem.edge_dofs[0]
    zm[edge] = 0.0
    zm[small_problem.end_dofs[0]] = 1.0
    u = Sm @ zm
    midpoint = MODELS["nodal"].edge_values(small_problem, u)[0]
    assert midpoint < 0 and (MODELS["mean"].constraint_values(small_problem, u) >= 0).all()


@pytest.mark.parametrize("model_name", MODEL_NAMES)
def test_gap_bounds_are_gap_values_or_edge_means(model_name):
    """With a gap alpha the bounds are alpha at vertices and midpoints, or its edge means."""
    case = load_case(str(DATA / "gap_case.py"))
    problem = discretise(case, coarse_mesh(case))
    alpha = contact_qp(case, problem, MODELS[model_name]).alpha
    nv = len(problem.vertex_dofs)
    np.testing.assert_allclose(alpha[:nv], evaluate(case.gap, problem.mesh, problem.trace.vertex_points), atol=1e-13)
    if model_name == "nodal":
        expected = evaluate(case.gap, problem.mesh, problem.trace.midpoints)
    else:
        expected = evaluate(case.gap, problem.mesh, problem.trace.points(GAUSS_T)) @ GAUSS_W
    np.testing.assert_allclose(alpha[nv:], expected, atol=1e-12)


@pytest.mark.parametrize("model_name", MODEL_NAMES)
def test_transformed_matrix_is_s_transpose_a_s_in_place_of_a(small_problem, model_name):
    """K built from the contact rows of A alone equals the full product S^T A S, and is a view
    of its NGSolve matrix (no scipy copy)."""
    qp = contact_qp(load_case("transition-r32"), small_problem, MODELS[model_name])
    full = (qp.S.T @ small_problem.A @ qp.S).toarray()
    np.testing.assert_allclose(qp.K.toarray(), full, atol=1e-13 * np.abs(full).max())
    assert np.shares_memory(qp.K.data, qp.K_ngs.CSR()[0].NumPy())
    assert np.shares_memory(small_problem.A.data, small_problem.A_ngs.CSR()[0].NumPy())


def test_last_model_takes_the_stiffness_matrix_memory(small_problem):
    """With take_stiffness the level keeps one matrix: K is made in A's own memory, and the
    problem refuses to hand out A afterwards instead of handing out K under A's name."""
    case = load_case("transition-r32")
    problem = discretise(case, small_problem.mesh)
    A_values = problem.A_ngs.CSR()[0].NumPy()
    copied = contact_qp(case, problem, MODELS["mean"])
    taken = contact_qp(case, problem, MODELS["mean"], take_stiffness=True)
    assert np.shares_memory(taken.K.data, A_values)
    np.testing.assert_array_equal(taken.K.toarray(), copied.K.toarray())
    with pytest.raises(RuntimeError, match="taken by its last contact QP"):
        problem.A


def test_the_03_name_of_the_edge_mean_rule_is_gone_as_its_deprecation_said():
    from harness.fem.cones import ContactModel
    with pytest.raises(ValueError, match="edge functional must be one of midpoint, edge-mean or None, got 'mean'"):
        ContactModel("mean")
