"""Multigrid for the contact solver: CG preconditioned by a V-cycle truncated at the active set.

With the active set fixed, each step of the active set method is the linear problem
K[F, F] z_F = b_F - K[F, P] z_P, the constraints in P acting as Dirichlet pins. A plain
multigrid does not know the pins and its CG iteration count grows like h^{-1/2}; truncating the
coarse spaces at the pins (Kornhuber, Numer. Math. 69 (1994); Graeser and Kornhuber, J. Comput.
Math. 27 (2009)) keeps it bounded independently of h.

The spaces, fine to coarse:
  X_h in the contact model's variables z (P2; ``models``), then P1 on the finest mesh, then P1
  on each coarser mesh of the hierarchy.
The hierarchical P2 basis contains the P1 hat functions as its vertex functions, and the
meshes are nested, so every coarse matrix (the P1 stiffness matrix of its mesh) is the exact
Galerkin product R A P of the finer one: the V-cycle is a symmetric positive definite
preconditioner. Truncation: a coarse hat whose prolongation is nonzero at a pinned fine variable
is dropped, so every coarse correction vanishes on the pins and the coarse spaces are subspaces
of {z: z_P = 0}. P1 prolongations have non-negative weights, so restricting the indicator of the
pins finds exactly those hats.
"""
from __future__ import annotations

from dataclasses import dataclass

import ngsolve as ngs
import numpy as np

DIRICHLET = "dirichlet"


class Multilevel:
    """The P1 spaces of a mesh hierarchy refined in place (``mesh.levels``): their stiffness
    matrices and free dofs per level, and NGSolve's P1 prolongation between them.

    Create it on the coarse mesh, call ``refined()`` at every level of the sequence. Between two
    levels the mesh may have been refined several times (a graded or adaptive level is many
    bisection sweeps, ``mesh.bisection``): a level's prolongation is then the product of the
    sweeps' ones, each parent-averaging only the vertices its sweep created, so it stays
    O(new vertices); the spaces are nested all the same and every coarse matrix is still the
    Galerkin product R A P.
    """

    def __init__(self, mesh: ngs.Mesh):
        self.mesh = mesh
        self.fes = ngs.H1(mesh, order=1, dirichlet=DIRICHLET)
        u, v = self.fes.TnT()
        self._form = ngs.BilinearForm(ngs.grad(u) * ngs.grad(v) * ngs.dx)
        self.matrices: list = []
        self.free: list[np.ndarray] = []
        self.mesh_levels: list[int] = []      # NGSolve's refinement count at each of our levels
        self._add_level()

    def _add_level(self) -> None:
        self._form.Assemble()
        self.matrices.append(self._form.mat)
        self.free.append(np.array(self.fes.FreeDofs(), dtype=bool))
        self.mesh_levels.append(self.mesh.levels - 1)

    def refined(self) -> "Multilevel":
        """The hierarchy with the mesh's current refinement as its finest level (unchanged if
        the mesh was not refined since: a graded level may need no bisection at all)."""
        if self.mesh.levels - 1 == self.mesh_levels[-1]:
            return self
        self.fes.Update()
        self._add_level()
        return self

    def _sweeps(self, level: int) -> range:
        """NGSolve's refinement steps from our ``level`` - 1 to ``level``."""
        return range(self.mesh_levels[level - 1] + 1, self.mesh_levels[level] + 1)

    def restrict(self, level: int, vector) -> None:
        """In place: the first nv(level - 1) entries of ``vector`` (of level's size) become the
        restriction (the prolongation's transpose) of level's entries."""
        for sweep in reversed(self._sweeps(level)):
            self._prolongation.Restrict(sweep, vector)

    def prolongate(self, level: int, vector) -> None:
        """In place: ``vector``'s first nv(level - 1) entries, prolongated to all of level's."""
        for sweep in self._sweeps(level):
            self._prolongation.Prolongate(sweep, vector)

    @property
    def _prolongation(self):
        return self.fes.Prolongation()

    @property
    def nvertices(self) -> int:
        return self.matrices[-1].height

    def truncated_pins(self, pinned_vertices: np.ndarray) -> list[np.ndarray]:
        """Pinned P1 dofs per level, coarse to fine: a coarse hat is pinned when its prolongation
        touches a pinned finer dof (or it lies on Gamma_u)."""
        pins = [pinned_vertices | ~self.free[-1]]
        for level in range(len(self.matrices) - 1, 0, -1):
            indicator = self.matrices[level].CreateColVector()
            indicator.FV().NumPy()[:] = pins[0]
            self.restrict(level, indicator)
            coarse = indicator.FV().NumPy()[: self.matrices[level - 1].height] > 0
            pins.insert(0, coarse | ~self.free[level - 1])
        return pins


def nested_start(multilevel: Multilevel, coarse_vertex_values: np.ndarray, problem, edges=None) -> np.ndarray:
    """A start for the finest level's CG: the coarser level's u_h at the vertices, interpolated
    by the P1 prolongation, in the variables of ``edges`` (default: the contact model's;
    bubbles zero)."""
    fine = multilevel.matrices[-1].CreateColVector()
    fine[:] = 0.0
    fine.FV().NumPy()[: len(coarse_vertex_values)] = coarse_vertex_values
    multilevel.prolongate(len(multilevel.matrices) - 1, fine)
    z = np.zeros(problem.ndof)
    (ContactEdges.of(problem) if edges is None else edges).prolongate(fine.FV().NumPy(), z)
    return z


