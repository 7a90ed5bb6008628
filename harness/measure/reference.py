"""Errors against a reference solution, for cases without a closed-form u.

Every method of such a case is measured against one reference: the solution u_R of
``REFERENCE_METHOD`` (nodal P2) on the mesh k levels finer than P2's finest studied level, so
4^k times the dofs of every method's finest studied level (P1 studies one level more, on the
same number of dofs, unless the case's ``asymptotic_levels_p1`` stops it with P2). One reference for all: the methods' errors are distances to the same
function (the cost at equal accuracy compares them), the most accurate one the study can make,
and solved once (each method's own solution k levels finer cost seven such solves, and P1's,
on a mesh four times larger than P2's for the same dofs, set the report's peak memory).

The meshes are nested (red refinement: every triangle splits into four, every tetrahedron into
eight), so X_h of a studied level is a subspace of X_R and each u_h is *exactly* a function of
X_R: its coefficients there follow from the hierarchical basis (docs/mathematics.md §3) without
interpolation error,

    fine vertex at a coarse vertex a:          u_a
    fine vertex at the midpoint of edge ab:    (u_a + u_b)/2 - c_ab/8
    fine edge on half of coarse edge ab:       c_ab/4
    fine edge joining midpoints of ab and ac:  c_bc/4 (the parallel coarse edge),
    3D, the inner diagonal joining the midpoints of opposite edges ab and cd of a tetrahedron:
                                               (c_ac + c_ad + c_bc + c_bd - c_ab - c_cd)/4,

because the bubble coefficient of an edge e is the second derivative of the function along it,
e^T H e with H the element's constant Hessian (halving an edge divides it by 4). The diagonal
is (c + d - a - b)/2, and the polarisation identity Q(x + y) = Q(x) + Q(y) + 2B(x, y) with
2B(c - a, d - b) = Q(c - b) + Q(d - a) - Q(c - d) - Q(a - b) (Q(v) = v^T H v) gives the last line. P1 keeps the first
two lines without the bubbles, and a P1 function is the P2 function with the same vertex
values and no bubbles (``embed``). Then e = u_R - P u_h is in X_R and its norms are exact
matrix norms: |e|_1^2 = e^T K_R e, ||e||_0^2 = e^T M_R e, and on Gamma_C with the boundary mass
matrix of the contact quadrature. No quadrature error and no point location.

Elasticity (Remark 2.3): NGSolve's VectorH1 numbers its dofs by component, one block of the
scalar space's dofs after the other, so in NGSolve's Cartesian basis the prolongation is
kron(I_d, P) and the H^1-seminorm and L^2 matrices kron(I_d, K_R), kron(I_d, M_R), each applied
block by block (``blockwise``, ``ReferenceNorms``). The solutions are carried in that basis
(``fem.assembly.DiscreteProblem.cartesian``: the rotated frame on Gamma_C is a level's own, and does not nest); the
energy a(e, e) (the elastic stiffness) and the trace of the contact variable c = -u . n are read in
the reference problem's own variables, e_ours = Q_R^T e (Q_R orthogonal). The discrete pressure is a
scalar on Gamma_C, on the contact dofs of the last component's block: the same kron(I_d, P) carries it.

With nested spaces and no contact, Galerkin orthogonality gives
|u - u_h|^2 = |u_R - u_h|^2 + |u - u_R|^2 (u_R is the Galerkin projection on X_R, which contains
every studied X_h of either order): against a reference k levels finer the error of a P2
method converging like h^p is underestimated by the factor sqrt(1 - 4^{-pk}) (p = 3/2, k = 2:
0.8%), and a P1 method's, whose error is larger at the same dofs, by less;
tests/test_reference.py checks both on transition-r32 against the exact errors.
"""
from __future__ import annotations

import contextlib
from collections import defaultdict
from dataclasses import dataclass
from itertools import combinations

import ngsolve as ngs
import numpy as np
import scipy.sparse as sp

from ..fem.contact_quadrature import contact_quadrature
from ..fem.sparse import csr_view
from ..mesh.points import TRIANGLE_EDGES, cells, mesh_points
from ..methods import METHODS, REFERENCE, with_role
from .errors import DiscretePressure, contact_error_points


