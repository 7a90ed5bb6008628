"""Multigrid for two bodies: the P1 hierarchies of both bodies as one, coupled by the mortar
change of variables, and the map of the joint P1 space into the variables of a mortar QP.

A dual mortar QP (``fem.two_body.dual_bound_qp``) is min 1/2 z^T K z - b^T z over bounds on the
slave's trace variables, K = S^T A S, A = diag(A_1, A_2) the two bodies' matrices and u = S z
the change of variables that makes the mortar rows bounds (Wohlmuth's, local to the slave's
trace: a slave trace variable is the dual projection of the opening). The V-cycle of
``multigrid.TruncatedVCycle`` needs coarse spaces inside the z variables. Here they are the
two bodies' P1 functions written in z (``mortar_injection``, E): a slave hat sets the slave's
trace variables to its values, a master hat moves the master and leaves them unchanged -- in
u, the slave's trace follows the master (u = S E c), as in the mortar basis of Wohlmuth and
Krause's monotone multigrid for contact on non-matching grids (SIAM J. Sci. Comput. 25 (2003),
abstract read: the basis, not their algorithm, is what is used here). With pins on the slave's
trace variables (the active bounds) a master hat touches no pin: the coarse spaces keep the
motion of both bodies together, which a smoother alone cannot resolve. (The coarse functions
S^{-1} I of each body's P1 functions give block-diagonal Galerkin matrices, but truncate every
master hat under the contact zone, and CG needs more iterations with them.) Not optimal either: the slave's
trace follows a master hat on the finest trace nodes only, a layer one fine element thick, and
the iterations grow with the level (``bench --only mortar``).

The coarse matrices are the Galerkin products of K, so the cycle stays symmetric positive
definite: E^T K E = I^T A I + C, the two bodies' own P1 matrices (``Multilevel``) plus a
coupling C, nonzero only near Gamma_C, which every coarser level restricts algebraically by
the bodies' prolongation matrices (``JointMultilevel.coupled``).
"""
from __future__ import annotations

import copy

import ngsolve as ngs
import numpy as np
import scipy.sparse as sp

from ..fem.contact_laws.two_body import JointProblem
from ..fem.p1_embedding import ContactEdges
from ..fem.sparse import csr_block_diag, csr_view
from .multigrid import Multilevel, truncated_pins
from .two_body_operator import CoupledBlocks


