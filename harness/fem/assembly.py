"""The conforming discretisation of (2.5) on one mesh level: X_h, a(., .), L(.), Dirichlet lift.

X_h is NGSolve's H1 space of order 2 (the paper's P2) or 1 (the P1 baseline), or its vector
counterpart for an elastic case (``physics``; Remark 2.3). An elastic problem is written in a
rotated frame at the nodes of Gamma_C: there the two nodal variables are the contact variable
c = -u . n and the tangential displacement (``RotatedFrame``), so the contact dofs carry one
scalar each, as in the scalar problem, and every cone, solver and error on Gamma_C is shared. Its basis is
hierarchical: vertex hat functions and, for order 2, one bubble phi_e = -1/2 lambda_a lambda_b
per edge (docs/mathematics.md §3). The stiffness matrix is
NGSolve's, with a scipy CSR view of the same memory (no copy); the contact models change
variables.
"""
from __future__ import annotations

from dataclasses import dataclass, field, replace

import ngsolve as ngs
import numpy as np
import scipy.sparse as sp

from ..mesh.hp import MAX_DEGREE
from ..mesh.points import evaluate
from ..mesh.trace import ContactTrace, contact_trace
from .element_quadrature import ElementQuadrature, singular_vertices
from .polynomials import barycentric_lattice, lagrange, lattice_degree, lattice_lagrange, lobatto_points, polynomial_minimum
from .rotated_frame import RotatedFrame, rotate_in_place
from .sparse import csr_view, free_dofs

# the orders of X_h: P1, the paper's P2, and P3, P4 (the degree axis)
ORDERS = (1, 2, 3, 4)
# Gauss order of the volume load f v away from singular points (the graded rule near them), by
# the order k of X_h: 2k, exact for f v with f of degree k, at least 4 (P1 too);
# tests/test_errors.py (test_load_quadrature_changes_no_error_by_more_than_1e_4) measures it
LOAD_ORDER = {1: 4, 2: 4, 3: 6, 4: 8}


def load_order(k: int) -> int:
    """``LOAD_ORDER`` of P_k, and 2k for the degrees of an hp space beyond it."""
    return LOAD_ORDER.get(k, 2 * k)
# Extra order for the Neumann load g on Gamma_g: O(h^-1) edges, cheap, and g may be singular at
# a junction.
BOUNDARY_LOAD_BONUS_ORDER = 6
# Gauss points per contact edge for the contact load g_C (graded at singular points)
CONTACT_LOAD_POINTS = 8


