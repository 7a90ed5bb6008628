"""Exact solution of the discrete contact problems (3.6) and (5.1).

In the variables of its contact model (``fem.cones``: NGSolve's hierarchical P2 variables with
each contact-edge bubble replaced by the midpoint value or the edge mean) each problem is

    minimise 1/2 z^T K z - b^T z   subject to   z = u_D on Gamma_u,   z_i >= alpha_i for i in C,

with K symmetric positive definite. Its KKT conditions,

    (K z - b) = 0 on the free dofs off C,  z_C >= alpha,  lambda = (K z - b)_C >= 0,
    lambda (z_C - alpha) = 0,

are solved exactly by a primal-dual active set method (the semismooth Newton method of
Hintermueller, Ito and Kunisch, SIAM J. Optim. 13 (2002)): guess the active set, solve the
linear system with z = alpha there, update the guess from the signs of lambda and z - alpha.

Exact and robust:
* it stops on the KKT residual, never only on a repeated active set: the `mean` model has
  degenerate complementarity (lambda_i = 0 = z_i - alpha_i) and plain PDAS can cycle among
  equivalent sets whose KKT residual is already at round-off (docs/mathematics.md §5);
* if an active set repeats while the residual is still large, it switches to Murty's
  least-index principal pivoting, finite for the positive definite Schur complement of K on C.
The iteration is ``pdas.primal_dual_active_set``, shared with ``general_constraints``: this
module gives it the bounds (``ActiveSetSolver``, a ``pdas.ConstraintKind``) and their systems.

Fast: an active constraint is a Dirichlet condition on its variable, so each iteration is a
linear solve with some dofs pinned, done by one of two systems:
* ``MultigridSystem`` (the study's, given the mesh hierarchy): CG preconditioned by a V-cycle
  whose coarse spaces are truncated at the pins (``multigrid``), started from the previous
  iterate; a solve costs about one unconstrained multigrid solve, linear in the number of dofs;
* ``FactorisedSystem`` (a single mesh, and the textbook reference): NGSolve's sparse Cholesky,
  one factorisation reused for later active sets that differ from it in a few dofs (a small
  bordered system, one extra solve per changed dof).
Nested iteration: the study passes the active set predicted by the previous level and, to the
multigrid, the previous solution as a start.
"""
from __future__ import annotations

import time
from dataclasses import dataclass, field

import ngsolve as ngs
import numpy as np
import scipy.sparse as sp

from ..fem.p1_embedding import ContactEdges
from ..fem.sparse import ngsolve_matrix
from .krylov import gmres
from .multigrid import TruncatedVCycle, max_abs, pcg
from .options import SolverOptions
from .pdas import KKT, primal_dual_active_set, resolved

_DEFAULT = SolverOptions()
# the default KKT tolerance, for the benchmarks (``bench``), which scale their linear solves by it
DEFAULT_TOLERANCE = _DEFAULT.tolerance


@dataclass
class QPSolution:
    z: np.ndarray
    multipliers: np.ndarray     # lambda on C
    active: np.ndarray          # bool on C
    kkt: KKT
    iterations: int
    work: dict                  # linear algebra spent: factorisations and solves, or CG iterations
    seconds: float
    status: str                 # "converged" or why not


class Cholesky:
    """K[F, F]^{-1} by NGSolve's sparse Cholesky, applied to numpy vectors (zero off F)."""

    def __init__(self, K_ngs, free: np.ndarray):
        self._inverse = K_ngs.Inverse(ngs.BitArray(np.asarray(free, dtype=bool).tolist()), inverse="sparsecholesky")
        self._rhs = K_ngs.CreateColVector()
        self._sol = K_ngs.CreateColVector()

    def solve(self, rhs: np.ndarray) -> np.ndarray:
        self._rhs.FV().NumPy()[:] = rhs
        self._sol.data = self._inverse * self._rhs
        return self._sol.FV().NumPy().copy()


@dataclass
class _Factored:
    """Cholesky of K with some dofs pinned at values y0[pinned], y0 the solution with those pins."""

    pinned: np.ndarray
    free: np.ndarray            # bool mask of the factorised dofs
    cholesky: Cholesky
    y0: np.ndarray
    columns: dict = field(default_factory=dict)


