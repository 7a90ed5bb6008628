"""Errors against a reference solution, for cases without a closed-form u (issue 16).

Each method's reference is its own discrete solution u_R on the mesh k levels finer than the
finest level it studies (same chain of levels, nested iteration all the way). The meshes are
nested (red refinement: every triangle splits into four), so X_h of a studied level is a
subspace of X_R and each u_h is *exactly* a function of X_R: its coefficients there follow
from the hierarchical basis (docs/mathematics.md §3) without interpolation error,

    fine vertex at a coarse vertex a:          u_a
    fine vertex at the midpoint of edge ab:    (u_a + u_b)/2 - c_ab/8
    fine edge on half of coarse edge ab:       c_ab/4
    fine edge joining midpoints of ab and ac:  c_bc/4 (the parallel coarse edge),

because the bubble coefficient of an edge is the second derivative of the function along it
(a quadratic has a constant Hessian, and halving an edge divides it by 4). P1 keeps the first
two lines without the bubbles. Then e = u_R - P u_h is in X_R and its norms are exact matrix
norms: |e|_1^2 = e^T K_R e, ||e||_0^2 = e^T M_R e, and on Gamma_C with the boundary mass
matrix of the contact quadrature. No quadrature error and no point location.

With nested spaces and no contact, Galerkin orthogonality gives
|u - u_h|^2 = |u_R - u_h|^2 + |u - u_R|^2: against a reference k levels finer the error of a
method converging like h^p is underestimated by the factor sqrt(1 - 4^{-pk}) (p = 1, k = 2:
3%), which tests/test_reference.py checks on transition-r32 against the exact errors.
"""
from __future__ import annotations

import contextlib
from collections import defaultdict
from dataclasses import dataclass

import ngsolve as ngs
import numpy as np
import scipy.sparse as sp

from ..fem.contact_quadrature import contact_quadrature
from .errors import CONTACT_ERROR_POINTS, DiscretePressure

# local edges of an NGSolve triangle (vertex pairs), in the order of its edge dofs
TRIANGLE_EDGES = ((0, 2), (1, 2), (0, 1))


@dataclass(frozen=True)
class LevelNumbering:
    """What the exact prolongation needs of one level: its vertices' parents (the two coarse
    vertices of the edge a new vertex halves; -1 for a vertex of the coarser mesh) and the P2
    edge dofs by vertex pair."""

    nv: int
    parents: np.ndarray       # (nv, 2)
    edge_keys: np.ndarray     # (ne,) sorted keys a * nv + b (a < b) of the edges
    edge_dofs: np.ndarray     # (ne,) their P2 dofs, in the order of edge_keys
    ndof2: int

    @classmethod
    def of(cls, mesh: ngs.Mesh, quadratic: bool = True) -> "LevelNumbering":
        """``quadratic``: with the P2 edge dofs (a level only P1 methods reach, such as P1's
        reference level, needs none: no P2 space is made on its mesh)."""
        nv = mesh.nv
        parents = np.array([mesh.GetParentVertices(v) for v in range(nv)], dtype=np.int64).reshape(nv, 2)
        if not quadratic:
            return cls(nv, parents, np.zeros(0, np.int64), np.zeros(0, np.int64), 0)
        fes = ngs.H1(mesh, order=2)
        dofs = np.array([el.dofs for el in fes.Elements(ngs.VOL)], dtype=np.int64)
        triangles = dofs[:, :3]                        # vertex dofs are the vertex numbers
        pairs = np.concatenate([triangles[:, list(e)] for e in TRIANGLE_EDGES])
        edge_dofs = dofs[:, 3:].T.ravel()
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
        shared = np.where((pa == qa) | (pa == qb), pa, pb)
        o1 = np.where(pa == shared, pb, pa)
        o2 = np.where(qa == shared, qb, qa)
        parallel_a = np.where(half, p, o1)
        parallel_b = np.where(half, other, o2)
        rows.append(fine.edge_dofs)
        cols.append(coarse.edge_dof(parallel_a, parallel_b))
        values.append(np.full(len(p), 0.25))
    shape = (fine.ndof(order), coarse.ndof(order))
    return sp.csr_matrix((np.concatenate(values), (np.concatenate(rows), np.concatenate(cols))), shape=shape)


def norm_matrices(mesh: ngs.Mesh, order: int) -> tuple[sp.csr_matrix, sp.csr_matrix]:
    """(K, M): stiffness and mass matrices of X_h of ``order`` on ``mesh``, every dof."""
    fes = ngs.H1(mesh, order=order)
    u, v = fes.TnT()
    forms = [ngs.BilinearForm(ngs.grad(u) * ngs.grad(v) * ngs.dx), ngs.BilinearForm(u * v * ngs.dx)]
    matrices = []
    for form in forms:
        form.Assemble()
        values, columns, pointers = form.mat.CSR()
        matrices.append(sp.csr_matrix((np.array(values), np.array(columns), np.array(pointers)),
                                      shape=(fes.ndof, fes.ndof)))
    return tuple(matrices)


