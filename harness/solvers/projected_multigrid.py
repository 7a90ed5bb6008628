"""The equality-constrained problem of one active set of ``general_constraints`` by multigrid:

    minimise 1/2 z^T K z - b^T z   subject to   z = lift on the pins,   B_A z = g_A,

for the 3D counterpart of K_h, whose rows are bounds at the vertices of Gamma_C and
the means of its triangles. An active row with a single entry is a bound on one variable: it
becomes a pin, as in the bound solver (``bound_constraints``). The others -- the face means, each
coupling the three vertices and three edge bubbles of a triangle -- are kept by CG on the affine
space {B_A z = g_A} (projected CG, ``multigrid.pcg``), with a V-cycle that maps into the kernel
of B_A (``ConstrainedVCycle``).

Why not P M P with M the V-cycle of the bounds: where the vertices of Gamma_C are pinned, the
face-mean rows restricted to the bubbles are nearly dependent (alternating multipliers on the
triangles around a vertex of even degree cancel: B B^T has eigenvalues near 0 beside ones
of order 1), so the Euclidean projector P is far from local and P M P a poor preconditioner:
CG needs many times the iterations of the same set with its vertex pins alone.
The kernel of B_A is not spanned by local functions there, so no pointwise smoother can
respect it; a block that holds all of Gamma_C's dofs can: ``ConstrainedVCycle``.

Multipliers: K z - b = B_A^T lambda on the free dofs, so the face rows' lambda are the least-
squares multipliers of the residual (``row_projection``; exact up to the CG residual P r that the
solve drives below its tolerance), and a bound's is its pin's reaction minus what the face rows
take.
"""
from __future__ import annotations

import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import splu

from ..fem.p1_embedding import HIERARCHICAL, ContactEdges
from .multigrid import TruncatedVCycle, pcg
from .options import SolverOptions
from .row_projection import RowProjection

_DEFAULT = SolverOptions()


class ConstrainedVCycle(TruncatedVCycle):
    """A symmetric V-cycle for K on {z_P = 0, B_A z = 0} (B_A: ``rows``, the active face means):

      Gauss-Seidel on the dofs off Gamma_C (which B does not see) -> the exact constrained
      solve on the block of Gamma_C's free dofs -> the P1 coarse correction, truncated at the
      pins and at every vertex of an active row -> the block again -> Gauss-Seidel backwards.

    Each step keeps B_A z = 0: Gauss-Seidel off Gamma_C touches no column of B, the block solve
    is constrained, a hierarchical P1 correction vanishing at a triangle's three vertices
    vanishes on it. So the cycle maps into the kernel of B_A and, a symmetric multiplicative
    Schwarz method with exact subspace solves, is symmetric positive definite there. The block
    is the trace layer, a 2D-sized saddle system factorised once per active set by SuperLU
    (regularised as in ``general_constraints.SaddleSystem``: the rows may be dependent)."""

    def __init__(self, multilevel, K_ngs, K_rows: sp.csr_matrix, free: np.ndarray, surface: np.ndarray,
                 rows: sp.csr_matrix, edges: ContactEdges = HIERARCHICAL, regularisation: float = _DEFAULT.regularisation):
        """``K_rows``: K's rows at ``surface`` (Gamma_C's dofs, pinned or not; made once per QP);
        ``regularisation``: the saddle block's, times its scale (``SolverOptions``)."""
        seen = np.zeros(len(free), bool)
        seen[rows.indices] = True
        stiff = edges.touched(seen, multilevel.ndof)       # the P1 dofs of the active rows' vertices
        block = surface[free[surface]]
        off_surface = free.copy()
        off_surface[block] = False
        super().__init__(multilevel, K_ngs, free, edges, stiff_vertices=stiff, smoothed=off_surface)
        self.surface = block
        self.K_surface = K_rows[free[surface]]                   # K's rows (= columns) there
        block = self.K_surface[:, self.surface]
        # the rows of K that a change on Gamma_C's block reaches, and that part of K's columns
        self._reached = np.unique(self.K_surface.indices)
        self._reached_free = self.free[self._reached]
        self._K_reached = self.K_surface[:, self._reached].T.tocsr()
        B_S = rows[:, self.surface]
        d = regularisation * float(np.abs(block.diagonal()).max(initial=1.0))
        saddle = sp.bmat([[block, B_S.T], [B_S, -d * sp.identity(B_S.shape[0])]], format="csc")
        # threshold pivoting (a pivot within a tenth of its column's largest): the same
        # residuals as partial pivoting on this quasi-definite matrix, with less fill, so a faster
        # factorisation and faster solves
        self._block = splu(saddle, diag_pivot_thresh=0.1)
        self._rhs = np.zeros(saddle.shape[0])
        self._n = len(self.surface)

    def _block_step(self, x_np: np.ndarray, residual_on_block: np.ndarray) -> np.ndarray:
        """x += the constrained correction on Gamma_C's block for the residual there; the correction."""
        self._rhs[: self._n] = residual_on_block
        delta = self._block.solve(self._rhs)[: self._n]
        x_np[self.surface] += delta
        return delta

    def _before_coarse(self, x_np: np.ndarray, d_np: np.ndarray) -> None:
        """The first block step, and the residual after it for the coarse level: changed only
        where K reaches."""
        delta = self._block_step(x_np, d_np[self.surface])
        d_np[self._reached] -= (self._K_reached @ delta) * self._reached_free

    def _after_coarse(self, x_np: np.ndarray, r) -> None:
        """The second block step: it needs the residual on its own rows only, K's rows there."""
        self._block_step(x_np, r.FV().NumPy()[self.surface] - self.K_surface @ x_np)


