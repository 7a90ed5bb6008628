"""K = diag(A_1, A_2) + C on the bodies' own NGSolve matrices (``harness.solvers.two_body_operator``):
it multiplies as the scipy K of the dual mortar QP, and its smoother is the symmetric block
Gauss-Seidel of K (bulk rows one by one, the interface rows as one block), checked against a
dense sweep written out here."""
from __future__ import annotations

import numpy as np
import pytest

from harness.fem.assembly import discretise
from harness.fem.mortar import mortar_coupling
from harness.fem.two_body import TwoBodyProblem, dual_bound_qp
from harness.mesh.levels import UniformRefinement
from harness.problem.bodies import lower_body
from harness.problem.case import load_case
from harness.solvers.bound_constraints import row_norm
from harness.solvers.two_body_operator import CoupledBlocks


def _dual_qp(case_name: str, order: int, levels: int = 2):
    case = load_case(case_name)
    bodies = (case, lower_body(case))
    meshes = [list(UniformRefinement(body).levels(levels))[-1].mesh for body in bodies]
    problem = TwoBodyProblem(*(discretise(body, mesh, order) for body, mesh in zip(bodies, meshes)))
    coupling = mortar_coupling(problem.upper, problem.lower, case.obstacle, "dual", "midpoint")
    qp = dual_bound_qp(problem, coupling, 4.0 if order == 2 else None)
    return qp, CoupledBlocks([body.A_ngs for body in problem.bodies], qp.K_interface)


def _vector(K, values):
    vector = K.CreateColVector()
    vector.FV().NumPy()[:] = values
    return vector


PAIRS = [("two-body-transition-r32", 1), ("two-body-transition-r32", 2), ("two-body-elastic-transition", 2)]


@pytest.mark.parametrize("case_name, order", PAIRS)
def test_coupled_blocks_multiply_as_the_dual_qps_matrix(case_name, order):
    qp, K = _dual_qp(case_name, order)
    x = np.random.default_rng(0).standard_normal(qp.K.shape[0])
    y = K.CreateColVector()
    y.data = K * _vector(K, x)
    expected = qp.K @ x
    assert np.abs(y.FV().NumPy() - expected).max() <= 1e-13 * np.abs(expected).max()
    # a residual, NGSolve's b - K x (MultAdd, no temporary vector)
    b = np.random.default_rng(4).standard_normal(len(x))
    y.data = _vector(K, b) - K * _vector(K, x)
    assert np.abs(y.FV().NumPy() - (b - expected)).max() <= 1e-13 * np.abs(expected).max()
    assert abs(K.scipy() - qp.K).max() <= 1e-13 * abs(qp.K).max()
    # the active set method's view of it: products of NumPy vectors and the row norms
    assert np.abs(K @ x - expected).max() <= 1e-13 * np.abs(expected).max()
    assert K.row_norm(qp.free) == pytest.approx(row_norm(qp.K, qp.free), rel=1e-13)
    # the interface is small: a few dofs per trace dof
    assert len(K.interface) <= 12 * len(qp.C)


def _reference_sweep(K, x, b, mask, interface, backward=False):
    """Block Gauss-Seidel written out: the bulk rows of ``mask`` one by one in order, then the
    interface rows of ``mask`` together (backward: the reverse)."""
    in_block = np.zeros(len(x), dtype=bool)
    in_block[interface] = True
    bulk = np.flatnonzero(mask & ~in_block)
    block = np.flatnonzero(mask & in_block)

    def bulk_sweep(rows):
        for i in rows:
            x[i] += (b[i] - K[i] @ x) / K[i, i]

    def block_solve():
        x[block] += np.linalg.solve(K[np.ix_(block, block)], (b - K @ x)[block])
    if backward:
        block_solve()
        bulk_sweep(bulk[::-1])
    else:
        bulk_sweep(bulk)
        block_solve()
    return x


@pytest.mark.parametrize("case_name, order", PAIRS[:2])
def test_the_smoother_is_block_gauss_seidel_of_k_forward_and_back(case_name, order):
    qp, K = _dual_qp(case_name, order, levels=1)
    dense = qp.K.toarray()
    n = dense.shape[0]
    rng = np.random.default_rng(1)
    x0, b = rng.standard_normal(n), rng.standard_normal(n)
    # two active sets (some bounds pinned): the second takes over the first's bulk sweeps
    smoothers = []
    for pinned in (qp.C[::3], qp.C[1::3]):
        mask = qp.free.copy()
        mask[pinned] = False
        smoothers.append(smoother := K.smoother(mask))
        for backward in (False, True):
            x = _vector(K, x0)
            (smoother.SmoothBack if backward else smoother.Smooth)(x, _vector(K, b))
            expected = _reference_sweep(dense, x0.copy(), b, mask, K.interface, backward)
            assert np.abs(x.FV().NumPy() - expected).max() <= 1e-12 * np.abs(expected).max()
    assert smoothers[1].smoothers is smoothers[0].smoothers
