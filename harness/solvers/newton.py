"""Semismooth Newton for the systems F(u_h) = 0 of the weak methods, each a contact law
(``fem.contact_laws``; the built-in penalty and Nitsche laws are ``fem.contact_laws.builtin``).

F is piecewise affine: on each set of Gauss points where the bracket P(u) is positive it is
the affine map J u - r. The generalised Newton step (Qi & Sun, Math. Program. 58 (1993); for
contact, Hintermueller, Ito & Kunisch, SIAM J. Optim. 13 (2002)) solves that affine system of
the current set exactly, so the method stops -- with the exact discrete solution, up to the
linear solver's tolerance -- as soon as the set no longer changes: like the active set method
of the cones, whose nested iteration (a start interpolated from the coarser level) it shares.

A friction law (``fem.contact_laws.channels.FrictionSystem``) has integer branch codes and, where
its terms are not affine on a branch (Tresca's disc in 3D: the slip branch s x/|x|), ``affine``
False: then every step is linearised at its iterate (J_S(u), r_S = J_S(u) u - F_S(u)) and damped
by the line search below, and Newton converges superlinearly rather than in finitely many steps.

Stopping test: the relative residual max |F(u)| / max |b - A u_D| over the free dofs <= 1e-10
(``SolverOptions.tolerance``; the stationarity part of the cones' KKT residual; F = 0 is the
whole discrete problem), or, once u solved the affine system of its own set, the normwise
backward error of that system at round-off (<= 1e-13, ``SolverOptions.roundoff_backward_error``:
the relative residual's floor grows like eps cond(J) on fine meshes; ``pdas.KKT.converged``).
No silent failure: a status "converged" or why not. A repeated set without convergence, or for
a friction law a full step that did not lower max |F| below its best (``UNDAMPED_STEPS``), switch to damped steps (halving on max |F|), which ends
cycling of the full steps (a repeat is seen only among the full-depth steps: a multigrid step
on a new set is loose, and sets that alternate A, B, A, ... are each new). Without the second
test Tresca's sets need not repeat to cycle: where the contact load is singular
(tresca-corner-r12, g_C ~ x^{-1/2} at the end of a stick zone) the discrete friction force
swings between -s and s from one Gauss point to the next, a full step sends a point from one
slip branch straight to the other (the stick slab |u| <~ gamma s is thin), every such flip
leaves 2 s times a vertex hat's integral (~ s h) in F, and the stick set drifts, one or two
points a step, without coming back; a run
whose max |F| has not fallen below its best for ``SolverOptions.stall_steps`` steps stops as
"stalled" (past Nitsche's coercivity bound, theta = 1, J is indefinite and the discrete problem
may have no solution: such runs would wander for all their steps). The stall count is chosen so
that every run of the report's sweeps that converges at all converges in the same steps with it
(the sweep's rows and their ``solver_iterations`` show it), while the others stop early.

Linear solves: J is A with the rows of the elements along Gamma_C changed. A nonsymmetric J of
a Coulomb law (every theta: ``fem.contact_laws.coulomb``) goes to GMRES with the same V-cycle
(``krylov.gmres``; its iterations are counted as CG's). Symmetric J
(penalty; Nitsche with theta = 1) goes to the cones' multigrid CG (``bound_constraints.MultigridSystem``:
the V-cycle smooths with J itself; its P1 coarse spaces are A's -- vector P1 in the rotated frame
for elasticity -- truncated at the Dirichlet dofs and at the Gamma_C vertices with an active
contact term, which are nearly pins); a
nonsymmetric J (theta = 0, -1), no hierarchy, or a CG that fails (J indefinite: theta = 1
past its gamma0 bound; CG stops at the first non-positive curvature) goes to a factorisation
kept across the steps and updated in place (J keeps its pattern): sparse LDL^T if J is
symmetric, else UMFPACK. Past the bound Newton may wander for its 60 steps; an update costs a
fifth of a new factorisation, which made the report's sweeps 3x faster.
"""
from __future__ import annotations

