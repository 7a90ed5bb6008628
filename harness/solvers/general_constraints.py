"""Exact solution of a QP with general linear inequality constraints,

    minimise 1/2 z^T K z - b^T z   subject to   z = lift on the pinned dofs,   B z >= g,

the form the 3D counterpart of K_h takes (per contact triangle the mean of u_h - alpha,
for P2 the average of the triangle's three edge-midpoint values, docs/mathematics.md, couples
midpoints shared by two triangles, so no local change of variables turns it into bounds as in
2D) and the one a mortar condition takes with standard multipliers.

Method: the primal-dual active set method of Hintermueller, Ito & Kunisch (SIAM J. Optim. 13
(2002)) for B z >= g. With lambda >= 0 the multipliers (K z - b = B^T lambda on the free dofs),
each step solves the equality-constrained problem of the current active set A by its KKT system

    [ K_FF   B_AF^T ] [  z_F ]   [ b_F - K_FP z_P ]
    [ B_AF   -d I   ] [ -l_A ] = [ g_A - B_AP z_P ],

d a regularisation at round-off (``SolverOptions.regularisation`` times the block's scale): active rows may be
linearly dependent -- the face means of the triangles at the boundary of Gamma_C whose midpoints
are Dirichlet dofs, where lambda is not unique but z is -- and then sets
A = {i : lambda_i + c (g - B z)_i > 0}. It stops on the KKT residual (relative, as the bound
solver's ``bound_constraints.KKT``), never on a repeated set alone; a set that repeats switches to
flipping the first violated row only (Murty's least-index rule, as in ``bound_constraints``): the
iteration is ``pdas.primal_dual_active_set``, this module gives it the rows.

Linear algebra, one of two systems for the equality-constrained problem of a set:
* ``SaddleSystem``: scipy's SuperLU of the saddle matrix, once per active set. The reference --
  exact, and cross-checked against Clarabel in tests/test_general_constraints.py -- for the
  sizes where a factorisation is affordable;
* ``ProjectedMultigridSystem`` (``projected_multigrid``): active rows with a single entry (a bound on one
  variable: the vertex conditions) become pins, the others are kept by projected CG whose
  V-cycle is truncated at their vertices; about a multigrid solve per set, the study's path.
"""
from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import splu

from .bound_constraints import row_norm
from .options import SolverOptions
from .pdas import KKT, primal_dual_active_set, resolved

_DEFAULT = SolverOptions()


@dataclass
class GeneralQPSolution:
    z: np.ndarray
    multipliers: np.ndarray     # lambda, one per row of B (0 off the active set)
    active: np.ndarray          # bool per row of B
    kkt: KKT                    # relative residuals: primal max (g - B z)^+ / max(|B z|, |g|);
                                # dual max (-lambda)^+, complementarity max |lambda (B z - g)|
                                # / max(|B z|, |g|), stationarity max |K z - b - B^T lambda| on
                                # the free dofs, each over the load scale; backward error
    iterations: int
    work: dict                  # the system's linear algebra
    seconds: float
    status: str

    @property
    def residual(self) -> float:
        return self.kkt.residual


