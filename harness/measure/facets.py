"""The facets of Gamma_g (the Neumann boundary), as the residual estimators need them in 2D
(``estimator.neumann_sides``) and 3D (``estimator_3d.neumann_faces``): an indicator on the
facets, the vertices of each of its boundary elements, and the elements along it."""
from __future__ import annotations

import ngsolve as ngs
import numpy as np


def neumann_facets(mesh: ngs.Mesh) -> tuple[ngs.GridFunction, np.ndarray]:
    """(neumann, vertices): a piecewise constant on the facets, 1 on those of Gamma_g; and the
    vertex numbers of each boundary element of Gamma_g (segments in 2D, triangles in 3D),
    sorted within each row."""
    neumann = ngs.GridFunction(ngs.FacetFESpace(mesh, order=0))
    neumann.Set(1.0, ngs.BND, definedon=mesh.Boundaries("neumann"))
    boundary = (mesh.ngmesh.Elements1D() if mesh.dim == 2 else mesh.ngmesh.Elements2D()).NumPy()
    names = mesh.GetBoundaries()
    labelled = np.array([names[index - 1] == "neumann" for index in boundary["index"]], dtype=bool)
    return neumann, np.sort(boundary["nodes"][labelled, :mesh.dim].astype(np.int64) - 1, axis=1)


def element_bits(mesh: ngs.Mesh, elements: np.ndarray) -> ngs.BitArray:
    """The elements ``elements`` of ``mesh`` as an NGSolve BitArray (``definedonelements``)."""
    bits = ngs.BitArray(mesh.ne)
    bits.Clear()
    for element in np.unique(elements):
        bits.Set(int(element))
    return bits