def boundary_load_points(order: int, points: int = CONTACT_LOAD_POINTS) -> int:
    """Gauss points per contact edge for a load on Gamma_C that is no polynomial (g_C, the exact
    flux of the best approximation): ``points``, or 2k + 4 for P_k beyond k = 2 (exact for the
    load's Taylor polynomial of degree 3k + 7 times a basis function). Eight points leave the
    degree-16 functions of an hp mesh a quadrature error above the discretisation error, which
    grew level by level on corner-r12."""
    return max(points, 2 * order + 4)


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
    edge_dofs: np.ndarray       # the k - 1 edge dofs of each contact edge (k: its degree), edge by edge; empty for order 1
    end_dofs: np.ndarray        # (m, 2) vertex dofs of the end points of each contact edge
    vertex_dofs: np.ndarray     # dofs of trace.vertices, same order
    quadrature: ElementQuadrature
    physics: object                             # the case's (``problem.physics``)
    contact_rows: sp.csr_matrix | None = None   # A's rows of ``contact_dofs``, kept after A is taken
    tangential_rows: sp.csr_matrix | None = None  # A's rows of ``tangential_dofs`` (elastic friction cases), kept too
    basis: sp.csr_matrix | None = None          # Q: NGSolve's (Cartesian) coefficients = Q @ ours; None: Q = I
    # what later stages make once per problem and share (the errors' discrete pressure), by kind
    cache: dict = field(default_factory=dict, repr=False, compare=False)
    # an hp space (``mesh.hp``): the degree of each element (None: every element has ``order``)
    degrees: np.ndarray | None = None

    def cartesian(self, vector: np.ndarray) -> np.ndarray:
        """The coefficients in NGSolve's own basis of a vector of this problem's variables."""
        return vector if self.basis is None else self.basis @ vector

    def values_at(self, function, points: np.ndarray) -> np.ndarray:
        """A case's coefficient function (an obstacle, a gap) at ``points`` of this problem's
        mesh (``mesh.points.evaluate``)."""
        return evaluate(function, self.mesh, points)

    @property
    def contact_dofs(self) -> np.ndarray:
        """The dofs whose basis functions have a trace on Gamma_C: its vertices, then its edges."""
        return np.concatenate([self.vertex_dofs, self.edge_dofs])

    @property
    def tangential_dofs(self) -> np.ndarray:
        """(d - 1, len(contact_dofs)) the tangential dofs of each contact dof's node in the rotated
        frame (the component blocks before the contact variable's, ``RotatedFrame``); empty for
        the scalar problem."""
        components = self.physics.components if self.physics.rotated_frame else 1
        block = self.ndof // components
        return self.contact_dofs[None, :] - block * np.arange(components - 1, 0, -1)[:, None]

    def contact_residual(self, u: np.ndarray) -> np.ndarray:
        """a(u, phi_i) - L(phi_i) for the dofs i of ``contact_dofs``: the discrete contact force."""
        return self.contact_rows @ u - self.b[self.contact_dofs]

    @property
    def ndof(self) -> int:
        return self.fes.ndof

    @property
    def order(self) -> int:
        """k of P_k; of an hp space, its largest element degree (what every rule sized by the
        degree, on Gamma_C, for the load and the errors, must integrate)."""
        return self.fes.globalorder

    @property
    def edge_degrees(self) -> np.ndarray:
        """(m,) the degree of each contact edge: its one element's (``set_degrees``' minimum rule
        gives a boundary edge its element's degree)."""
        if self.degrees is None:
            return np.full(len(self.trace.edges), self.order)
        return self.degrees[self.trace.volumes]

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
        place into its own matrix (``cones.contact_qp``), so a level holds one matrix, not two."""
        taken = self._stiffness()
        self._A = self._A_ngs = None
        return taken

    def gridfunction(self, vector: np.ndarray) -> ngs.GridFunction:
        gf = ngs.GridFunction(self.fes)
        gf.vec.FV().NumPy()[:] = self.cartesian(vector)
        return gf


def _contact_dofs(fes, node, components: int) -> list[int]:
    """The dofs of ``node`` that carry the contact variable (one at a vertex, k - 1 on an edge of
    degree k): all of them (scalar), or the last component's block, where ``RotatedFrame`` puts
    c = -u . n (elasticity; NGSolve numbers a node's dofs in component blocks)."""
    dofs = fes.GetDofNrs(node)
    return list(dofs[len(dofs) - len(dofs) // components:])


def set_degrees(fes, mesh: ngs.Mesh, degrees: np.ndarray) -> None:
    """Give ``fes`` (a scalar H1 space made with the largest of ``degrees``) the degree of each
    element, and each edge the least degree of its elements (the minimum rule: conforming, and a
    boundary edge has its element's degree). NGSolve's own variable order: the interior of a 2D
    element is its CELL node (``ngsolve.comp.NodeId``)."""
    for element, degree in enumerate(degrees):
        fes.SetOrder(ngs.NodeId(ngs.CELL, element), int(degree))
    for edge in mesh.edges:
        fes.SetOrder(edge, int(min(degrees[e.nr] for e in edge.elements)))
    fes.Update()


def load_vector(case, fes, quadrature: ElementQuadrature) -> np.ndarray:
    """L(v) of (2.5) in NGSolve's basis: the volume load and the Neumann data (du/dn, or the
    traction sigma(u) n), plus, in elasticity, the traction g_C on Gamma_C (the scalar contact
    load, which may be singular, is integrated on its own: ``contact_load_vector``)."""
    v = fes.TestFunction()
    load = ngs.LinearForm(fes)
    if not case.f_vanishes:
        f = case.f.Compile()
        for dx in quadrature.measures(load_order(fes.globalorder)):
            load += f * v * dx
    n = ngs.specialcf.normal(fes.mesh.dim)
    # compiled (common subexpressions once per point): the derived traction sigma(u) n of an elastic u
    # is a deep tree, whose shared subexpressions would otherwise be evaluated once per use
    load += case.neumann_data(n).Compile() * v * ngs.ds("neumann", bonus_intorder=BOUNDARY_LOAD_BONUS_ORDER)
    if case.physics.traction_load and case.contact_load is not None:
        load += case.contact_load.Compile() * v * ngs.ds("contact", bonus_intorder=BOUNDARY_LOAD_BONUS_ORDER)
    load.Assemble()
    return load.vec.FV().NumPy().copy()


def discretise(case, mesh: ngs.Mesh, order: int = 2, quadrature: ElementQuadrature | None = None,
               degrees: np.ndarray | None = None) -> DiscreteProblem:
    """X_h of ``order`` on ``mesh`` for the case's physics; ``quadrature`` (made here if not
    given) is shared by the problems of one level. ``degrees`` (one per element, at least
    ``order``): an hp space (``mesh.hp``; scalar physics, 2D)."""
    if order not in ORDERS:
        raise ValueError(f"order must be one of {', '.join(map(str, ORDERS))}, got {order}")
    physics = case.physics
    degrees = _checked_degrees(case, mesh, order, degrees)
    fes = physics.space(mesh, order if degrees is None else int(degrees.max()))
    if degrees is not None:
        set_degrees(fes, mesh, degrees)
    u, v = fes.TnT()
    a = ngs.BilinearForm(physics.form(u, v) * ngs.dx).Assemble()
    quadrature = quadrature or ElementQuadrature.of(case, mesh)

    free = free_dofs(fes)
    lift, b = dirichlet_lift(case, fes, free), load_vector(case, fes, quadrature)

    trace = contact_trace(mesh)
    A = csr_view(a.mat)
    basis = None
    if physics.rotated_frame:
        frame = RotatedFrame.of(fes, trace)
        if not frame.identity:
            basis = frame.matrix(fes.ndof)
            rotate_in_place(A, basis)
            b, lift = basis.T @ b, basis.T @ lift
    components = mesh.dim if physics.rotated_frame else 1
    edge_dofs = np.array([d for e in trace.edges for d in _contact_dofs(fes, ngs.NodeId(ngs.EDGE, int(e)), components)],
                         dtype=np.int64)
    end_dofs = np.array([[_contact_dofs(fes, ngs.NodeId(ngs.VERTEX, int(v)), components)[0] for v in pair]
                         for pair in trace.edge_vertices])
    if not free[edge_dofs].all() or not free[end_dofs].all():
        raise ValueError("Gamma_C touches Gamma_u; the paper (Section 2) assumes they do not")
    problem = DiscreteProblem(
        mesh=mesh, fes=fes, _A=A, _A_ngs=a.mat, b=b, lift=lift, free=free, trace=trace, edge_dofs=edge_dofs,
        end_dofs=end_dofs, quadrature=quadrature, physics=physics, basis=basis, degrees=degrees,
        vertex_dofs=np.array([_contact_dofs(fes, ngs.NodeId(ngs.VERTEX, int(v)), components)[0] for v in trace.vertices]),
    )
    problem.contact_rows = problem.A[problem.contact_dofs].copy()
    if physics.rotated_frame and getattr(case, "frictional", False):    # the friction force (``measure.errors.DiscreteTraction``)
        problem.tangential_rows = problem.A[problem.tangential_dofs.ravel()].copy()
    if case.contact_load is not None and not physics.traction_load:
        problem.b += contact_load_vector(case, problem)
    return problem


def dirichlet_lift(case, fes, free: np.ndarray) -> np.ndarray:
    """u_D interpolated on Gamma_u's dofs (NGSolve's basis), zero on the free ones."""
    dirichlet = ngs.GridFunction(fes)
    dirichlet.Set(case.dirichlet_data, ngs.BND, definedon=fes.mesh.Boundaries("dirichlet"))
    return np.where(free, 0.0, dirichlet.vec.FV().NumPy())


def at_load_step(case, problem: DiscreteProblem, step: int) -> DiscreteProblem:
    """``problem`` with the load and Dirichlet data of the case's load step ``step``
    (``problem.friction.LoadHistory``; the last step's are the problem's own), in its variables:
    the same space, matrix and trace, another b and lift."""
    if step == len(case.history) - 1:
        return problem
    stepped = case.at_step(step)
    lift, b = dirichlet_lift(stepped, problem.fes, problem.free), load_vector(stepped, problem.fes, problem.quadrature)
    if problem.basis is not None:
        b, lift = problem.basis.T @ b, problem.basis.T @ lift
    if stepped.contact_load is not None and not problem.physics.traction_load:
        b += contact_load_vector(stepped, problem)
    return replace(problem, b=b, lift=lift, cache={})


def _checked_degrees(case, mesh: ngs.Mesh, order: int, degrees) -> np.ndarray | None:
    """``degrees`` as an int array, or a one-line ValueError: one per element, within ``order`` ..
    ``MAX_DEGREE``, on a scalar 2D case (a vector space's per-element degrees are not set)."""
    if degrees is None:
        return None
    degrees = np.asarray(degrees, dtype=np.int64)
    if case.physics.rotated_frame or mesh.dim != 2:
        raise ValueError("per-element degrees (hp) are implemented for the scalar problem in 2D")
    if degrees.shape != (mesh.ne,) or degrees.min() < order or degrees.max() > MAX_DEGREE:
        raise ValueError(f"degrees must be one per element ({mesh.ne}), between {order} and {MAX_DEGREE}")
    return degrees


def contact_load_vector(case, problem: DiscreteProblem) -> np.ndarray:
    """int_{Gamma_C} g_C v for every basis function v. g_C is the flux of u up to the pressure,
    so it is as singular as du/dn where u is (r^{-1/2} in corner-r12, r^{-1/4} with infinitely
    many oscillations in oscillating-r34, where a Gauss rule on the first edge errs by O(1)):
    the rule is graded on the edges at singular points, as for the best approximation's flux."""
    from .contact_quadrature import at_points, contact_quadrature
    quadrature = contact_quadrature(problem, boundary_load_points(problem.order), graded_at=singular_vertices(case, problem.mesh))
    return quadrature.T.T @ (quadrature.weights * at_points(case.contact_load, problem.mesh, quadrature))


@dataclass(frozen=True)
class ContactTraceFunction:
    """The trace on Gamma_C of a P2 (or P1: c = 0) function: on edge t_i,
    v(t) = (1-t) v_a + t v_b - c t(1-t)/2; in 3D also on each triangle of Gamma_C,
    v = sum_k lambda_k v_k - 1/2 sum_k c_k lambda_k lambda_{k+1} (corner values v_k, bubble c_k of
    side k, from corner k to corner k+1).

    Kept independently of the mesh so that it survives refinement: the next level uses it to
    predict its active set (nested iteration, ``fem.nested``), the errors module to find the largest
    penetration between nodes, the report to draw u_h along Gamma_C.
    """

    a: np.ndarray
    b: np.ndarray
    va: np.ndarray
    vb: np.ndarray
    bubble: np.ndarray
    end_active: np.ndarray      # (m, 2) bool: the vertex constraints at a and b were active
    edge_active: np.ndarray     # (m,) bool: the edge constraint was active
    face_points: np.ndarray | None = None   # 3D: (f, 3, 3) corners of the triangles of Gamma_C
    face_values: np.ndarray | None = None   # 3D: (f, 3) values at the corners
    face_bubbles: np.ndarray | None = None  # 3D: (f, 3) bubble coefficients of the sides
    volumes: np.ndarray | None = None       # 2D: (m,) the triangles on the edges (``mesh.points.in_elements``)
    face_active: np.ndarray | None = None   # 3D, face-mean cone: (f,) the triangle's mean constraint was active
    lobatto: np.ndarray | None = None       # P_k with k >= 3: (m, k + 1) values at ``lobatto_points(k)`` of each edge
    face_lattice: np.ndarray | None = None  # 3D, P_k with k >= 3: (f, (k + 1)(k + 2)/2) values at ``barycentric_lattice(k)``

    @classmethod
    def of(cls, problem: DiscreteProblem, u: np.ndarray, end_active=None, edge_active=None,
           face_active=None) -> "ContactTraceFunction":
        ends = u[problem.end_dofs]
        trace = problem.trace
        m = len(trace.edges)
        end_active = np.zeros((m, 2), bool) if end_active is None else np.asarray(end_active, bool)
        edge_active = np.zeros(m, bool) if edge_active is None or not len(edge_active) else np.asarray(edge_active, bool)
        bubbles = problem.bubbles(u)
        faces = {}
        if trace.faces is not None:
            corners = np.searchsorted(trace.vertices, trace.faces.vertices)
            faces = {"face_points": trace.faces.corners(trace), "face_values": u[problem.vertex_dofs][corners],
                     "face_bubbles": bubbles[trace.faces.edges]}
        if problem.order > 2:
            if trace.faces is not None:
                faces = {"face_points": faces["face_points"], "face_values": faces["face_values"],
                         "face_lattice": _face_lattice_values(problem, u)}
            return cls(trace.a, trace.b, ends[:, 0], ends[:, 1], np.zeros(m), end_active, edge_active, **faces,
                       volumes=edge_volumes(trace), lobatto=_lobatto_values(problem, u), face_active=face_active)
        return cls(trace.a, trace.b, ends[:, 0], ends[:, 1], bubbles, end_active, edge_active, **faces,
                   volumes=trace.volumes, face_active=face_active)

    def value(self, edge: np.ndarray, t: np.ndarray) -> np.ndarray:
        """Value on edge[k] at parameter t[k] (broadcasting)."""
        if self.lobatto is not None:
            k = self.lobatto.shape[1] - 1
            return (self.lobatto[edge] * lagrange(lobatto_points(k), t)).sum(axis=-1)
        return (1 - t) * self.va[edge] + t * self.vb[edge] - 0.5 * self.bubble[edge] * t * (1 - t)

    def at(self, t: np.ndarray) -> np.ndarray:
        """Values at parameters t (k,) on every edge: array (m, k)."""
        return self.value(np.arange(len(self.va))[:, None], np.asarray(t)[None, :])

    def on_faces(self, barycentric: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """3D: (points (f, k, 3), values (f, k)) at the barycentric points (k, 3) of every triangle
        (P_k, k >= 3: the Lagrange interpolant of the lattice values, ``lattice_lagrange``)."""
        lam = np.asarray(barycentric)
        if self.face_lattice is not None:
            values = self.face_lattice @ lattice_lagrange(lattice_degree(self.face_lattice.shape[1]), lam).T
        else:
            bubble_shapes = lam * np.roll(lam, -1, axis=1)           # lambda_k lambda_{k+1}: side k
            values = self.face_values @ lam.T - 0.5 * self.face_bubbles @ bubble_shapes.T
        return np.einsum("kc,fcd->fkd", lam, self.face_points), values

    def minimum_parameters(self) -> np.ndarray:
        """Parameter of the stationary point of each edge's quadratic, clipped to [0, 1]; for P_k,
        k >= 3, the parameter of each edge's least value (``fem.polynomials.polynomial_minimum``)."""
        if self.lobatto is not None:
            return polynomial_minimum(self.lobatto)
        with np.errstate(divide="ignore", invalid="ignore"):
            t = 0.5 - (self.vb - self.va) / np.where(self.bubble != 0, self.bubble, np.nan)
        return np.clip(np.nan_to_num(t, nan=0.0), 0.0, 1.0)


def _lobatto_values(problem: DiscreteProblem, u: np.ndarray) -> np.ndarray:
    """(m, k + 1) the contact variable of u at the Gauss-Lobatto points of each contact edge: k + 1
    values that fix its degree-k trace there."""
    from .contact_quadrature import trace_rows
    trace, k = problem.trace, problem.order
    t = lobatto_points(k)
    points = trace.a[:, None, :] + t[None, :, None] * (trace.b - trace.a)[:, None, :]
    volumes = np.repeat(edge_volumes(trace), k + 1)
    normals = np.repeat(trace.normals, k + 1, axis=0)
    T = trace_rows(problem.fes, problem.physics, problem.basis, volumes, points.reshape(-1, points.shape[-1]), normals)
    return (T @ u).reshape(-1, k + 1)


def edge_volumes(trace: ContactTrace) -> np.ndarray:
    """The volume element holding each contact edge: the trace's own in 2D, in 3D the tetrahedron
    of a triangle of Gamma_C with that side."""
    if trace.faces is None:
        return trace.volumes
    volumes = np.empty(len(trace.edges), dtype=np.int64)
    volumes[trace.faces.edges.ravel()] = np.repeat(trace.faces.volumes, 3)
    return volumes


def _face_lattice_values(problem: DiscreteProblem, u: np.ndarray) -> np.ndarray:
    """(f, (k + 1)(k + 2)/2) the contact variable of u at ``barycentric_lattice(k)`` of each triangle
    of a 3D Gamma_C: values that fix its degree-k trace there."""
    from .contact_quadrature import trace_rows
    faces, lattice = problem.trace.faces, barycentric_lattice(problem.order)
    points = np.einsum("lc,fcd->fld", lattice, faces.corners(problem.trace))
    count = len(lattice)
    T = trace_rows(problem.fes, problem.physics, problem.basis, np.repeat(faces.volumes, count),
                   points.reshape(-1, 3), np.repeat(faces.normals, count, axis=0))
    return (T @ u).reshape(-1, count)
