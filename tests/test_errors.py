"""Error measurement: quadrature fine enough for singular solutions; penetration between nodes."""
import numpy as np
import pytest

from conftest import MODEL_NAMES
from harness.case import registered_cases
from harness.discrete import ContactTraceFunction, discretise
from harness.errors import ERROR_QUADRATURE_ORDER, GRADING_DEPTH, error_norms, max_penetration
from harness.mesh import mesh_hierarchy
from harness.models import MODELS
from harness.study import solve_level

QUADRATURE_LEVEL = 4


@pytest.mark.parametrize("case_name", list(registered_cases()))
def test_raising_quadrature_order_changes_finest_error_below_one_percent(case_name):
    case = registered_cases()[case_name]
    *_, (level, mesh) = mesh_hierarchy(case, QUADRATURE_LEVEL + 1)
    problem = discretise(case, mesh)
    _, u, _, _ = solve_level(case, problem, MODELS["nodal"])
    gf = problem.gridfunction(u)
    used = error_norms(case, gf)
    finer = error_norms(case, gf, order=ERROR_QUADRATURE_ORDER + 8, depth=GRADING_DEPTH + 6)
    for key in ("err_h1", "err_h1_semi", "err_l2"):
        assert abs(used[key] - finer[key]) <= 0.01 * finer[key], key


def test_penetration_sees_the_dip_between_nodes(small_problem):
    """A P2 trace with zero vertex values and a positive bubble dips to -c/8 at midpoints."""
    u = np.zeros(small_problem.ndof)
    u[small_problem.edge_dofs[3]] = 2.0
    trace_u = ContactTraceFunction.of(small_problem, u)
    case = registered_cases()["transition-r32"]
    assert max_penetration(case, small_problem.mesh, trace_u) == pytest.approx(2.0 / 8, rel=1e-12)


@pytest.mark.parametrize("model_name", MODEL_NAMES)
def test_discrete_solutions_are_nonconforming_only_between_nodes(small_problem, model_name):
    case = registered_cases()["transition-r32"]
    row, u, trace_u, solution = solve_level(case, small_problem, MODELS[model_name])
    # nodes satisfy the constraints, so any penetration is between them and small
    assert (MODELS[model_name].constraint_values(small_problem, u) >= -1e-12).all()
    assert row["max_penetration"] >= -1e-14
    assert row["max_penetration"] < 0.1 * np.abs(u).max()
