"""Multigrid for the contact solver: CG preconditioned by a V-cycle truncated at the active set.

With the active set fixed, each step of the active set method is the linear problem
K[F, F] z_F = b_F - K[F, P] z_P, the constraints in P acting as Dirichlet pins. A plain
multigrid does not know the pins and its CG iteration count grows like h^{-1/2}; truncating the
coarse spaces at the pins (Kornhuber, Numer. Math. 69 (1994); Graeser and Kornhuber, J. Comput.
Math. 27 (2009)) keeps it bounded independently of h.

The spaces, fine to coarse:
  X_h in the contact model's variables z (P2; ``fem.cones``), then P1 on the finest mesh, then P1
  on each coarser mesh of the hierarchy.
The hierarchical P2 basis contains the P1 hat functions as its vertex functions, and the
meshes are nested, so every coarse matrix (the P1 stiffness matrix of its mesh) is the exact
Galerkin product R A P of the finer one: the V-cycle is a symmetric positive definite
preconditioner. Truncation: a coarse hat whose prolongation is nonzero at a pinned fine variable
is dropped, so every coarse correction vanishes on the pins and the coarse spaces are subspaces
of {z: z_P = 0}. P1 prolongations have non-negative weights, so restricting the indicator of the
pins finds exactly those hats.

Elasticity: the same cycle on the vector spaces, in the frame of the problem. Each
level is vector P1 of its mesh (the physics' own order-1 space and form), written, like the
problem (``fem.rotated_frame.RotatedFrame``), in the rotated frame (t, c) = (u . tau, -u . n) at the
vertices of its Gamma_C: A_l <- Q_l^T A_l Q_l and the prolongation Q_f^T P Q_c, so the coarse
matrices are still exact Galerkin products. Truncation stays per variable: a coarse hat of an
interior vertex vanishes on Gamma_C (it vanishes on every boundary edge not at its vertex),
and that of a vertex of Gamma_C prolongates, at the fine vertices of the same straight piece,
to (t, c) in the same frame: its c reaches the fine c only, its t the fine t only. So only the
normal variable is truncated at the contact zone, and the tangential one keeps its coarse
corrections, as the contact condition leaves it free. (In Cartesian coarse spaces a tilted
Gamma_C forces both components' truncation there, and the CG iterations grow under refinement:
tests/test_elasticity.py's tilted case counts them.)
"""
from __future__ import annotations

import ngsolve as ngs
import numpy as np
import scipy.sparse as sp

from ..fem.p1_embedding import ContactEdges
from ..fem.rotated_frame import RotatedFrame, rotate_in_place
from ..fem.sparse import csr_block_diag, csr_view, free_dofs
from ..mesh.trace import contact_trace
from ..problem.physics import SCALAR