class FactorisedSystem:
    """Solves with some dofs pinned by sparse Cholesky, reusing one factorisation for pin sets
    that differ from its own in a few dofs (a bordered system, each new dof one extra solve).

    ``refactor_above``: a pin set needing more than this many new bordered columns is
    refactorised instead (``SolverOptions.refactor_above``); 0 gives the textbook method
    (refactorise at every iteration).
    """

    def __init__(self, K: sp.csr_matrix, K_ngs, b: np.ndarray, refactor_above: int = _DEFAULT.refactor_above):
        self.K, self.K_ngs, self.b, self.refactor_above = K, K_ngs, b, refactor_above
        self._factored: _Factored | None = None
        self.factorizations = 0
        self.extra_solves = 0

    def _factorize(self, pinned: np.ndarray, values: np.ndarray) -> _Factored:
        free = ~pinned
        cholesky = Cholesky(self.K_ngs, free)
        self.factorizations += 1
        y0 = np.where(pinned, values, 0.0)
        y0[free] = cholesky.solve(np.where(free, self.b - self.K @ y0, 0.0))[free]
        return _Factored(pinned=pinned, free=free, cholesky=cholesky, y0=y0)

    def set_load(self, b: np.ndarray) -> None:
        """Solve with the load ``b`` from now on (a friction set's slip forces move into it,
        ``solvers.friction``): the factorisation and its bordered columns depend on K alone;
        only the factorised set's solution y0 is solved again (one solve)."""
        if np.array_equal(b, self.b):
            return
        self.b = b
        fac = self._factored
        if fac is not None:
            y0 = np.where(fac.pinned, fac.y0, 0.0)
            y0[fac.free] = fac.cholesky.solve(np.where(fac.free, b - self.K @ y0, 0.0))[fac.free]
            fac.y0 = y0

    def _column(self, fac: _Factored, key, rhs_of) -> np.ndarray:
        if key not in fac.columns:
            fac.columns[key] = np.where(fac.free, fac.cholesky.solve(np.where(fac.free, rhs_of(), 0.0)), 0.0)
            self.extra_solves += 1
        return fac.columns[key]

    def _K_column(self, dof: int) -> np.ndarray:
        """Column dof of the symmetric K, read as its (CSR-cheap) row."""
        lo, hi = self.K.indptr[dof], self.K.indptr[dof + 1]
        column = np.zeros(len(self.b))
        column[self.K.indices[lo:hi]] = self.K.data[lo:hi]
        return column

    def solve(self, pinned: np.ndarray, values: np.ndarray, start=None, tol=None) -> np.ndarray:
        """z with z[pinned] = values[pinned] and (K z - b) = 0 elsewhere, exactly up to round-off
        (``start`` and ``tol`` are for iterative systems)."""
        fac = self._factored
        if fac is not None and self.refactor_above > 0:
            released = np.flatnonzero(fac.pinned & ~pinned)
            added = np.flatnonzero(pinned & ~fac.pinned)
            needed = [("released", int(d)) for d in released] + [("pinned", int(q)) for q in added]
            if sum(key not in fac.columns for key in needed) > self.refactor_above:
                fac = None
        if fac is None or self.refactor_above == 0:
            self._factored = self._factorize(pinned, values)
            return self._factored.y0.copy()
        if len(released) == 0 and len(added) == 0:
            return fac.y0.copy()
        return self._bordered(fac, released, added, values)

    def _bordered(self, fac, released, added, values) -> np.ndarray:
        """z = y0 + d with d = -W_R dR + W_Q mu on the factorised dofs and dR on the released ones
        (R: pinned in the factorisation, free now; Q: free there, pinned now at values[Q]).
        Block elimination against the factorised block leaves a system of size |R| + |Q|:

            [K_RR - K_R W_R    K_R W_Q] [dR]   [b_R - K_R y0     ]
            [-W_R[Q]           W_Q[Q] ] [mu] = [values[Q] - y0[Q]]
        """
        n = len(self.b)
        W_R = _columns(n, [self._column(fac, ("released", int(d)), lambda d=d: self._K_column(d)) for d in released])
        W_Q = _columns(n, [self._column(fac, ("pinned", int(q)), lambda q=q: np.eye(1, n, q).ravel()) for q in added])
        K_R = self.K[released]
        top = np.hstack([K_R[:, released].toarray() - K_R @ W_R, K_R @ W_Q])
        bottom = np.hstack([-W_R[added], W_Q[added]])
        rhs = np.concatenate([self.b[released] - K_R @ fac.y0, values[added] - fac.y0[added]])
        solution = np.linalg.solve(np.vstack([top, bottom]), rhs)
        dR, mu = solution[: len(released)], solution[len(released):]
        z = fac.y0 - W_R @ dR + W_Q @ mu
        z[released] += dR
        z[added] = values[added]
        return z

    def work(self) -> dict:
        return {"factorizations": self.factorizations, "extra_solves": self.extra_solves}