import time
from dataclasses import dataclass

import ngsolve as ngs
import numpy as np

from ..fem.contact_laws.two_body import JointProblem
from .bound_constraints import MultigridSystem, row_norm
from .options import SolverOptions
from .pdas import loose_depth
from .two_body_multigrid import law_embedding, law_hierarchy

_DEFAULT = SolverOptions()
# a friction law's full steps without a new lowest max |F| before its steps are damped (the
# module's note). Friction laws only: frictionless Nitsche past its coercivity bound (corner-r12,
# gamma0 = 0.3, tests/test_weak_contact.py) converges undamped after up to 9 such steps, and
# damping stalls it
UNDAMPED_STEPS = 1


@dataclass
class NewtonSolution:
    u: np.ndarray
    active: np.ndarray          # the branch at the Gauss points: bool (P(u) > 0), or a friction law's codes
    residual: float             # max |F(u)| / max |b - A u_D| on the free dofs
    iterations: int
    linear_iterations: int      # CG iterations (multigrid), or LU factorisations
    seconds: float
    status: str
    backward: float = 0.0       # the normwise backward error of the last affine system (``backward_error``)


class _DirectSystem:
    """J^{-1} by a sparse factorisation, updated for every Newton step (J changes in place, on
    one pattern): NGSolve's sparse Cholesky (LDL^T) for a symmetric J, whose numeric update on
    the kept ordering is much cheaper than a new UMFPACK factorisation (``bench --only solver``
    times both); UMFPACK for a nonsymmetric J, or when the LDL^T (without pivoting, J maybe
    indefinite) misses the tolerance."""

    def __init__(self, J_ngs, rhs, symmetric: bool):
        self.J_ngs, self.rhs = J_ngs, rhs
        self.kind = "sparsecholesky" if symmetric else "umfpack"
        self.inverse, self.pinned = None, None
        self.factorizations = 0

    def for_step(self, rhs) -> "_DirectSystem":
        """The same factorisation, to be updated with the step's J, for the step's ``rhs``."""
        self.rhs = rhs
        return self

    def _factorize(self, pinned) -> None:
        if self.inverse is not None and np.array_equal(pinned, self.pinned):
            self.inverse.Update()
        else:
            self.inverse = self.J_ngs.Inverse(ngs.BitArray((~pinned).tolist()), inverse=self.kind)
            self.pinned = pinned.copy()
        self.factorizations += 1

    def solve(self, pinned, values, start=None, tol=None):
        self._factorize(pinned)
        b, x = self.J_ngs.CreateColVector(), self.J_ngs.CreateColVector()
        z = np.where(pinned, values, 0.0)
        b.FV().NumPy()[:] = np.where(pinned, 0.0, self.rhs - _apply(self.J_ngs, z))
        x.data = self.inverse * b
        u = z + np.where(pinned, 0.0, x.FV().NumPy())
        if self.kind == "sparsecholesky" and tol is not None and not _free_residual(self.J_ngs, u, self.rhs, pinned) <= tol:
            self.kind, self.inverse = "umfpack", None
            return self.solve(pinned, values, start, tol)
        return u


def _free_residual(J_ngs, u: np.ndarray, rhs: np.ndarray, pinned: np.ndarray) -> float:
    return float(np.abs(np.where(pinned, 0.0, _apply(J_ngs, u) - rhs)).max(initial=0.0))


def _apply(matrix, z: np.ndarray) -> np.ndarray:
    x, y = matrix.CreateColVector(), matrix.CreateColVector()
    x.FV().NumPy()[:] = z
    y.data = matrix * x
    return y.FV().NumPy().copy()


