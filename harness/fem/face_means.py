"""The 3D counterpart of K_h as general linear constraints (issue 33): on every triangle T of
Gamma_C, the mean of v_h - alpha is non-negative,

    (1/|T|) int_T v_h  >=  (1/|T|) int_T alpha,

beside v_h(x) >= alpha(x) at the vertices of Gamma_C. In 2D the edge mean of the paper's K_h
(Section 3) is a bound on one variable after a local change of variables (``cones``); on a
triangle the P2 mean is the average of the three edge-midpoint values (the vertex functions
of the Lagrange basis integrate to 0 over T; docs/mathematics.md), and each midpoint belongs
to two triangles, so these rows couple variables and stay general rows of a matrix B, solved by
``solvers.general_constraints``. (The edge-wise cone of the 3D ``mean`` so far constrains edge
means only, which do not control the trace inside the triangles: its H^1 rate stalls near 1/2.)
"""
from __future__ import annotations

import ngsolve as ngs
import numpy as np
import scipy.sparse as sp

CONTACT = "contact"


def face_mean_rows(problem, obstacle: ngs.CoefficientFunction | None = None,
                   order: int = 8) -> tuple[sp.csr_matrix, np.ndarray, np.ndarray]:
    """(B, g, elements): one row per triangle of Gamma_C (``elements``: its surface element
    number), B u = the mean over the triangle of the function with coefficients u (NGSolve's
    basis of ``problem.fes``) and g = the mean of ``obstacle`` (alpha; 0 if None) there,
    integrated with ``order`` more than the integrands' degree."""
    mesh = problem.mesh
    faces = ngs.SurfaceL2(mesh, order=0, definedon=mesh.Boundaries(CONTACT))
    u, q = problem.fes.TrialFunction(), faces.TestFunction()
    ds = ngs.ds(definedon=mesh.Boundaries(CONTACT), bonus_intorder=order)
    coupling = ngs.BilinearForm(problem.fes, faces)
    coupling += u * q * ds
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
    areas, integrals = area.vec.FV().NumPy()[dofs], load.vec.FV().NumPy()[dofs]
    return (sp.diags(1.0 / areas) @ B[dofs]).tocsr(), integrals / areas, elements
