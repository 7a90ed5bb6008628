"""The Newton system of a contact law (``fem.contact_laws.protocol``) on one level: the
interface the harness's semismooth Newton method (``solvers.newton``) solves, for the method
protocol's second level (``harness.methods.ContactLawMethod``). The built-in penalty and
Nitsche methods are such laws (``fem.contact_laws.builtin``).

The law's pressure p and flux term f at the Gauss points of Gamma_C enter the discrete system as
F(u) = A u - b - T^T W p + N^T W f (the protocol's module).

Semismooth Newton converges in finitely many steps, to the exact discrete solution, when F is
piecewise affine (Qi & Sun, Math. Program. 58 (1993); Hintermueller, Ito & Kunisch, SIAM J.
Optim. 13 (2002)). So a law has two branches per point, told by ``branch`` (True: "in contact"),
and on each branch its terms are affine in (c, flux):

    p = p0 + p_u c + p_dn flux,      f = f0 + f_u c + f_dn flux,

``derivative`` returning (p_u, p_dn, f_u, f_dn) of the given branch. The Jacobian of a branch set
S is then J_S = A - T^T W (p_u T + p_dn N) + N^T W (f_u T + f_dn N), symmetric exactly when
f_u = -p_dn; and F_S(v) = J_S v - r_S with r_S = -F_S(0). ``check_law`` verifies both
promises (affine terms, a derivative that is theirs) on every level before the solve, and
refuses a law that breaks them in one line. J_S differs from A only in the rows and columns of
the elements along Gamma_C, inside A's sparsity pattern (each Gauss point lies in one element):
it is A with a few values changed, written in place (``BoundaryTerms``).
"""
from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np
import scipy.sparse as sp

from ...mesh.points import evaluate
from ..assembly import DiscreteProblem
from ..contact_quadrature import ContactQuadrature, at_points, contact_quadrature
from ..sparse import csr_positions, csr_view
from .protocol import GammaPoints, LawError

# the relative mismatch of ``check_law`` beyond which a law's terms are not affine on a branch
# or its derivative is not theirs (round-off of the terms' evaluation is ~1e-15)
LAW_TOLERANCE = 1e-8


class BoundaryTerms:
    """What a system of the form F(u) = A u - b - T^T W p + N^T W f shares: its Jacobian J is A
    with the boundary terms written into A's pattern (``J``, ``delta``, ``positions``), and the
    multigrid's hint of the P1 dofs an active term stiffens."""

    def stiff_vertices(self, active: np.ndarray, n: int) -> np.ndarray:
        """The P1 dofs (vertex v of component k at k nv + v, ``n`` of them) whose contact dof
        carries an active contact term (a multigrid hint: ``solvers.multigrid.TruncatedVCycle``)."""
        return touched_p1(self.problem, self.quadrature.T[np.flatnonzero(active)].indices, n)

    def at_step(self, problem) -> None:
        """Solve with ``problem``'s load and Dirichlet data from now on: a load step's
        (``fem.assembly.at_load_step``; the same space, matrix and trace)."""
        self.problem, self.rhs = problem, problem.b.copy()

    def write_terms(self, terms: sp.spmatrix) -> None:
        """J = A + ``terms`` (within ``delta``'s pattern), written into J's memory."""
        terms = terms.tocoo()
        values = np.zeros(self.delta.nnz)
        np.add.at(values, _index_in(self.delta, terms.row, terms.col), terms.data)
        self.J.data[self.positions] += values - self.delta.data
        self.delta.data[:] = values


