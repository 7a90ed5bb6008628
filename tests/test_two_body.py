"""Two bodies on non-matching meshes (issue 34): the mortar rows, the matching-mesh limit, the
exact solves, the case contract."""
import dataclasses

import numpy as np
import pandas as pd
import pytest
from conftest import trace_values

from harness.fem.assembly import discretise
from harness.fem.mortar import TraceElements, intersection, mortar_coupling
from harness.fem.nested import mortar_prediction as predicted_active
from harness.fem.two_body import TwoBodyProblem
from harness.mesh.levels import coarse_mesh
from harness.methods import METHODS, methods_for, methods_named
from harness.methods.method import MortarCarry
from harness.methods.mortar import Mortar
from harness.problem.bodies import MirrorBody, lower_body
from harness.problem.case import CaseError, case_from_module, registered_cases
from harness.problem.geometry import contact_strip
from harness.study.chain import run_chain

TWO_BODY = [name for name, case in registered_cases().items() if case.bodies == 2]
# the exact ones (the reference cases, cattaneo-two-body-*: tests/test_two_body_reference.py)
EXACT_TWO_BODY = [name for name in TWO_BODY if registered_cases()[name].exact]
# the methods between two bodies: the mortar methods (multipliers) and the contact laws on the jumps
TWO_BODY_METHODS = [name for name, method in METHODS.items() if 2 in method.bodies]
MORTAR = [name for name, method in METHODS.items() if isinstance(method, Mortar)]


@pytest.fixture(scope="module")
def case():
    return registered_cases()["two-body-transition-r32"]


@pytest.fixture(scope="module")
def refined_pair(case):
    """Both bodies' coarse meshes refined once (non-matching: element sizes 2:3 on Gamma_C)."""
    meshes = [coarse_mesh(body) for body in (case, lower_body(case))]
    for mesh in meshes:
        mesh.Refine()
    return case, meshes


@pytest.mark.parametrize("order", [1, 2])
def test_dual_rows_are_the_slave_node_values_of_the_jump_for_polynomials(refined_pair, order):
    """Biorthogonality: for c_1 + c_2 in the slave's trace space, row i / D_i is its value at the
    slave node i, whatever the master's (non-matching) mesh: the intersection integrals are exact."""
    case, meshes = refined_pair
    upper, lower = (discretise(body, mesh, order) for body, mesh in zip((case, lower_body(case)), meshes))
    p = lambda x: 0.3 + x - 0.7 * x ** order          # noqa: E731 -- degree k on each body
    q = lambda x: -1.1 + 0.5 * x + 0.2 * x ** order   # noqa: E731
    coupling = mortar_coupling(upper, lower, multipliers="dual")
    z = np.concatenate([trace_values(upper, p), trace_values(lower, q)])
    nodes = upper.trace.vertex_points[:, 0]
    if order == 2:
        nodes = np.concatenate([nodes, upper.trace.midpoints[:, 0]])
    assert not np.allclose(TraceElements.of(upper).left[:6], TraceElements.of(lower).left[:6])
    np.testing.assert_allclose((coupling.B @ z) / coupling.D, p(nodes) + q(nodes), rtol=0, atol=1e-13)


@pytest.mark.parametrize("order", [1, 2])
def test_standard_rows_integrate_the_slave_basis_against_the_master_trace_exactly(refined_pair, order):
    """Standard multipliers: sum over the rows of int phi_i (c_1 + c_2) = int (c_1 + c_2) (the
    Lagrange basis is a partition of unity): for polynomials, the exact integral over Gamma_C."""
    case, meshes = refined_pair
    upper, lower = (discretise(body, mesh, order) for body, mesh in zip((case, lower_body(case)), meshes))
    coupling = mortar_coupling(upper, lower, multipliers="standard")
    z = np.concatenate([np.zeros(upper.ndof), trace_values(lower, lambda x: x ** order)])
    assert (coupling.B @ z).sum() == pytest.approx((1.0 - (-1.0) ** (order + 1)) / (order + 1), abs=1e-14)


