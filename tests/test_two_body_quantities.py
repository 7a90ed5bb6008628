"""Two-body quantities of interest from the pointwise jumps between the bodies
(``harness.measure.two_body_quantities``; issue 76): the lower body's trace read at the upper
body's Gauss points, the jumps' signs, the matching-mesh limit (the one-body columns), the
contact measure's convergence on non-matching meshes, and the slip and stick zones of a
sheared two-body Coulomb run through ``harness.run``."""
from __future__ import annotations

import dataclasses

import ngsolve as ngs
import numpy as np
import pytest
from conftest import pair_traces, trace_values

import harness
from harness.fem.assembly import discretise
from harness.fem.mortar import mortar_coupling
from harness.fem.two_body import TwoBodyProblem, dual_bound_qp
from harness.measure.errors import DiscretePressure
from harness.measure.quantities import contact_zone, friction_threshold, slip_zone
from harness.measure.two_body_quantities import MasterTrace, tangential_jump, two_body_interface
from harness.mesh.levels import coarse_mesh
from harness.methods import get_method
from harness.problem.bodies import MirrorBody, lower_body
from harness.problem.case import registered_cases
from harness.problem.friction import Coulomb, LoadHistory, LoadStep

MU = 0.3
XI = 1.0
# the columns a matching mirror pair shares with its one-body case
SHARED = ("qoi_force", "qoi_contact_measure", "qoi_peak_pressure", "qoi_slip_measure", "qoi_stick_slip_point")


def _pair(case, order: int) -> TwoBodyProblem:
    """``case``'s two bodies' coarse meshes refined once (non-matching: 2:3 on Gamma_C)."""
    bodies = (case, lower_body(case))
    meshes = [coarse_mesh(body) for body in bodies]
    for mesh in meshes:
        mesh.Refine()
    return TwoBodyProblem(*(discretise(body, mesh, order) for body, mesh in zip(bodies, meshes)))


@pytest.fixture(scope="module", params=[1, 2], ids=["P1", "P2"])
def elastic_pair(request):
    """two-body-elastic-transition under Coulomb, with the gap x^2/2 of each body (its obstacle
    -x^2/2: the rows impose c_1 + c_2 >= -x^2)."""
    case = dataclasses.replace(registered_cases()["two-body-elastic-transition"], friction=Coulomb(MU), gap=ngs.x ** 2 / 2)
    return case, _pair(case, request.param)


def test_the_lower_trace_at_points_is_ngsolves_basis_there(elastic_pair):
    """``MasterTrace`` (the mortar's trace elements and hierarchical basis) at the lower body's
    own Gauss points gives what its pressure rule's NGSolve rows give, for a random u_h: the
    contact variable and (one block earlier) the tangential one, to 1e-13."""
    _, problem = elastic_pair
    lower = problem.lower
    q = DiscretePressure.of(lower).quadrature
    u = np.random.default_rng(7).standard_normal(lower.ndof)
    master = MasterTrace.at(lower, q.points[:, 0])
    np.testing.assert_allclose(master.values(u), q.T @ u, rtol=0, atol=1e-13 * np.abs(u).max())
    own = DiscretePressure.of(lower).T
    np.testing.assert_allclose(master.values(u, tangential=True), own @ u[lower.tangential_dofs[0]], rtol=0,
                               atol=1e-13 * np.abs(u).max())
    np.testing.assert_allclose(master.h, q.h, rtol=1e-14)