class JointMultilevel:
    """Two bodies' ``Multilevel`` hierarchies, level l the pair of their levels l: the joint
    P1 dofs (body 1's, then body 2's), the prolongations and restrictions body by body. Both
    hierarchies must have the same number of levels (uniform pairs: each body refined once per
    level). Its matrices are those of a mortar QP's coarse spaces (``coupled``): it has none of
    its own."""

    def __init__(self, upper: Multilevel, lower: Multilevel):
        self.bodies = (upper, lower)
        self.free: list[np.ndarray] = []
        self.level_sizes: list[list[int]] = []      # each level's dofs per body, read at every V-cycle step
        self._extend()

    def refined(self, meshes) -> "JointMultilevel":
        """Both hierarchies with ``meshes`` (the pair, each refined in place) as their finest level."""
        for body, mesh in zip(self.bodies, meshes):
            body.refined(mesh)
        self._extend()
        return self

    def _extend(self) -> None:
        upper, lower = self.bodies
        if len(upper.matrices) != len(lower.matrices):
            raise ValueError("the two bodies' hierarchies have different numbers of levels")
        for level in range(len(self.free), len(upper.matrices)):
            self.free.append(np.concatenate([body.free[level] for body in self.bodies]))
            self.level_sizes.append([body.matrices[level].height for body in self.bodies])

    @property
    def ndof(self) -> int:
        return sum(self._sizes(len(self.free) - 1))

    def _sizes(self, level: int) -> list[int]:
        return self.level_sizes[level]

    def restrict(self, level: int, vector, rotate: bool = True) -> None:
        """In place, as ``Multilevel.restrict``: each body's part restricted by its hierarchy in
        its own range of ``vector`` (NGSolve views, no copies), then the master's coarse part
        moved next to the slave's."""
        (fine_slave, fine_master), (n_slave, n_master) = self._sizes(level), self._sizes(level - 1)
        upper, lower = self.bodies
        upper.restrict(level, vector.Range(0, fine_slave), rotate)
        lower.restrict(level, vector.Range(fine_slave, fine_slave + fine_master), rotate)
        values = vector.FV().NumPy()
        values[n_slave: n_slave + n_master] = values[fine_slave: fine_slave + n_master]

    def prolongate(self, level: int, vector) -> None:
        """In place, as ``Multilevel.prolongate``: the master's coarse part moved to its fine
        range, then each body's part prolongated by its hierarchy there."""
        (n_slave, n_master), (fine_slave, fine_master) = self._sizes(level - 1), self._sizes(level)
        values = vector.FV().NumPy()
        values[fine_slave: fine_slave + n_master] = values[n_slave: n_slave + n_master]
        upper, lower = self.bodies
        upper.prolongate(level, vector.Range(0, fine_slave))
        lower.prolongate(level, vector.Range(fine_slave, fine_slave + fine_master))

    def truncated_pins(self, pinned: np.ndarray) -> list[np.ndarray]:
        return truncated_pins(self, pinned)

    def prolongation_matrix(self, level: int) -> sp.csr_matrix:
        return csr_block_diag([body.prolongation_matrix(level) for body in self.bodies])

    def prolongation_rows(self, level: int, rows: np.ndarray) -> sp.csr_matrix:
        """The rows ``rows`` (sorted) of ``prolongation_matrix(level)``, from each body's."""
        (n_slave, n_master), (fine_slave, _) = self.level_sizes[level - 1], self.level_sizes[level]
        upper, lower = (body.prolongation_matrix(level) for body in self.bodies)
        blocks = [upper[rows[rows < fine_slave]], lower[rows[rows >= fine_slave] - fine_slave]]
        return sp.bmat([[blocks[0], sp.csr_matrix((blocks[0].shape[0], n_master))],
                        [sp.csr_matrix((blocks[1].shape[0], n_slave)), blocks[1]]], format="csr")

    def prolongated(self, coarse: np.ndarray) -> np.ndarray:
        """A vector of the level below the finest, prolongated to the finest, body by body."""
        top = len(self.free) - 1
        vector = ngs.BaseVector(self.ndof)
        vector.FV().NumPy()[: len(coarse)] = coarse
        self.prolongate(top, vector)
        return vector.FV().NumPy().copy()

    def coupled(self, coupling: sp.csr_matrix) -> "JointMultilevel":
        """The same hierarchy with the matrices diag(A_1, A_2)_l + C_l, C_L = ``coupling`` on
        the finest level and C_{l-1} = P_l^T C_l P_l: the Galerkin products of the finest, each
        the bodies' own level matrices and C_l (``two_body_operator.CoupledBlocks``)."""
        view = copy.copy(self)
        view.matrices = [None] * len(self.free)
        C = coupling.tocsr()
        for level in range(len(self.free) - 1, -1, -1):
            view.matrices[level] = CoupledBlocks([body.matrices[level] for body in self.bodies], C)
            if level:
                C = galerkin_near(C, lambda rows, level=level: self.prolongation_rows(level, rows))
        return view


def galerkin_near(C: sp.csr_matrix, prolongation_rows) -> sp.csr_matrix:
    """P^T C P for a symmetric C nonzero only in the rows (and columns) T, from P's rows there
    (``prolongation_rows(T)``): never all of P."""
    near = np.union1d(np.flatnonzero(np.diff(C.indptr)), np.unique(C.indices))
    R = prolongation_rows(near)
    return (R.T @ C[near][:, near] @ R).tocsr()