class GeneralConstraintSolver:
    """The QP above: ``K`` (n x n, symmetric positive definite on the free dofs), ``b``, ``free``
    (bool, n), ``lift`` (the values of the pinned dofs), ``B`` (m x n), ``g`` (m). The rows as a
    ``pdas.ConstraintKind``."""

    def __init__(self, K, b, free, B, g, lift=None, system=None, options: SolverOptions = _DEFAULT):
        self.K, self.B = sp.csr_matrix(K), sp.csr_matrix(B)
        self.b, self.g = np.asarray(b, float), np.asarray(g, float)
        self.free = np.asarray(free, bool)
        n = len(self.b)
        self.lift = np.zeros(n) if lift is None else np.where(self.free, 0.0, np.asarray(lift, float))
        self.options = options
        self.F = np.flatnonzero(self.free)
        # what the pinned dofs contribute to the free rows and to the constraints
        self.rhs_F = (self.b - self.K @ self.lift)[self.F]
        self.g_F = self.g - self.B @ self.lift
        # the scale of the forces: the loads, or, in a problem driven by its constraints alone,
        # the force of the unconstrained minimiser against them (K applied to the size of g)
        self.load_scale = max(np.abs(self.rhs_F).max(initial=0.0),
                              np.abs(self.K.data).max(initial=0.0) * np.abs(self.g_F).max(initial=0.0), np.finfo(float).tiny)
        # ||K||_inf and ||b||_inf over the free rows: the scale of the normwise backward error
        self.K_norm = row_norm(self.K, self.free)
        self.b_norm = float(np.abs(self.b[self.F]).max(initial=0.0))
        self.system = SaddleSystem(options) if system is None else system
        # |B|, its row sums and gamma_{n+1} of each row (n its nonzeros): ``pdas.resolved``
        self.B_abs = abs(self.B)
        self.row_sums = np.asarray(self.B_abs.sum(axis=1)).ravel()
        self.row_gamma = (np.diff(self.B.indptr) + 1) * np.finfo(float).eps

    def slack(self, z: np.ndarray) -> tuple[np.ndarray, float]:
        """B z - g, each value below what double precision resolves in it set to 0
        (``pdas.resolved``), and the scale of the constraint values, max(|B z|, |g|)."""
        Bz = self.B @ z
        bound = self.row_gamma * (self.B_abs @ np.abs(z) + np.abs(self.g)) + self.row_sums * np.finfo(float).eps * np.abs(z).max(initial=0.0)
        return resolved(Bz - self.g, bound), max(np.abs(Bz).max(initial=0.0), np.abs(self.g).max(initial=0.0), np.finfo(float).tiny)

    def kkt(self, z: np.ndarray, lam: np.ndarray) -> KKT:
        slack, scale_z = self.slack(z)
        force = (self.K @ z - self.b - self.B.T @ lam)[self.F]
        negative = max(0.0, -lam.min(initial=0.0))
        stationarity = np.abs(force).max(initial=0.0)
        complementarity = np.abs(lam * slack).max(initial=0.0) / scale_z
        return KKT(
            primal=float(max(0.0, -slack.min(initial=0.0)) / scale_z),
            dual=float(negative / self.load_scale),
            complementarity=float(complementarity / self.load_scale),
            stationarity=float(stationarity / self.load_scale),
            backward=float(max(stationarity, negative, complementarity)
                           / max(self.K_norm * np.abs(z).max(initial=0.0) + self.b_norm, np.finfo(float).tiny)),
        )

    def start_residual(self, z: np.ndarray, active: np.ndarray) -> float:
        """max |K z - b| on the free dofs over the load scale: how far a start is (its
        multipliers are not known yet)."""
        return float(np.abs((self.K @ z - self.b)[self.F]).max(initial=0.0) / self.load_scale)

    def solve_set(self, active: np.ndarray, start, tol: float) -> tuple[np.ndarray, np.ndarray, KKT]:
        """The equality-constrained problem of the rows ``active`` by the system, to tol; its
        multipliers and KKT residuals."""
        z, lam = self.system.solve(self, np.flatnonzero(active), start, tol)
        return z, lam, self.kkt(z, lam)

    def solve(self, initial_active: np.ndarray | None = None, start: np.ndarray | None = None) -> GeneralQPSolution:
        """From a predicted active set and, for iterative systems, a start vector (nested
        iteration), by ``pdas.primal_dual_active_set``. It stops on the KKT residual
        (``KKT.converged``: <= tol, or feasible with the force parts at round-off), never on a
        repeated set alone. With an iterative system the steps are inexact as in
        ``bound_constraints.ActiveSetSolver.solve``: a new set is solved to ``options.forcing`` times
        the current residual (the first to that of the start's stationarity; whenever that is
        shallower than the full depth, ``options.loose_gain_general``), the set such a solve
        leaves unchanged again to the full depth, and only sets judged on full-depth solves
        count as seen (Murty's rule)."""
        clock = time.perf_counter()
        active = np.zeros(len(self.g), bool) if initial_active is None else np.asarray(initial_active, bool).copy()
        options = self.options
        end = primal_dual_active_set(self, active, start, options, options.loose_gain_general, options.general_iterations)
        return GeneralQPSolution(z=end.z, multipliers=end.multipliers, active=end.active, kkt=end.kkt,
                                 iterations=end.iterations, work=self.system.work(),
                                 seconds=time.perf_counter() - clock, status=end.status)


class SaddleSystem:
    """The equality-constrained problem of a set by SuperLU of its saddle matrix (above), with
    ``options.regularisation`` and ``options.refinement_steps``."""

    def __init__(self, options: SolverOptions = _DEFAULT):
        self.regularisation, self.refinement_steps = options.regularisation, options.refinement_steps
        self.factorizations = 0
        self._blocks = None         # K[F, F], B[:, F] and the regularisation, made at the first solve

    def solve(self, qp: GeneralConstraintSolver, rows: np.ndarray, start, tol: float) -> tuple[np.ndarray, np.ndarray]:
        if self._blocks is None:
            K_FF = qp.K[qp.F][:, qp.F].tocsc()
            self._blocks = K_FF, qp.B[:, qp.F].tocsr(), self.regularisation * float(np.abs(K_FF.diagonal()).max(initial=1.0))
        K_FF, B_F, d = self._blocks
        B_A = B_F[rows]
        saddle = sp.bmat([[K_FF, B_A.T], [B_A, -d * sp.identity(len(rows))]], format="csc")
        factor = splu(saddle)
        rhs = np.concatenate([qp.rhs_F, qp.g_F[rows]])
        solution = factor.solve(rhs)
        # iterative refinement against the unregularised system: the -d I block leaves the
        # active rows off by d lambda, which a singular pressure (large lambda, e.g. at a
        # junction) made 1e-9 of the load; the same factorisation corrects it (where rows are
        # dependent the correction keeps z and leaves lambda's null-space part alone)
        n = len(qp.F)
        for _ in range(self.refinement_steps):
            z_F, l_A = solution[:n], solution[n:]
            residual = np.concatenate([qp.rhs_F - K_FF @ z_F - B_A.T @ l_A, qp.g_F[rows] - B_A @ z_F])
            solution += factor.solve(residual)
        self.factorizations += 1
        z = qp.lift.copy()
        z[qp.F] = solution[: len(qp.F)]
        lam = np.zeros(len(qp.g))
        lam[rows] = -solution[len(qp.F):]
        return z, lam

    def work(self) -> dict:
        return {"factorizations": self.factorizations}