class MultigridSystem:
    """Solves with some dofs pinned by CG with a V-cycle truncated at the pins (``multigrid``),
    from the previous iterate: one preconditioner per pin set, no factorisation of K.
    ``symmetric`` False: GMRES with the same V-cycle (``krylov.gmres``; a nonsymmetric K)."""

    iterative = True            # its solves are as deep as asked: loose ones cost less

    def __init__(self, K_ngs, b: np.ndarray, multilevel, edges: ContactEdges, stiff_vertices=None,
                 options: SolverOptions = _DEFAULT, symmetric: bool = True):
        self.K_ngs, self.b, self.multilevel, self.edges = K_ngs, b, multilevel, edges
        self.krylov = pcg if symmetric else gmres
        self.stiff_vertices = stiff_vertices        # see ``multigrid.TruncatedVCycle``
        self.max_cg_iterations = options.cg_iterations
        self.cg_iterations = 0
        self.preconditioners = 0
        self._last = None           # (pins, V-cycle) of the last solve

    def set_load(self, b: np.ndarray) -> None:
        """Solve with the load ``b`` from now on (``solvers.friction``)."""
        self.b = b

    def solve(self, pinned: np.ndarray, values: np.ndarray, start=None, tol: float = 0.0) -> np.ndarray:
        """The same to max |K z - b| <= tol off the pins, from ``start`` (else zero)."""
        free = ~pinned
        z = np.where(pinned, values, 0.0 if start is None else start)
        key = free.tobytes()
        if self._last is None or self._last[0] != key:
            # the same pins again (a loose solve's set, solved to the full depth): the same V-cycle
            previous = None if self._last is None else self._last[1]
            self._last = key, TruncatedVCycle(self.multilevel, self.K_ngs, free, self.edges, self.stiff_vertices,
                                              previous=previous)
            self.preconditioners += 1
        preconditioner = self._last[1]
        z, iterations = self.krylov(self.K_ngs, preconditioner, self.b, z, free, tol, self.max_cg_iterations)
        self.cg_iterations += iterations
        return z

    def work(self) -> dict:
        return {"cg_iterations": self.cg_iterations, "preconditioners": self.preconditioners}


