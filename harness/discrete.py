"""The conforming discretisation of (2.5) on one mesh level: X_h, a(., .), L(.), Dirichlet lift.

X_h is NGSolve's H1 space of order 2 (the paper's P2) or 1 (the P1 baseline). Its basis is
hierarchical: vertex hat functions and, for order 2, one bubble phi_e = -1/2 lambda_a lambda_b
per edge (MATH.md Section 5). The stiffness matrix is
NGSolve's, with a scipy CSR view of the same memory (no copy); the contact models change
variables.
"""
from __future__ import annotations

from dataclasses import dataclass

import ngsolve as ngs
import numpy as np
import scipy.sparse as sp

from .mesh import ContactTrace, contact_trace
from .quadrature import ElementQuadrature, singular_vertices

# Gauss order of the volume load f v away from singular points (the graded rule near them):
# see LOAD_ORDER_NOTE in tests/test_errors.py for the measurement that chose it.
LOAD_ORDER = 4
# Extra order for the Neumann load g on Gamma_g: O(h^-1) edges, cheap, and g may be singular at
# a junction.
BOUNDARY_LOAD_BONUS_ORDER = 6
# Gauss points per contact edge for the contact load g_C (graded at singular points)
CONTACT_LOAD_POINTS = 8


@dataclass
class DiscreteProblem:
    mesh: ngs.Mesh
    fes: ngs.H1
    _A: sp.csr_matrix | None    # stiffness matrix a(phi_j, phi_i), all dofs: a view of _A_ngs
    _A_ngs: object              # the same, as assembled by NGSolve
    b: np.ndarray               # load vector L(phi_i), all dofs
    lift: np.ndarray            # Dirichlet data on Gamma_u dofs, zero elsewhere
    free: np.ndarray            # bool: dofs not on Gamma_u
    trace: ContactTrace
    edge_dofs: np.ndarray       # (m,) bubble dof of each contact edge; empty for order 1
    end_dofs: np.ndarray        # (m, 2) vertex dofs of the end points of each contact edge
    vertex_dofs: np.ndarray     # dofs of trace.vertices, same order
    quadrature: ElementQuadrature
    contact_rows: sp.csr_matrix | None = None   # A's rows of ``contact_dofs``, kept after A is taken

    @property
    def contact_dofs(self) -> np.ndarray:
        """The dofs whose basis functions have a trace on Gamma_C: its vertices, then its edges."""
        return np.concatenate([self.vertex_dofs, self.edge_dofs])

    def contact_residual(self, u: np.ndarray) -> np.ndarray:
        """a(u, phi_i) - L(phi_i) for the dofs i of ``contact_dofs``: the discrete contact force."""
        return self.contact_rows @ u - self.b[self.contact_dofs]

    @property
    def ndof(self) -> int:
        return self.fes.ndof

    @property
    def order(self) -> int:
        return self.fes.globalorder

    def bubbles(self, u: np.ndarray) -> np.ndarray:
        """The bubble coefficient of u on each contact edge (zero for order 1)."""
        return u[self.edge_dofs] if len(self.edge_dofs) else np.zeros(len(self.trace.edges))

    @property
    def A(self) -> sp.csr_matrix:
        return self._stiffness()[0]

    @property
    def A_ngs(self):
        return self._stiffness()[1]

    def _stiffness(self):
        if self._A is None:
            raise RuntimeError("the stiffness matrix of this level was taken by its last contact QP (take_stiffness)")
        return self._A, self._A_ngs

    def take_stiffness(self):
        """(A, A_ngs), handed over for good: the last method of a level changes A's values in
        place into its own matrix (``models.contact_qp``), so a level holds one matrix, not two."""
        taken = self._stiffness()
        self._A = self._A_ngs = None
        return taken

    def gridfunction(self, vector: np.ndarray) -> ngs.GridFunction:
        gf = ngs.GridFunction(self.fes)
        gf.vec.FV().NumPy()[:] = vector
        return gf


def _single_dof(fes, node) -> int:
    (dof,) = fes.GetDofNrs(node)
    return dof


