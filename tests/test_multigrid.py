"""The truncated multigrid: exact Galerkin coarse spaces, an SPD preconditioner that keeps the
pins, and CG iteration counts that do not grow under refinement."""
import numpy as np
import pytest
import scipy.sparse as sp
from conftest import CONE_NAMES, problem_with_hierarchy

from harness.fem.cones import contact_qp
from harness.methods import METHODS
from harness.problem.case import load_case
from harness.solvers.active_set import MultigridSystem, solve_contact_qp
from harness.solvers.multigrid import ContactEdges, TruncatedVCycle


def _csr(matrix) -> sp.csr_matrix:
    values, columns, pointers = matrix.CSR()
    return sp.csr_matrix((np.array(values), np.array(columns), np.array(pointers)), shape=(matrix.height, matrix.width))


def test_p1_coarse_matrices_are_galerkin_products_of_the_finer():
    """P^T A_fine P = A_coarse on every level: the V-cycle's coarse spaces are exact subspaces."""
    _, multilevel = problem_with_hierarchy("transition-r32", 3)
    prolongation = multilevel.fes.Prolongation()
    for level in range(1, len(multilevel.matrices)):
        fine, coarse = multilevel.matrices[level], multilevel.matrices[level - 1]
        columns = []
        vector = fine.CreateColVector()
        for j in range(coarse.height):
            vector[:] = 0.0
            vector[j] = 1.0
            prolongation.Prolongate(level, vector)
            columns.append(vector.FV().NumPy().copy())
        P = sp.csr_matrix(np.array(columns).T)
        galerkin = (P.T @ _csr(fine) @ P - _csr(coarse)).toarray()
        assert np.abs(galerkin).max() <= 1e-12 * np.abs(_csr(coarse)).max()
        assert P.min() >= 0.0   # what lets restriction of the pin indicator find the truncated hats


def _exact_pins(case_name, method_name, level):
    method = METHODS[method_name]
    problem, multilevel = problem_with_hierarchy(case_name, level, method.order)
    qp = contact_qp(load_case(case_name), problem, method.cone)
    active = solve_contact_qp(qp).active
    pinned = ~qp.free
    pinned[qp.C[active]] = True
    return qp, multilevel, pinned


@pytest.mark.parametrize("model_name", CONE_NAMES)
def test_truncated_vcycle_is_symmetric_positive_and_keeps_the_pins(model_name, rng):
    """CG needs a symmetric positive definite preconditioner on the free dofs; the truncated
    coarse spaces must never move a pinned dof."""
    qp, multilevel, pinned = _exact_pins("transition-r32", model_name, 3)
    vcycle = TruncatedVCycle(multilevel, qp.K_ngs, ~pinned, ContactEdges.of(qp.problem))
    vectors = [qp.K_ngs.CreateColVector() for _ in range(4)]
    r, s, Br, Bs = vectors
    r.FV().NumPy()[:] = np.where(pinned, 0.0, rng.standard_normal(len(pinned)))
    s.FV().NumPy()[:] = np.where(pinned, 0.0, rng.standard_normal(len(pinned)))
    vcycle.apply(r, Br)
    vcycle.apply(s, Bs)
    assert np.all(Br.FV().NumPy()[pinned] == 0.0)
    sBr, rBs = s.FV().NumPy() @ Br.FV().NumPy(), r.FV().NumPy() @ Bs.FV().NumPy()
    assert abs(sBr - rBs) <= 1e-12 * abs(sBr)
    assert r.FV().NumPy() @ Br.FV().NumPy() > 0


# mean (11 s, the same truncation as nodal's on the edge variables) in `make test-full`
@pytest.mark.parametrize("model_name", [pytest.param(n, marks=pytest.mark.slow) if n == "mean" else n for n in CONE_NAMES])
def test_multigrid_cg_iterations_do_not_grow_under_refinement(model_name):
    """Truncation makes the coarse spaces see the contact zone: with the exact active set pinned,
    CG iterations from zero stay bounded as h halves (an untruncated multigrid grows like
    h^(-1/2))."""
    iterations = []
    for level in (2, 3, 4, 5):
        qp, multilevel, pinned = _exact_pins("transition-r32", model_name, level)
        system = MultigridSystem(qp.K_ngs, qp.b, multilevel, ContactEdges.of(qp.problem))
        values = np.where(qp.free, 0.0, qp.lift)
        initial_residual = np.abs(np.where(pinned, 0.0, qp.b - qp.K @ values)).max()
        system.solve(pinned, values, tol=1e-10 * initial_residual)
        iterations.append(system.cg_iterations)
    assert max(iterations) <= min(iterations) + 3, iterations