class ActiveSetSolver:
    """Primal-dual active set solver for min 1/2 z'Kz - b'z, z[~free] = lift[~free], z[C] >= alpha:
    the bounds as a ``pdas.ConstraintKind``.

    ``system`` solves the linear problem of one active set (a ``FactorisedSystem`` by default).
    """

    def __init__(self, K, b, free, C, alpha, K_ngs=None, lift=None, system=None, options: SolverOptions = _DEFAULT):
        # K: a scipy matrix, or an operator that multiplies NumPy vectors and knows its row norms
        # (``two_body_operator.CoupledBlocks``: a mortar QP's K, never made into one matrix)
        self.K = K if hasattr(K, "row_norm") else sp.csr_matrix(K)
        self.b = np.asarray(b, float)
        self.free = np.asarray(free, bool)
        self.C = np.asarray(C, np.int64)
        self.alpha = np.asarray(alpha, float)
        self.lift = np.zeros(len(self.b)) if lift is None else np.where(self.free, 0.0, lift)
        self.options = options
        if not self.free[self.C].all():
            raise ValueError("a constrained dof lies on the Dirichlet boundary")
        # the scale of the forces: the loads, and the force that holds the constrained dofs at
        # the obstacle (the only one in a problem driven by its gap alone); a zero lift or
        # obstacle makes no product with K (8e6 dofs: 0.05 s each)
        self._pinned_rows = np.flatnonzero(~self.free)
        self.load_scale = max(max_abs(self._gradient(self.lift)), self._obstacle_force(), np.finfo(float).tiny)
        # ||K||_inf and ||b||_inf over the free rows: the scale of the normwise backward error
        self.K_norm = self.K.row_norm(self.free) if hasattr(self.K, "row_norm") else row_norm(self.K, self.free)
        self.b_norm = float(np.abs(self.b[self.free]).max(initial=0.0))
        if system is None:
            system = FactorisedSystem(self.K, ngsolve_matrix(self.K) if K_ngs is None else K_ngs, self.b,
                                      options.refactor_above)
        self.system = system

    def _obstacle_force(self) -> float:
        """max |K p| on the free rows, p = alpha on C and 0 elsewhere."""
        if not self.alpha.any():
            return 0.0
        pins = np.zeros(len(self.b))
        pins[self.C] = self.alpha
        return max_abs(self._gradient(pins, with_load=False))

    def _gradient(self, z: np.ndarray, with_load: bool = True) -> np.ndarray:
        """K z - b (``with_load``; else K z) on the free rows, zero on the Dirichlet ones, made
        in one vector (8e6 dofs: each full-length temporary costs some 10 ms)."""
        g = self.K @ z if z.any() else np.zeros(len(self.b))
        if with_load:
            g -= self.b
        g[self._pinned_rows] = 0.0
        return g

    def slack(self, z: np.ndarray, z_max: float | None = None) -> tuple[np.ndarray, float]:
        """z_C - alpha, each value below what double precision resolves in it set to 0
        (``pdas.resolved``: a row of one nonzero), and the scale of the constraint values,
        max(|z_C|, |alpha|). ``z_max``: max |z|, if known."""
        eps, zC = np.finfo(float).eps, z[self.C]
        bound = 2 * eps * (np.abs(zC) + np.abs(self.alpha)) + eps * (max_abs(z) if z_max is None else z_max)
        return resolved(zC - self.alpha, bound), max(np.abs(zC).max(initial=0.0), np.abs(self.alpha).max(initial=0.0),
                                                     np.finfo(float).tiny)

    def kkt(self, z: np.ndarray, active: np.ndarray) -> tuple[KKT, np.ndarray]:
        g = self._gradient(z)
        lam = g[self.C]
        z_max = max_abs(z)
        slack, scale_z = self.slack(z, z_max)
        g[self.C[active]] = 0.0         # off the active rows: what stationarity asks to vanish
        stationary = max_abs(g)
        dual = max(0.0, -lam[active].min(initial=0.0))
        complementarity = np.abs(lam * slack).max(initial=0.0)
        return KKT(
            primal=float(max(0.0, -slack.min(initial=0.0)) / scale_z),
            dual=float(dual / self.load_scale),
            complementarity=float(complementarity / (self.load_scale * scale_z)),
            stationarity=float(stationary / self.load_scale),
            backward=float(max(stationary, dual, complementarity / scale_z)
                           / max(self.K_norm * z_max + self.b_norm, np.finfo(float).tiny)),
        ), lam

    def start_residual(self, z: np.ndarray, active: np.ndarray) -> float:
        """The KKT residual of a start with the set ``active``."""
        return self.kkt(z, active)[0].residual

    def solve_set(self, active: np.ndarray, start: np.ndarray | None, tol: float) -> tuple[np.ndarray, np.ndarray, KKT]:
        """The active constraints as pins z_i = alpha_i, beside the Dirichlet pins, solved to
        max |K z - b| <= tol off the pins; its multipliers and KKT residuals."""
        pinned = ~self.free.copy()
        pinned[self.C[active]] = True
        values = self.lift.copy()
        values[self.C[active]] = self.alpha[active]
        z = self.system.solve(pinned, values, start, tol=tol)
        kkt, lam = self.kkt(z, active)
        return z, lam, kkt

    # -- the active set iteration ---------------------------------------------------------
    def solve(self, initial_active: np.ndarray | None = None, start: np.ndarray | None = None) -> QPSolution:
        """From a predicted active set and, for iterative systems, a start vector (nested
        iteration), by ``pdas.primal_dual_active_set`` with the gain ``options.loose_gain``.

        With an iterative system a new set is solved only to ``options.forcing`` times the
        current KKT residual, when that is much shallower, and the set that solve leaves
        unchanged again, from there and with the same V-cycle, to the full depth. Same KKT
        point; the nested iteration's prediction is usually a few rows off, and a full-depth solve
        of a set that then changes is CG work thrown away (``python -m harness bench`` counts each
        contact solve's CG iterations)."""
        clock = time.perf_counter()
        m = len(self.C)
        active = np.zeros(m, dtype=bool) if initial_active is None else np.asarray(initial_active, bool).copy()
        options = self.options
        end = primal_dual_active_set(self, active, start, options, options.loose_gain, options.active_set_iterations)
        return QPSolution(
            z=end.z, multipliers=end.multipliers, active=end.active, kkt=end.kkt, iterations=end.iterations,
            work=self.system.work(),
            seconds=time.perf_counter() - clock, status=end.status,
        )


