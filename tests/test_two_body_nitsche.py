"""The master-slave Nitsche method between two bodies (``fem.contact_laws.two_body``,
``methods.protocol.TwoBodyLaw``): its rows are the jumps of the two traces, on a matching mirror pair
with theta = 0 it is the one-body Nitsche method with half gamma0 (frictionless and Tresca,
scalar and elastic), and its coupled Coulomb Newton solve agrees with the fixed point over
Tresca problems (the independent cross-check) on non-matching meshes."""
from __future__ import annotations

import dataclasses

import ngsolve as ngs
import numpy as np
import pytest
from conftest import pair_traces

import harness
from harness.fem.assembly import discretise
from harness.fem.contact_laws.friction_laws import law_for
from harness.fem.contact_laws.two_body import interface_rows, two_body_system
from harness.fem.two_body import TwoBodyProblem
from harness.mesh.levels import coarse_mesh
from harness.methods import get_method
from harness.problem.bodies import MirrorBody, lower_body
from harness.problem.case import registered_cases
from harness.problem.friction import Coulomb
from harness.solvers.coulomb_fixed_point import solve_fixed_point
from harness.solvers.multigrid import Multilevel
from harness.solvers.newton import solve_semismooth_newton
from harness.solvers.two_body_multigrid import JointMultilevel


def _pair(case, order: int, refinements: int) -> TwoBodyProblem:
    bodies = (case, lower_body(case))
    meshes = [coarse_mesh(body) for body in bodies]
    for mesh in meshes:
        for _ in range(refinements):
            mesh.Refine()
    return TwoBodyProblem(*(discretise(body, mesh, order) for body, mesh in zip(bodies, meshes)))


@pytest.mark.parametrize("order", [1, 2], ids=["P1", "P2"])
def test_the_interface_rows_are_the_jumps_of_polynomial_traces(order):
    """Traces of degree k on both non-matching meshes (2:3): at the law's points the normal
    channel's rows give the opening c_1 + c_2 and its gap -(x^2/2 + x^2/2) (each body's
    obstacle), the slip channel's t_1 - t_2, both to 1e-13; the fluxes read the slave's dofs
    only, and the weights integrate the overlap of the two traces exactly."""
    case = dataclasses.replace(registered_cases()["two-body-elastic-transition"], friction=Coulomb(0.3), gap=ngs.x ** 2 / 2)
    pair = _pair(case, order, 1)
    rows = interface_rows(case, pair, friction=True)
    k = order
    c = [lambda x: 0.3 + x - 0.7 * x ** k, lambda x: -1.1 + 0.5 * x + 0.2 * x ** k]
    t = [lambda x: 0.2 - 0.4 * x + 0.9 * x ** k, lambda x: 0.7 + 0.3 * x - 0.5 * x ** k]
    u = pair_traces(pair, c, t)
    x = rows.quadrature.points[:, 0]
    np.testing.assert_allclose(rows.T[-1] @ u, c[0](x) + c[1](x), rtol=0, atol=1e-13)
    np.testing.assert_allclose(rows.T[0] @ u, t[0](x) - t[1](x), rtol=0, atol=1e-13)
    np.testing.assert_allclose(rows.gap, -x ** 2, rtol=0, atol=1e-13)
    assert all(abs(N[:, pair.upper.ndof:]).sum() == 0 for N in rows.N)
    overlap = min(pair.upper.trace.vertex_points[:, 0].max(), pair.lower.trace.vertex_points[:, 0].max()) - \
        max(pair.upper.trace.vertex_points[:, 0].min(), pair.lower.trace.vertex_points[:, 0].min())
    np.testing.assert_allclose(rows.quadrature.weights.sum(), overlap, rtol=1e-13)


# one-body case -> its matching mirror pair (the lower body meshed as the upper)
MATCHING = {"transition-r32": "two-body-transition-r32-matching", "elastic-transition-r32": None, "tresca-r32": "two-body-tresca-r32"}


def _matching(one_body: str):
    cases = registered_cases()
    two = cases[MATCHING[one_body]] if MATCHING[one_body] else dataclasses.replace(cases[one_body], name="matching")
    return dataclasses.replace(two, second_body=MirrorBody(two.geometry, two.maxh))