class OpeningLevels:
    """Two bodies' P1 levels in opening variables at every level (scalar problems, uniform pairs):
    on level l a slave trace vertex's variable is the opening there, w = u_1 + I_l u_2 (I_l: the
    master's level-l trace function at that vertex), every other variable a displacement -- on
    the finest level that is the dual mortar QP's own change of variables (its trace variable
    the dual projection of the opening). The prolongation keeps that meaning on each level:

        master:                   P_2 c_2
        slave trace vertices:     P_1 c_1 (on the trace: the 1D interpolation of the openings)
        other slave vertices:     P_1 (c_1 - Q I_{l-1} c_2)   (the coarse slave displacement)

    (Q: the coarse trace vertices' values into the slave's coarse vector). So a master coarse hat
    with zero opening drags the slave with it in a layer as thick as its own level, and touches
    no trace variable (no pin) on any finer level; in ``JointMultilevel.coupled`` it moves the
    slave on the finest trace nodes only, a spike one fine element thick whose energy grows
    with the level, and the CG iterations with it. The idea is Wohlmuth and Krause's mortar
    basis on every level (SIAM J. Sci. Comput. 25 (2003), abstract read), made nested by this
    prolongation. Coarse matrices: the Galerkin products of the finest (the mortar QP's P1 level,
    diag(A_1, A_2) + ``coupling``, ``mortar_coupling_matrix``), each held as the bodies' own
    level matrices and a coupling near Gamma_C (``_levels``).

    Vertex v of a body lies on its level l when v < nv_l: NGSolve refines in place and numbers
    new vertices last."""

    def __init__(self, joint: JointMultilevel, problem, coupling: sp.csr_matrix):
        if problem.upper.physics.rotated_frame:
            raise ValueError("opening variables on every level are built for a contact condition on u itself (scalar)")
        self.joint = joint
        self.free = joint.free
        self.body_sizes = joint.level_sizes        # (slave, master) dofs per level
        self.sizes = [sum(pair) for pair in joint.level_sizes]
        self.drags = [None] + [self._drag(joint, problem, level) for level in range(1, len(self.sizes))]
        # the V-cycle applies Delta and Delta^T on their nonzero rows only, a layer near Gamma_C
        # (full-length products cost two passes over each body's vector per level and cycle)
        self._near = [None] + [_nonzero_rows(drag) for drag in self.drags[1:]]
        self._near_T = [None] + [_nonzero_rows(drag.T.tocsr()) for drag in self.drags[1:]]
        # the pins' indicators are restricted by |P|^T: the drag's entries are negative
        self._abs_near_T = [None] + [(rows, abs(block)) for rows, block in self._near_T[1:]]
        self.matrices = self._levels(joint, coupling.tocsr())

    @staticmethod
    def _drag(joint: JointMultilevel, problem, level: int) -> sp.csr_matrix:
        """Delta of level ``level``: -P_1 Q I_{l-1} off the slave's trace (the class docstring),
        (the level's slave dofs) x (the coarser level's master dofs)."""
        slave_x = problem.upper.mesh.ngmesh.Coordinates()[:, 0]
        master_x = problem.lower.mesh.ngmesh.Coordinates()[:, 0]
        slave_trace, master_trace = problem.upper.trace.vertices, problem.lower.trace.vertices
        (n_slave, n_master), (fine_slave, _) = joint.level_sizes[level - 1], joint.level_sizes[level]
        on_slave = slave_trace[slave_trace < n_slave]
        on_master = master_trace[master_trace < n_master]
        master_at_slave = trace_interpolation(slave_x[on_slave], master_x[on_master], on_master, n_master)
        # P_1 Q: the columns of the coarse trace vertices (no product with all of P_1: its rows
        # are the level's, 4e6 at 8e6 dofs)
        drag = -(joint.bodies[0].prolongation_matrix(level)[:, on_slave] @ master_at_slave).tocsr()
        off_trace = np.ones(fine_slave)
        off_trace[slave_trace[slave_trace < fine_slave]] = 0.0
        drag.data *= np.repeat(off_trace, np.diff(drag.indptr))
        drag.eliminate_zeros()
        return drag

    def _levels(self, joint: JointMultilevel, C: sp.csr_matrix) -> list:
        """Each level's matrix diag(A_1, A_2)_l + C_l (``two_body_operator.CoupledBlocks``: the
        bodies' own level matrices), C_L = ``C`` (the mortar QP's P1 level minus the bodies',
        ``mortar_coupling_matrix``) and C_{l-1} such that A_{l-1} + C_{l-1} is the Galerkin
        product P^T (A_l + C_l) P. With P = diag(P_1, P_2) + Delta (Delta: the drag, slave rows
        and master columns) and P_k^T A_k P_k = A_{k, l-1} (nested P1 spaces),

            C_{l-1} = P^T C_l P + X + X^T + Delta^T A_l Delta,   X = Delta^T A_l diag(P_1, P_2),

        every term near Gamma_C: no product with all of A_l or P."""
        slave = joint.bodies[0]
        matrices = [None] * len(self.sizes)
        for level in range(len(self.sizes) - 1, -1, -1):
            matrices[level] = CoupledBlocks([body.matrices[level] for body in joint.bodies], C)
            if level:
                drag = self.drags[level]
                A_drag = (csr_view(slave.matrices[level]) @ drag).tocsr()                # fine slave x coarse master
                X = (A_drag.T @ slave.prolongation_matrix(level)).tocsr()                # coarse master x coarse slave
                n_slave = self.body_sizes[level - 1][0]
                C = (galerkin_near(C, lambda rows, level=level: self.prolongation_rows(level, rows))
                     + sp.bmat([[sp.csr_matrix((n_slave, n_slave)), X.T], [X, drag.T @ A_drag]])).tocsr()
        return matrices

    @property
    def ndof(self) -> int:
        return self.sizes[-1]

    def restrict(self, level: int, vector, rotate: bool = True) -> None:
        """In place, as ``Multilevel.restrict`` (``rotate=False``: the indicators of
        ``truncated_pins``, by |P|^T): each body's by its hierarchy, and Delta^T on the slave's part."""
        values = vector.FV().NumPy()
        rows, block = (self._near_T if rotate else self._abs_near_T)[level]
        dragged = block @ values[: self.body_sizes[level][0]]
        self.joint.restrict(level, vector, rotate)
        values[self.body_sizes[level - 1][0] + rows] += dragged

    def prolongate(self, level: int, vector) -> None:
        """In place: each body's by its hierarchy, plus Delta of the coarse master part on the slave's."""
        values = vector.FV().NumPy()
        n_slave, n_master = self.body_sizes[level - 1]
        rows, block = self._near[level]
        dragged = block @ values[n_slave: n_slave + n_master]
        self.joint.prolongate(level, vector)
        values[rows] += dragged

    def prolongation_rows(self, level: int, rows: np.ndarray) -> sp.csr_matrix:
        """The rows ``rows`` (sorted) of ``prolongation_matrix(level)``."""
        n_slave = self.body_sizes[level - 1][0]
        slave_rows = rows[rows < self.body_sizes[level][0]]
        drag = sp.hstack([sp.csr_matrix((len(slave_rows), n_slave)), self.drags[level][slave_rows]])
        drag.resize(len(rows), self.sizes[level - 1])
        return (self.joint.prolongation_rows(level, rows) + drag).tocsr()

    def prolongation_matrix(self, level: int) -> sp.csr_matrix:
        """diag(P_1, P_2) + Delta (for the tests: the V-cycle applies it body by body)."""
        return self.prolongation_rows(level, np.arange(self.sizes[level]))

    def truncated_pins(self, pinned: np.ndarray) -> list[np.ndarray]:
        return truncated_pins(self, pinned)