class Multilevel:
    """The P1 spaces of a nested mesh hierarchy (``mesh.levels``): their stiffness matrices and
    free dofs per level, and the P1 prolongations between them.

    Create it on the coarse mesh, call ``refined(mesh, prolongation)`` at every level of the
    sequence (``mesh.levels.Level``'s two fields). A mesh
    refined in place carries its prolongation in NGSolve (the parents of its new vertices);
    between two levels it may have been refined several times (a 3D graded or adaptive level
    is many bisection sweeps, ``mesh.bisection``), and a level's prolongation is then the
    product of the sweeps' ones, each parent-averaging only the vertices its sweep created. A
    level that is a new mesh (2D bisection, ``mesh.newest_vertex``) brings its prolongation as
    a sparse matrix (``mesh.levels.Level.prolongation``), the product of its sweeps already. Either way the
    spaces are nested and every coarse matrix is the Galerkin product R A P.
    """

    def __init__(self, mesh: ngs.Mesh, physics=SCALAR):
        """``physics`` (``problem.physics``): the P1 space and bilinear form of its own
        (``space(mesh, 1)``, ``form``): P1 hats for the scalar problem, vector P1 for elasticity."""
        self.physics = physics
        self.components = physics.components
        self._rotated = physics.rotated_frame
        self.matrices: list = []
        self.free: list[np.ndarray] = []
        self.frames: list = []                # per level: (pairs (k, dim), Q (k, dim, dim)) at Gamma_C, or None
        self.rotations: list = []             # per level: the sparse rotation Q (u_cartesian = Q u_ours), or None
        self.mesh_levels: list[int] = []      # NGSolve's refinement count at each of our levels
        self._prolongations: dict = {}        # level -> ``prolongation_matrix(level)``, made once
        # per level from 1: (the P1 space whose NGSolve prolongation goes there, or None) and
        # (the explicit prolongation from the level below, a sparse vertex matrix, or None)
        self._steps: list[tuple] = [(None, None, None)]  # (space, P, P^T as CSR) per level
        self._space(mesh)
        self._add_level()

    def _space(self, mesh) -> None:
        """The P1 space and form of a new mesh, and a scalar P1 space beside it, whose
        prolongation is each component's (``prolongation_matrix``)."""
        self.mesh = mesh
        self.fes = self.physics.space(mesh, 1)
        self._scalar = ngs.H1(mesh, order=1)
        u, v = self.fes.TnT()
        self._form = ngs.BilinearForm(self.physics.form(u, v) * ngs.dx)

    def _add_level(self) -> None:
        self._form.Assemble()
        frame, rotation = None, None
        if self._rotated:
            rotated = RotatedFrame.of(self.fes, contact_trace(self.mesh))
            if not rotated.identity:
                rotation = rotated.matrix(self.fes.ndof)
                rotate_in_place(csr_view(self._form.mat), rotation)
                frame = rotated.pairs, rotated.blocks()
        self.matrices.append(self._form.mat)
        self.frames.append(frame)
        self.rotations.append(rotation)
        self.free.append(free_dofs(self.fes))
        self.mesh_levels.append(self.mesh.levels - 1)

    def _rotate(self, level: int, values: np.ndarray, to_cartesian: bool) -> None:
        """In place at level's Gamma_C vertices: ours -> Cartesian = Q ours, or back by Q^T."""
        if self.frames[level] is None:
            return
        pairs, Q = self.frames[level]
        values[pairs] = np.einsum("kij,kj->ki" if to_cartesian else "kji,kj->ki", Q, values[pairs])

    def refined(self, mesh, prolongation=None) -> "Multilevel":
        """The hierarchy with ``mesh`` as its finest level: the mesh refined in place, or a new
        mesh with its ``prolongation`` from the finest level so far (``mesh.levels.Level``).
        Unchanged if the mesh is the finest level's, not refined since (a graded level may need
        no bisection at all)."""
        if mesh is not self.mesh:
            if prolongation is None:
                raise ValueError("a new mesh in a nested hierarchy needs its prolongation (Level.prolongation)")
            self._space(mesh)
            matrix = prolongation.tocsr()
            # the restriction's own CSR copy: a transposed view is CSC, rebuilt at every call
            self._steps.append((None, matrix, matrix.T.tocsr()))
        elif self.mesh.levels - 1 == self.mesh_levels[-1]:
            return self
        else:
            self.fes.Update()
            self._scalar.Update()
            self._steps.append((self.fes, None, None))
        self._add_level()
        return self

    def _sweeps(self, level: int) -> range:
        """NGSolve's refinement steps from our ``level`` - 1 to ``level``."""
        return range(self.mesh_levels[level - 1] + 1, self.mesh_levels[level] + 1)

    def restrict(self, level: int, vector, rotate: bool = True) -> None:
        """In place: the first ndof(level - 1) entries of ``vector`` (of level's size) become the
        restriction (the prolongation's transpose) of level's entries: Q_c^T P^T Q_f.
        ``rotate=False``: P^T alone, for indicators (``truncated_pins``)."""
        if rotate:
            self._rotate(level, vector.FV().NumPy(), to_cartesian=True)
        space, _, restriction = self._steps[level]
        if restriction is not None:
            values = vector.FV().NumPy()
            coarse = (restriction @ values.reshape(self.components, -1).T).T
            values[: coarse.size] = coarse.ravel()
        else:
            for sweep in reversed(self._sweeps(level)):
                space.Prolongation().Restrict(sweep, vector)
        if rotate:
            self._rotate(level - 1, vector.FV().NumPy(), to_cartesian=False)

    def prolongate(self, level: int, vector) -> None:
        """In place: ``vector``'s first ndof(level - 1) entries, prolongated to all of level's:
        Q_f^T P Q_c."""
        self._rotate(level - 1, vector.FV().NumPy(), to_cartesian=True)
        space, matrix, _ = self._steps[level]
        if matrix is not None:
            values = vector.FV().NumPy()
            coarse = values[: matrix.shape[1] * self.components].reshape(self.components, -1)
            values[:] = (matrix @ coarse.T).T.ravel()
        else:
            for sweep in self._sweeps(level):
                space.Prolongation().Prolongate(sweep, vector)
        self._rotate(level, vector.FV().NumPy(), to_cartesian=False)

    def prolongation_matrix(self, level: int) -> sp.csr_matrix:
        """The prolongation from ``level`` - 1 to ``level`` as a sparse matrix, Q_f^T P Q_c in the
        variables of the levels (components blocked): for an algebraic Galerkin product (two
        bodies' coupled coarse matrices, ``two_body_multigrid``); made once per level (a level's
        prolongation never changes)."""
        if level in self._prolongations:
            return self._prolongations[level]
        space, matrix, _ = self._steps[level]
        if matrix is None:
            for sweep in self._sweeps(level):
                step = csr_view(self._scalar.Prolongation().CreateMatrix(sweep)).copy()
                matrix = step if matrix is None else step @ matrix
        P = csr_block_diag([matrix] * self.components)      # the components blocked (a Kronecker product: slower)
        fine, coarse = self.rotations[level], self.rotations[level - 1]
        if fine is not None:
            P = fine.T @ P
        if coarse is not None:
            P = P @ coarse
        self._prolongations[level] = P.tocsr()
        return self._prolongations[level]

    @property
    def nvertices(self) -> int:
        """Vertices of the finest mesh."""
        return self.matrices[-1].height // self.components

    @property
    def ndof(self) -> int:
        """P1 dofs of the finest level: one per vertex and component (components blocked)."""
        return self.matrices[-1].height

    def truncated_pins(self, pinned: np.ndarray) -> list[np.ndarray]:
        return truncated_pins(self, pinned)


