"""Graded and adaptive meshes on the Tresca cases: the residual estimator's friction terms
(``harness.measure.friction_terms``) vanish at the exact solution and see violations of the
friction law; the estimator converges at the error's rate under uniform refinement with an
effectivity in a measured band; the adaptive P2 chain reaches the optimal N-rate.

Measured (tresca-r32 / tresca-r72, uniform levels 0-4; adaptive: the budget of 6 uniform levels):

  method  mesh      eta rate in h   effectivity eta / ||u - u_h||_a     H1 N-rate (last 3)
  nodal   uniform   1.50 / 2.00     7.20-7.21 / 7.70-7.81
  nodal   adaptive                  6.7-7.2 (r32)                        0.99
  mean    uniform   1.4 / 1.8       5.2-6.5 / 7.0-9.6 (rising)
  mean    adaptive                  5.2-8.1 (r32)                        0.99
  p1      uniform   1.00 / 1.00     3.3-3.5 / 4.5-4.7
  p1      adaptive                  2.8-3.3 (r32)                        0.50

elastic-tresca-r32: nodal uniform eta rate 1.50, effectivity 6.28-6.32, adaptive 5.5-6.3 and
N-rate 1.00; p1 uniform 1.00, 3.42-3.62, adaptive 2.3-3.4 and 0.50.

The mean method's effectivity rises: its u_h has zero edge means on the stick zone but is not
zero between the nodes, so the friction law's complementarity, linear in |u_h| there, decays
slower than the squared error (measured h^1.3 against h^1.5 on tresca-r32). The band below
holds every measured value with a margin; the nodal and P1 ones are also asymptotically
constant (ratio max/min over the last levels near 1), what an estimator that is both reliable
and efficient up to constants shows.
"""
import numpy as np
import pytest
from conftest import problem_at

import harness
from harness.measure.estimator import ResidualEstimator
from harness.measure.friction_terms import elastic_density, scalar_density
from harness.measure.rates import fit_ndof_rate
from harness.mesh.points import evaluate
from harness.problem.case import load_case

slow = pytest.mark.slow
TRESCA_CASES = ["tresca-r32", "tresca-r72"]
# effectivity eta / ||u - u_h||_a: the measured ranges in the module docstring, widened by ~30%
EFFECTIVITY_BAND = {"nodal": (4.0, 10.0), "mean": (4.0, 12.0), "p1": (1.8, 6.0)}


def exact_on_contact_points(case_name: str, level: int = 1, order: int = 2):
    """The estimator of ``case_name``'s problem (P_order, level) and the exact u, lambda and s at
    its contact points."""
    case, problem = load_case(case_name), problem_at(case_name, level, order)
    estimator = ResidualEstimator(case, problem)
    q, mesh = estimator.q, problem.mesh
    u = case.physics.contact_value(case, mesh, q.points, q.normals)
    lam = case.physics.pressure(case, mesh, q.points, q.normals)
    return estimator, u, lam, evaluate(case.friction.threshold_function, mesh, q.points)


@pytest.mark.parametrize("case_name", TRESCA_CASES)
def test_each_friction_term_vanishes_at_the_exact_solution(case_name):
    """At the estimator's own contact points, with u_h = u and lambda_h = lambda(u), the flux,
    excess and complementarity densities are zero (to rounding), on both the stick and the slip
    part of Gamma_C (both are sampled)."""
    estimator, u, lam, s = exact_on_contact_points(case_name)
    assert (np.abs(u) > 1e-3).any() and (np.abs(u) < 1e-14).any()        # slip and stick points
    for term, density in scalar_density(lam, lam, u, s, estimator.q.h).items():
        assert np.abs(density).max() <= 1e-13, term


def test_each_elastic_friction_term_vanishes_at_the_exact_solution():
    """elastic-tresca-r32 at the estimator's contact points: u . n = 0, the exact traction as
    both the discrete and the pointwise friction force, the exact slip: every term zero."""
    case, problem = load_case("elastic-tresca-r32"), problem_at("elastic-tresca-r32", 1, 2)
    estimator = ResidualEstimator(case, problem)
    q, mesh, physics = estimator.q, problem.mesh, case.physics
    p = physics.pressure(case, mesh, q.points, q.normals)
    traction_t = physics.tangential_traction(case, mesh, q.points, q.normals)
    u = evaluate(case.u, mesh, q.points).reshape(q.normals.shape)
    u_t = u - (u * q.normals).sum(axis=-1)[:, None] * q.normals
    normal = physics.contact_value(case, mesh, q.points, q.normals) - estimator.friction.obstacle
    assert (np.linalg.norm(u_t, axis=-1) > 1e-3).any() and (np.linalg.norm(u_t, axis=-1) < 1e-14).any()
    s = evaluate(case.friction.threshold_function, mesh, q.points)
    for term, density in elastic_density(p, p, normal, traction_t, traction_t, u_t, s, q.h).items():
        assert np.abs(density).max() <= 1e-12, term


@pytest.mark.parametrize("case_name", TRESCA_CASES)
@pytest.mark.parametrize("violation, term", [("flip", "complementarity"), ("exceed", "excess"), ("shift", "flux")])
def test_each_friction_term_sees_its_violation(case_name, violation, term):
    """Break one condition of the exact pair and that term turns positive: the force pointing
    along the slip (complementarity), a force beyond the threshold (excess), a discrete force
    other than the flux of u_h (flux)."""
    estimator, u, lam, s = exact_on_contact_points(case_name)
    lam_h, force = lam.copy(), lam.copy()
    if violation == "flip":
        lam_h = np.where(np.abs(u) > 0, -lam, lam)
        force = lam_h
    elif violation == "exceed":
        lam_h = force = 1.5 * s * np.sign(lam)
    else:
        lam_h = lam + 0.1
    density = scalar_density(lam_h, force, u, s, estimator.q.h)[term]
    assert estimator.q.weights @ density > 1e-6