@dataclass(frozen=True)
class LevelNumbering:
    """What the exact prolongation needs of one level: its new vertices' parents (the two
    coarse vertices of the edge a new vertex halves; for a vertex of the coarser mesh -1, or
    what netgen keeps from an earlier refinement: left as it is) and the P2 edge dofs by vertex pair."""

    nv: int
    parents: np.ndarray       # (nv, 2)
    edge_keys: np.ndarray     # (ne,) sorted keys a * nv + b (a < b) of the edges
    edge_dofs: np.ndarray     # (ne,) their P2 dofs, in the order of edge_keys
    ndof2: int

    @classmethod
    def of(cls, mesh: ngs.Mesh, quadratic: bool = True, coarse_nv: int | None = None) -> "LevelNumbering":
        """``quadratic``: with the P2 edge dofs. ``coarse_nv``: the vertex count of the mesh
        this one refines (0 for a coarse mesh), whose vertices keep their numbers: the parents
        then come from the cell table (``red_parents``), else from netgen one vertex at a time."""
        nv = mesh.nv
        parents = red_parents(mesh, coarse_nv) if coarse_nv is not None else None
        if parents is None:
            parents = np.array([mesh.GetParentVertices(v) for v in range(nv)], dtype=np.int64).reshape(nv, 2)
        if not quadratic:
            return cls(nv, parents, np.zeros(0, np.int64), np.zeros(0, np.int64), 0)
        fes = ngs.H1(mesh, order=2)
        pairs, edge_dofs = edge_dofs_of_sides(mesh, fes)
        pairs.sort(axis=1)
        keys, first = np.unique(pairs[:, 0] * nv + pairs[:, 1], return_index=True)
        return cls(nv, parents, keys, edge_dofs[first], fes.ndof)

    def ndof(self, order: int) -> int:
        return self.nv if order == 1 else self.ndof2

    def edge_dof(self, a: np.ndarray, b: np.ndarray) -> np.ndarray:
        """P2 dofs of the edges with end points a, b (arrays)."""
        keys = np.minimum(a, b) * self.nv + np.maximum(a, b)
        where = np.searchsorted(self.edge_keys, keys)
        if not np.array_equal(self.edge_keys[np.minimum(where, len(self.edge_keys) - 1)], keys):
            raise RuntimeError("a vertex pair is no edge of the coarser mesh: the meshes are not nested")
        return self.edge_dofs[where]


def edge_dofs_of_sides(mesh: ngs.Mesh, fes: ngs.H1) -> tuple[np.ndarray, np.ndarray]:
    """((s ne, 2) the end vertices of every side of every cell (s = 3 in 2D, 6 in 3D), (s ne,)
    the P2 edge dof of each), without a loop over NGSolve's elements: a P2 function with zero
    vertex values and edge coefficients 1, 2, 3, ... is c_e phi_e at the midpoint of edge e,
    where every edge's bubble phi_e has the same value (a multiple of lambda_a lambda_b = 1/4);
    read there, at mesh points made directly, it gives c_e. Vertex dofs are the vertex numbers,
    so the P2 dofs past nv are the edges' (checked: a mesh that breaks this raises)."""
    nv, ndof, dim = mesh.nv, fes.ndof, mesh.dim
    table = cells(mesh)
    ne = len(table)
    # NGSolve's reference cells: vertices at (1, 0), (0, 1), (0, 0) and (1, 0, 0), (0, 1, 0), (0, 0, 1), (0, 0, 0)
    local = np.vstack([np.eye(dim), np.zeros(dim)])
    sides = TRIANGLE_EDGES if dim == 2 else tuple(combinations(range(4), 2))
    midpoints = np.array([(local[a] + local[b]) / 2 for a, b in sides])
    points = mesh_points(mesh, len(sides) * ne)
    for k, name in enumerate("xyz"[:dim]):
        points[name] = np.tile(midpoints[:, k], ne)
    points["nr"] = np.repeat(np.arange(ne), len(sides))
    numbered = ngs.GridFunction(fes)
    values = numbered.vec.FV().NumPy()
    values[:nv], values[nv:] = 0.0, np.arange(1, ndof - nv + 1)
    label = np.asarray(numbered(points), dtype=float).ravel()
    # the common bubble value, read at one midpoint (a bubble of another value or sign would
    # give a label off the integers 1 ... ndof - nv, which raises below)
    values[nv:] = 1.0
    bubble = float(np.asarray(numbered(points[:1]), dtype=float).ravel()[0])
    edge = np.rint(label / bubble).astype(np.int64)
    if np.abs(label / bubble - edge).max() > 1e-6 or edge.min() < 1 or edge.max() > ndof - nv:
        raise RuntimeError("the P2 space's dofs past the vertices are not one per edge")
    pairs = np.concatenate([table[:, list(e)] for e in sides], axis=1).reshape(-1, 2)
    return pairs, nv + edge - 1