def _with_columns(matrix: sp.csr_matrix, n: int) -> sp.csr_matrix:
    """``matrix`` with n columns, its own the first (the same arrays)."""
    return sp.csr_matrix((matrix.data, matrix.indices, matrix.indptr), shape=(matrix.shape[0], n))


def _nonzero_rows(matrix: sp.csr_matrix) -> tuple[np.ndarray, sp.csr_matrix]:
    """(the rows of ``matrix`` with an entry, those rows as a CSR matrix)."""
    rows = np.flatnonzero(np.diff(matrix.indptr))
    return rows, matrix[rows]


def trace_interpolation(x: np.ndarray, nodes_x: np.ndarray, nodes: np.ndarray, n: int) -> sp.csr_matrix:
    """(len(x), n): the values at ``x`` of a P1 function on the line through the vertices
    ``nodes`` (at ``nodes_x``; ends: constant beyond them), columns its n vertex values."""
    order = np.argsort(nodes_x)
    sorted_x = nodes_x[order]
    k = np.clip(np.searchsorted(sorted_x, x, side="right") - 1, 0, len(sorted_x) - 2)
    t = np.clip((x - sorted_x[k]) / (sorted_x[k + 1] - sorted_x[k]), 0.0, 1.0)
    columns = nodes[order][np.stack([k, k + 1], axis=1)].ravel()
    rows = np.repeat(np.arange(len(x)), 2)
    return sp.csr_matrix((np.stack([1.0 - t, t], axis=1).ravel(), (rows, columns)), shape=(len(x), n))