def test_intersection_segments_cover_gamma_c_once(refined_pair):
    case, meshes = refined_pair
    upper, lower = (discretise(body, mesh, 1) for body, mesh in zip((case, lower_body(case)), meshes))
    segments = intersection(TraceElements.of(upper), TraceElements.of(lower))
    assert segments[0, 0] == -1.0 and segments[-1, 1] == 1.0
    np.testing.assert_array_equal(segments[1:, 0], segments[:-1, 1])
    assert (np.diff(segments, axis=1) > 0).all()
    assert len(segments) > max(len(upper.trace.edges), len(lower.trace.edges))


@pytest.fixture(scope="module", params=["transition-r32", "elastic-transition-r32"])
def matching(request):
    """A one-body case with a second body meshed like the first: the matching-mesh limit."""
    one = registered_cases()[request.param]
    two = dataclasses.replace(one, name="matching", second_body=MirrorBody(one.geometry, one.maxh))
    frames = {name: pd.DataFrame(run_chain(case, methods_named(methods), 3).rows)
              for name, case, methods in (("two", two, ["mortar-mean", "mortar-nodal", "mortar-p1"]),
                                          ("one", one, ["mean", "nodal", "p1"]))}
    return frames


@pytest.mark.parametrize("method", ["mean", "nodal", "p1"])
def test_matching_meshes_reproduce_the_one_body_errors(matching, method):
    """On matching meshes the dual mortar condition is the one-body cone on the jump, and by the
    mirror symmetry each body's solution is the one-body one (scalar and elastic): every error is
    sqrt(2) times the one-body error (two equal bodies), to 1e-8 relative."""
    two = matching["two"][matching["two"].method == f"mortar-{method}"].reset_index()
    one = matching["one"][matching["one"].method == method].reset_index()
    assert len(two) == len(one) >= 3
    for column in ("err_h1", "err_l2", "err_best_h1", "err_trace_l2"):
        np.testing.assert_allclose(two[column], np.sqrt(2.0) * one[column], rtol=1e-8)
    np.testing.assert_allclose(two.err_h1_over_best, one.err_h1_over_best, rtol=1e-8)


@pytest.mark.parametrize("case_name, method", [(c, m) for c in EXACT_TWO_BODY for m in TWO_BODY_METHODS
                                               if METHODS[m].supports(registered_cases()[c])])
def test_two_body_solves_are_exact_on_non_matching_meshes(case_name, method):
    """Every method between two bodies: KKT (mortar) or Newton (contact law) residual <= 1e-10
    on every level, some contact active."""
    case = registered_cases()[case_name]
    rows = pd.DataFrame(run_chain(case, methods_named([method]), 2).rows)
    assert (rows.status == "converged").all()
    assert rows.kkt_residual.max() <= 1e-10
    assert rows.active_constraints.min() > 0
    # a mortar's rows are its constraints (a contact law has Gauss points, no rows: 0, as on one body)
    assert rows.n_contact_constraints.min() > 0 or method not in MORTAR
    # R_h u is the best approximation in the energy norm (in elasticity not in the H^1 norm)
    assert (rows.err_energy >= rows.err_best_energy * (1.0 - 1e-9)).all()


@pytest.mark.parametrize("case_name", TWO_BODY)
def test_every_two_body_case_satisfies_the_signorini_conditions_in_both_bodies(case_name):
    from harness.problem.validate import validate_case
    validate_case(registered_cases()[case_name])


def test_a_lower_body_whose_gamma_c_differs_is_refused_in_one_line():
    from harness.problem.geometry import polygon
    from harness.problem.validate import validate_case
    two = registered_cases()["two-body-transition-r32"]
    shorter = polygon([(-1, 0), (0, 0), (0.8, 0), (1, 0), (1, 1), (-1, 1)],
                      ["contact", "contact", "neumann", "neumann", "dirichlet", "neumann"])
    with pytest.raises(CaseError, match="Gamma_C differ"):
        validate_case(dataclasses.replace(two, second_body=MirrorBody(shorter, 0.3)))