def red_parents(mesh: ngs.Mesh, coarse_nv: int) -> np.ndarray | None:
    """(nv, 2) the parents of every vertex of a red refinement of a mesh with ``coarse_nv``
    vertices (-1 for the coarse vertices), from the cells alone: a new vertex halves the coarse
    edge ab and, of the coarse vertices, is joined by a fine edge to a and b only (its other
    fine edges join midpoints: corner children a-m_ab-m_ac, and the centre child), also on a
    curved boundary, where the new vertex is moved onto the curve. None if some new vertex has
    not exactly two coarse neighbours (not one red refinement)."""
    nv = mesh.nv
    parents = np.full((nv, 2), -1, dtype=np.int64)
    if coarse_nv in (0, nv):               # a coarse mesh, or nothing new
        return parents
    table = cells(mesh)
    corners = table.shape[1]
    ends = np.concatenate([table[:, [i, j]] for i in range(corners) for j in range(i + 1, corners)])
    new_first = np.where(ends[:, :1] >= coarse_nv, ends, ends[:, ::-1])
    links = new_first[(new_first[:, 0] >= coarse_nv) & (new_first[:, 1] < coarse_nv)]
    links = np.unique(links[:, 0] * coarse_nv + links[:, 1])
    new, old = links // coarse_nv, links % coarse_nv
    if len(new) != 2 * (nv - coarse_nv) or not np.array_equal(new[::2], np.arange(coarse_nv, nv)) \
            or not np.array_equal(new[1::2], np.arange(coarse_nv, nv)):
        return None
    parents[coarse_nv:] = old.reshape(-1, 2)
    return parents


def prolongation(coarse: LevelNumbering, fine: LevelNumbering, order: int) -> sp.csr_matrix:
    """The matrix of the embedding X_h(coarse) -> X_h(fine) of order 1 or 2 (module docstring)."""
    new = np.arange(coarse.nv, fine.nv)
    a, b = fine.parents[new, 0], fine.parents[new, 1]
    if (a < 0).any() or (b < 0).any() or (a >= coarse.nv).any() or (b >= coarse.nv).any():
        raise RuntimeError("the fine mesh is not one red refinement of the coarse mesh")
    old = np.arange(coarse.nv)
    rows = [old, new, new]
    cols = [old, a, b]
    values = [np.ones(coarse.nv), np.full(len(new), 0.5), np.full(len(new), 0.5)]
    if order == 2:
        rows.append(new)
        cols.append(coarse.edge_dof(a, b))
        values.append(np.full(len(new), -0.125))
        p, q = fine.edge_keys // fine.nv, fine.edge_keys % fine.nv      # p < q
        half = p < coarse.nv                   # p a coarse vertex, q the midpoint of (p, other)
        qa, qb = fine.parents[q, 0], fine.parents[q, 1]
        other = np.where(qa == p, qb, qa)
        pa, pb = fine.parents[p, 0], fine.parents[p, 1]
        # both ends midpoints, of (s, o1) and (s, o2): the parallel coarse edge is (o1, o2)
        disjoint = ~half & (pa != qa) & (pa != qb) & (pb != qa) & (pb != qb)
        shared = np.where((pa == qa) | (pa == qb), pa, pb)
        o1 = np.where(pa == shared, pb, pa)
        o2 = np.where(qa == shared, qb, qa)
        parallel = ~disjoint
        rows.append(fine.edge_dofs[parallel])
        cols.append(coarse.edge_dof(np.where(half, p, o1)[parallel], np.where(half, other, o2)[parallel]))
        values.append(np.full(parallel.sum(), 0.25))
        # 3D: midpoints of the opposite edges (a, b) = (pa, pb) and (c, d) = (qa, qb) of a
        # tetrahedron (the module's note)
        a, b, c, d = (x[disjoint] for x in (pa, pb, qa, qb))
        for (x, y), sign in (((a, c), 1), ((a, d), 1), ((b, c), 1), ((b, d), 1), ((a, b), -1), ((c, d), -1)):
            rows.append(fine.edge_dofs[disjoint])
            cols.append(coarse.edge_dof(x, y))
            values.append(np.full(len(a), 0.25 * sign))
    shape = (fine.ndof(order), coarse.ndof(order))
    return sp.csr_matrix((np.concatenate(values), (np.concatenate(rows), np.concatenate(cols))), shape=shape)