class ProjectedMultigridSystem:
    """Solves one active set of a ``GeneralConstraintSolver`` by projected, truncated multigrid CG
    from the previous iterate; one V-cycle per set (a set solved again reuses it)."""

    iterative = True

    def __init__(self, K_ngs, multilevel, edges: ContactEdges = HIERARCHICAL, options: SolverOptions = _DEFAULT):
        self.K_ngs, self.multilevel, self.edges, self.options = K_ngs, multilevel, edges, options
        self.cg_iterations = 0
        self.preconditioners = 0
        self._last = None           # (key, V-cycle, projection) of the last set
        self._surface = None        # (Gamma_C's dofs, K's rows there), once per QP

    @staticmethod
    def split(B: sp.csr_matrix, rows: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(rows that bound a single variable, the other rows) among ``rows``."""
        single = np.diff(B.indptr)[rows] == 1
        return rows[single], rows[~single]

    def _preconditioner(self, qp, free: np.ndarray, general: np.ndarray):
        key = free.tobytes() + general.tobytes()
        if self._last is None or self._last[0] != key:
            rows = (qp.B[general] @ sp.diags(free.astype(float))).tocsr()
            if self._surface is None:
                surface = np.unique(qp.B.indices)                # every dof a row of B sees: Gamma_C's
                self._surface = surface, qp.K[surface].tocsr()
            surface, K_rows = self._surface
            options = self.options
            if len(general):
                vcycle = ConstrainedVCycle(self.multilevel, self.K_ngs, K_rows, free, surface, rows, self.edges,
                                           options.regularisation)
                projection = RowProjection(rows, options.projection_shift, options.projection_refinements)
            else:
                vcycle, projection = TruncatedVCycle(self.multilevel, self.K_ngs, free, self.edges), None
            self._last = key, vcycle, projection
            self.preconditioners += 1
        return self._last[1], self._last[2]

    def solve(self, qp, rows: np.ndarray, start, tol: float) -> tuple[np.ndarray, np.ndarray]:
        """(z, lambda) of the set ``rows`` of ``qp`` (a ``GeneralConstraintSolver``), to
        max |P (K z - b)| <= tol off the pins."""
        B = qp.B
        bounds, general = self.split(B, rows)
        dofs, coefficients = B.indices[B.indptr[bounds]], B.data[B.indptr[bounds]]
        pinned = ~qp.free.copy()
        pinned[dofs] = True
        values = qp.lift.copy()
        values[dofs] = qp.g[bounds] / coefficients
        z = np.where(pinned, values, 0.0 if start is None else start)
        vcycle, projection = self._preconditioner(qp, ~pinned, general)
        if projection is not None:
            # a start on the affine space: the nearest point whose active face means are g_A
            pinned_part = B[general] @ np.where(pinned, z, 0.0)
            z = projection.onto(z, qp.g[general] - pinned_part)
        z, iterations = pcg(self.K_ngs, vcycle, qp.b, z, ~pinned, tol, self.options.cg_iterations, projection=projection)
        self.cg_iterations += iterations
        force = np.where(qp.free, qp.K @ z - qp.b, 0.0)
        lam = np.zeros(len(qp.g))
        if projection is not None:
            lam[general] = projection.multipliers(np.where(pinned, 0.0, force))
            force -= B[general].T @ lam[general]
        lam[bounds] = force[dofs] / coefficients
        return z, lam

    def work(self) -> dict:
        return {"cg_iterations": self.cg_iterations, "preconditioners": self.preconditioners}