@pytest.mark.parametrize("dim", [2, 3])
def test_the_elastic_friction_terms_vanish_on_stick_and_slip_and_see_violations(dim, rng):
    """Elasticity, bilateral contact: sigma_t in the disc of radius s on stick points (u_t = 0),
    sigma_t = -s u_t / |u_t| on slip points, u . n = 0: every term zero; a tangential force
    along the slip, beyond s, other than the traction of u_h, or a normal gap each turn their
    term positive."""
    m = 50
    s, h = np.full(2 * m, 0.7), np.full(2 * m, 0.1)
    u_t = np.zeros((2 * m, dim))
    u_t[m:, :-1] = rng.standard_normal((m, dim - 1))              # slip: tangential (last axis = n)
    traction = np.zeros((2 * m, dim))
    traction[:m, :-1] = rng.uniform(-0.4, 0.4, (m, dim - 1)) / np.sqrt(dim - 1)
    traction[m:] = -s[m:, None] * u_t[m:] / np.linalg.norm(u_t[m:], axis=-1)[:, None]
    p = rng.standard_normal(2 * m)
    exact = elastic_density(p, p, np.zeros(2 * m), traction, traction, u_t, s, h)
    for term, density in exact.items():
        assert np.abs(density).max() <= 1e-14, term
    assert elastic_density(p, p, np.zeros(2 * m), -traction, -traction, u_t, s, h)["complementarity"].sum() > 1e-3
    assert elastic_density(p, p, np.zeros(2 * m), 2 * traction, 2 * traction, u_t, s, h)["excess"].sum() > 1e-3
    assert elastic_density(p, p, np.zeros(2 * m), 0.5 * traction, traction, u_t, s, h)["flux"].sum() > 1e-6
    assert elastic_density(p, p, np.full(2 * m, 1e-3), traction, traction, u_t, s, h)["normal"].sum() > 1e-6


def study(case_name: str, methods: list, meshes: str, levels: int):
    return harness.run(case_name, methods=methods, meshes=meshes, levels=levels, show_progress=False)


# tresca-r32 in `make test`, the others in `make test-full`
@pytest.mark.parametrize("case_name, method, rate", [
    ("tresca-r32", "nodal", 1.5), ("tresca-r32", "p1", 1.0),
    *(pytest.param(*row, marks=slow) for row in [("tresca-r72", "nodal", 2.0), ("tresca-r72", "p1", 1.0),
                                                  ("elastic-tresca-r32", "nodal", 1.5), ("elastic-tresca-r32", "p1", 1.0)])])
def test_the_estimator_converges_at_the_error_rate_under_uniform_refinement(case_name, method, rate):
    """eta's fitted rate in h over levels 2-4 is the error's (P2 h^1.5 on the r^{3/2} point,
    h^2 on the H^{7/2-eps} one; P1 h): the friction terms do not stagnate (the Signorini tension
    term h ||(lambda_h)_-||^2 did, at h^{1/2}, before they replaced it); its effectivity is in the
    measured band and constant over the last levels to 5%."""
    rows = study(case_name, [method], "uniform", 5).sort_values("level")
    assert (rows.kkt_residual <= 1e-10).all() and (rows.status == "converged").all()
    tail = rows.tail(3)
    assert abs(np.polyfit(np.log(tail.h), np.log(tail.estimator), 1)[0] - rate) <= 0.05
    low, high = EFFECTIVITY_BAND[method]
    assert rows.effectivity.between(low, high).all()
    assert tail.effectivity.max() / tail.effectivity.min() <= 1.05


@pytest.mark.parametrize("case_name", [TRESCA_CASES[0], *(pytest.param(c, marks=slow) for c in TRESCA_CASES[1:])])
def test_graded_meshes_run_the_friction_methods_at_the_optimal_n_rate(case_name):
    """Graded meshes (toward the stick-slip point) with nodal, mean and p1: every row converged,
    H1 N-rate over the last 3 levels near k/2 (0.9 for P2, 0.45 for P1)."""
    rows = study(case_name, ["nodal", "mean", "p1"], "graded", 5)
    assert (rows.kkt_residual <= 1e-10).all() and (rows.status == "converged").all()
    for method, floor in (("nodal", 0.9), ("mean", 0.9), ("p1", 0.45)):
        g = rows[rows.method == method].sort_values("ndof")
        assert fit_ndof_rate(g.ndof, g.err_h1, 3) >= floor, method


@slow
@pytest.mark.parametrize("case_name, method, floor", [
    ("tresca-r32", "nodal", 0.9), ("tresca-r32", "mean", 0.9), ("tresca-r32", "p1", 0.45),
    ("elastic-tresca-r32", "nodal", 0.9)])
def test_adaptive_p2_reaches_the_optimal_n_rate_on_the_stick_slip_case(case_name, method, floor):
    """The issue's target: adaptive refinement driven by the friction estimator on tresca-r32
    (and the elastic plane-strain case),
    H1 error against N fitted over the last 5 levels >= 0.9 for P2 (k/2 = 1; measured 0.98-1.00)
    and ~ 0.5 for P1 (measured 0.50); every row converged (KKT <= 1e-10); the effectivity stays
    in the measured band."""
    rows = study(case_name, [method], "adaptive", 6).sort_values("ndof")
    assert (rows.kkt_residual <= 1e-10).all() and (rows.status == "converged").all()
    assert len(rows) >= 12
    assert fit_ndof_rate(rows.ndof, rows.err_h1, 5) >= floor
    low, high = EFFECTIVITY_BAND[method]
    assert rows.effectivity.between(low, high).all()