def norm_matrices(mesh: ngs.Mesh, order: int, stiffness: sp.csr_matrix | None = None) -> tuple[sp.csr_matrix, sp.csr_matrix]:
    """(K, M): stiffness and mass matrices of X_h of ``order`` on ``mesh``, every dof.
    ``stiffness``: K if already assembled (the scalar problem's A, a copy of which is taken)."""
    fes = ngs.H1(mesh, order=order)
    u, v = fes.TnT()
    forms = [ngs.BilinearForm(u * v * ngs.dx)]
    if stiffness is None:
        forms.insert(0, ngs.BilinearForm(ngs.grad(u) * ngs.grad(v) * ngs.dx))
    matrices = [] if stiffness is None else [stiffness.copy()]
    for form in forms:
        form.Assemble()
        # on NGSolve's memory, not a copy (the mass matrix of a reference level: 3.5e7 entries)
        matrices.append(csr_view(form.mat))
    return tuple(matrices)


def reference_method(case=None, methods=()):
    """The method whose solution k levels finer is every method's reference on ``case``: the
    first of ``methods``, then of the registered methods, that declares the role REFERENCE
    (``methods.method.Method.roles``), is P2 and discretises ``case`` (without a case: one body). The
    registered one is P2 with the paper's nodal cone (Theorem 4.1 / 5.1), converged to a KKT
    residual <= 1e-10 like every solve, and discretising every physics and dimension of the
    harness."""
    for method in with_role(REFERENCE, [*methods, *METHODS.values()]):
        if method.order == 2 and (method.supports(case) if case is not None else 1 in method.bodies):
            return method
    raise ValueError(f"no P2 method declares the role {REFERENCE!r} for {getattr(case, 'name', 'one body')}")


# The name of the registered reference method of one body (``reference_method``).
REFERENCE_METHOD = reference_method().name


def components_of(vector: np.ndarray, ndof: int) -> int:
    """The components d of a vector of a space of ``ndof`` scalar dofs per component (1: scalar;
    elasticity: one per dimension), from its length (ValueError if it is no whole multiple)."""
    blocks, rest = divmod(len(vector), ndof)
    if rest or not blocks:
        raise ValueError(f"a vector of {len(vector)} entries is not one of {ndof} dofs per component")
    return blocks


def blockwise(P: sp.csr_matrix, vector: np.ndarray) -> np.ndarray:
    """kron(I_d, P) @ ``vector``: each of the d component blocks of NGSolve's component-blocked
    (VectorH1) ordering is a scalar function of the space P maps, prolonged alone; d = 1 for a
    scalar. Applied as P times the (n, d) array of the blocks, without the Kronecker product."""
    components = components_of(vector, P.shape[1])
    return (P @ vector.reshape(components, -1).T).T.ravel()


def embed(vector: np.ndarray, numbering: LevelNumbering, order: int) -> np.ndarray:
    """A vector of X_h of ``order`` as one of X_h of order 2 on the same mesh: P2's vertex dofs
    are the vertex numbers and its edge dofs hierarchical bubbles, zero for a P1 function (in
    each component block of a vector space)."""
    if order == 2:
        return vector
    blocks = vector.reshape(components_of(vector, numbering.nv), numbering.nv)
    return np.concatenate([blocks, np.zeros((len(blocks), numbering.ndof2 - numbering.nv))], axis=1).ravel()


def squares(matrix: sp.csr_matrix, vectors: np.ndarray) -> np.ndarray:
    """v^T A v of every column v of ``vectors`` (clipped at 0 against round-off); a scalar
    space's ``matrix`` on vectors of d component blocks is kron(I_d, matrix), summed over blocks."""
    n = matrix.shape[0]
    blocks = vectors.reshape(components_of(vectors, n), n, -1)
    return np.maximum(sum(np.einsum("ij,ij->j", block, matrix @ block) for block in blocks), 0.0)