def test_one_body_methods_and_mortar_methods_keep_to_their_cases(case):
    assert {m.name for m in methods_for(case, METHODS.values())} == set(TWO_BODY_METHODS) >= {"mortar-nodal", "mortar-standard",
                                                                                              "mortar-nitsche"}
    assert not [m for m in methods_for(registered_cases()["transition-r32"], METHODS.values()) if m.name in TWO_BODY_METHODS]


class _Module:
    def __init__(self, **fields):
        self.__dict__.update(fields)


def _two_body_module(**changes):
    from ngsolve import x
    fields = dict(name="t", description="d", geometry=contact_strip(), maxh=0.5, u=x, nu=3.0, expected_rate=2.0,
                  theorem="4.1", second_body=MirrorBody(contact_strip(), 0.4))
    fields.update(changes)
    return _Module(**fields)


def test_a_two_body_case_declares_a_mirror_body():
    assert case_from_module(_two_body_module(), "t").bodies == 2
    with pytest.raises(CaseError, match="second_body must be"):
        case_from_module(_two_body_module(second_body=(contact_strip(), 0.4)), "t")


def test_a_two_body_case_without_u_is_a_reference_case():
    """Its data are the upper body's (tests/test_two_body_reference.py runs one)."""
    module = _two_body_module(f=0, dirichlet=0, neumann=0)
    del module.u
    case = case_from_module(module, "t")
    assert case.bodies == 2 and not case.exact and case.reference_levels == 2


@pytest.mark.parametrize("maxh", [0, -1.0, float("nan"), "0.2", True])
def test_a_mirror_body_refuses_a_bad_mesh_size(maxh):
    with pytest.raises(ValueError, match="maxh must be a finite number > 0"):
        MirrorBody(contact_strip(), maxh)


@pytest.mark.parametrize("method", [name for name in MORTAR if METHODS[name].multipliers == "dual"])
def test_the_bound_form_of_the_dual_condition_solves_the_same_qp_as_its_rows(refined_pair, method):
    """Cross-check of two solvers: the dual rows as bounds after the local change of variables
    (active set method on sparse Cholesky) and as general constraints (active set on the saddle
    system, SuperLU) give the same u_h on non-matching meshes."""
    case, meshes = refined_pair
    chosen = METHODS[method]
    problem = TwoBodyProblem(*(discretise(body, mesh, chosen.order) for body, mesh in zip((case, lower_body(case)), meshes)))
    bounds = chosen.solve(case, problem, None, None)
    rows = chosen.solve(case, problem, None, None, general=True)
    assert bounds.fields["kkt_residual"] <= 1e-10 and rows.fields["kkt_residual"] <= 1e-10
    assert bounds.fields["active_constraints"] == rows.fields["active_constraints"] > 0
    np.testing.assert_allclose(bounds.u, rows.u, rtol=0, atol=1e-10 * np.abs(rows.u).max())


@pytest.mark.parametrize("case_name", ["two-body-transition-r32", "two-body-elastic-transition"])
def test_vtk_files_hold_both_bodies_and_the_interface(tmp_path, case_name):
    import meshio

    from harness.report.vtk import VtkWriter, level_files
    case = registered_cases()[case_name]
    run_chain(case, methods_named(["mortar-nodal"]), 2, on_level=VtkWriter(tmp_path))
    omega, gamma = (meshio.read(path) for path in level_files(tmp_path, case.name, "mortar-nodal", 1))
    assert omega.points[:, 1].min() == -1.0 and omega.points[:, 1].max() == 1.0
    assert set(np.concatenate(omega.cell_data["body"])) == {0, 1}
    # the lower body's values are the real u_2 (mirrored back): the error against u is small on both
    name = "displacement" if case.physics.elastic else "u_h"
    assert np.abs(omega.point_data["error"]).max() < 0.05 * np.abs(omega.point_data[name]).max()
    assert gamma.cells[0].type == "line" and np.abs(gamma.points[:, 1]).max() == 0.0
    assert gamma.point_data["gap_h"].min() > -1e-2 and np.concatenate(gamma.cell_data["pressure"]).max() > 0