def touched_p1(problem, columns: np.ndarray, n: int) -> np.ndarray:
    """(n,) bool: the P1 dofs of the vertex dofs among ``columns`` (vertex v of component k at
    k nv + v), body by body on a joint problem (``two_body.JointProblem.bodies``: the lower
    body's after the upper's, in its dofs and in the joint P1 hierarchy's)."""
    touched = np.zeros(n, bool)
    offset = p1 = 0
    for body in getattr(problem, "bodies", (problem,)):
        mine = columns[(columns >= offset) & (columns < offset + body.ndof)] - offset
        block, nv = body.ndof // body.physics.components, body.mesh.nv
        vertex = mine % block
        touched[p1 + (mine // block * nv + vertex)[vertex < nv]] = True
        offset, p1 = offset + body.ndof, p1 + nv * body.physics.components
    return touched


@dataclass
class LawSystem(BoundaryTerms):
    """F(u) and J of a contact law on one level: the interface ``solvers.newton`` solves."""

    problem: DiscreteProblem
    quadrature: ContactQuadrature
    law: object
    gap: np.ndarray
    load: np.ndarray
    rhs: np.ndarray             # b: the part of -F independent of u and of the law
    J: sp.csr_matrix
    J_ngs: object
    delta: sp.csr_matrix        # J - A: the boundary terms, on their own (sorted) pattern
    positions: np.ndarray
    obstacle_force: float
    symmetric: bool
    affine = True               # its terms are affine on each branch: J_S is one matrix per set

    def at(self, u: np.ndarray) -> GammaPoints:
        q = self.quadrature
        physics = self.problem.physics
        return GammaPoints(q.T @ u, q.N @ u, self.gap, self.load, q.h, q.points, physics.name, physics.modulus,
                           q.degree)

    def zero(self) -> GammaPoints:
        """The state u_h = 0: where an affine term takes its constant part."""
        return self.at(np.zeros(self.problem.ndof))

    def bracket(self, u: np.ndarray) -> np.ndarray:
        """Positive where the law's branch is "in contact" (what ``newton`` reads as active)."""
        return np.where(self.branch(u), 1.0, -1.0)

    def branch(self, u: np.ndarray) -> np.ndarray:
        return np.asarray(self.law.branch(self.at(u)), bool)

    def terms(self, state: GammaPoints, branch: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        p, f = self.law.term(state, branch)
        return np.broadcast_to(p, branch.shape), np.broadcast_to(f, branch.shape)

    def pressure(self, u: np.ndarray) -> np.ndarray:
        """The law's own contact pressure p at the Gauss points."""
        return self.terms(self.at(u), self.branch(u))[0]

    def residual(self, u: np.ndarray) -> np.ndarray:
        """F(u) on the free dofs (zero on Gamma_u)."""
        return np.where(self.problem.free, self._F(u, self.branch(u)), 0.0)

    def _F(self, u: np.ndarray, branch: np.ndarray) -> np.ndarray:
        W, T, N = self.quadrature.weights, self.quadrature.T, self.quadrature.N
        p, f = self.terms(self.at(u), branch)
        return self.J @ u - self.delta @ u - self.rhs - T.T @ (W * p) + N.T @ (W * f)      # A u = J u - delta u

    def affine_rhs(self, active: np.ndarray, u: np.ndarray | None = None) -> np.ndarray:
        """r_S = -F_S(0): F_S(v) = J_S v - r_S on the branch set ``active`` (whatever ``u``: affine)."""
        return -self._F(np.zeros(self.problem.ndof), active)

    def set_jacobian(self, active: np.ndarray, u: np.ndarray | None = None) -> None:
        """J_S = A - T^T W (p_u T + p_dn N) + N^T W (f_u T + f_dn N), into J's memory (the same
        at every ``u``: the terms are affine on a branch)."""
        W, T, N = self.quadrature.weights, self.quadrature.T, self.quadrature.N
        p_u, p_dn, f_u, f_dn = self.derivatives(active)
        self.write_terms(-(T.T @ sp.diags(W * p_u) @ T) - T.T @ sp.diags(W * p_dn) @ N
                         + N.T @ sp.diags(W * f_u) @ T + N.T @ sp.diags(W * f_dn) @ N)

    def derivatives(self, active: np.ndarray) -> list[np.ndarray]:
        return [np.broadcast_to(np.asarray(d, float), active.shape) for d in self.law.derivative(self.zero(), active)]


def law_system(case, problem: DiscreteProblem, law, take_stiffness: bool = False) -> LawSystem:
    """The system of ``law`` on ``problem`` (any physics, dimension and order), its law checked
    (``check_law``), its Jacobian set for no active point. ``take_stiffness``: J is made in A's
    memory (the level's last method of its order)."""
    quadrature = contact_quadrature(problem)
    gap, load = contact_data(case, problem, quadrature)
    T, N = quadrature.T, quadrature.N
    both = (abs(T) + abs(N)).tocsr()
    J, J_ngs, delta, positions = boundary_jacobian(problem, both.T @ both, take_stiffness)
    system = LawSystem(problem, quadrature, law, gap, load, problem.b.copy(), J, J_ngs, delta, positions,
                       obstacle_force(case, problem, J), symmetric=True)
    system.symmetric = check_law(system)
    system.set_jacobian(np.zeros(len(gap), bool))
    return system


def check_law(system: LawSystem, seed: int = 0) -> bool:
    """Whether the law's Jacobian is symmetric, after checking on both branches, at two random
    states, that its terms are affine and ``derivative`` is theirs; LawError naming the broken
    promise else (a wrong derivative would make Newton's "exact" solve silently inexact)."""
    rng = np.random.default_rng(seed)
    q = len(system.gap)
    for name, branch in (("in contact", np.ones(q, bool)), ("separated", np.zeros(q, bool))):
        states = [replace(system.zero(), u=rng.standard_normal(q), dn=rng.standard_normal(q)) for _ in range(2)]
        (p0, f0), (p1, f1) = (system.terms(s, branch) for s in states)
        p_u, p_dn, f_u, f_dn = system.derivatives(branch)
        du, ddn = states[1].u - states[0].u, states[1].dn - states[0].dn
        for label, change, predicted in (("pressure", p1 - p0, p_u * du + p_dn * ddn), ("flux term", f1 - f0, f_u * du + f_dn * ddn)):
            scale = max(np.abs(change).max(initial=0.0), np.abs(predicted).max(initial=0.0), np.finfo(float).tiny)
            if not np.all(np.isfinite(change)) or np.abs(change - predicted).max(initial=0.0) > LAW_TOLERANCE * scale:
                raise LawError(f"contact law {type(system.law).__name__}: its {label} on the branch '{name}' is not affine "
                               f"in (u, d_n u) with the slopes its derivative gives")
    # J_S is symmetric for every set S when the cross slopes cancel on both branches
    return all(np.allclose(d[2], -d[1], rtol=1e-12, atol=0.0) for d in (system.derivatives(np.full(q, b)) for b in (True, False)))


def contact_data(case, problem: DiscreteProblem, quadrature: ContactQuadrature) -> tuple[np.ndarray, np.ndarray]:
    """(obstacle, load) of the contact variable at the points (``GammaPoints.gap``, ``.load``)."""
    physics, mesh = problem.physics, problem.mesh
    gap = physics.obstacle(at_points(case.gap, mesh, quadrature))
    if case.contact_load is None:
        return gap, np.zeros(len(gap))
    return gap, physics.normal_load(evaluate(case.contact_load, mesh, quadrature.points), quadrature.normals)


def _index_in(M: sp.csr_matrix, rows: np.ndarray, cols: np.ndarray) -> np.ndarray:
    """Index in M.data of the entries (rows, cols) of M's (sorted) pattern."""
    keys = np.repeat(np.arange(M.shape[0], dtype=np.int64), np.diff(M.indptr)) * M.shape[1] + M.indices
    return np.searchsorted(keys, rows.astype(np.int64) * M.shape[1] + cols)


def boundary_jacobian(problem: DiscreteProblem, pattern: sp.spmatrix, take_stiffness: bool):
    """(J, J_ngs, delta, positions): J a copy of A (or A itself: ``take_stiffness``, the level's
    last method of its order), delta a zero matrix on ``pattern`` (every entry a boundary term
    can touch, inside A's pattern: each Gauss point lies in one element) and where its entries
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
    """max |A w| over the free dofs, w = the obstacle at Gamma_C's vertices (in their contact
    dofs): the force that holds Gamma_C at the obstacle, a scale of F beside the loads
    (``solvers.newton.load_scale``). J's values off Gamma_C's elements are A's, and w lives on Gamma_C's
    vertices; set before any term."""
    obstacle = np.zeros(problem.ndof)
    if case.gap is not None:
        obstacle[problem.vertex_dofs] = problem.physics.obstacle(evaluate(case.gap, problem.mesh, problem.trace.vertex_points))
    return float(np.abs((J @ obstacle)[problem.free]).max(initial=0.0))