def test_the_opening_and_the_slip_are_the_jumps_of_polynomialpair_traces(elastic_pair):
    """Traces of degree k on both non-matching meshes: at the upper body's Gauss points the
    opening less the gap is c_1 + c_2 - 2 alpha (alpha = -x^2/2), the slip t_1 - t_2 (a rigid translation of both
    bodies along x slips nothing), less the previous step's; eps = h_1/E + h_2/E."""
    case, problem = elastic_pair
    k = problem.order
    c = [lambda x: 0.3 + x - 0.7 * x ** k, lambda x: -1.1 + 0.5 * x + 0.2 * x ** k]
    t = [lambda x: 0.2 - 0.4 * x + 0.9 * x ** k, lambda x: 0.7 + 0.3 * x - 0.5 * x ** k]
    u = pair_traces(problem, c, t)
    bodies = (case, lower_body(case))
    interface = two_body_interface(bodies, problem, u)
    x = interface.q.points[:, 0]
    np.testing.assert_allclose(interface.gap, c[0](x) + c[1](x) + x ** 2, rtol=0, atol=1e-13)
    np.testing.assert_allclose(interface.slip[:, 0], t[0](x) - t[1](x), rtol=0, atol=1e-13)
    translated = pair_traces(problem, c, [lambda x: 0.4 + 0 * x] * 2)
    assert np.abs(tangential_jump(problem, MasterTrace.at(problem.lower, x), translated)).max() <= 1e-14
    stepped = two_body_interface(bodies, problem, u, previous=pair_traces(problem, c, [lambda x: 0.1 + 0 * x, lambda x: 0 * x]))
    np.testing.assert_allclose(stepped.slip[:, 0], t[0](x) - t[1](x) - 0.1, rtol=0, atol=1e-13)
    h_2 = MasterTrace.at(problem.lower, x).h
    assert not np.allclose(h_2, interface.q.h)          # non-matching
    np.testing.assert_allclose(interface.stiffness, case.physics.modulus / (interface.q.h + h_2), rtol=1e-14)


def test_the_scalar_jump_is_the_sum_of_the_two_contact_variables():
    """Scalar model: the lower body's variable is -u_2 (``problem.bodies``), so the jump the
    friction acts on is [u] = u_1 - u_2 = c_1 + c_2, the opening itself."""
    case = registered_cases()["two-body-tresca-r32"]
    problem = _pair(case, 2)
    f, g = (lambda x: 0.3 + x - 0.7 * x ** 2), (lambda x: -1.1 + 0.5 * x + 0.2 * x ** 2)
    u = np.concatenate([trace_values(problem.upper, f), trace_values(problem.lower, g)])
    interface = two_body_interface((case, lower_body(case)), problem, u)
    x = interface.q.points[:, 0]
    np.testing.assert_allclose(interface.slip[:, 0], f(x) + g(x), rtol=0, atol=1e-13)


# one-body case -> its matching mirror pair (the lower body meshed as the upper): the registered
# control for transition-r32, the others built alike
MATCHING = {"transition-r32": "two-body-transition-r32-matching", "elastic-transition-r32": None,
            "tresca-r32": "two-body-tresca-r32"}
# each dual mortar method and the one-body method it is on matching meshes (tests/test_two_body.py)
COUNTERPART = {"mortar-mean": "mean", "mortar-nodal": "nodal", "mortar-p1": "p1"}


def _matching(one_body: str):
    cases = registered_cases()
    two = cases[MATCHING[one_body]] if MATCHING[one_body] else dataclasses.replace(cases[one_body], name="matching")
    if one_body == "tresca-r32":        # two-body-tresca-r32 with its lower body meshed as the upper
        assert two.maxh == cases[one_body].maxh
    return dataclasses.replace(two, second_body=MirrorBody(two.geometry, two.maxh))


@pytest.mark.slow
@pytest.mark.parametrize("one_body", list(MATCHING))
def test_a_matching_mirror_pair_measures_the_one_body_quantities(one_body):
    """On matching meshes each body's solution is the one-body one (tests/test_two_body.py), the
    opening twice the one body's gap and the jump (scalar) twice its u, and eps = 2h/E: the
    contact measure, the force, the peak pressure, the slip measure and the stick-slip point
    are the one-body case's at every level (to 1e-8 relative, the solves' agreement), the energy twice it. (With eps = h/E on the opening instead, the elastic pair's
    contact measure is 1.0253, 1, 1 on levels 0-2 against `nodal`'s 1.0253, 1.0127, 1.0063, and
    `mortar-mean`'s 1.0253, 1.0127, 1.0063 against `mean`'s 1.0809, 1.0405, 1.0202; the
    scalar Tresca pair's `mortar-p1` slip measure 1 against `p1`'s 0.9873 on level 0, measured: the
    series compliance is what makes the mirror pair's zones the one body's.)"""
    two = harness.run(_matching(one_body), list(COUNTERPART), levels=2, show_progress=False)
    one = harness.run(registered_cases()[one_body], list(COUNTERPART.values()), levels=2, show_progress=False)
    for mortar, method in COUNTERPART.items():
        pair = two[two.method == mortar].reset_index(drop=True)
        single = one[one.method == method].reset_index(drop=True)
        assert len(pair) == len(single) >= 2
        for column in SHARED:
            np.testing.assert_allclose(pair[column], single[column], rtol=1e-8, atol=1e-14, err_msg=f"{mortar} {column}")
        np.testing.assert_allclose(pair.qoi_energy, 2 * single.qoi_energy, rtol=1e-8)
        assert pair.qoi_contact_measure.notna().all() != (one_body == "tresca-r32")    # the scalar Tresca model's: NaN
        assert pair.qoi_slip_measure.notna().all() == (one_body == "tresca-r32")


