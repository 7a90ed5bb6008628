"""Two bodies on multigrid (``harness.solvers.two_body_multigrid``): the coupled coarse matrices
are the Galerkin products of the mortar QP, the sparse prolongations are the hierarchy's, and
the mortar methods solve on it what they solve on sparse Cholesky."""
from __future__ import annotations

import dataclasses

import ngsolve as ngs
import numpy as np
import pytest
import scipy.sparse as sp

from harness.fem.assembly import discretise
from harness.fem.mortar import mortar_coupling
from harness.fem.two_body import TwoBodyProblem, dual_bound_qp
from harness.mesh.levels import UniformRefinement
from harness.mesh.strategies import MeshStrategy
from harness.methods import METHODS, get_method
from harness.problem.bodies import lower_body
from harness.problem.case import load_case
from harness.solvers.bound_constraints import ActiveSetSolver, MultigridSystem
from harness.solvers.multigrid import Multilevel
from harness.solvers.two_body_multigrid import (
    JointMultilevel,
    OpeningLevels,
    SparseEdges,
    mortar_coupling_matrix,
    mortar_injection,
    p1_injected,
)
from harness.solvers.two_body_operator import CoupledBlocks
from harness.study.chain.two_body import run_two_body_chain

TWO_BODY_CASES = ["two-body-transition-r32", "two-body-elastic-transition"]
DUAL_MORTAR = [m.name for m in METHODS.values() if 2 in m.bodies and getattr(m, "multipliers", None) == "dual"]


def _pair_on_hierarchy(case_name: str, levels: int, order: int = 2):
    case = load_case(case_name)
    bodies = (case, lower_body(case))
    walks = [UniformRefinement(body).levels(levels) for body in bodies]
    multilevel = None
    for _ in range(levels):
        meshes = [next(walk).mesh for walk in walks]
        multilevel = JointMultilevel(*(Multilevel(mesh, case.physics) for mesh in meshes)) if multilevel is None \
            else multilevel.refined(meshes)
    problem = TwoBodyProblem(*(discretise(body, mesh, order) for body, mesh in zip(bodies, meshes)))
    return case, problem, multilevel


@pytest.mark.parametrize("case_name", TWO_BODY_CASES)
def test_the_coupled_coarse_matrices_are_galerkin_products_of_the_mortar_qp(case_name):
    """E^T K E = diag(A_1, A_2)^P1 + C on the finest P1 level, and P^T A_l P = A_{l-1} below."""
    case, problem, multilevel = _pair_on_hierarchy(case_name, 3)
    qp = dual_bound_qp(problem, mortar_coupling(problem.upper, problem.lower, case.obstacle, "dual", "midpoint"))
    E = mortar_injection(problem)
    hierarchy = multilevel.coupled(mortar_coupling_matrix(problem, qp.S_rows(qp.C), qp.C, E))
    top = hierarchy.matrices[-1].scipy()
    scale = abs(top).max()
    assert abs(E.T @ qp.K @ E - top).max() <= 1e-13 * scale
    for level in range(len(hierarchy.matrices) - 1, 0, -1):
        P = multilevel.prolongation_matrix(level)
        galerkin = P.T @ hierarchy.matrices[level].scipy() @ P
        assert abs(galerkin - hierarchy.matrices[level - 1].scipy()).max() <= 1e-12 * scale


@pytest.mark.parametrize("case_name", TWO_BODY_CASES)
def test_the_joint_p1_injection_is_ngsolves_interpolation_of_each_bodys_p1_function(case_name):
    """I c, the nested start's map of the joint P1 vector into the joint dofs, against NGSolve
    interpolating each body's P1 function (vertex values c, components blocked) into its space."""
    case, problem, _ = _pair_on_hierarchy(case_name, 2)
    rng = np.random.default_rng(5)
    spaces = [case.physics.space(body.mesh, 1) for body in problem.bodies]
    c = rng.standard_normal(sum(space.ndof for space in spaces))
    expected, offset = [], 0
    for body, space in zip(problem.bodies, spaces):
        p1, interpolated = ngs.GridFunction(space), ngs.GridFunction(body.fes)
        p1.vec.FV().NumPy()[:] = c[offset: offset + space.ndof]
        interpolated.Set(p1)
        expected.append(interpolated.vec.FV().NumPy().copy())
        offset += space.ndof
    expected = np.concatenate(expected)
    assert np.abs(p1_injected(problem, c) - expected).max() <= 1e-12 * np.abs(c).max()