@dataclass(frozen=True)
class ReferenceNorms:
    """The matrices of the error norms on the reference level (module docstring). ``K``, ``M``:
    the scalar space's H^1-seminorm and L^2 matrices, applied per component block of an error in
    NGSolve's Cartesian basis. In the reference problem's own variables (rotated on Gamma_C by
    ``basis`` Q_R; None where Q_R = I): ``energy``, the elastic stiffness a(., .) (None for the
    Laplacian, whose energy matrix is K), and ``boundary``, ``boundary_h``, the Gamma_C mass
    matrices (the second weighted by h) on the contact variable's dofs ``contact_dofs``."""

    K: sp.csr_matrix
    M: sp.csr_matrix
    energy: sp.csr_matrix | None          # None: the H^1 seminorm's K (the Laplacian's energy)
    boundary: sp.csr_matrix
    boundary_h: sp.csr_matrix
    contact_dofs: np.ndarray
    basis: sp.csr_matrix | None

    @classmethod
    def of(cls, problem, mesh: ngs.Mesh) -> "ReferenceNorms":
        """From the reference level's problem, before its solve takes the stiffness matrix."""
        quadrature = contact_quadrature(problem, contact_error_points(problem.order))
        weighted = quadrature.T.multiply(quadrature.weights[:, None])
        on = problem.contact_dofs
        elastic = problem.physics.elastic
        # a scalar problem's A is the H^1-seminorm's matrix (every dof), assembled already
        K, M = norm_matrices(mesh, problem.order, problem.A if not elastic else None)
        return cls(K, M, problem.A.copy() if elastic else None,
                   (quadrature.T.T @ weighted).tocsr()[on][:, on],
                   (quadrature.T.T @ weighted.multiply(quadrature.h[:, None])).tocsr()[on][:, on],
                   on, problem.basis)

    def errors(self, e: np.ndarray, d: np.ndarray) -> dict[str, np.ndarray]:
        """The squared norms of the columns of ``e`` (u_R - P u_h, Cartesian) and ``d``
        (lambda_R - P lambda_h on the contact dofs): H^1-semi, L^2, energy, trace of the contact
        variable, pressure in L^2 and h-weighted L^2 of Gamma_C."""
        ours = e if self.basis is None else self.basis.T @ e
        semi = squares(self.K, e)
        on = self.contact_dofs
        return {"semi": semi, "l2": squares(self.M, e),
                "energy": semi if self.energy is None else squares(self.energy, ours),
                "trace": squares(self.boundary, ours[on]), "pressure": squares(self.boundary, d[on]),
                "pressure_h": squares(self.boundary_h, d[on])}


