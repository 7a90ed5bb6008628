"""The Newton system of a friction law (``fem.contact_laws.protocol.FrictionLaw``) on one level:
the channels of Gamma_C's Gauss points (``protocol.FrictionPoints``), their rows, and the
interface the harness's semismooth Newton method (``solvers.newton``) solves, as
``system.LawSystem`` is for a frictionless law.

With T_j, N_j the rows of channel j's variable and flux at the points and W the weights,

    F(u) = A u - b - sum_j T_j^T W p_j + sum_j N_j^T W f_j,

and on a branch set S, at the state of u, the Jacobian

    J_S(u) = A + R^T W B R,   R = [T_1; ..; T_m; N_1; ..; N_m],   B = [[-p_u, -p_dn], [f_u, f_dn]],

each block of B the law's (q, m, m) derivative: symmetric exactly when p_u and f_dn are
symmetric in the channels and f_u = -p_dn^T. Where the law is affine on every branch (the 1D
slip: the scalar model and 2D elasticity) J_S is one matrix per set, and Newton ends in
finitely many steps; where it is not (the projection onto the disc in 3D) ``affine`` is False
and Newton relinearises at every step (r_S = J_S(u) u - F_S(u)). ``check_friction_law``
verifies the law's derivative before the solve: the affine promise where it holds, else
central finite differences.

The rows: the scalar model's one channel is the contact quadrature's own (u and d_n u);
elasticity's slip channels are u . tau_a and tau_a . sigma(u) n on an orthonormal tangent frame
(``tangent_frames``), sigma(e_i phi) n . tau = mu (tau_i d_n phi + n_i d_tau phi) (tau . n = 0
removes lambda's part), and its last channel the contact quadrature's normal rows (-u . n,
-sigma_n(u)).
"""
from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np
import scipy.sparse as sp

from ...mesh.points import evaluate
from ..assembly import DiscreteProblem
from ..contact_quadrature import ROUNDOFF, ContactQuadrature, _component_rows, _scalar_space, contact_quadrature, scalar_basis_at
from .protocol import FrictionPoints, LawError
from .system import LAW_TOLERANCE, BoundaryTerms, boundary_jacobian, contact_data, obstacle_force, touched_p1

# finite differences of a law that is not affine on a branch: central, step FD_STEP times the
# state's scale; their error is O(step^2) beside round-off O(1e-16 / step). Where a random state
# lies near a kink of the law's terms' smoothness (Coulomb's slip direction w/|w| at a small
# slip: its curvature grows like 1/|w|^2), the check is repeated with steps FD_REFINEMENTS times
# smaller: a right derivative's difference error falls with step^2, a wrong one's stays.
FD_STEP = 1e-5
FD_TOLERANCE = 1e-6
FD_REFINEMENTS = (1.0, 0.1, 0.01)
# a channel of a point is "stiff" (a multigrid hint, ``BoundaryTerms.stiff_vertices``) where
# -p_u h / M exceeds this: Nitsche's and the penalty's stick branch give 1/gamma0 (20 by default)
STIFF = 1.0


def tangent_frames(normals: np.ndarray) -> np.ndarray:
    """(q, t, dim) an orthonormal frame of the tangent space at each point (t = dim - 1): in 2D
    tau = (-n_y, n_x) (the tangent of ``problem.physics.Elasticity.contact_forces``); in 3D tau_1
    = n x e / |n x e| (e the axis least aligned with n), tau_2 = n x tau_1."""
    if normals.shape[1] == 2:
        return np.stack([-normals[:, 1], normals[:, 0]], axis=1)[:, None, :]
    axis = np.eye(3)[np.argmin(np.abs(normals), axis=1)]
    first = np.cross(normals, axis)
    first /= np.linalg.norm(first, axis=1)[:, None]
    return np.stack([first, np.cross(normals, first)], axis=1)


