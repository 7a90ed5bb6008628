"""Exact solution of the discrete Tresca problems (``fem.friction``):

    minimise 1/2 z^T K z - b^T z + sum_i c_i |z_{F_i}|,   z = u_D on Gamma_u,

K symmetric positive definite on the free dofs, c >= 0. Optimality: the friction force
lambda = (b - K z)_F lies in c * d|z_F| (the subdifferential), row by row one of three branches:

    stick:  z_i = 0,   |lambda_i| <= c_i;     slip+:  z_i >= 0, lambda_i = c_i;
    slip-:  z_i <= 0,  lambda_i = -c_i.

These are the optimality conditions of a bound-constrained dual (derived here from the
subdifferential of |.|; Stadler, SIAM J. Optim. 15 (2004), poses the simplified friction problem
and solves its dual by semismooth Newton: only his abstract and the start of his Section 1 were
read): two constraints per row, lambda_i <= c_i (active: slip+) and -lambda_i <= c_i (active:
slip-), with multipliers z_i >= 0 and -z_i >= 0. The primal-dual active set method on them is a
semismooth Newton method (Hintermueller, Ito & Kunisch 2002), and each set's problem is linear: a stick row is a pin
z_i = 0, a slip row a Neumann row with the force c_i moved into the load. So a set costs one
solve with some dofs pinned, by the same systems as the cones' (``bound_constraints``:
the truncated multigrid CG, or Cholesky reused across sets), and the iteration is
``pdas.primal_dual_active_set`` itself (the stopping test on the KKT residual, the loose solves
of new sets, Murty's least-index rule once a set would repeat).

In ``pdas``'s terms the 2m dual constraints are its rows: ``active`` is (slip+, slip-); a row's
"multiplier" is the slip z_i (resp. -z_i) and its "slack" c_i -+ lambda_i, each returned in
force units (the slip times load scale over slip scale) so that the iteration's tests are the
relative ones it applies to the cones.
"""
from __future__ import annotations

import time

import numpy as np

from ..fem.sparse import ngsolve_matrix
from .bound_constraints import FactorisedSystem, MultigridSystem, QPSolution, row_norm
from .multigrid import max_abs
from .options import SolverOptions
from .pdas import KKT, primal_dual_active_set

_DEFAULT = SolverOptions()


class FrictionBounds:
    """The Tresca problem as a ``pdas.ConstraintKind`` (``active``: slip+ rows, then slip- rows)."""

    def __init__(self, K, b, free, F, c, lift, system, options: SolverOptions = _DEFAULT):
        self.K, self.b = K, np.asarray(b, float)
        self.free, self.F, self.c = np.asarray(free, bool), np.asarray(F, np.int64), np.asarray(c, float)
        if (self.c < 0).any():
            raise ValueError("the friction weights must be >= 0 (a quadrature with negative weights makes j_h non-convex)")
        if not self.free[self.F].all():
            raise ValueError("a friction variable lies on the Dirichlet boundary")
        self.lift = np.where(self.free, 0.0, lift)
        self.system, self.options = system, options
        self._pinned_rows = np.flatnonzero(~self.free)
        # the scale of the forces: the loads, the friction forces, the lift's
        self.load_scale = max(max_abs(self._gradient(self.lift)), float(self.c.max(initial=0.0)), np.finfo(float).tiny)
        # K: a scipy matrix, or an operator that knows its row norms (two bodies:
        # ``two_body_operator.CoupledBlocks``)
        self.K_norm = self.K.row_norm(self.free) if hasattr(self.K, "row_norm") else row_norm(self.K, self.free)
        self.b_norm = float(np.abs(self.b[self.free]).max(initial=0.0))

    def _gradient(self, z: np.ndarray) -> np.ndarray:
        g = self.K @ z - self.b
        g[self._pinned_rows] = 0.0
        return g

    def _branches(self, active: np.ndarray):
        m = len(self.F)
        plus, minus = active[:m], active[m:]
        return plus, minus, ~(plus | minus)

    def slip_scale(self, z: np.ndarray) -> float:
        return max(max_abs(z), np.finfo(float).tiny)

    def kkt(self, z: np.ndarray, active: np.ndarray) -> tuple[KKT, np.ndarray]:
        """The relative residuals of ``z`` under the set ``active``, and the rows' multipliers
        (the slips, in force units). Stationarity: K z - b plus the slip rows' forces, on the
        free dofs off the stick rows; dual: |lambda| beyond c on the stick rows; primal: a slip
        of the wrong sign on a slip row."""
        plus, minus, stick = self._branches(active)
        g = self._gradient(z)
        lam = -g[self.F]
        z_max, zF = self.slip_scale(z), z[self.F]
        g[self.F[plus]] += self.c[plus]
        g[self.F[minus]] -= self.c[minus]
        g[self.F[stick]] = 0.0
        stationary = max_abs(g)
        beyond = float(np.maximum(np.abs(lam[stick]) - self.c[stick], 0.0).max(initial=0.0))
        wrong_sign = float(max(np.maximum(-zF[plus], 0.0).max(initial=0.0), np.maximum(zF[minus], 0.0).max(initial=0.0)))
        kkt = KKT(primal=wrong_sign / z_max, dual=beyond / self.load_scale, complementarity=0.0,
                  stationarity=stationary / self.load_scale,
                  backward=max(stationary, beyond) / max(self.K_norm * max_abs(z) + self.b_norm, np.finfo(float).tiny))
        ratio = self.load_scale / z_max
        self._lam = lam
        return kkt, np.concatenate([zF, -zF]) * ratio

    def start_residual(self, z: np.ndarray, active: np.ndarray) -> float:
        return self.kkt(z, active)[0].residual

    def solve_set(self, active: np.ndarray, start, tol: float):
        """Stick rows pinned at 0, slip rows' forces in the load; solved to max |K z - b| <= tol."""
        plus, minus, stick = self._branches(active)
        pinned = ~self.free.copy()
        pinned[self.F[stick]] = True
        load = self.b.copy()
        load[self.F[plus]] -= self.c[plus]
        load[self.F[minus]] += self.c[minus]
        self.system.set_load(load)
        z = self.system.solve(pinned, self.lift, start, tol=tol)
        kkt, multipliers = self.kkt(z, active)
        return z, multipliers, kkt

    def slack(self, z: np.ndarray) -> tuple[np.ndarray, float]:
        """c - lambda and c + lambda (each row's two dual constraints), in force units."""
        lam = -self._gradient(z)[self.F]
        return np.concatenate([self.c - lam, self.c + lam]), self.load_scale

    def forces(self, z: np.ndarray) -> np.ndarray:
        """lambda = (b - K z) at the friction rows: the discrete friction force per node."""
        return -self._gradient(z)[self.F]

    def solve(self, predicted: np.ndarray | None = None, start: np.ndarray | None = None) -> QPSolution:
        """From a predicted set (slip+, slip-) and a start (nested iteration)."""
        clock = time.perf_counter()
        active = np.zeros(2 * len(self.F), bool) if predicted is None else np.asarray(predicted, bool).copy()
        options = self.options
        end = primal_dual_active_set(self, active, start, options, options.loose_gain, options.active_set_iterations)
        return QPSolution(z=end.z, multipliers=self.forces(end.z), active=end.active, kkt=end.kkt,
                          iterations=end.iterations, work=self.system.work(), seconds=time.perf_counter() - clock,
                          status=end.status)