@pytest.mark.parametrize("case_name", ["two-body-transition-r32", "two-body-elastic-transition"])
def test_the_contact_measure_of_a_non_matching_pair_converges_to_the_exact_one(case_name):
    """Non-matching meshes (2:3), every mortar method, levels 0-1 (`mortar-p1` 0-2): the exact contact measure is
    the upper body's one-body value, 1 (the binding half of Gamma_C), and the measured one is
    within 0.12 h of it (h the coarser body's), its error halving level by level (O(h): the
    transition point is found to within an edge; measured error / h = 0.036 `mortar-nodal`,
    0.114 `mortar-mean`, 0 or 0.036 `mortar-p1`) or zero."""
    rows = harness.run(registered_cases()[case_name], "all", levels=2, show_progress=False)
    assert (rows.qoi_contact_measure_exact == 1.0).all() and rows.qoi_contact_measure.notna().all()
    error = (rows.qoi_contact_measure - 1.0).abs()
    assert (error <= 0.12 * rows.h).all(), rows[["method", "level", "h", "qoi_contact_measure"]]
    for method, chain in rows.assign(error=error).groupby("method"):
        e = chain.sort_values("level").error.to_numpy()
        assert ((e[1:] <= 0.51 * e[:-1]) | (e[1:] <= 1e-12)).all(), (method, e)


def _sheared(case, matching: bool):
    """tests/test_two_body_coulomb.py's sheared case: Coulomb (mu_F = 0.3), step 1 the case's
    data on both bodies, step 2 the upper body's Dirichlet values moved by XI along x, the lower
    body holding the mirror data; ``matching``: the lower body meshed as the upper."""
    body = case.second_body
    geometry, maxh = (case.geometry, case.maxh) if matching else (body.geometry, body.maxh)
    return dataclasses.replace(case, friction=Coulomb(MU), dirichlet=case.u + ngs.CF((XI, 0.0)),
                               second_body=MirrorBody(geometry, maxh, dirichlet=case.u),
                               history=LoadHistory((LoadStep("normal", dirichlet=case.u), LoadStep("tangential"))),
                               predicted_traction=_uniform_shear)


def _uniform_shear(s, force, tangential):
    """A predicted shear traction: Q spread evenly over Gamma_C = (-1, 1) (a probe of
    ``err_traction_prediction``, no theory)."""
    return np.full(len(s), 0.5 * tangential)


def _slip_on_stick_edges(case, method, level, problem, solve) -> dict:
    """``harness.run``'s on_level hook: the largest pointwise slip |[u_t]| over the last step
    at the Gauss points of the slave edges whose every node sticks by the method's dual
    projection (in contact, z_T at its previous value), against the largest over the contact
    zone, and how many of those points the slip zone's device calls slipping."""
    coupling = mortar_coupling(problem.upper, problem.lower, case.obstacle, "dual", "midpoint")
    qp = dual_bound_qp(problem, coupling, method.contact_weight(problem.order), tangential=True)
    z = qp.to_z(solve.u)
    moved = np.abs(z[qp.T] - qp.to_z(solve.previous)[qp.T])
    stick = (moved <= 1e-12 * np.abs(z).max()) & ((qp.K @ z - qp.b)[qp.C] > 0)
    trace = problem.upper.trace
    nodes = np.searchsorted(trace.vertices, trace.edge_vertices)
    if problem.order == 2:
        nodes = np.column_stack([nodes, len(trace.vertices) + np.arange(len(trace.edges))])
    interface = two_body_interface((case, lower_body(case)), problem, solve.u, solve.previous)
    q, slip = interface.q, np.abs(interface.slip[:, 0])
    on_stick = stick[nodes].all(axis=1)[q.edge]
    contact = contact_zone(interface.pressure, interface.gap, interface.stiffness)
    zone = slip_zone(interface.force, interface.slip, interface.stiffness,
                     friction_threshold(case, problem.upper, q, interface.pressure)) & contact
    P, Q = q.weights @ interface.pressure, q.weights @ -interface.force[:, 0]
    shear_error = np.sqrt(q.weights @ (-interface.force[:, 0] - 0.5 * Q) ** 2 / (q.weights @ np.full(len(q.weights), 0.25 * Q * Q)))
    return {"stick_points": int(on_stick.sum()), "stick_slip": float(slip[on_stick].max(initial=0.0)),
            "largest": float(slip[contact].max()), "called_slipping": int((zone & on_stick).sum()),
            "P": P, "Q": Q, "shear_error": shear_error}