class SparseEdges:
    """The finest P1 level inside the variables z of a QP, z = E c for a sparse E: the interface
    of ``multigrid.ContactEdges`` (which is E for one body's contact models) for any E."""

    def __init__(self, E: sp.csr_matrix):
        self.E = E.tocsr()
        # z = c (a P1 mortar QP: S changes the trace variables, the hierarchy's top level is K's)
        n = self.E.shape[0]
        self.identity = self.E.shape[1] == n and self.E.nnz == n and bool(
            np.array_equal(self.E.indices, np.arange(n)) and (self.E.data == 1.0).all())
        # (the identity's: never applied, the V-cycle starts at the P1 level)
        self.ET = None if self.identity else self.E.T.tocsr()
        self._pattern = None if self.identity else abs(self.ET).astype(bool).astype(float)

    def prolongate(self, c: np.ndarray, z: np.ndarray) -> None:
        """z += E c."""
        z += self.E @ c

    def restrict(self, r: np.ndarray, n: int) -> np.ndarray:
        """E^T r."""
        return self.ET @ r

    def touched(self, mask: np.ndarray, n: int) -> np.ndarray:
        """The P1 dofs whose image E e_j reaches a variable of ``mask``."""
        if self.identity:
            return np.asarray(mask, dtype=bool).copy()
        return self._pattern @ mask.astype(float) > 0


def p1_injected(problem, c: np.ndarray) -> np.ndarray:
    """I c, I: the joint P1 dofs of a ``fem.two_body.TwoBodyProblem`` -> its joint dofs (a P1
    function's vertex values, bubbles zero; components blocked as each body's space numbers
    them), body by body without the matrix."""
    z = np.zeros(problem.ndof)
    offset = 0
    for body, part in zip(problem.bodies, problem.split(z)):
        n = body.mesh.nv * body.physics.components
        ContactEdges.of(body, model=False).prolongate(c[offset: offset + n], part)
        offset += n
    return z


def law_embedding(problem):
    """The P1 embedding of a contact law's Newton system on ``problem`` (its V-cycle's
    ``edges``): one body's P1 functions in its dofs; on both bodies' joint dofs
    (``fem.contact_laws.two_body.JointProblem``) each body's in its own."""
    if not isinstance(problem, JointProblem):
        return ContactEdges.of(problem, model=False)
    return SparseEdges(csr_block_diag([_injection(body, ContactEdges.of(body, model=False)) for body in problem.bodies]))