def _bits(mask: np.ndarray) -> ngs.BitArray:
    return ngs.BitArray(np.asarray(mask, dtype=bool).tolist())


@dataclass(frozen=True)
class ContactEdges:
    """Where the model's variables z differ from NGSolve's hierarchical ones: the bubble of
    contact edge k is replaced by a combination of its ends (u = S z, ``models``). A P1 function
    with vertex values c has z_e = (c_a + c_b)/2 there, and z = c at vertices, z_e = 0 elsewhere."""

    edge_dofs: np.ndarray
    end_dofs: np.ndarray

    @classmethod
    def of(cls, problem) -> "ContactEdges":
        """From a ``discrete.DiscreteProblem``, whose P2 space must number vertex v's dof v."""
        nv = problem.mesh.nv
        if problem.fes.GetDofNrs(ngs.NodeId(ngs.VERTEX, nv - 1)) != (nv - 1,) or \
                not np.array_equal(problem.vertex_dofs, problem.trace.vertices):
            raise RuntimeError("the space does not number vertex dofs by vertex; the multigrid needs it")
        ends = problem.end_dofs if len(problem.edge_dofs) else np.zeros((0, 2), dtype=np.int64)
        return cls(problem.edge_dofs, ends)

    def prolongate(self, c: np.ndarray, z: np.ndarray) -> None:
        """z += the model variables of the P1 function c (vertex dofs are 0..nv-1 in H1)."""
        z[: len(c)] += c
        z[self.edge_dofs] += 0.5 * (c[self.end_dofs[:, 0]] + c[self.end_dofs[:, 1]])

    def restrict(self, r: np.ndarray, nv: int) -> np.ndarray:
        """The transpose of ``prolongate``."""
        c = r[:nv].copy()
        half = 0.5 * r[self.edge_dofs]
        np.add.at(c, self.end_dofs[:, 0], half)
        np.add.at(c, self.end_dofs[:, 1], half)
        return c


class TruncatedVCycle:
    """One symmetric V-cycle for K[F, F]: Gauss-Seidel on K (forward before, backward after the
    coarse correction), then the truncated P1 levels down to a sparse Cholesky on the coarsest.
    For a P1 problem K is the finest P1 level itself: the cycle starts there.

    ``stiff_vertices``: vertices whose rows carry a boundary term much stiffer than A (an
    active penalty or Nitsche term, (1/eps) with eps ~ h), which the coarse spaces, made of A,
    do not see: they are truncated there as at a pin -- nearly a pin is what such a term
    makes of a vertex -- while the finest smoother still relaxes them.
    """

    def __init__(self, multilevel: Multilevel, K_ngs, free: np.ndarray, edges: ContactEdges,
                 stiff_vertices: np.ndarray | None = None, smoothed: np.ndarray | None = None):
        nv = multilevel.nvertices
        pinned_vertices = ~free[:nv]
        ends = edges.end_dofs[~free[edges.edge_dofs]]
        pinned_vertices[ends.ravel()] = True
        self.multilevel, self.K, self.edges, self.nv = multilevel, K_ngs, edges, nv
        self.free = free.astype(float)
        self.fine_is_p1 = K_ngs.height == nv
        truncated = pinned_vertices if stiff_vertices is None else pinned_vertices | stiff_vertices
        self.pins = multilevel.truncated_pins(truncated)
        if self.fine_is_p1:
            self.pins[-1] = pinned_vertices     # the finest level smooths the stiff vertices too
        self.keep = [(~p).astype(float) for p in self.pins]
        # ``smoothed``: the dofs the finest Gauss-Seidel relaxes (default: every free one)
        self.smoother = None if self.fine_is_p1 else K_ngs.CreateSmoother(_bits(free if smoothed is None else smoothed))
        # a P1 problem's own matrix is the top P1 level (the same as A for the cone methods,
        # A plus its Gamma_C terms for penalty and Nitsche)
        self.matrices = [*multilevel.matrices[:-1], K_ngs if self.fine_is_p1 else multilevel.matrices[-1]]
        self.smoothers = [m.CreateSmoother(_bits(~p)) for m, p in zip(self.matrices, self.pins)]
        self.coarsest = self.matrices[0].Inverse(_bits(~self.pins[0]), inverse="sparsecholesky")
        # NGSolve work vectors with their NumPy views made once: a view costs microseconds, which
        # on small meshes is a good part of a V-cycle
        self._work = [_vectors(m, 3) for m in multilevel.matrices]
        self._x, self._d = _vectors(K_ngs, 2)

    def _p1_cycle(self, level: int, d: np.ndarray) -> np.ndarray:
        (x, x_np), (b, b_np), (r, r_np) = self._work[level]
        b_np[:] = d
        if level == 0:
            x.data = self.coarsest * b
            return x_np.copy()
        x_np[:] = 0.0
        self.smoothers[level].Smooth(x, b)
        r.data = b - self.matrices[level] * x
        r_np *= self.keep[level]
        self.multilevel.restrict(level, r)
        nc = len(self.keep[level - 1])
        correction = self._p1_cycle(level - 1, r_np[:nc] * self.keep[level - 1])
        r_np[:] = 0.0
        r_np[:nc] = correction
        self.multilevel.prolongate(level, r)
        x_np += r_np * self.keep[level]
        self.smoothers[level].SmoothBack(x, b)
        return x_np.copy()

    def apply(self, r, out) -> None:
        """out = B r for NGSolve vectors (r vanishes on the pins; so does out)."""
        (x, x_np), (d, d_np) = self._x, self._d
        top = len(self.multilevel.matrices) - 1
        if self.fine_is_p1:
            # K is the top P1 matrix (S = I for P1) with the same pins: one P1 V-cycle
            x_np[:] = self._p1_cycle(top, r.FV().NumPy() * self.keep[top])
            out.data = x
            out.FV().NumPy()[:] *= self.free
            return
        x_np[:] = 0.0
        self.smoother.Smooth(x, r)
        d.data = r - self.K * x
        d_np *= self.free
        correction = self._p1_cycle(top, self.edges.restrict(d_np, self.nv) * self.keep[top])
        self.edges.prolongate(correction, x_np)
        self.smoother.SmoothBack(x, r)
        out.data = x
        out.FV().NumPy()[:] *= self.free