@pytest.mark.slow
@pytest.mark.parametrize("matching", [False, True], ids=["non-matching", "matching"])
@pytest.mark.parametrize("method_name", ["mortar-nodal", "mortar-p1"])
def test_the_slip_and_stick_zones_of_a_sheared_pair_come_from_the_jump(method_name, matching):
    """The sheared exact two-body Coulomb case through ``harness.run``, levels 0-2: every
    quantity finite, stick + slip = the contact measure (to round-off), both zones and Q > 0;
    the exact contact measure the upper body's (1), the exact slip zone NaN (a mirror pair has
    none); P, Q and err_traction_prediction (against a probe prediction) the upper body's. On the slave edges whose nodes all stick (the dual projection pins the slip) the
    pointwise slip is 0 to round-off on matching meshes (measured <= 2.5e-16); on non-matching
    ones it is what the master's trace less its projection leaves, measured relative to the
    largest slip: P2 1.0e-3, 5.7e-4 (levels 1, 2; 3.7e-4 on level 3), P1 2.5e-3, 1.2e-3 (1.1e-3,
    2.1e-4 on levels 3, 4), and the device calls 2 such points slipping on P1's levels 0 and 1,
    none from level 2 on (P2: none)."""
    kept = {}
    rows = harness.run(_sheared(registered_cases()["two-body-elastic-transition"], matching), [get_method(method_name)],
                       levels=3, show_progress=False,
                       on_level=lambda *args: kept.setdefault(args[2], _slip_on_stick_edges(*args)))
    assert (rows.status == "converged").all() and len(rows) >= 3          # P1: a level more
    measured = ["qoi_force", "qoi_contact_measure", "qoi_peak_pressure", "qoi_slip_measure", "qoi_stick_measure",
                "qoi_stick_slip_point", "qoi_tangential_force"]
    assert np.isfinite(rows[measured].to_numpy(float)).all(), rows[measured]
    np.testing.assert_allclose(rows.qoi_stick_measure + rows.qoi_slip_measure, rows.qoi_contact_measure, rtol=0, atol=1e-14)
    assert (rows.qoi_slip_measure > 0).all() and (rows.qoi_stick_measure > 0).all() and (rows.qoi_tangential_force > 0).all()
    assert (rows.qoi_contact_measure_exact == 1.0).all() and rows[["qoi_slip_measure_exact", "qoi_stick_slip_point_exact"]].isna().all().all()
    for level in (1, 2):
        found = kept[level]
        assert found["stick_points"] > 0, (level, found)
        relative = found["stick_slip"] / found["largest"]
        assert relative <= (1e-14 if matching else 3e-3), (level, found)
    assert kept[2]["called_slipping"] == 0 and (not matching or all(k["called_slipping"] == 0 for k in kept.values())), kept
    if not matching:
        assert kept[2]["stick_slip"] < kept[1]["stick_slip"], kept
    # P, Q and the traction's error against the (probe) prediction at them: the upper body's
    for row in rows.itertuples():
        found = kept[row.level]
        np.testing.assert_allclose([row.qoi_force, row.qoi_tangential_force, row.err_traction_prediction],
                                   [found["P"], found["Q"], found["shear_error"]], rtol=1e-12)