def slip_rows(problem: DiscreteProblem, quadrature: ContactQuadrature) -> tuple[list, list]:
    """(T, N): the rows of the slip channels' variables and fluxes (``FrictionPoints``), one
    matrix (q, ndof) per channel."""
    if not problem.physics.rotated_frame:
        return [quadrature.T], [quadrature.N]
    fes, physics, basis, volumes = quadrature._flux
    scalar = _scalar_space(fes)
    dofs, values, grads = scalar_basis_at(scalar, volumes, quadrature.points)
    normals = quadrature.normals
    dn = np.einsum("qld,qd->ql", grads, normals)
    T, N = [], []
    for tau in np.moveaxis(tangent_frames(normals), 1, 0):
        dtau = np.einsum("qld,qd->ql", grads, tau)
        rows = _component_rows(fes, scalar.ndof, basis, dofs, [(i, tau[:, i, None] * values) for i in range(physics.dim)])
        rows.data[np.abs(rows.data) <= ROUNDOFF] = 0.0
        rows.eliminate_zeros()
        T.append(rows)
        N.append(_component_rows(fes, scalar.ndof, basis, dofs,
                                 [(i, physics.mu * (tau[:, i, None] * dn + normals[:, i, None] * dtau)) for i in range(physics.dim)]))
    return T, N


def channel_data(case, problem: DiscreteProblem, quadrature: ContactQuadrature, tangential: int):
    """(gap (q,), load (q, m), threshold (q,), coefficient (q,) or None) at the points: the normal
    channel's obstacle, every channel's load (the tangential components of g_C on the frames,
    then -g_C . n; the scalar g_C), Tresca's s (zeros for Coulomb), Coulomb's mu_F (None for
    Tresca)."""
    gap, normal_load = contact_data(case, problem, quadrature)
    friction, q = case.friction, len(gap)
    coulomb = friction.name == "coulomb"
    threshold = np.zeros(q) if coulomb else evaluate(friction.threshold_function, problem.mesh, quadrature.points)
    coefficient = np.full(q, float(friction.coefficient)) if coulomb else None
    if not problem.physics.rotated_frame:
        return gap, normal_load[:, None], threshold, coefficient
    frames = tangent_frames(quadrature.normals)
    g = np.zeros((q, problem.physics.dim)) if case.contact_load is None else \
        evaluate(case.contact_load, problem.mesh, quadrature.points).reshape(q, -1)
    return gap, np.column_stack([np.einsum("qtd,qd->qt", frames, g), normal_load]), threshold, coefficient