def truncated_pins(hierarchy, pinned: np.ndarray) -> list[np.ndarray]:
    """Pinned P1 dofs per level of ``hierarchy`` (a ``Multilevel``, or two bodies'
    ``two_body_multigrid.JointMultilevel``), coarse to fine, from those of the finest level: a
    coarse hat is pinned when its prolongation touches a pinned finer dof (or it lies on
    Gamma_u). In a rotated frame, variable by variable (the module's note): the indicator is
    restricted by P^T alone, component block by component block."""
    pins = [pinned | ~hierarchy.free[-1]]
    for level in range(len(hierarchy.matrices) - 1, 0, -1):
        indicator = hierarchy.matrices[level].CreateColVector()
        indicator.FV().NumPy()[:] = pins[0]
        hierarchy.restrict(level, indicator, rotate=False)
        coarse = indicator.FV().NumPy()[: hierarchy.matrices[level - 1].height] > 0
        pins.insert(0, coarse | ~hierarchy.free[level - 1])
    return pins


def _bits(mask: np.ndarray) -> ngs.BitArray:
    return ngs.BitArray(np.asarray(mask, dtype=bool).tolist())


def smoother(matrix, mask: np.ndarray):
    """Gauss-Seidel of ``matrix`` over the dofs of ``mask``: the matrix's own where it has one
    (``two_body_operator.CoupledBlocks``, an operator, not one NGSolve matrix), else NGSolve's."""
    own = getattr(matrix, "smoother", None)
    return own(mask) if own is not None else matrix.CreateSmoother(_bits(mask))