def csr_view(matrix) -> sp.csr_matrix:
    """A scipy CSR matrix on the memory of an NGSolve sparse matrix (values and column indices
    shared, not copied); it keeps ``matrix`` alive."""
    values, columns, pointers = matrix.CSR()
    view = sp.csr_matrix((values.NumPy(), np.asarray(columns), np.asarray(pointers, dtype=np.int64)),
                         shape=(matrix.height, matrix.width), copy=False)
    view.owner = matrix
    return view


def load_vector(case, fes: ngs.H1, quadrature: ElementQuadrature) -> np.ndarray:
    """L(v) of (2.5), plus the contact-boundary load g_C of the manufactured-solution
    generalisation: du/dn = g_C + lambda on Gamma_C with lambda >= 0 the contact pressure."""
    v = fes.TestFunction()
    load = ngs.LinearForm(fes)
    if not case.f_vanishes:
        f = case.f.Compile()
        for dx in quadrature.measures(LOAD_ORDER):
            load += f * v * dx
    n = ngs.specialcf.normal(2)
    load += case.neumann_data(n) * v * ngs.ds("neumann", bonus_intorder=BOUNDARY_LOAD_BONUS_ORDER)
    load.Assemble()
    return load.vec.FV().NumPy().copy()


def discretise(case, mesh: ngs.Mesh, order: int = 2, quadrature: ElementQuadrature | None = None) -> DiscreteProblem:
    """X_h of ``order`` on ``mesh``; ``quadrature`` (made here if not given) is shared by the
    problems of one level."""
    if order not in (1, 2):
        raise ValueError(f"order must be 1 or 2, got {order}")
    fes = ngs.H1(mesh, order=order, dirichlet="dirichlet")
    u, v = fes.TnT()
    a = ngs.BilinearForm(ngs.grad(u) * ngs.grad(v) * ngs.dx).Assemble()
    quadrature = quadrature or ElementQuadrature.of(case, mesh)

    dirichlet = ngs.GridFunction(fes)
    dirichlet.Set(case.dirichlet_data, ngs.BND, definedon=mesh.Boundaries("dirichlet"))
    free = np.array(fes.FreeDofs(), dtype=bool)
    lift = np.where(free, 0.0, dirichlet.vec.FV().NumPy())

    trace = contact_trace(mesh)
    edge_dofs = np.array([_single_dof(fes, ngs.NodeId(ngs.EDGE, int(e))) for e in trace.edges] if order == 2 else [],
                         dtype=np.int64)
    end_dofs = np.array([[_single_dof(fes, ngs.NodeId(ngs.VERTEX, int(v))) for v in pair]
                         for pair in trace.edge_vertices])
    if not free[edge_dofs].all() or not free[end_dofs].all():
        raise ValueError("Gamma_C touches Gamma_u; the paper (Section 2) assumes they do not")
    problem = DiscreteProblem(
        mesh=mesh, fes=fes, _A=csr_view(a.mat), _A_ngs=a.mat, b=load_vector(case, fes, quadrature),
        lift=lift, free=free, trace=trace, edge_dofs=edge_dofs, end_dofs=end_dofs,
        vertex_dofs=np.array([_single_dof(fes, ngs.NodeId(ngs.VERTEX, int(v))) for v in trace.vertices]),
        quadrature=quadrature,
    )
    problem.contact_rows = problem.A[problem.contact_dofs].copy()
    if case.contact_load is not None:
        problem.b += contact_load_vector(case, problem)
    return problem


def contact_load_vector(case, problem: DiscreteProblem) -> np.ndarray:
    """int_{Gamma_C} g_C v for every basis function v. g_C is the flux of u up to the pressure,
    so it is as singular as du/dn where u is (r^{-1/2} in corner-r12, r^{-1/4} with infinitely
    many oscillations in oscillating-r34, where a Gauss rule on the first edge errs by O(1)):
    the rule is graded on the edges at singular points, as for the best approximation's flux."""
    from .boundary import contact_quadrature, at_points
    quadrature = contact_quadrature(problem, CONTACT_LOAD_POINTS, graded_at=singular_vertices(case, problem.mesh))
    return quadrature.T.T @ (quadrature.weights * at_points(case.contact_load, problem.mesh, quadrature))