class _AffineSolves:
    """The linear solves of the Newton steps, J u_new = r of the step's set: multigrid CG while J
    is symmetric, a hierarchy is given and CG converges, else a factorisation kept across the
    steps (the module's note). ``iterations``: CG iterations, or factorisations."""

    def __init__(self, system, multilevel, options: SolverOptions):
        self.system, self.multilevel, self.options = system, multilevel, options
        # the V-cycle's P1 embedding (one body's; two bodies' joint one), made once
        self.edges = None if multilevel is None else law_embedding(system.problem)
        # a nonsymmetric J with a hierarchy: GMRES with the same V-cycle (``krylov``) for the
        # laws that ask for it (Coulomb's, ``nonsymmetric_krylov``); the frictionless theta = 0, -1
        # variants keep their factorisation, whose updates the report's sweeps are timed with
        self.krylov = bool(getattr(system, "nonsymmetric_krylov", False))
        self.direct = multilevel is None or not (system.symmetric or self.krylov)
        self.factored = None        # the factorisation of J, updated step by step once direct
        self.linear = None          # the multigrid system of the current set
        self.rhs, self.step_set = None, None
        self.iterations = 0

    def new_set(self, step_set: np.ndarray, u: np.ndarray | None = None) -> None:
        """The Newton step as the affine system of this set, J u_new = r (= J u - F(u) for the
        set of u), linearised at ``u`` where the terms are not affine on a branch; the linear
        solver starts from u."""
        self.system.set_jacobian(step_set, u)
        self.rhs = self.system.affine_rhs(step_set, u)
        self.linear, self.step_set = None, step_set

    def solve(self, u: np.ndarray, tol: float, direct_tol: float) -> np.ndarray:
        """u_new to max |J u_new - r| <= tol by CG from u (``direct_tol`` for a factorisation)."""
        if not self.direct:
            candidate = self._multigrid(u, tol)
            # CG did not converge: J is not positive definite (Nitsche theta = 1 with gamma0 past
            # its coercivity bound); a factorisation solves what CG cannot, from now on
            missed = _linear_residual(self.system, candidate, self.rhs)
            self.direct = not missed <= 10 * tol
            if self.direct:
                _refuse_large_factorisation(self.system.problem, self.iterations, missed, tol)
        if self.direct:
            candidate = self._factorised(direct_tol)
        return candidate

    def _multigrid(self, u: np.ndarray, tol: float) -> np.ndarray:
        # the same set again: the same J, r and V-cycle; CG goes on from u
        system, problem = self.system, self.system.problem
        if self.linear is None:
            levels = law_hierarchy(problem, self.multilevel, self.edges, system.delta)
            # the coarse levels carry the law's terms between two bodies (Galerkin): none is truncated
            stiff = None if isinstance(problem, JointProblem) else system.stiff_vertices(self.step_set, levels.ndof)
            self.linear = MultigridSystem(system.J_ngs, self.rhs, levels, self.edges, stiff_vertices=stiff,
                                          options=self.options, symmetric=system.symmetric)
        before = self.linear.cg_iterations
        candidate = self.linear.solve(~problem.free, problem.lift, start=u, tol=tol)
        self.iterations += self.linear.cg_iterations - before
        return candidate

    def _factorised(self, tol: float) -> np.ndarray:
        system, problem = self.system, self.system.problem
        self.factored = (self.factored or _DirectSystem(system.J_ngs, self.rhs, system.symmetric)).for_step(self.rhs)
        before = self.factored.factorizations
        candidate = self.factored.solve(~problem.free, problem.lift, tol=tol)
        self.iterations += self.factored.factorizations - before
        return candidate


# The largest 3D problem a failed Krylov solve may fall back to a sparse factorisation for: its
# fill grows like n^(4/3) (nested dissection), and 3D vector P2's couples each dof with ~100
# others. Measured (UMFPACK, 2 cores): 23,817 dofs (mindlin-sphere at nu = 0.47, level 0), 5 s a
# factorisation; 1.4e6 dofs (level 2) passed 23 GiB before it finished. 2D's fill (n log n) fits.
DIRECT_FALLBACK_DOFS_3D = 200_000


class LinearSolveFailed(RuntimeError):
    """A multigrid Krylov solve missed its tolerance on a problem too large to factorise."""