@dataclass
class FrictionSystem(BoundaryTerms):
    """F(u) = 0 of a friction law on one level: the interface ``solvers.newton`` solves (the
    module's note). ``branch`` gives integer codes (0: stick)."""

    problem: DiscreteProblem
    quadrature: ContactQuadrature
    law: object
    T: list                     # the channels' variable rows, each (q, ndof)
    N: list                     # their flux rows
    gap: np.ndarray
    load: np.ndarray            # (q, m)
    threshold: np.ndarray       # (q,)
    tangential: int
    rhs: np.ndarray
    J: sp.csr_matrix
    J_ngs: object
    delta: sp.csr_matrix
    positions: np.ndarray
    obstacle_force: float
    symmetric: bool = True
    affine: bool = True
    stiff: np.ndarray | None = None     # (q, m) bool: the stiff channels of the last Jacobian
    coefficient: np.ndarray | None = None   # (q,) Coulomb's mu_F, None for Tresca
    # a nonsymmetric Jacobian goes to GMRES with the multigrid V-cycle, not to a factorisation
    # (``solvers.newton``): Coulomb's laws, nonsymmetric for every theta, on fine meshes
    nonsymmetric_krylov: bool = False
    # (q, tangential) u_t at the end of the previous load step (``problem.friction.LoadHistory``):
    # the slip channels hold the step's slip u_t - reference; None: zero (a static problem)
    reference: np.ndarray | None = None

    def __post_init__(self):
        self.R = sp.vstack(self.T + self.N).tocsr()

    def at(self, u: np.ndarray) -> FrictionPoints:
        q, physics = self.quadrature, self.problem.physics
        channels = np.column_stack([T @ u for T in self.T])
        if self.reference is not None:
            channels[:, :self.tangential] -= self.reference
        return FrictionPoints(channels, np.column_stack([N @ u for N in self.N]),
                              self.gap, self.load, self.threshold, q.h, q.points, self.tangential, physics.name,
                              physics.modulus, q.degree, self.coefficient,
                              2.0 * physics.mu if physics.rotated_frame else None)

    def slip_state(self, u: np.ndarray) -> np.ndarray:
        """(q, tangential) u_t of u_h at the points: the next load step's ``reference``."""
        return np.column_stack([T @ u for T in self.T[:self.tangential]])

    def zero(self) -> FrictionPoints:
        return self.at(np.zeros(self.problem.ndof))

    def branch(self, u: np.ndarray) -> np.ndarray:
        return np.asarray(self.law.branch(self.at(u)), np.int64)

    def terms(self, state: FrictionPoints, branch: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        p, f = self.law.term(state, branch)
        return np.broadcast_to(p, state.u.shape), np.broadcast_to(f, state.u.shape)

    def pressure(self, u: np.ndarray) -> np.ndarray:
        """The row's force at the points: the normal channel's pressure in elasticity (the
        bilateral reaction), the friction force itself in the scalar model (as the cones')."""
        return self.terms(self.at(u), self.branch(u))[0][:, -1]

    def residual(self, u: np.ndarray) -> np.ndarray:
        return np.where(self.problem.free, self._F(u, self.branch(u)), 0.0)

    def _F(self, u: np.ndarray, branch: np.ndarray) -> np.ndarray:
        W = self.quadrature.weights[:, None]
        p, f = self.terms(self.at(u), branch)
        return self.J @ u - self.delta @ u - self.rhs + self.R.T @ np.concatenate([-(W * p).T.ravel(), (W * f).T.ravel()])

    def affine_rhs(self, active: np.ndarray, u: np.ndarray | None = None) -> np.ndarray:
        """r_S = J_S u - F_S(u) (= -F_S(0) on an affine branch set), J_S the Jacobian last set."""
        u = np.zeros(self.problem.ndof) if u is None or self.affine else u
        return self.J @ u - self._F(u, active)

    def set_jacobian(self, active: np.ndarray, u: np.ndarray | None = None) -> None:
        """J_S(u) = A + R^T W B R (the module's note), into J's memory."""
        state = self.zero() if u is None else self.at(u)
        p_u, p_dn, f_u, f_dn = self.derivatives(active, state)
        q, m = state.u.shape
        W = self.quadrature.weights[:, None, None]
        blocks = np.block([[-W * p_u, -W * p_dn], [W * f_u, W * f_dn]])         # (q, 2m, 2m)
        index = np.arange(2 * m)[None, :] * q + np.arange(q)[:, None]        # (q, 2m): point i of block row a
        rows = np.broadcast_to(index[:, :, None], blocks.shape)
        cols = np.broadcast_to(index[:, None, :], blocks.shape)
        B = sp.csr_matrix((blocks.ravel(), (rows.ravel(), cols.ravel())), shape=(2 * m * q, 2 * m * q))
        self.stiff = -np.einsum("qjj->qj", p_u) * (state.h / state.modulus)[:, None] > STIFF
        self.write_terms(self.R.T @ B @ self.R)

    def derivatives(self, active: np.ndarray, state: FrictionPoints | None = None) -> list[np.ndarray]:
        state = self.zero() if state is None else state
        m = state.u.shape[1]
        return [np.broadcast_to(np.asarray(d, float), (len(active), m, m)) for d in self.law.derivative(state, active)]

    def stiff_vertices(self, active: np.ndarray, n: int) -> np.ndarray:
        """The P1 dofs whose channel carries a stiff term (``STIFF``) at the last Jacobian."""
        stiff = np.zeros((len(active), len(self.T)), bool) if self.stiff is None else self.stiff
        columns = np.concatenate([T[np.flatnonzero(stiff[:, j])].indices for j, T in enumerate(self.T)])
        return touched_p1(self.problem, columns, n)


def friction_system(case, problem: DiscreteProblem, law, take_stiffness: bool = False) -> FrictionSystem:
    """The system of the friction ``law`` on ``problem`` (a Tresca case, any physics and
    dimension, any order), its law checked (``check_friction_law``), its Jacobian set for the
    stick branch everywhere."""
    quadrature = contact_quadrature(problem)
    T, N = slip_rows(problem, quadrature)
    tangential = len(T)
    if problem.physics.rotated_frame:
        T, N = T + [quadrature.T], N + [quadrature.N]
    gap, load, threshold, coefficient = channel_data(case, problem, quadrature, tangential)
    touched = sum((abs(M) for M in T + N[1:]), abs(N[0])).tocsr()
    J, J_ngs, delta, positions = boundary_jacobian(problem, touched.T @ touched, take_stiffness)
    system = FrictionSystem(problem, quadrature, law, T, N, gap, load, threshold, tangential, problem.b.copy(), J, J_ngs,
                            delta, positions, obstacle_force(case, problem, J), coefficient=coefficient,
                            nonsymmetric_krylov=coefficient is not None)
    system.symmetric, system.affine = check_friction_law(system)
    system.set_jacobian(np.zeros(len(gap), np.int64))
    return system


def check_friction_law(system: FrictionSystem, seed: int = 0) -> tuple[bool, bool]:
    """(symmetric, affine) of the law's Jacobian, after checking on every branch, at random
    states, that ``derivative`` is its terms': exactly where they are affine, by central finite
    differences where not; LawError naming the broken promise else."""
    rng = np.random.default_rng(seed)
    base = system.zero()
    q, m = base.u.shape
    symmetric, affine = True, True
    for code in system.law.branches:
        branch = np.full(q, code, np.int64)
        s0, s1 = (replace(base, u=rng.standard_normal((q, m)), dn=rng.standard_normal((q, m))) for _ in range(2))
        d0 = system.derivatives(branch, s0)
        exact = _matches(system, branch, s0, s1, d0, 1.0, LAW_TOLERANCE) and \
            all(np.allclose(a, b, rtol=1e-12, atol=0.0) for a, b in zip(d0, system.derivatives(branch, s1)))
        if not exact:
            affine = False
            if not any(_central_difference_matches(system, branch, s0, s1, d0, FD_STEP * k) for k in FD_REFINEMENTS):
                raise LawError(f"friction law {type(system.law).__name__}: its derivative on the branch {code} is not its "
                               f"terms' (finite differences disagree)")
        symmetric = symmetric and all(_symmetric(d) for d in (d0, system.derivatives(branch, s1)))
    return symmetric, affine


def _central_difference_matches(system, branch, s0, s1, derivative, relative_step: float) -> bool:
    """``_matches`` of the central difference about ``s0`` along s1 - s0, its step
    ``relative_step`` times the state's scale."""
    step = relative_step / max(np.abs(s1.u - s0.u).max(), np.abs(s1.dn - s0.dn).max())
    ahead = replace(s0, u=s0.u + step * (s1.u - s0.u), dn=s0.dn + step * (s1.dn - s0.dn))
    behind = replace(s0, u=s0.u - step * (s1.u - s0.u), dn=s0.dn - step * (s1.dn - s0.dn))
    return _matches(system, branch, behind, ahead, derivative, 2 * step, FD_TOLERANCE)


def _matches(system, branch, before, after, derivative, scale: float, tolerance: float) -> bool:
    """Do the terms' changes from ``before`` to ``after`` equal ``derivative`` applied to the
    change (over ``scale``: 1, or the central difference's span)?"""
    p_u, p_dn, f_u, f_dn = derivative
    (p0, f0), (p1, f1) = (system.terms(s, branch) for s in (before, after))
    du, ddn = (after.u - before.u) / scale, (after.dn - before.dn) / scale
    for change, slope_u, slope_dn in (((p1 - p0) / scale, p_u, p_dn), ((f1 - f0) / scale, f_u, f_dn)):
        predicted = np.einsum("qjk,qk->qj", slope_u, du) + np.einsum("qjk,qk->qj", slope_dn, ddn)
        size = max(np.abs(change).max(initial=0.0), np.abs(predicted).max(initial=0.0), np.finfo(float).tiny)
        if not np.all(np.isfinite(change)) or np.abs(change - predicted).max(initial=0.0) > tolerance * size:
            return False
    return True


def _symmetric(derivative) -> bool:
    """B = [[-p_u, -p_dn], [f_u, f_dn]] symmetric at every point."""
    p_u, p_dn, f_u, f_dn = derivative
    B = np.block([[-p_u, -p_dn], [f_u, f_dn]])
    return bool(np.allclose(B, np.swapaxes(B, 1, 2), rtol=1e-12, atol=1e-14 * max(np.abs(B).max(), 1.0)))