class TruncatedVCycle:
    """One symmetric V-cycle for K[F, F]: Gauss-Seidel on K (forward before, backward after the
    coarse correction), then the truncated P1 levels down to a sparse Cholesky on the coarsest.
    For a P1 problem K is the finest P1 level itself: the cycle starts there.

    ``stiff_vertices``: P1 dofs (vertices, for a scalar problem) whose rows carry a boundary term much stiffer than A (an
    active penalty or Nitsche term, (1/eps) with eps ~ h), which the coarse spaces, made of A,
    do not see: they are truncated there as at a pin -- nearly a pin is what such a term
    makes of a vertex -- while the finest smoother still relaxes them.

    ``previous``: the V-cycle of the last active set on the same hierarchy and matrix, whose
    coarse smoothers and coarsest factorisation are taken over on every level whose pins are the
    same (a new set flips a few rows near Gamma_C; most coarse levels' truncated pins stay).
    """

    def __init__(self, multilevel: Multilevel, K_ngs, free: np.ndarray, edges: ContactEdges,
                 stiff_vertices: np.ndarray | None = None, smoothed: np.ndarray | None = None,
                 previous: "TruncatedVCycle | None" = None):
        n = multilevel.ndof
        pinned_vertices = edges.touched(~free, n)
        self.multilevel, self.K, self.edges, self.nv = multilevel, K_ngs, edges, n
        self.free = free.astype(float)
        # a P1 problem in the P1 hierarchy's own variables: the cycle starts at its finest level
        self.fine_is_p1 = K_ngs.height == n and edges.identity
        truncated = pinned_vertices if stiff_vertices is None else pinned_vertices | stiff_vertices
        self.pins = multilevel.truncated_pins(truncated)
        if self.fine_is_p1:
            self.pins[-1] = pinned_vertices     # the finest level smooths the stiff vertices too
        self.keep = [(~p).astype(float) for p in self.pins]
        # ``smoothed``: the dofs the finest Gauss-Seidel relaxes (default: every free one)
        self.smoother = None if self.fine_is_p1 else smoother(K_ngs, free if smoothed is None else smoothed)
        # a P1 problem's own matrix is the top P1 level (the same as A for the cone methods,
        # A plus its Gamma_C terms for penalty and Nitsche)
        self.matrices = [*multilevel.matrices[:-1], K_ngs if self.fine_is_p1 else multilevel.matrices[-1]]
        same = _same_pins(previous, self.matrices, self.pins)
        self.smoothers = [previous.smoothers[level] if same[level] else smoother(m, ~p)
                          for level, (m, p) in enumerate(zip(self.matrices, self.pins))]
        self.coarsest = previous.coarsest if same[0] else \
            self.matrices[0].Inverse(_bits(~self.pins[0]), inverse="sparsecholesky")
        # NGSolve work vectors with their NumPy views made once: a view costs microseconds, which
        # on small meshes is a good part of a V-cycle. A new active set on the same hierarchy and
        # K takes over the last set's (and pcg's, ``cg_vectors``): at 8e6 dofs a set made some 30
        # vectors of up to 65 MB afresh, and memory first touched is dear on these machines
        # (``bench --only mortar``'s first runs)
        same = previous is not None and previous.multilevel is multilevel and previous.K is K_ngs
        self._work = previous._work if same else [_vectors(m, 3) for m in multilevel.matrices]
        # (a P1 problem's cycle runs in the levels' vectors alone)
        self._x, self._d = (previous._x, previous._d) if same else \
            (_vectors(K_ngs, 2) if not self.fine_is_p1 else (None, None))
        self._cg_vectors = previous._cg_vectors if same else []     # filled on first use, shared

    def _p1_cycle(self, level: int) -> None:
        """x_l = B_l b_l on level ``level``'s work vectors (b_l set by the caller; x_l valid until
        the level's next cycle). No full-length temporary: past 32 MB (4e6 dofs) every NumPy
        temporary is a fresh mmap whose pages are touched anew, and in the two-body V-cycle at
        8e6 dofs those made its NumPy work several times what it is in place."""
        (x, x_np), (b, _), (r, r_np) = self._work[level]
        if level == 0:
            x.data = self.coarsest * b
            return
        x_np[:] = 0.0
        self.smoothers[level].Smooth(x, b)
        r.data = b - self.matrices[level] * x
        r_np *= self.keep[level]
        self.multilevel.restrict(level, r)
        (_, coarse_x), (_, coarse_b), _ = self._work[level - 1]
        nc = len(coarse_b)
        np.multiply(r_np[:nc], self.keep[level - 1], out=coarse_b)
        self._p1_cycle(level - 1)
        r_np[nc:] = 0.0
        r_np[:nc] = coarse_x
        self.multilevel.prolongate(level, r)
        r_np *= self.keep[level]
        x_np += r_np
        self.smoothers[level].SmoothBack(x, b)

    def cg_vectors(self) -> list[tuple]:
        """``pcg``'s five work vectors of K with their NumPy views, made on first use and kept
        (a new active set's V-cycle takes them over)."""
        if not self._cg_vectors:
            self._cg_vectors.extend(_vectors(self.K, 5))
        return self._cg_vectors

    def apply(self, r, out) -> None:
        """out = B r for NGSolve vectors (r vanishes on the pins; so does out): smoothing on K,
        the hooks of a subclass's exact subspace steps before and after the coarse correction
        (none here; ``projected_multigrid.ConstrainedVCycle``'s Gamma_C block), smoothing back."""
        if self.fine_is_p1:
            self._apply_p1(r, out)
            return
        (x, x_np), (d, d_np) = self._x, self._d
        top = len(self.multilevel.matrices) - 1
        x_np[:] = 0.0
        self.smoother.Smooth(x, r)
        d.data = r - self.K * x
        d_np *= self.free
        self._before_coarse(x_np, d_np)
        (_, top_x), (_, top_b), _ = self._work[top]
        np.multiply(self.edges.restrict(d_np, self.nv), self.keep[top], out=top_b)
        self._p1_cycle(top)
        self.edges.prolongate(top_x, x_np)
        self._after_coarse(x_np, r)
        self.smoother.SmoothBack(x, r)
        out.data = x
        out.FV().NumPy()[:] *= self.free

    def _apply_p1(self, r, out) -> None:
        """K is the top P1 matrix (S = I for P1) with the same pins: one P1 V-cycle."""
        top = len(self.multilevel.matrices) - 1
        (x, _), (_, b), _ = self._work[top]
        np.multiply(r.FV().NumPy(), self.keep[top], out=b)
        self._p1_cycle(top)
        out.data = x
        out.FV().NumPy()[:] *= self.free

    def _before_coarse(self, x_np: np.ndarray, d_np: np.ndarray) -> None:
        """A step between the smoothing and the coarse correction: x and its residual d in place."""

    def _after_coarse(self, x_np: np.ndarray, r) -> None:
        """A step between the coarse correction and the smoothing back (x in place; r the input)."""