def _refuse_large_factorisation(problem, iterations: int, missed: float, tol: float) -> None:
    if problem.mesh.dim == 3 and problem.ndof > DIRECT_FALLBACK_DOFS_3D:
        raise LinearSolveFailed(
            f"the Krylov solve with the V-cycle missed max|r| <= {tol:.1e} ({missed:.1e} after {iterations} "
            f"iterations in all) on {problem.ndof} 3D dofs, and a sparse factorisation that large would not fit "
            f"(DIRECT_FALLBACK_DOFS_3D = {DIRECT_FALLBACK_DOFS_3D}): raise the method's "
            f"solver=SolverOptions(cg_iterations=...), or use fewer levels")


def solve_semismooth_newton(system, start: np.ndarray | None = None, multilevel=None,
                            predicted: np.ndarray | None = None, options: SolverOptions = _DEFAULT) -> NewtonSolution:
    """F(u) = 0 for a ``fem.contact_laws.system.LawSystem``, from ``start`` (Dirichlet values are
    imposed on it), with multigrid CG when ``multilevel`` is given and J is symmetric.
    ``predicted``: the active Gauss points of the first step (nested iteration), instead of
    those of ``start``."""
    clock = time.perf_counter()
    problem = system.problem
    u = np.where(~problem.free, problem.lift, 0.0 if start is None else start)
    scale = load_scale(system)
    steps = _NewtonSteps(system, multilevel, options, scale)
    stall = _StallWatch(options.stall_steps)
    status = f"not converged in {options.newton_iterations} iterations"
    for iteration in range(options.newton_iterations + 1):
        F = system.residual(u)
        residual = float(np.abs(F).max(initial=0.0) / scale)
        # the branch of every point: bool (a contact law: in contact) or integer codes (a
        # friction law, ``fem.contact_laws.channels``; 0 the stick branch)
        active = system.branch(u)
        # a stall is what is left after the convergence and divergence tests
        stopped = _stopped(system, u, F, residual, active, steps.last_set, options) or stall.stalled(residual, iteration)
        if stopped:
            status = stopped
            break
        if iteration == options.newton_iterations:
            break
        u = steps.step(u, residual, predicted if iteration == 0 and predicted is not None else active)
    backward = backward_error(system, u, F)
    return NewtonSolution(u, active, residual, iteration, steps.solves.iterations, time.perf_counter() - clock, status, backward)


def _stopped(system, u: np.ndarray, F: np.ndarray, residual: float, active: np.ndarray, last_set, options) -> str | None:
    """The status "converged" or "diverged: ..." when u ends the iteration (the module's
    stopping test), else None. ``last_set``: the set the last step solved on (None before the first step)."""
    if residual <= options.tolerance:
        return "converged"
    if last_set is not None and np.array_equal(active, last_set):
        # u solved the affine system of its own set: what is left of F is the linear solve's,
        # at the round-off floor when its backward error is (``pdas.KKT.converged``)
        if backward_error(system, u, F) <= options.roundoff_backward_error:
            return "converged"
    if not np.isfinite(residual):
        return "diverged: the residual is not finite"
    return None


class _StallWatch:
    """The best max |F| so far and its step: a run that has not gone below it for ``steps``
    steps stops as "stalled" (``SolverOptions.stall_steps``; the module's note: past Nitsche's
    coercivity bound the discrete problem may have no solution, and Newton wanders)."""

    def __init__(self, steps: int):
        self.steps = steps
        self.best, self.best_iteration = np.inf, 0

    def stalled(self, residual: float, iteration: int) -> str | None:
        """The status "stalled: ..." once the best is ``steps`` steps old, else None."""
        if residual < self.best:
            self.best, self.best_iteration = residual, iteration
        elif iteration - self.best_iteration >= self.steps:
            return f"stalled: max |F| not below its best ({self.best:.1e}) in {self.steps} steps"
        return None