def _vectors(matrix, count: int) -> list[tuple]:
    """``count`` column vectors of ``matrix``, each with its NumPy view."""
    vectors = [matrix.CreateColVector() for _ in range(count)]
    return [(v, v.FV().NumPy()) for v in vectors]


def _max_abs(a: np.ndarray) -> float:
    """max |a| without a temporary the size of a."""
    return max(a.max(initial=0.0), -a.min(initial=0.0))


def pcg(K_ngs, preconditioner: TruncatedVCycle, rhs: np.ndarray, z: np.ndarray, free: np.ndarray,
        tol: float, max_iterations: int = 500, projection=None) -> tuple[np.ndarray, int]:
    """Solve K[F, F] z_F = rhs_F - K[F, P] z_P by preconditioned CG from the start z (whose pinned
    entries stay), until max |residual| <= tol, checked on the true residual. All vector work is
    NGSolve's (multithreaded, and no BLAS threads competing with its task manager).

    ``projection`` (``projection.RowProjection``, or None): CG on the affine space {B z = B z0}
    of a start z0 that satisfies active general constraints B z = g (projected CG, Gould,
    Hribar & Nocedal, SIAM J. Sci. Comput. 23 (2001)). The preconditioner must map into the
    kernel of B (``projected.ConstrainedVCycle``; then M = P M P, P the orthogonal projector);
    its output is projected once more all the same, so that round-off never moves the iterate
    off the affine space (without it the drift stalled CG at 1e-9 relative on transition-line-3d).
    The residual that decides convergence is P r, the stationarity once the constraints'
    least-squares multipliers are taken off."""
    mask = preconditioner.free      # the float indicator of ``free``, made once per pin set
    (x, x_np), (r, r_np), (p, _), (q, q_np), (s, s_np) = _vectors(K_ngs, 5)
    x_np[:] = z
    iterations = 0

    def converged(bound: float) -> bool:
        if projection is None:
            return _max_abs(r_np) <= bound
        # max |P r|: P changes r on the constraints' columns only
        kept = r_np[projection.columns]
        projection.apply_in_place(r_np)
        largest = _max_abs(r_np)
        r_np[projection.columns] = kept
        return largest <= bound

    def precondition() -> None:
        preconditioner.apply(r, s)
        if projection is not None:
            projection.apply_in_place(s_np)

    for _restart in range(3):
        r.data = K_ngs * x
        r_np[:] = (rhs - r_np) * mask
        if converged(tol):
            break
        precondition()
        p.data = s
        rs = ngs.InnerProduct(r, s)
        while iterations < max_iterations:
            iterations += 1
            q.data = K_ngs * p
            q_np *= mask
            curvature = ngs.InnerProduct(p, q)
            if not (curvature > 0 and rs > 0):
                # K or the V-cycle (smoothing with K) is not positive definite (Nitsche with
                # theta = 1 past its gamma0 bound): CG cannot converge, the caller checks the
                # residual and solves directly (without the max_iterations CG steps first)
                return x_np.copy(), iterations
            step = rs / curvature
            x.data += step * p
            r.data -= step * q
            if converged(0.5 * tol):
                break
            precondition()
            rs_new = ngs.InnerProduct(r, s)
            p.data = s + (rs_new / rs) * p
            rs = rs_new
    return x_np.copy(), iterations


# No change of variables: penalty, Nitsche and the Ritz projection work in NGSolve's own
# hierarchical variables, where a P1 function is its vertex values and zero bubbles.
HIERARCHICAL = ContactEdges(np.zeros(0, np.int64), np.zeros((0, 2), np.int64))