@dataclass(frozen=True)
class ContactTraceFunction:
    """The trace on Gamma_C of a P2 (or P1: c = 0) function: on edge t_i,
    v(t) = (1-t) v_a + t v_b - c t(1-t)/2.

    Kept independently of the mesh so that it survives refinement: the next level uses it to
    predict its active set (nested iteration), the errors module to find the largest
    penetration between nodes, the report to draw u_h along Gamma_C.
    """

    a: np.ndarray
    b: np.ndarray
    va: np.ndarray
    vb: np.ndarray
    bubble: np.ndarray
    end_active: np.ndarray      # (m, 2) bool: the vertex constraints at a and b were active
    edge_active: np.ndarray     # (m,) bool: the edge constraint was active

    @classmethod
    def of(cls, problem: DiscreteProblem, u: np.ndarray, end_active=None, edge_active=None) -> "ContactTraceFunction":
        ends = u[problem.end_dofs]
        m = len(problem.trace.edges)
        end_active = np.zeros((m, 2), bool) if end_active is None else np.asarray(end_active, bool)
        edge_active = np.zeros(m, bool) if edge_active is None or not len(edge_active) else np.asarray(edge_active, bool)
        return cls(problem.trace.a, problem.trace.b, ends[:, 0], ends[:, 1], problem.bubbles(u), end_active, edge_active)

    def value(self, edge: np.ndarray, t: np.ndarray) -> np.ndarray:
        """Value on edge[k] at parameter t[k] (broadcasting)."""
        return (1 - t) * self.va[edge] + t * self.vb[edge] - 0.5 * self.bubble[edge] * t * (1 - t)

    def at(self, t: np.ndarray) -> np.ndarray:
        """Values at parameters t (k,) on every edge: array (m, k)."""
        return self.value(np.arange(len(self.va))[:, None], np.asarray(t)[None, :])

    def minimum_parameters(self) -> np.ndarray:
        """Parameter of the stationary point of each edge's quadratic, clipped to [0, 1]."""
        with np.errstate(divide="ignore", invalid="ignore"):
            t = 0.5 - (self.vb - self.va) / np.where(self.bubble != 0, self.bubble, np.nan)
        return np.clip(np.nan_to_num(t, nan=0.0), 0.0, 1.0)

    def locate(self, points: np.ndarray, tol: float = 1e-9):
        """Boolean (len(points), m): point lies on edge; and the edge parameters t."""
        d = self.b - self.a
        length2 = (d**2).sum(axis=1)
        rel = points[:, None, :] - self.a[None, :, :]
        t = (rel * d[None]).sum(axis=2) / length2[None]
        off = rel - t[..., None] * d[None]
        on = (t > -tol) & (t < 1 + tol) & ((off**2).sum(axis=2) <= (tol**2) * length2[None])
        return on, np.clip(t, 0.0, 1.0)

    def vertex_status(self, points: np.ndarray, tol: float = 1e-9) -> np.ndarray:
        """Active status of the vertex constraint at each point: that of the coarse vertex it
        coincides with, or, inside a coarse edge, that of the edge constraint: the coarse function
        meets the gap at the midpoint (nodal) or dips to it on the edge (mean)."""
        on, t = self.locate(points)
        at_a, at_b = on & (t <= tol), on & (t >= 1 - tol)
        inside = on & ~at_a & ~at_b
        status = (at_a & self.end_active[None, :, 0]) | (at_b & self.end_active[None, :, 1]) | (inside & self.edge_active[None, :])
        return status.any(axis=1)

    def edge_status(self, midpoints: np.ndarray) -> np.ndarray:
        """Active status of the coarse edge constraint on the edge containing each midpoint."""
        on, _ = self.locate(midpoints)
        return (on & self.edge_active[None, :]).any(axis=1)