@pytest.mark.parametrize("edge_functional", ["midpoint", "mean"])
@pytest.mark.parametrize("case_name", TWO_BODY_CASES)
def test_the_dual_qps_matrix_is_the_congruence_of_both_bodies_matrices(case_name, edge_functional):
    """K = S^T diag(A_1, A_2) S, made from the slave trace's rows of A only
    (``fem.sparse.congruence_terms``), equals the triple product, in P2 (both weights of the
    edge variables: `mortar-nodal`, `mortar-mean`) and P1."""
    for order in (1, 2):
        case, problem, _ = _pair_on_hierarchy(case_name, 2, order)
        coupling = mortar_coupling(problem.upper, problem.lower, case.obstacle, "dual", "midpoint")
        weight = {"midpoint": 4.0, "mean": 6.0}[edge_functional] if order == 2 else None
        qp = dual_bound_qp(problem, coupling, weight)
        A = sp.block_diag([problem.upper.A, problem.lower.A], format="csr")
        product = qp.S.T @ A @ qp.S
        assert abs(qp.K - product).max() <= 1e-13 * abs(product).max()
        # the rows the congruence reads: S is the identity off the constrained (slave trace) dofs
        changed = np.flatnonzero(abs(qp.S - sp.identity(problem.ndof)).sum(axis=1).A.ravel())
        assert np.isin(changed, qp.C).all()
        # and the nested start's change of variables inverts it
        u = np.random.default_rng(3).standard_normal(problem.ndof)
        assert np.abs(qp.to_u(qp.to_z(u)) - u).max() <= 1e-13 * np.abs(u).max()


@pytest.mark.parametrize("case_name, strategy", [("transition-r32", "uniform"), ("elastic-transition-r32", "uniform"),
                                                 ("corner-r12", "graded"), ("elastic-wedge", "graded")])
def test_the_prolongation_matrix_is_the_hierarchys_prolongation(case_name, strategy):
    """Scalar and vector P1 (rotated frame), meshes refined in place and new bisected meshes."""
    case = load_case(case_name)
    multilevel = None
    for level in MeshStrategy(strategy).sequence(case, 2).levels(3):
        multilevel = Multilevel(level.mesh, case.physics) if multilevel is None \
            else multilevel.refined(level.mesh, level.prolongation)
    top = len(multilevel.matrices) - 1
    assert top >= 1
    P = multilevel.prolongation_matrix(top)
    coarse = np.random.default_rng(1).standard_normal(P.shape[1])
    vector = multilevel.matrices[top].CreateColVector()
    vector[:] = 0.0
    vector.FV().NumPy()[: len(coarse)] = coarse
    multilevel.prolongate(top, vector)
    assert np.abs(vector.FV().NumPy() - P @ coarse).max() <= 1e-14 * np.abs(coarse).max()


@pytest.mark.parametrize("case_name", TWO_BODY_CASES)
@pytest.mark.parametrize("method_name", DUAL_MORTAR)
def test_mortar_on_multigrid_solves_what_it_solves_on_cholesky(case_name, method_name):
    """Independent cross-check: every level of a uniform chain on the coupled multigrid (the
    threshold set to 0) against the same chain on sparse Cholesky: the same u_h, both exact."""
    method = get_method(method_name)
    on_multigrid, on_cholesky = (dataclasses.replace(method, solver=dataclasses.replace(method.solver, mortar_multigrid_from=n))
                                 for n in (0, 10**12))
    case = load_case(case_name)
    levels = 3 + method.extra_levels
    outputs = [run_two_body_chain(case, [m], levels, on_level=lambda case, method, level, problem, solve: solve.u)
               for m in (on_multigrid, on_cholesky)]
    for multigrid_row, cholesky_row in zip(outputs[0].rows, outputs[1].rows):
        assert multigrid_row["status"] == cholesky_row["status"] == "converged"
        assert multigrid_row["kkt_residual"] <= 1e-10 and cholesky_row["kkt_residual"] <= 1e-10
        u_multigrid, u_cholesky = (output.kept[(method_name, multigrid_row["level"])] for output in outputs)
        assert np.abs(u_multigrid - u_cholesky).max() <= 1e-8 * np.abs(u_cholesky).max()
    # CG iterations against factorisations: the two solvers did run
    assert outputs[0].rows[-1]["linear_iterations"] > outputs[1].rows[-1]["linear_iterations"]



def _opening_hierarchy(levels: int, order: int = 1):
    """The scalar pair's dual QP on ``levels`` levels, with both hierarchies in its variables: the
    body-wise one (``JointMultilevel.coupled``) and the one in opening variables."""
    case, problem, multilevel = _pair_on_hierarchy("two-body-transition-r32", levels, order)
    qp = dual_bound_qp(problem, mortar_coupling(problem.upper, problem.lower, case.obstacle, "dual", "midpoint"),
                       4.0 if order == 2 else None)
    E = mortar_injection(problem)
    coupling = mortar_coupling_matrix(problem, qp.S_rows(qp.C), qp.C, E)
    return problem, qp, E, multilevel.coupled(coupling), OpeningLevels(multilevel, problem, coupling)