def _same_pins(previous: TruncatedVCycle | None, matrices: list, pins: list) -> list[bool]:
    """Per level, whether ``previous`` has that level's matrix (the same object) and pins."""
    if previous is None or len(previous.pins) != len(pins):
        return [False] * len(pins)
    return [old is new and np.array_equal(old_pins, new_pins)
            for old, new, old_pins, new_pins in zip(previous.matrices, matrices, previous.pins, pins)]


def _vectors(matrix, count: int) -> list[tuple]:
    """``count`` column vectors of ``matrix``, each with its NumPy view."""
    vectors = [matrix.CreateColVector() for _ in range(count)]
    return [(v, v.FV().NumPy()) for v in vectors]


def max_abs(a: np.ndarray) -> float:
    """max |a| without a temporary the size of a."""
    return max(a.max(initial=0.0), -a.min(initial=0.0))


def pcg(K_ngs, preconditioner: TruncatedVCycle, rhs: np.ndarray, z: np.ndarray, free: np.ndarray,
        tol: float, max_iterations: int = 500, projection=None) -> tuple[np.ndarray, int]:
    """Solve K[F, F] z_F = rhs_F - K[F, P] z_P by preconditioned CG from the start z (whose pinned
    entries stay), until max |residual| <= tol, checked on the true residual. All vector work is
    NGSolve's (multithreaded, and no BLAS threads competing with its task manager).

    ``row_projection`` (``row_projection.RowProjection``, or None): CG on the affine space {B z = B z0}
    of a start z0 that satisfies active general constraints B z = g (projected CG, Gould,
    Hribar & Nocedal, SIAM J. Sci. Comput. 23 (2001)). The preconditioner must map into the
    kernel of B (``projected_multigrid.ConstrainedVCycle``; then M = P M P, P the orthogonal projector);
    its output is projected once more all the same, so that round-off never moves the iterate
    off the affine space (without it the drift stalled CG at 1e-9 relative on transition-line-3d).
    The residual that decides convergence is P r, the stationarity once the constraints'
    least-squares multipliers are taken off."""
    cg = _PreconditionedCG(K_ngs, preconditioner, projection, z)
    for _restart in range(3):
        cg.true_residual(rhs)
        if cg.converged(tol) or not cg.iterate(tol, max_iterations):
            break
    return cg.x_np.copy(), cg.iterations