class ReferenceErrors:
    """The error columns of a study of a case measured against a reference solution.

    The study calls ``begin_level`` with every mesh of the chain (studied levels, then k more),
    ``solved`` after every solve and ``end_level`` after each level; every method's rows get
    their errors at the end of the level ``reference_level``, where ``reference`` solves.
    ``studied``: each method's number of studied levels (0 for a method solved only for the
    reference).
    """

    def __init__(self, studied: dict[str, int], orders: dict[str, int], reference: str, reference_level: int,
                 phases=None):
        self.phases = phases            # ``study.chain.rows.Phases``: this measurement's set-up counts as "errors"
        self.studied = dict(studied)
        self.orders = dict(orders)
        self.reference, self.reference_level = reference, reference_level
        self.reference_order = orders[reference]
        if self.reference_order != 2 or any(n > reference_level + 1 for n in studied.values()):
            raise ValueError("the reference must be a P2 solution no coarser than every studied level")
        self.numbering: list[LevelNumbering] = []
        self.prolongations: dict[int, list[sp.csr_matrix]] = {1: [], 2: []}
        self.kept = defaultdict(list)             # method -> [(u_h, lambda_h coefficients as X_h vector)]
        self.rows = defaultdict(list)             # method -> its studied rows, to complete
        self.pressure: dict[int, DiscretePressure] = {}
        self.norms = None
        self.solution = None                     # (u_R, lambda_R) once solved

    @property
    def total_levels(self) -> int:
        return self.reference_level + 1

    def skip_level(self, level: int, mesh: ngs.Mesh) -> None:
        """A level no method solves (a resumed study's finished levels): its numbering and
        prolongations still carry the kept solutions up to the reference."""
        with self._phase():
            self._number(level, mesh)

    def _phase(self):
        return self.phases("errors") if self.phases is not None else contextlib.nullcontext()

    def _number(self, level: int, mesh: ngs.Mesh) -> None:
        # every order's solutions are carried up to the reference level, a P2 one
        orders = set(self.orders.values())
        numbering = LevelNumbering.of(mesh, quadratic=2 in orders,
                                      coarse_nv=self.numbering[-1].nv if self.numbering else 0)
        if self.numbering:
            for order in orders:
                self.prolongations[order].append(prolongation(self.numbering[-1], numbering, order))
        self.numbering.append(numbering)

    def begin_level(self, level: int, mesh: ngs.Mesh, problems: dict, quadrature=None, multilevel=None) -> None:
        """Number the new level, prolongations from the previous one, norms on the reference's."""
        with self._phase():
            self._begin(level, mesh, problems)

    def _begin(self, level: int, mesh: ngs.Mesh, problems: dict) -> None:
        self._number(level, mesh)
        self.pressure = {order: DiscretePressure.of(problem) for order, problem in problems.items()}
        if level == self.reference_level:
            self.norms = ReferenceNorms.of(problems[self.reference_order], mesh)

    def solved(self, method, level: int, problem, u: np.ndarray, row: dict | None) -> dict:
        """Columns known at once (``max_tension``); the reference solution is kept for
        ``end_level``, which completes every row."""
        own = self.pressure[method.order]
        coefficients = own.coefficients(u)
        lam = np.zeros(problem.ndof)
        lam[problem.contact_dofs] = coefficients
        # u_h in NGSolve's Cartesian basis (a copy), where the levels nest (module docstring)
        cartesian = problem.cartesian(u).copy()
        if method.name == self.reference and level == self.reference_level:
            self.solution = (cartesian, lam)
        if level < self.studied[method.name]:
            self.kept[method.name].append((cartesian, lam))
            self.rows[method.name].append(row)
            return {"max_tension": own.max_tension(coefficients)}
        return {}

    def end_level(self) -> None:
        """On the reference level, after every solve of it: the error columns of every row."""
        if self.solution is None:
            return
        with self._phase():
            for name in list(self.kept):
                self._complete(name)
        self.solution, self.norms = None, None

    def state_of(self, method_name: str) -> list:
        """What a method's chain must keep to be resumed (``study.chain.walk.ChainState``): its studied
        (u_h, lambda_h) that wait for the reference."""
        return list(self.kept.get(method_name, []))

    def restore(self, method_name: str, state: list, rows: list[dict]) -> None:
        """A resumed chain: the kept solutions and the rows they belong to (the studied rows,
        while the reference has not been solved)."""
        if state:
            self.kept[method_name] = list(state)
            self.rows[method_name] = [row for row in rows if row["level"] < self.studied[method_name]]

    def _lift(self, vector: np.ndarray, order: int, start: int) -> np.ndarray:
        """``vector`` of X_h(level ``start``) of ``order`` as a vector of X_R."""
        for P in self.prolongations[order][start:self.reference_level]:
            vector = blockwise(P, vector)
        return embed(vector, self.numbering[self.reference_level], order)

    def _complete(self, name: str) -> None:
        """The error columns of every kept solution of ``name``: all its levels' u_R - P u_h
        (and lambda_R - P lambda_h) as the columns of one matrix, so that each norm matrix is
        applied once to all of them."""
        u_ref, lam_ref = self.solution
        order, level = self.orders[name], self.reference_level
        kept, rows = self.kept.pop(name), self.rows.pop(name)
        if not kept:
            return
        e = u_ref[:, None] - np.column_stack([self._lift(u_h, order, studied) for studied, (u_h, _) in enumerate(kept)])
        d = lam_ref[:, None] - np.column_stack([self._lift(lam_h, order, studied) for studied, (_, lam_h) in enumerate(kept)])
        norms = self.norms.errors(e, d)
        semi, l2, energy = norms["semi"], norms["l2"], norms["energy"]
        trace, pressure, pressure_h = norms["trace"], norms["pressure"], norms["pressure_h"]
        for studied, row in enumerate(rows):
            # h of the studied level is 2^(level - studied) times the reference's (red refinement)
            row.update({
                "err_h1": float(np.sqrt(semi[studied] + l2[studied])), "err_h1_semi": float(np.sqrt(semi[studied])),
                "err_l2": float(np.sqrt(l2[studied])), "err_energy": float(np.sqrt(energy[studied])),
                "err_trace_l2": float(np.sqrt(trace[studied])),
                "err_pressure_l2": float(np.sqrt(pressure[studied])),
                "err_pressure_h12": float(np.sqrt(2.0 ** (level - studied) * pressure_h[studied])),
            })
