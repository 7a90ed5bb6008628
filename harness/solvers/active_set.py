"""Exact solution of the discrete contact problems (3.6) and (5.1).

In the variables of its contact model (``models``: NGSolve's hierarchical P2 variables with
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

from .multigrid import ContactEdges, TruncatedVCycle, pcg

DEFAULT_TOLERANCE = 1e-10
# a stationarity residual this small relative to ||K|| ||z|| + ||b|| is round-off (``KKT.converged``)
ROUNDOFF_BACKWARD_ERROR = 1e-13
DEFAULT_REFACTOR_ABOVE = 24  # ~ the cost of a factorisation in solves, at 1e5-1e6 dofs
# the forcing term: a set that is new is solved to this fraction of the current residual
# (``ActiveSetSolver.solve``; Newton's steps alike), when that is at least LOOSE_GAIN times
# shallower than the full depth (about 7 CG iterations saved, more than an extra step costs)
FORCING = 1e-3
LOOSE_GAIN = 1e3


def loose_depth(residual: float, full: float, gain: float = LOOSE_GAIN) -> float:
    """The depth of the solve of a new set, from the current relative residual: FORCING times
    it, when that is at least ``gain`` times shallower than the full depth."""
    depth = FORCING * residual
    return depth if depth >= gain * full else full


@dataclass(frozen=True)
class KKT:
    """Relative KKT residuals of a candidate solution (each dimensionless), and the normwise
    backward error of its stationarity."""

    primal: float           # max (alpha - z_C)^+ / max(|z_C|, |alpha|)
    dual: float             # max (-lambda)^+ on the active set / |b - K u_D|
    complementarity: float  # max |lambda_i (z_i - alpha_i)| / (|b - K u_D| max(|z_C|, |alpha|))
    stationarity: float     # max |K z - b| on free dofs off the active set / |b - K u_D|
    backward: float = 0.0   # the three force parts (dual, complementarity, stationarity), unscaled,
                            # over ||K||_inf ||z||_inf + ||b||_inf: a normwise backward error

    @property
    def residual(self) -> float:
        return max(self.primal, self.dual, self.complementarity, self.stationarity)

    def converged(self, tol: float) -> bool:
        """``residual`` <= tol; or, where tol times the load lies below what double precision
        resolves in K z - b, primal feasibility <= tol and the force parts at round-off.

        The relative stationarity has a floor: K z - b is computed with an error of about
        eps ||K|| ||z||, while the load |b| ~ h^d |f| shrinks under refinement, so the floor
        grows like eps cond(K) ~ eps h^-2 (measured on a P1 problem: 4.5e-12, 6.5e-12, 2.8e-11,
        1.3e-10 on 1.2e4 ... 7.9e5 dofs; a direct solve on the same active set gives 3.8e-9, a
        tighter CG 1.7e-10). No polishing goes below it. What double precision can certify is
        the normwise backward error (Rigal & Gaches 1967; Higham, Accuracy and Stability of
        Numerical Algorithms, 2002, Theorem 7.1): z solves the system of a K and b perturbed by
        that relative amount. The multipliers and the complementarity are forces of the same
        K z - b and share its floor. ``ROUNDOFF_BACKWARD_ERROR`` = 1e-13, about 450 eps."""
        return self.residual <= tol or (self.primal <= tol and self.backward <= ROUNDOFF_BACKWARD_ERROR)


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


def ngsolve_matrix(K: sp.spmatrix):
    """An NGSolve copy of a scipy matrix (slow: prefer ``models.transformed_matrix``)."""
    coo = sp.coo_matrix(K)
    return ngs.la.SparseMatrixd.CreateFromCOO(
        coo.row.astype(np.int64), coo.col.astype(np.int64), coo.data.astype(float), K.shape[0], K.shape[1])


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
    refactorised instead; 0 gives the textbook method (refactorise at every iteration).
    """

    def __init__(self, K: sp.csr_matrix, K_ngs, b: np.ndarray, refactor_above: int = DEFAULT_REFACTOR_ABOVE):
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
    from the previous iterate: one preconditioner per pin set, no factorisation of K."""

    iterative = True            # its solves are as deep as asked: loose ones cost less

    def __init__(self, K_ngs, b: np.ndarray, multilevel, edges: ContactEdges, stiff_vertices=None):
        self.K_ngs, self.b, self.multilevel, self.edges = K_ngs, b, multilevel, edges
        self.stiff_vertices = stiff_vertices        # see ``multigrid.TruncatedVCycle``
        self.cg_iterations = 0
        self.preconditioners = 0
        self._last = None           # (pins, V-cycle) of the last solve

    def solve(self, pinned: np.ndarray, values: np.ndarray, start=None, tol: float = 0.0) -> np.ndarray:
        """The same to max |K z - b| <= tol off the pins, from ``start`` (else zero)."""
        free = ~pinned
        z = np.where(pinned, values, 0.0 if start is None else start)
        key = free.tobytes()
        if self._last is None or self._last[0] != key:
            # the same pins again (a loose solve's set, solved to the full depth): the same V-cycle
            self._last = key, TruncatedVCycle(self.multilevel, self.K_ngs, free, self.edges, self.stiff_vertices)
            self.preconditioners += 1
        preconditioner = self._last[1]
        z, iterations = pcg(self.K_ngs, preconditioner, self.b, z, free, tol)
        self.cg_iterations += iterations
        return z

    def work(self) -> dict:
        return {"cg_iterations": self.cg_iterations, "preconditioners": self.preconditioners}


class ActiveSetSolver:
    """Primal-dual active set solver for min 1/2 z'Kz - b'z, z[~free] = lift[~free], z[C] >= alpha.

    ``system`` solves the linear problem of one active set (a ``FactorisedSystem`` by default).
    """

    def __init__(self, K, b, free, C, alpha, K_ngs=None, lift=None, tol: float = DEFAULT_TOLERANCE,
                 max_iterations: int = 500, system=None):
        self.K = sp.csr_matrix(K)
        self.b = np.asarray(b, float)
        self.free = np.asarray(free, bool)
        self.C = np.asarray(C, np.int64)
        self.alpha = np.asarray(alpha, float)
        self.lift = np.zeros(len(self.b)) if lift is None else np.where(self.free, 0.0, lift)
        self.tol, self.max_iterations = tol, max_iterations
        if not self.free[self.C].all():
            raise ValueError("a constrained dof lies on the Dirichlet boundary")
        # the scale of the forces: the loads, and the force that holds the constrained dofs at
        # the obstacle (the only one in a problem driven by its gap alone)
        pins = np.zeros(len(self.b))
        pins[self.C] = self.alpha
        self.load_scale = max(np.abs((self.b - self.K @ self.lift)[self.free]).max(initial=0.0),
                              np.abs((self.K @ pins)[self.free]).max(initial=0.0), np.finfo(float).tiny)
        # ||K||_inf and ||b||_inf over the free rows: the scale of the normwise backward error
        self.K_norm = row_norm(self.K, self.free)
        self.b_norm = float(np.abs(self.b[self.free]).max(initial=0.0))
        if system is None:
            system = FactorisedSystem(self.K, ngsolve_matrix(self.K) if K_ngs is None else K_ngs, self.b)
        self.system = system

    def kkt(self, z: np.ndarray, active: np.ndarray) -> tuple[KKT, np.ndarray]:
        g = np.where(self.free, self.K @ z - self.b, 0.0)
        lam, slack = g[self.C], z[self.C] - self.alpha
        scale_z = max(np.abs(z[self.C]).max(initial=0.0), np.abs(self.alpha).max(initial=0.0), np.finfo(float).tiny)
        off_active = g.copy()
        off_active[self.C[active]] = 0.0
        return KKT(
            primal=float(max(0.0, -slack.min(initial=0.0)) / scale_z),
            dual=float(max(0.0, -lam[active].min(initial=0.0)) / self.load_scale),
            complementarity=float(np.abs(lam * slack).max(initial=0.0) / (self.load_scale * scale_z)),
            stationarity=float(np.abs(off_active).max(initial=0.0) / self.load_scale),
            backward=float(max(np.abs(off_active).max(initial=0.0), max(0.0, -lam[active].min(initial=0.0)),
                               np.abs(lam * slack).max(initial=0.0) / scale_z)
                           / max(self.K_norm * np.abs(z).max(initial=0.0) + self.b_norm, np.finfo(float).tiny)),
        ), lam

    def _solve_active(self, active: np.ndarray, start: np.ndarray | None, depth: float) -> np.ndarray:
        """The active constraints as pins z_i = alpha_i, beside the Dirichlet pins, solved to
        max |K z - b| <= depth * load_scale off the pins."""
        pinned = ~self.free.copy()
        pinned[self.C[active]] = True
        values = self.lift.copy()
        values[self.C[active]] = self.alpha[active]
        return self.system.solve(pinned, values, start, tol=depth * self.load_scale)

    # -- the active set iteration ---------------------------------------------------------
    def solve(self, initial_active: np.ndarray | None = None, start: np.ndarray | None = None) -> QPSolution:
        """From a predicted active set and, for iterative systems, a start vector (nested iteration).

        Linear solves go a tenth of the KKT tolerance deep, so that the stationarity they leave
        never decides the KKT check. With an iterative system, a set that is new is
        solved only to ``FORCING`` times the current KKT residual, when that is much shallower
        (``loose_depth``): an inexact semismooth Newton step (the forcing term of Dembo,
        Eisenstat & Steihaug, SIAM J. Numer. Anal. 19 (1982); the exact method is Hintermueller,
        Ito & Kunisch 2002). That solve only decides the next set; the set it leaves unchanged
        is solved again, from there and with the same V-cycle, to the full depth, which decides
        convergence, and only sets judged on full-depth solves count as seen (for Murty's rule).
        Same KKT point; the nested iteration's prediction is usually a few rows off, and its
        full-depth solve was half the CG work (measured: 30% fewer CG iterations on the report's
        seven-level cases, the same rows to 1e-8 relative, every KKT residual <= 1e-10)."""
        clock = time.perf_counter()
        m = len(self.C)
        active = np.zeros(m, dtype=bool) if initial_active is None else np.asarray(initial_active, bool).copy()
        seen: set[bytes] = set()
        pivoting = False
        iterative = getattr(self.system, "iterative", False)
        full = 0.1 * self.tol
        initial = self.lift if start is None else start
        depth = loose_depth(self.kkt(initial, active)[0].residual, full) if iterative else full
        status = f"not converged in {self.max_iterations} iterations"
        z = start                   # each solve starts from the previous iterate
        for iteration in range(1, self.max_iterations + 1):
            z = self._solve_active(active, z, depth)
            kkt, lam = self.kkt(z, active)
            if kkt.converged(self.tol):
                status = "converged"
                break
            # Decisions use a fraction of the solve's depth so that neither round-off nor
            # a loose solve's residual flips a row.
            slack = z[self.C] - self.alpha
            scale_z = max(np.abs(z[self.C]).max(), np.abs(self.alpha).max(initial=0.0), np.finfo(float).tiny)
            leave = active & (lam < -depth * self.load_scale)
            enter = ~active & (slack < -depth * scale_z)
            if not (leave.any() or enter.any()):
                if depth > full:
                    depth = full        # the set of a loose solve: solve it to the full depth
                    continue
                status = f"stalled: KKT residual {kkt.residual:.2e} with a consistent active set"
                break
            if depth <= full:
                seen.add(active.tobytes())      # sets judged on a full-depth solve only
            active, pivoting = next_active_set(active, leave, enter, seen, pivoting)
            depth = loose_depth(kkt.residual, full) if iterative and not pivoting else full
        return QPSolution(
            z=z, multipliers=lam, active=active, kkt=kkt, iterations=iteration,
            work=self.system.work(),
            seconds=time.perf_counter() - clock, status=status,
        )


def next_active_set(active: np.ndarray, leave: np.ndarray, enter: np.ndarray, seen: set,
                    pivoting: bool) -> tuple[np.ndarray, bool]:
    """(the next active set, whether pivoting): the primal-dual update (the rows that ``leave``
    out, those that ``enter`` in), or, once a set would repeat (or already when ``pivoting``),
    Murty's least-index rule: flip only the first violated row. Shared by the bound solver and
    ``general_constraints``."""
    candidate = (active & ~leave) | enter
    if pivoting or candidate.tobytes() in seen:
        first = int(np.flatnonzero(leave | enter)[0])
        candidate = active.copy()
        candidate[first] = not active[first]
        return candidate, True
    return candidate, False


def row_norm(K: sp.csr_matrix, rows: np.ndarray, chunk: int = 1 << 22) -> float:
    """max over ``rows`` of sum_j |K_ij| (||K||_inf restricted to them), from K's CSR arrays a
    block of about ``chunk`` entries at a time: no copy of K (0.25 s at 5.7e5 P2 dofs by row
    slices, which the study paid once per method and level; row sums by ``np.add.reduceat``
    over each block's non-empty rows, a third of the time of differences of a cumulative sum)."""
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
    return float(sums[rows].max(initial=0.0))


def _columns(n: int, columns: list) -> np.ndarray:
    return np.column_stack(columns) if columns else np.zeros((n, 0))


def solve_contact_qp(qp, initial_active=None, textbook: bool = False, tol: float = DEFAULT_TOLERANCE,
                     multilevel=None, start=None) -> QPSolution:
    """The harness's solver on a ``models.ContactQP``: multigrid-preconditioned CG when the
    mesh hierarchy's ``multilevel`` is given, else sparse Cholesky; ``textbook=True`` gives the
    reference PDAS (cold start, refactorisation at every iteration) used by the benchmark and
    the tests."""
    if textbook:
        system = FactorisedSystem(qp.K, qp.K_ngs, qp.b, refactor_above=0)
    elif multilevel is not None:
        if multilevel.ndof != qp.problem.mesh.nv * qp.problem.physics.components:
            raise ValueError("the multilevel hierarchy does not end at this problem's mesh (refined() missed?)")
        system = MultigridSystem(qp.K_ngs, qp.b, multilevel, ContactEdges.of(qp.problem))
    else:
        system = FactorisedSystem(qp.K, qp.K_ngs, qp.b)
    solver = ActiveSetSolver(qp.K, qp.b, qp.free, qp.C, qp.alpha, lift=qp.lift, tol=tol, system=system)
    if textbook:
        return solver.solve()
    return solver.solve(initial_active, start)