@pytest.mark.parametrize("one_body", list(MATCHING))
def test_theta_zero_on_a_matching_mirror_pair_is_the_one_body_nitsche_with_half_gamma0(one_body):
    """A mirror pair on matching meshes: u_2 = u_1 by symmetry, the opening 2 c_1 against 2 alpha,
    so the law's argument lambda - (2 c_1 - 2 alpha) / gamma is the one body's with gamma / 2; with
    theta = 0 the slave's flux term vanishes and each body solves the one-body problem of
    `nitsche` with gamma0 / 2 (Tresca's slip 2 u alike). Levels 0-1: u_1's errors are the
    one-body errors times sqrt(2) (two equal bodies) and the force is the one body's, to 1e-8."""
    two = harness.run(_matching(one_body), ["mortar-nitsche:theta=0,gamma0=0.1"], levels=2, show_progress=False)
    one = harness.run(registered_cases()[one_body], ["nitsche:theta=0,gamma0=0.05"], levels=2, show_progress=False)
    two, one = (frame.sort_values("level").reset_index(drop=True) for frame in (two, one))
    assert len(two) == len(one) == 2 and (two.status == "converged").all() and (two.kkt_residual <= 1e-10).all()
    np.testing.assert_allclose(two.err_h1, np.sqrt(2.0) * one.err_h1, rtol=1e-8)
    np.testing.assert_allclose(two.qoi_force, one.qoi_force, rtol=1e-8)


@pytest.mark.slow
def test_the_coupled_coulomb_newton_solve_and_the_fixed_point_over_tresca_reach_one_solution():
    """cattaneo-two-body-q03 on level 0 (non-matching meshes, 4,140 dofs), its final data as one
    static Coulomb problem: the coupled semismooth Newton method (a nonsymmetric Jacobian, a
    factorisation) and the fixed point over Tresca problems (symmetric Jacobians; the threshold
    never linearised) reach the same u_h to 1e-8 relative, each with a residual <= 1e-10."""
    case = registered_cases()["cattaneo-two-body-q03"]
    pair = _pair(case, 2, 0)
    method = get_method("mortar-nitsche")
    system = two_body_system(case, pair, law_for(method.calibrated_law, case.friction))
    assert not system.symmetric
    newton = solve_semismooth_newton(system)
    fixed = solve_fixed_point(system)
    assert newton.status == "converged" and fixed.status == "converged", (newton.status, fixed.status)
    assert newton.residual <= 1e-10 and fixed.residual <= 1e-10
    assert np.abs(newton.u - fixed.u).max() <= 1e-8 * np.abs(newton.u).max()
    # the shear is on: some points slip, some stick
    branches = set(np.unique(newton.active))
    assert {0, 1} <= branches or {0, 2} <= branches, branches


@pytest.mark.slow
def test_the_joint_v_cycle_and_the_factorisation_give_one_newton_solution():
    """cattaneo-two-body-q03 on level 1 (15,940 dofs), its final data as one static Coulomb
    problem: Newton with GMRES preconditioned by the joint V-cycle (the Galerkin coarse levels,
    ``solvers.two_body_multigrid.law_hierarchy``) and Newton with the factorisation, both
    converged, reach the same u_h to 1e-7 relative (measured 1.5e-8: GMRES stops at a relative
    residual of 5e-12 where the factorisation leaves 2e-17, and the stiffness's condition number
    carries the difference into u); GMRES needs fewer than 40 iterations a Newton step (measured
    363 over 15 steps from zero)."""
    case = registered_cases()["cattaneo-two-body-q03"]
    bodies = (case, lower_body(case))
    meshes = [coarse_mesh(body) for body in bodies]
    multilevel = JointMultilevel(*(Multilevel(mesh, case.physics) for mesh in meshes))
    for mesh in meshes:
        mesh.Refine()
    multilevel = multilevel.refined(meshes)
    pair = TwoBodyProblem(*(discretise(body, mesh, 2) for body, mesh in zip(bodies, meshes)))
    law = law_for(get_method("mortar-nitsche").calibrated_law, case.friction)
    direct = solve_semismooth_newton(two_body_system(case, pair, law))
    krylov = solve_semismooth_newton(two_body_system(case, pair, law), multilevel=multilevel)
    assert direct.status == krylov.status == "converged"
    assert np.abs(direct.u - krylov.u).max() <= 1e-7 * np.abs(direct.u).max()
    assert krylov.linear_iterations < 40 * krylov.iterations, (krylov.linear_iterations, krylov.iterations)
