"""Contact imposed weakly, by a term on Gamma_C: the penalty method and Nitsche's method, as one
nonlinear system F(u_h) = 0 on X_h (no constraint on the discrete space).

The contact law. With lambda = d_n u - g_C (the contact pressure, g_C the contact load of the
manufactured-solution generalisation; g_C = 0 in the paper), the Signorini conditions
u - alpha >= 0, lambda >= 0, lambda (u - alpha) = 0 are equivalent, for any eps > 0, to

    lambda = (1/eps) [P(u)]_+,      P(u) = eps lambda - (u - alpha)                      (*)

(if u > alpha: lambda = 0 = [-(u - alpha)/eps]_+; if u = alpha: lambda = [lambda]_+ >= 0).
Green's formula gives a(u, v) - int_{Gamma_C} lambda v = L(v) for every v in X (L includes g_C v).

Nitsche (Chouly & Hild, SIAM J. Numer. Anal. 51 (2013); the theta-family of Chouly, Hild &
Renard, Math. Comp. 84 (2015), their eq. (10), here with their sigma_n = -lambda and
u_n - g = alpha - u): write v = theta eps d_n v - P_theta(v), P_theta(v) = theta eps d_n v - v,
so -int lambda v = int lambda P_theta(v) - theta int eps lambda d_n v, and put (*) in the
first term only:

    a(u, v) - theta int eps (d_n u - g_C) d_n v + int (1/eps) [P(u)]_+ P_theta(v) = L(v).  (N)

The exact solution satisfies (N) (consistency); theta = 1 is symmetric (the derivative of an
energy, coercive for eps = gamma0 h with gamma0 small enough), theta = 0 incomplete, theta = -1
skew-symmetric (coercive for every gamma0 > 0: CHR 2015 Theorem 3.4).

Penalty (Chouly & Hild, Appl. Numer. Math. 65 (2013)): (*) without the flux,
lambda ~ (1/eps) [alpha - u]_+, the derivative of 1/2 a(v,v) - L(v) + (1/2 eps) int [alpha - v]_+^2:

    a(u, v) - int (1/eps) [alpha - u]_+ v = L(v).                                           (P)

Not consistent: where the body is in contact, u_h sits about eps lambda below the obstacle.

Both are (N) with a switch: ``flux = 1`` (Nitsche) or 0 (penalty, where theta plays no role),

    P(u) = flux eps (d_n u - g_C) + alpha - u,   P_theta(v) = theta flux eps d_n v - v.

Discretely: eps = gamma0 h_e on each contact edge (h_e its length), the Gamma_C integrals by
Gauss points (``boundary``), so with T, N the trace and normal-derivative rows of the basis
there and W the weights,

    F(u) = A u - b - theta flux N^T W eps (N u - g_C) + B_theta^T W (1/eps) [P(u)]_+,
    B_theta = theta flux eps N - T,     P(u) = B_1 u + (alpha - flux eps g_C),

piecewise affine in u. Its generalised Jacobian for the points where P(u) > 0 (set D),

    J = A - theta flux N^T W eps N + B_theta^T W D (1/eps) B_1,

differs from A only in the rows and columns of the triangles along Gamma_C, inside A's sparsity
pattern (each Gauss point lies in one triangle): it is A with a few values changed.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
from scipy.spatial import cKDTree

from ..mesh.points import evaluate
from .assembly import DiscreteProblem
from .contact_quadrature import ContactQuadrature, at_points, contact_quadrature
from .sparse import csr_positions, csr_view


class BoundaryTerms:
    """What every system of the form F(u) = A u - b + (terms on Gamma_C) shares: its Jacobian
    J is A with the boundary terms written into A's pattern (``J``, ``delta``, ``positions``),
    and the multigrid's hint of the Gamma_C vertices an active term stiffens. Used by
    ``WeakContactSystem`` (penalty, Nitsche) and ``contact_law.LawSystem`` (a user's law)."""

    def stiff_vertices(self, active: np.ndarray, nv: int) -> np.ndarray:
        """Vertices whose trace carries an active contact term (a multigrid hint)."""
        touched = np.zeros(nv, bool)
        rows = self.quadrature.T[np.flatnonzero(active)]
        touched[rows.indices[rows.indices < nv]] = True
        return touched

    def write_terms(self, terms: sp.spmatrix) -> None:
        """J = A + ``terms`` (within ``delta``'s pattern), written into J's memory."""
        terms = terms.tocoo()
        values = np.zeros(self.delta.nnz)
        np.add.at(values, _index_in(self.delta, terms.row, terms.col), terms.data)
        self.J.data[self.positions] += values - self.delta.data
        self.delta.data[:] = values


@dataclass
class WeakContactSystem(BoundaryTerms):
    """F(u) and J of a penalty (``flux`` = 0) or Nitsche (``flux`` = 1) method on one level."""

    problem: DiscreteProblem
    quadrature: ContactQuadrature
    eps: np.ndarray             # (q,) eps = gamma0 h_e at each Gauss point
    theta: float
    flux: float
    shift: np.ndarray           # (q,) alpha - flux eps g_C: P(u) = B_1 u + shift
    B1: sp.csr_matrix           # flux eps N - T
    Btheta: sp.csr_matrix       # theta flux eps N - T
    rhs: np.ndarray             # b - theta flux N^T W eps g_C: the part of -F independent of u
    J: sp.csr_matrix            # the Jacobian, in a copy of A's memory or in A's own (``take``)
    J_ngs: object
    delta: sp.csr_matrix        # J - A: the boundary terms, on their own (sorted) pattern
    positions: np.ndarray       # where delta's entries sit in J.data
    obstacle_force: float = 0.0 # max |A w| over the free dofs, w = alpha at the Gamma_C vertices

    @property
    def symmetric(self) -> bool:
        return self.flux == 0 or self.theta == 1

    def bracket(self, u: np.ndarray) -> np.ndarray:
        """P(u) at the Gauss points; the contact term is active where it is positive."""
        return self.B1 @ u + self.shift

    def pressure(self, u: np.ndarray) -> np.ndarray:
        """The method's own contact pressure (1/eps) [P(u)]_+ at the Gauss points, >= 0."""
        return np.maximum(self.bracket(u), 0.0) / self.eps

    def residual(self, u: np.ndarray) -> np.ndarray:
        """F(u) on the free dofs (zero on Gamma_u)."""
        W, N = self.quadrature.weights, self.quadrature.N
        F = self.J @ u - self.delta @ u - self.rhs + self.Btheta.T @ (W * self.pressure(u))   # A u = J u - delta u
        if self.flux and self.theta:
            F -= self.theta * (N.T @ (W * self.eps * (N @ u)))
        return np.where(self.problem.free, F, 0.0)

    def affine_rhs(self, active: np.ndarray) -> np.ndarray:
        """r with F(v) = J v - r for every v whose active Gauss points are ``active`` (J set for
        them): the Newton step for that set solves J u = r."""
        W = self.quadrature.weights
        return self.rhs - self.Btheta.T @ (W * active * self.shift / self.eps)

    def set_jacobian(self, active: np.ndarray) -> None:
        """J for the Gauss points ``active`` (where P(u) > 0), written into J's memory."""
        W, N = self.quadrature.weights, self.quadrature.N
        terms = self.Btheta.T @ sp.diags(W * active / self.eps) @ self.B1
        if self.flux and self.theta:
            terms = terms - self.theta * (N.T @ sp.diags(W * self.eps) @ N)
        self.write_terms(terms)


def _index_in(M: sp.csr_matrix, rows: np.ndarray, cols: np.ndarray) -> np.ndarray:
    """Index in M.data of the entries (rows, cols) of M's (sorted) pattern."""
    keys = np.repeat(np.arange(M.shape[0], dtype=np.int64), np.diff(M.indptr)) * M.shape[1] + M.indices
    return np.searchsorted(keys, rows.astype(np.int64) * M.shape[1] + cols)


def weak_contact_system(case, problem: DiscreteProblem, gamma0: float, theta: float, flux: float,
                        take_stiffness: bool = False) -> WeakContactSystem:
    """The system (N) (``flux`` = 1) or (P) (``flux`` = 0) on ``problem`` with eps = gamma0 h_e,
    its Jacobian set for no active point. ``take_stiffness``: J is made in A's memory (the
    level's last method of its order)."""
    if not gamma0 > 0:
        raise ValueError(f"the penalty/Nitsche parameter must be positive, got {gamma0}")
    quadrature = contact_quadrature(problem)
    eps = gamma0 * quadrature.h
    alpha = at_points(case.gap, problem.mesh, quadrature)
    load = at_points(case.contact_load, problem.mesh, quadrature)
    N, T = quadrature.N, quadrature.T
    B1 = (sp.diags(flux * eps) @ N - T).tocsr()
    Btheta = (sp.diags(theta * flux * eps) @ N - T).tocsr()
    rhs = problem.b.copy()
    if flux and theta:
        rhs -= theta * (N.T @ (quadrature.weights * eps * load))
    # every entry a boundary term can touch: the pattern of B_theta^T B_1 and N^T N
    J, J_ngs, delta, positions = boundary_jacobian(problem, abs(Btheta).T @ abs(B1) + abs(N).T @ abs(N), take_stiffness)
    system = WeakContactSystem(problem, quadrature, eps, theta, flux, alpha - flux * eps * load, B1, Btheta, rhs,
                               J, J_ngs, delta, positions, obstacle_force(case, problem, J))
    system.set_jacobian(np.zeros(len(eps), bool))
    return system


def boundary_jacobian(problem: DiscreteProblem, pattern: sp.spmatrix, take_stiffness: bool):
    """(J, J_ngs, delta, positions): J a copy of A (or A itself: ``take_stiffness``, the level's
    last method of its order), delta a zero matrix on ``pattern`` (every entry a boundary term
    can touch, inside A's pattern: each Gauss point lies in one triangle) and where its entries
    sit in J.data."""
    delta = pattern.tocsr()
    delta.sum_duplicates()
    delta.sort_indices()
    delta.data[:] = 0.0
    if take_stiffness:
        J, J_ngs = problem.take_stiffness()
    else:
        J_ngs = problem.A_ngs.CreateMatrix()
        J = csr_view(J_ngs)
    coo = delta.tocoo()
    return J, J_ngs, delta, csr_positions(J, coo.row.astype(np.int64), coo.col.astype(np.int64))


def obstacle_force(case, problem: DiscreteProblem, J: sp.csr_matrix) -> float:
    """max |A w| over the free dofs, w = alpha at the Gamma_C vertices: the force that holds
    Gamma_C at the obstacle, a scale of F beside the loads (``newton.load_scale``). J's values
    off Gamma_C's triangles are A's, and w lives on Gamma_C's vertices; set before any term."""
    obstacle = np.zeros(problem.ndof)
    if case.gap is not None:
        obstacle[problem.vertex_dofs] = evaluate(case.gap, problem.mesh, problem.trace.vertex_points)
    return float(np.abs((J @ obstacle)[problem.free]).max(initial=0.0))


def predicted_active(coarse_points: np.ndarray, coarse_active: np.ndarray, points: np.ndarray) -> np.ndarray:
    """Nested iteration: each Gauss point takes the status of the nearest Gauss point of the
    coarser level's solution. (The sign of the bracket of the interpolated coarse solution is a
    poor guess: its bubbles are zero and near a transition where u - alpha and lambda both vanish
    smoothly (the smooth case) it took Newton 15 steps on level 6, a few points per step.)"""
    return coarse_active[cKDTree(coarse_points).query(points)[1]]
