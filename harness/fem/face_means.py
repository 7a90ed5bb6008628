"""The 3D counterpart of K_h as general linear constraints: on every triangle T of
Gamma_C, the mean of v_h - alpha is non-negative,

    (1/|T|) int_T v_h  >=  (1/|T|) int_T alpha,

beside v_h(x) >= alpha(x) at the vertices of Gamma_C. In 2D the edge mean of the paper's K_h
(Section 3) is a bound on one variable after a local change of variables (``cones``); on a
triangle the P2 mean is the average of the three edge-midpoint values (the vertex functions
of the Lagrange basis integrate to 0 over T; docs/mathematics.md §6), and each midpoint belongs
to two triangles, so these rows couple variables and stay general rows of a matrix B, solved by
``solvers.general_constraints`` (and ``solvers.projected_multigrid``): the 3D ``mean``. (The
edge-wise cone, ``mean-edges``, constrains edge means only, which do not control the trace
inside the triangles: its H^1 rate stalls near 1/2.)
"""
from __future__ import annotations

from dataclasses import dataclass

import ngsolve as ngs
import numpy as np
import scipy.sparse as sp

from .assembly import ContactTraceFunction, DiscreteProblem
from .cones import GeneralRowsQP, contact_pressure, end_status, vertex_rows
from .nested import face_mean_prediction

CONTACT = "contact"


def face_mean_rows(problem, obstacle: ngs.CoefficientFunction | None = None,
                   order: int = 8) -> tuple[sp.csr_matrix, np.ndarray, np.ndarray]:
    """(B, g, elements): one row per triangle of Gamma_C (``elements``: its surface element
    number), B u = the mean over the triangle of the contact variable (u, or -u . n in
    elasticity: ``problem.physics.Elasticity.contact_variable``) of the function with coefficients u (the
    problem's variables: NGSolve's basis, rotated at Gamma_C in elasticity) and g = the mean of
    ``obstacle`` (alpha; 0 if None) there, integrated with ``order`` more than the integrands'
    degree."""
    mesh = problem.mesh
    faces = ngs.SurfaceL2(mesh, order=0, definedon=mesh.Boundaries(CONTACT))
    u, q = problem.fes.TrialFunction(), faces.TestFunction()
    ds = ngs.ds(definedon=mesh.Boundaries(CONTACT), bonus_intorder=order)
    coupling = ngs.BilinearForm(problem.fes, faces)
    coupling += problem.physics.contact_variable(u) * q * ds
    coupling.Assemble()
    area, load = ngs.LinearForm(faces), ngs.LinearForm(faces)
    area += q * ds
    load += (obstacle if obstacle is not None else ngs.CF(0.0)) * q * ds
    area.Assemble()
    load.Assemble()
    elements = np.array([el.nr for el in mesh.Elements(ngs.BND) if el.mat == CONTACT], dtype=np.int64)
    dofs = np.array([faces.GetDofNrs(ngs.ElementId(ngs.BND, int(e)))[0] for e in elements], dtype=np.int64)
    rows, columns, values = coupling.mat.COO()
    B = sp.csr_matrix((np.asarray(values), (np.asarray(rows), np.asarray(columns))), shape=(faces.ndof, problem.fes.ndof))
    if problem.basis is not None:
        B = B @ problem.basis                   # NGSolve's coefficients = Q @ ours
    areas, integrals = area.vec.FV().NumPy()[dofs], load.vec.FV().NumPy()[dofs]
    # entries below round-off of the rows' scale: a Cartesian component orthogonal to n
    B = (sp.diags(1.0 / areas) @ B[dofs]).tocsr()
    B.data[np.abs(B.data) < 1e-14 * np.abs(B.data).max(initial=0.0)] = 0.0
    B.eliminate_zeros()
    return B, integrals / areas, elements


def _in_trace_order(problem, elements: np.ndarray) -> np.ndarray:
    """The position of each triangle of ``problem.trace.faces`` among the surface ``elements``."""
    mesh = problem.mesh
    keys = {tuple(sorted(v.nr for v in mesh[ngs.ElementId(ngs.BND, int(e))].vertices)): k for k, e in enumerate(elements)}
    return np.array([keys[tuple(sorted(corners))] for corners in problem.trace.faces.vertices.tolist()], dtype=np.int64)


@dataclass
class FaceMeanQP(GeneralRowsQP):
    """The 3D counterpart of K_h (``cones.GeneralRowsQP``) in NGSolve's hierarchical P2
    variables: after the vertex rows, its triangles' means (in the order of
    ``problem.trace.faces``), g the obstacle's values and means there (``face_mean_rows``)."""

    def predicted_active(self, previous: ContactTraceFunction | None) -> np.ndarray | None:
        """Nested iteration: the active set predicted by the previous level's trace
        (``fem.nested.face_mean_prediction``)."""
        return face_mean_prediction(previous, self.problem)

    def trace_function(self, u: np.ndarray, active: np.ndarray) -> ContactTraceFunction:
        problem, nv = self.problem, self.n_vertices
        end_active = end_status(problem, active[:nv])
        # no edge constraint: an edge counts as in contact when both its ends are (what the
        # fine vertex at its midpoint inherits)
        return ContactTraceFunction.of(problem, u, end_active, end_active.all(axis=1), face_active=active[nv:])

    def pressure(self, multipliers: np.ndarray) -> np.ndarray:
        """The discrete pressure per triangle: a face row's force lambda_f B_f is the uniform
        pressure lambda_f / |T| on its triangle; the vertex rows' as for the cones."""
        problem, nv = self.problem, self.n_vertices
        vertex_part = contact_pressure(problem, np.concatenate([multipliers[:nv], np.zeros(len(problem.edge_dofs))]))
        return vertex_part + multipliers[nv:] / problem.trace.cell_sizes


def face_mean_qp(case, problem: DiscreteProblem, take_stiffness: bool = False) -> FaceMeanQP:
    """The face-mean QP of ``case`` on ``problem`` (P2 on tetrahedra); ``take_stiffness`` as
    for the cones (``cones.contact_qp``): A itself is K, no change of variables."""
    if problem.trace.faces is None or problem.order != 2:
        raise ValueError("the face-mean cone is the 3D counterpart of K_h: P2 on a tetrahedral mesh")
    B_faces, g_faces, elements = face_mean_rows(problem, case.obstacle)
    order = _in_trace_order(problem, elements)
    bounds, g_vertices = vertex_rows(case, problem)
    K, K_ngs = problem.take_stiffness() if take_stiffness else (problem.A, problem.A_ngs)
    return FaceMeanQP(problem, K, K_ngs, problem.b, sp.vstack([bounds, B_faces[order]]).tocsr(),
                      np.concatenate([g_vertices, g_faces[order]]))