def solve_friction_qp(qp, predicted=None, multilevel=None, start=None, textbook: bool = False,
                      options: SolverOptions = _DEFAULT) -> QPSolution:
    """The harness's solver on a ``fem.friction.FrictionQP``: the truncated multigrid CG on
    ``multilevel``'s hierarchy, else sparse Cholesky (``textbook``: refactorised at every set,
    from a cold start: the reference)."""
    if multilevel is not None and not textbook:
        if multilevel.ndof != qp.problem.mesh.nv * qp.problem.physics.components:
            raise ValueError("the multilevel hierarchy does not end at this problem's mesh (refined() missed?)")
        system = MultigridSystem(qp.K_ngs, qp.b, multilevel, qp.edges, options=options)
    else:
        K_ngs = qp.K_ngs if qp.K_ngs is not None else ngsolve_matrix(qp.K)
        system = FactorisedSystem(qp.K, K_ngs, qp.b, 0 if textbook else options.refactor_above)
    return solve_friction(qp.K, qp.b, qp.free, qp.F, qp.c, qp.lift, system, options,
                          None if textbook else predicted, None if textbook else start)


def solve_friction(K, b, free, F, c, lift, system, options: SolverOptions = _DEFAULT, predicted=None,
                   start=None) -> QPSolution:
    """min 1/2 z'Kz - b'z + sum c_i |z[F_i]| (z = lift off ``free``) on ``system``'s solves, from
    ``predicted`` (slip+, slip- flags of every row of F) and ``start``. The returned branches
    (``active``) and forces (``multipliers``: lambda = (b - K z)[F]) cover every row of F."""
    # a row of weight 0 (the vertices of the mean analogue and of 3D P2) carries no friction: it
    # is a free dof, not a row (as a row each of its branches would be degenerate: lambda = 0)
    rows = np.asarray(c) > 0
    solver = FrictionBounds(K, b, free, F[rows], c[rows], lift, system, options)
    if predicted is not None:
        predicted = np.concatenate([predicted[:len(rows)][rows], predicted[len(rows):][rows]])
    solution = solver.solve(predicted, start)
    # every row's branch, a weightless one slipping with the sign of its value (its force is 0
    # up to the solve's residual)
    slip = solution.z[F]
    plus, minus = slip > 0, slip < 0
    plus[rows], minus[rows] = solution.active[:rows.sum()], solution.active[rows.sum():]
    solution.active = np.concatenate([plus, minus])
    solution.multipliers = -(K @ solution.z - np.asarray(b, float))[F]
    return solution