def law_hierarchy(problem, multilevel, edges, delta: sp.csr_matrix):
    """The P1 hierarchy of a contact law's V-cycle at the Jacobian J = A + ``delta``: one body's
    own (A's levels: the law's stiff terms are truncated there, ``multigrid.TruncatedVCycle``);
    two bodies' joint one with the Galerkin products of J, each body's own level matrices plus
    C = E^T delta E restricted level by level (``JointMultilevel.coupled``), so that the coarse
    spaces carry the law's coupling of the bodies across Gamma_C. Measured on
    cattaneo-two-body-q03, levels 0-2, the GMRES iterations of all Newton steps: 1442, 204, 345
    with the bodies' own levels uncoupled and the stiff vertices truncated, 470, 48, 57 so."""
    if not isinstance(problem, JointProblem):
        return multilevel
    # P1: the joint dofs are the P1 hierarchy's own (E = I)
    return multilevel.coupled(delta.tocsr() if edges.identity else (edges.ET @ delta @ edges.E).tocsr())


def mortar_injection(problem, tangential: bool = False) -> sp.csr_matrix:
    """E: the joint P1 dofs -> the variables z of the dual mortar QP: each body's P1 function in
    its variables, the slave's trace variables its values there (a trace edge's: the mean of its
    ends', ``multigrid.ContactEdges`` of the slave's contact model), the master's unchanged.
    ``tangential`` (``fem.two_body.dual_bound_qp(..., tangential=True)``): the tangential jump's
    edge variables too, as the one-body Coulomb cones' (``fem.coulomb_cones.coulomb_cone_qp``)."""
    upper, lower = problem.bodies
    slave = ContactEdges.of(upper)
    if tangential and len(upper.edge_dofs):
        block = upper.ndof // upper.physics.components
        ends = upper.end_dofs[:len(upper.edge_dofs)]
        slave = ContactEdges.of_edges(upper, np.concatenate([upper.edge_dofs, upper.edge_dofs - block]),
                                      np.concatenate([ends, ends - block]))
    return csr_block_diag([_injection(upper, slave), _injection(lower, ContactEdges.of(lower, model=False))])


def _injection(body, edges: ContactEdges) -> sp.csr_matrix:
    """``edges`` (z = E c for one body) as a sparse matrix."""
    n1 = body.mesh.nv * body.physics.components
    # one entry per row of a P1 dof, made as CSR arrays (increasing rows: no sort)
    column = np.full(body.ndof, -1, dtype=np.int64)
    column[np.arange(n1) if edges.p1_dofs is None else edges.p1_dofs] = np.arange(n1)
    indptr = np.concatenate([[0], np.cumsum(column >= 0)])
    E = sp.csr_matrix((np.ones(n1), column[column >= 0], indptr), shape=(body.ndof, n1))
    if len(edges.edge_dofs):
        ends = edges.end_dofs
        half = sp.csr_matrix((np.full(2 * len(ends), 0.5), (np.repeat(edges.edge_dofs, 2), ends.ravel())), shape=E.shape)
        E = E + half
    return E.tocsr()


def mortar_coupling_matrix(problem, S_trace: sp.csr_matrix, trace: np.ndarray, E: sp.csr_matrix) -> sp.csr_matrix:
    """C = E^T K E - I^T A I for K = S^T A S (``trace``: the rows where S is not the identity,
    the slave's trace dofs; ``S_trace``: S's rows there, ``fem.two_body.BoundQP.S_rows``): with
    S E = I + D, D nonzero in those rows only, C = D^T A I + I^T A D + D^T A D, from the slave's
    rows there (never a product with all of A)."""
    upper = problem.upper
    # T is in body 1: of I only body 1's block is read (its columns are the joint P1's first)
    injection = _injection(upper, ContactEdges.of(upper, model=False))
    joint_columns = E.shape[1]
    I_T = _with_columns(injection[trace], joint_columns)
    D = (S_trace @ E - I_T).tocsr()                                # |T| x joint P1
    A_T = upper.A[trace]                                            # the slave's rows there
    AI = _with_columns((A_T @ injection).tocsr(), joint_columns)    # (A I)[T]
    X = (D.T @ AI).tocsr()
    return (X + X.T + D.T @ A_T[:, trace] @ D).tocsr()