class ReferenceErrors:
    """The error columns of a study of a case measured against reference solutions.

    The study calls ``begin_level`` with every mesh of the chain (studied levels, then k more),
    and ``solved`` after every solve; a method's rows get their errors when its reference
    level is solved. ``total_levels``: how many levels the study must run.
    """

    def __init__(self, levels_of: dict[str, int], orders: dict[str, int], reference_levels: int, phases=None):
        self.k = reference_levels
        self.phases = phases            # ``study.Phases``: this measurement's set-up counts as "errors"
        self.studied = dict(levels_of)
        self.reference_level = {name: n + reference_levels - 1 for name, n in levels_of.items()}
        # the norm matrices of an order are needed only where a method of that order has its reference
        self.reference_orders = {(self.reference_level[name], order) for name, order in orders.items()}
        # the levels up to which each order's solutions are carried (its finest reference)
        self.last_level = {order: max(self.reference_level[name] for name in orders if orders[name] == order)
                           for order in set(orders.values())}
        self.numbering: list[LevelNumbering] = []
        self.prolongations: dict[int, list[sp.csr_matrix]] = {1: [], 2: []}
        self.kept = defaultdict(list)             # method -> [(u_h, lambda_h coefficients as X_h vector)]
        self.rows = defaultdict(list)             # method -> its studied rows, to complete
        self.pressure: dict[int, DiscretePressure] = {}
        self.norms: dict[int, tuple] = {}

    @property
    def total_levels(self) -> int:
        return max(self.reference_level.values()) + 1

    def skip_level(self, level: int, mesh: ngs.Mesh) -> None:
        """A level no method solves (a resumed study's finished levels): its numbering and
        prolongations still carry the kept solutions up to the reference."""
        with self._phase():
            self._number(level, mesh)

    def _phase(self):
        return self.phases("errors") if self.phases is not None else contextlib.nullcontext()

    def _number(self, level: int, mesh: ngs.Mesh) -> None:
        needed = [order for order in self.prolongations if level <= self.last_level.get(order, -1)]
        numbering = LevelNumbering.of(mesh, quadratic=2 in needed)
        if self.numbering:
            for order in needed:
                self.prolongations[order].append(prolongation(self.numbering[-1], numbering, order))
        self.numbering.append(numbering)

    def begin_level(self, level: int, mesh: ngs.Mesh, problems: dict, quadrature=None, multilevel=None) -> None:
        """Number the new level, prolongations from the previous one, norms where a reference lies."""
        with self._phase():
            self._begin(level, mesh, problems)

    def _begin(self, level: int, mesh: ngs.Mesh, problems: dict) -> None:
        self._number(level, mesh)
        self.pressure = {order: DiscretePressure.of(problem) for order, problem in problems.items()}
        self.norms = {}
        for order, problem in problems.items():
            if (level, order) in self.reference_orders:
                quadrature = contact_quadrature(problem, CONTACT_ERROR_POINTS)
                weighted = quadrature.T.multiply(quadrature.weights[:, None])
                self.norms[order] = norm_matrices(mesh, order) + (
                    (quadrature.T.T @ weighted).tocsr(), (quadrature.T.T @ weighted.multiply(quadrature.h[:, None])).tocsr())

    def solved(self, method, level: int, problem, u: np.ndarray, row: dict | None) -> dict:
        """Columns known at once (``max_tension``); at the method's reference level, the error
        columns of all its rows (returned for the reference row itself: its KKT residual)."""
        own = self.pressure[method.order]
        coefficients = own.coefficients(u)
        if level < self.studied[method.name]:
            lam = np.zeros(problem.ndof)
            lam[problem.contact_dofs] = coefficients
            self.kept[method.name].append((u.copy(), lam))
            self.rows[method.name].append(row)
            return {"max_tension": own.max_tension(coefficients)}
        if level == self.reference_level[method.name]:
            self._complete(method, level, problem, u, coefficients)
        return {}

    def end_level(self) -> None:
        """Nothing waits for the end of a level: errors come with the reference solves."""

    def state_of(self, method_name: str) -> list:
        """What a method's chain must keep to be resumed (``study.ChainState``): its studied
        (u_h, lambda_h) that wait for the reference."""
        return list(self.kept.get(method_name, []))

    def restore(self, method_name: str, state: list, rows: list[dict]) -> None:
        """A resumed chain: the kept solutions and the rows they belong to (the studied rows,
        while the reference has not been solved)."""
        if state:
            self.kept[method_name] = list(state)
            self.rows[method_name] = [row for row in rows if row["level"] < self.studied[method_name]]

    def _lift(self, vector: np.ndarray, order: int, start: int, stop: int) -> np.ndarray:
        for P in self.prolongations[order][start:stop]:
            vector = P @ vector
        return vector

    def _complete(self, method, level: int, problem, u_ref: np.ndarray, coefficients: np.ndarray) -> None:
        K, M, boundary, boundary_h = self.norms[method.order]
        lam_ref = np.zeros(problem.ndof)
        lam_ref[problem.contact_dofs] = coefficients
        for studied, ((u_h, lam_h), row) in enumerate(zip(self.kept.pop(method.name), self.rows.pop(method.name))):
            e = u_ref - self._lift(u_h, method.order, studied, level)
            d = lam_ref - self._lift(lam_h, method.order, studied, level)
            semi, l2 = max(e @ (K @ e), 0.0), max(e @ (M @ e), 0.0)
            # h of the studied level is 2^(level - studied) times the reference's (red refinement)
            row.update({
                "err_h1": float(np.sqrt(semi + l2)), "err_h1_semi": float(np.sqrt(semi)), "err_l2": float(np.sqrt(l2)),
                "err_energy": float(np.sqrt(semi)),
                "err_trace_l2": float(np.sqrt(max(e @ (boundary @ e), 0.0))),
                "err_pressure_l2": float(np.sqrt(max(d @ (boundary @ d), 0.0))),
                "err_pressure_h12": float(np.sqrt(max(2.0 ** (level - studied) * (d @ (boundary_h @ d)), 0.0))),
            })