def row_norm(K: sp.csr_matrix, rows: np.ndarray, chunk: int = 1 << 22) -> float:
    """max over ``rows`` of sum_j |K_ij| (||K||_inf restricted to them)."""
    return float(row_sums(K, chunk)[rows].max(initial=0.0))


def row_sums(K: sp.csr_matrix, chunk: int = 1 << 22) -> np.ndarray:
    """sum_j |K_ij| of every row, from K's CSR arrays a block of about ``chunk`` entries at a
    time: no copy of K (which row slices make, once per method and level); row sums by
    ``np.add.reduceat`` over each block's non-empty rows, faster than differences of a
    cumulative sum."""
    n, indptr = K.shape[0], K.indptr
    step = max(1, chunk // max(1, K.nnz // max(1, n)))
    sums = np.zeros(n)
    for start in range(0, n, step):
        stop = min(n, start + step)
        low = indptr[start]
        starts = indptr[start:stop]
        filled = np.flatnonzero(indptr[start + 1:stop + 1] > starts)
        if len(filled):
            # consecutive starts of the non-empty rows bound each row's entries exactly
            sums[start + filled] = np.add.reduceat(np.abs(K.data[low:indptr[stop]]), starts[filled] - low)
    return sums


def _columns(n: int, columns: list) -> np.ndarray:
    return np.column_stack(columns) if columns else np.zeros((n, 0))


def solve_contact_qp(qp, initial_active=None, textbook: bool = False, multilevel=None, start=None,
                     options: SolverOptions = _DEFAULT) -> QPSolution:
    """The harness's solver on a ``fem.cones.ContactQP``: multigrid-preconditioned CG when the
    mesh hierarchy's ``multilevel`` is given, else sparse Cholesky; ``textbook=True`` gives the
    reference PDAS (cold start, refactorisation at every iteration) used by the benchmark and
    the tests."""
    if textbook:
        system = FactorisedSystem(qp.K, qp.K_ngs, qp.b, refactor_above=0)
    elif multilevel is not None:
        if multilevel.ndof != qp.problem.mesh.nv * qp.problem.physics.components:
            raise ValueError("the multilevel hierarchy does not end at this problem's mesh (refined() missed?)")
        system = MultigridSystem(qp.K_ngs, qp.b, multilevel, ContactEdges.of(qp.problem), options=options)
    else:
        system = FactorisedSystem(qp.K, qp.K_ngs, qp.b, options.refactor_above)
    solver = ActiveSetSolver(qp.K, qp.b, qp.free, qp.C, qp.alpha, lift=qp.lift, system=system, options=options)
    if textbook:
        return solver.solve()
    return solver.solve(initial_active, start)