class _NewtonSteps:
    """The Newton steps of a run: each one's set, the depth its affine system is solved to, and
    damping once a set comes again (the module's note)."""

    def __init__(self, system, multilevel, options: SolverOptions, scale: float):
        self.system, self.options, self.scale = system, options, scale
        self.full = options.linear_depth * options.tolerance
        self.solves = _AffineSolves(system, multilevel, options)
        self.seen, self.damped = set(), False
        self.last_set = None        # the set of the last step
        self.best, self.since_best = np.inf, 0      # the lowest max |F| so far, and the steps since

    def step(self, u: np.ndarray, residual: float, step_set: np.ndarray) -> np.ndarray:
        """The next iterate from u (of max |F| ``residual``, relative) by the step on ``step_set``.

        A set that differs from the last step's is solved to ``options.forcing`` times the
        residual when that is much shallower (``pdas.loose_depth``; inexact semismooth Newton:
        such a step decides the next set); a set a step leaves unchanged is solved to the full
        depth (``options.linear_depth`` of the tolerance), which decides convergence, keeping
        J, r and the V-cycle. A set solved to full depth before, met again, or ``UNDAMPED_STEPS``
        steps without a new lowest max |F|, mean cycling of the full steps: from then on every step is damped."""
        options, full, solves = self.options, self.full, self.solves
        key = step_set.tobytes()
        affine = getattr(self.system, "affine", True)
        # not affine on a branch (the disc of 3D Tresca): the same set comes again as the
        # iterates converge, so every step is damped (a monotone line search on max |F|)
        # full steps that have not lowered max |F| below its best for ``UNDAMPED_STEPS`` steps (the
        # module's note: Tresca's slip branches cycle through sets that never repeat): from then
        # on every step is damped
        self.best, self.since_best = (residual, 0) if residual < self.best else (self.best, self.since_best + 1)
        friction = step_set.dtype != bool       # a friction law's integer branch codes
        self.damped = self.damped or key in self.seen or not affine or (friction and self.since_best >= UNDAMPED_STEPS)
        new_set = self.last_set is None or not np.array_equal(step_set, self.last_set)
        loose = new_set and not (solves.direct or self.damped)
        depth = loose_depth(residual, full, options.forcing, options.loose_gain) if loose else full
        if depth <= full:
            self.seen.add(key)      # sets of full-depth steps only: a loose one is solved again
        self.last_set = step_set
        if new_set or not affine:
            solves.new_set(step_set, u)
        candidate = solves.solve(u, depth * self.scale, full * self.scale)
        if self.damped:
            candidate = _damped(self.system, u, candidate, residual * self.scale)
        return candidate


def backward_error(system, u: np.ndarray, F: np.ndarray) -> float:
    """max |F(u)| / (||J||_inf ||u||_inf + ||rhs||_inf) over the free dofs: the normwise backward
    error of the affine system J u = rhs of u's set (Higham 2002, Theorem 7.1)."""
    free = system.problem.free
    return float(np.abs(F[free]).max(initial=0.0)
                 / max(row_norm(system.J, free) * np.abs(u).max(initial=0.0) + np.abs(system.rhs[free]).max(initial=0.0), np.finfo(float).tiny))


def _linear_residual(system, u: np.ndarray, rhs: np.ndarray) -> float:
    return float(np.abs(np.where(system.problem.free, system.J @ u - rhs, 0.0)).max(initial=0.0))


def load_scale(system) -> float:
    """max |b - A u_D| on the free dofs, or the force holding Gamma_C at the obstacle if larger:
    the scale of the residual (as for the cones' KKT)."""
    problem = system.problem
    lift = np.where(problem.free, 0.0, problem.lift)
    Au = system.J @ lift - system.delta @ lift
    return max(np.abs((problem.b - Au)[problem.free]).max(initial=0.0), system.obstacle_force, np.finfo(float).tiny)


def _damped(system, u: np.ndarray, full: np.ndarray, current: float) -> np.ndarray:
    """The longest of the steps 1, 1/2, 1/4, ... that lowers max |F|."""
    step = full - u
    for k in range(12):
        candidate = u + 0.5**k * step
        if np.abs(system.residual(candidate)).max() < current:
            return candidate
    return full