def test_opening_levels_keep_a_zero_opening_zero_and_are_galerkin_products():
    """A master coarse hat prolongates to zero openings on the finer level (it touches no trace
    variable: no pin) while it drags the slave's vertices off the trace with it; and every
    coarse matrix is P^T K P of the finer one."""
    problem, qp, E, _, levels = _opening_hierarchy(3)
    trace = problem.upper.trace.vertices
    top = len(levels.sizes) - 1
    (coarse_slave, _), (fine_slave, _) = levels.body_sizes[top - 1], levels.body_sizes[top]
    P = levels.prolongation_matrix(top)
    master_hats = P[:, coarse_slave:].tocsc()
    slave_rows = master_hats[:fine_slave]
    assert abs(slave_rows[trace[trace < fine_slave]]).max() == 0.0      # the openings stay zero
    assert abs(slave_rows).max() > 0.0                                  # the slave follows
    finest = levels.matrices[-1].scipy()
    scale = abs(finest).max()
    assert abs(E.T @ qp.K @ E - finest).max() <= 1e-13 * scale
    for level in range(top, 0, -1):
        P = levels.prolongation_matrix(level)
        galerkin = P.T @ levels.matrices[level].scipy() @ P
        assert abs(galerkin - levels.matrices[level - 1].scipy()).max() <= 1e-12 * scale


def test_opening_levels_apply_their_prolongation_matrix_body_by_body():
    """The V-cycle's prolongation (each body's hierarchy plus the drag) and restriction (with the
    pins' |P|^T) are the sparse P of the Galerkin products and its transposes."""
    _, _, _, _, levels = _opening_hierarchy(3)
    rng = np.random.default_rng(2)
    top = len(levels.sizes) - 1
    P = levels.prolongation_matrix(top)
    vector = levels.matrices[top].CreateColVector()
    coarse = rng.standard_normal(P.shape[1])
    vector.FV().NumPy()[:] = 0.0
    vector.FV().NumPy()[: len(coarse)] = coarse
    levels.prolongate(top, vector)
    assert np.abs(vector.FV().NumPy() - P @ coarse).max() <= 1e-14 * np.abs(coarse).max()
    for rotate, transposed in ((True, P.T), (False, abs(P).T)):
        fine = rng.standard_normal(P.shape[0])
        vector.FV().NumPy()[:] = fine
        levels.restrict(top, vector, rotate)
        expected = transposed @ fine
        assert np.abs(vector.FV().NumPy()[: len(expected)] - expected).max() <= 1e-13 * np.abs(expected).max()


@pytest.mark.parametrize("order", [1, 2])
def test_opening_levels_solve_with_far_fewer_cg_iterations_than_the_body_wise_levels(order):
    """The same dual QP from a cold start (the same active sets) on both hierarchies: in opening
    variables the coarse levels carry the bodies' joint motion, and CG needs at most half the
    iterations (measured: 53 against 235 in P1 on 5 levels, 53 against 153 in P2 on 4); both exact,
    the same u_h. K as the study holds it (``CoupledBlocks``)."""
    problem, qp, E, coupled, levels = _opening_hierarchy(5 if order == 1 else 4, order)
    edges = SparseEdges(E)
    K_ngs = CoupledBlocks([body.A_ngs for body in problem.bodies], qp.K_interface)
    solutions = [ActiveSetSolver(qp.K, qp.b, qp.free, qp.C, qp.alpha, lift=qp.lift,
                                 system=MultigridSystem(K_ngs, qp.b, hierarchy, edges)).solve()
                 for hierarchy in (coupled, levels)]
    assert all(s.status == "converged" and s.kkt.residual <= 1e-10 for s in solutions)
    assert [s.iterations for s in solutions][0] == solutions[1].iterations
    assert np.abs(solutions[0].z - solutions[1].z).max() <= 1e-8 * np.abs(solutions[0].z).max()
    assert solutions[1].work["cg_iterations"] <= 0.5 * solutions[0].work["cg_iterations"]


def test_opening_levels_refuse_a_contact_condition_in_a_rotated_frame():
    """Elastic pairs (u . n in the normal-tangential frame) keep the body-wise levels: the opening
    levels say so rather than take a displacement component for the opening."""
    case, problem, multilevel = _pair_on_hierarchy("two-body-elastic-transition", 2)
    with pytest.raises(ValueError, match="rotated|scalar"):
        OpeningLevels(multilevel, problem, None)