# the rates of issue 34's goals: P2 mortar >= 1.4 on the transition at >= 5e5 dofs (`make test-scale`), P1 mortar >= 0.9,
# the junction within 0.1 of h^{1/2}, the elastic transition h^{3/2} (a fit over the finest three levels)
RATE_GOALS = [("two-body-transition-r32", 6, {"mortar-nodal": (1.4, None), "mortar-mean": (1.4, None), "mortar-standard": (1.4, None),
                                               "mortar-p1": (0.9, None)}),
              ("two-body-junction", 5, {"mortar-nodal": (0.4, 0.6), "mortar-mean": (0.4, 0.6), "mortar-p1": (0.4, 0.6)}),
              ("two-body-elastic-transition", 6, {"mortar-nodal": (1.4, None), "mortar-mean": (1.4, None), "mortar-p1": (0.9, None)})]


@pytest.mark.slow
@pytest.mark.parametrize("case_name, levels, goals", [pytest.param(*goal, marks=pytest.mark.scale) if goal[0] == "two-body-transition-r32"
                                                      else goal for goal in RATE_GOALS], ids=[goal[0] for goal in RATE_GOALS])
def test_mortar_methods_meet_their_rates_on_non_matching_meshes(case_name, levels, goals):
    from harness.measure.rates import fit_rate
    case = registered_cases()[case_name]
    rows = pd.DataFrame(run_chain(case, methods_named(list(goals)), levels).rows)
    assert rows.kkt_residual.max() <= 1e-10
    for method, (low, high) in goals.items():
        mine = rows[rows.method == method]
        rate, _ = fit_rate(mine.h.to_numpy(), mine.err_h1.to_numpy())
        assert rate >= low and (high is None or rate <= high), f"{method}: {rate:.3f}"
    if case_name == "two-body-transition-r32":
        assert rows[rows.order == 2].ndof.max() >= 5e5


def test_a_mortar_edge_row_is_predicted_from_its_parent_edge_and_a_vertex_row_from_the_row_at_its_point():
    """Nested iteration, as the one-body cones predict (``fem.cones.ContactQP.predicted_active``):
    a coarse level with vertex rows at 0 and 1 (inactive) and an active edge row at 0.5 gives
    the fine vertex at 0.5 and both halves of the edge the edge's status, the vertices at 0 and 1
    theirs. (The nearest row of either kind gives the half-edges' midpoints, 0.25 and 0.75, as
    near to a vertex row as to the edge row.)"""
    coarse = MortarCarry(np.zeros(2), points=np.array([0.0, 1.0, 0.5]), active=np.array([False, False, True]), vertex_rows=2)
    fine = np.array([0.0, 0.5, 1.0, 0.25, 0.75])
    assert predicted_active(coarse, fine, 3).tolist() == [False, True, False, True, True]
    # P1 (vertex rows only): a new vertex is active when the coarse edge it halves has both ends
    # active, as the one-body P1 cones predict
    p1 = MortarCarry(np.zeros(2), points=np.array([0.0, 0.5, 1.0]), active=np.array([False, True, True]), vertex_rows=3)
    assert predicted_active(p1, np.array([0.0, 0.25, 0.5, 0.75, 1.0]), 5).tolist() == [False, False, True, True, True]
    # beyond the coarse ends: the end's status
    assert predicted_active(p1, np.array([-0.1, 1.1]), 2).tolist() == [False, True]