class _PreconditionedCG:
    """``pcg``'s iteration: its NGSolve work vectors with their NumPy views, made once per solve
    (a view costs microseconds, ``TruncatedVCycle``), and the iterate x and the count of CG
    steps, which carry over the restarts."""

    def __init__(self, K_ngs, preconditioner: TruncatedVCycle, projection, z: np.ndarray):
        self.K, self.preconditioner, self.projection = K_ngs, preconditioner, projection
        self.mask = preconditioner.free      # the float indicator of ``free``, made once per pin set
        (self.x, self.x_np), (self.r, self.r_np), (self.p, _), (self.q, self.q_np), (self.s, self.s_np) = \
            preconditioner.cg_vectors() if preconditioner.K is K_ngs else _vectors(K_ngs, 5)
        self.x_np[:] = z
        self.iterations = 0

    def true_residual(self, rhs: np.ndarray) -> None:
        """r = rhs - K x on the free dofs, computed afresh: the recurrence's r drifts from it by
        round-off, and a restart must judge convergence on the true one."""
        self.r.data = self.K * self.x
        np.subtract(rhs, self.r_np, out=self.r_np)
        self.r_np *= self.mask

    def converged(self, bound: float) -> bool:
        """max |r| <= bound, or max |P r| with a projection: the stationarity once the constraints'
        least-squares multipliers are taken off (``pcg``)."""
        r_np, projection = self.r_np, self.projection
        if projection is None:
            return max_abs(r_np) <= bound
        # P changes r on the constraints' columns only: those are kept and put back, not all of r
        kept = r_np[projection.columns]
        projection.apply_in_place(r_np)
        largest = max_abs(r_np)
        r_np[projection.columns] = kept
        return largest <= bound

    def precondition(self) -> None:
        """s = B r, projected once more with a projection so that round-off never moves the
        iterate off the affine space (``pcg``)."""
        self.preconditioner.apply(self.r, self.s)
        if self.projection is not None:
            self.projection.apply_in_place(self.s_np)

    def iterate(self, tol: float, max_iterations: int) -> bool:
        """CG steps from the current residual until the recurrence's max |r| <= tol / 2 (the
        restart then checks the true one against tol) or ``max_iterations`` steps in all. False
        when a curvature is not positive: K or the V-cycle (smoothing with K) is not positive
        definite (Nitsche with theta = 1 past its gamma0 bound), CG cannot converge, and the
        caller checks the residual and solves directly (without the max_iterations CG steps
        first)."""
        K, mask, x, r, p, q, q_np, s = self.K, self.mask, self.x, self.r, self.p, self.q, self.q_np, self.s
        converged, precondition = self.converged, self.precondition
        precondition()
        p.data = s
        rs = ngs.InnerProduct(r, s)
        while self.iterations < max_iterations:
            self.iterations += 1
            q.data = K * p
            q_np *= mask
            curvature = ngs.InnerProduct(p, q)
            if not (curvature > 0 and rs > 0):
                return False
            step = rs / curvature
            x.data += step * p
            r.data -= step * q
            if converged(0.5 * tol):
                break
            precondition()
            rs_new = ngs.InnerProduct(r, s)
            p.data = s + (rs_new / rs) * p
            rs = rs_new
        return True
