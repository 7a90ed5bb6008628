"""Level sequences: the meshes a study walks, coarse to fine, each with its h.

``UniformRefinement`` is red refinement's sequence (h halves per level); a mesh strategy
(graded, adaptive) is another implementation of ``LevelSequence``: the study (``study.chain``)
only iterates over ``levels(count)`` and asks ``nested`` whether a level's mesh refines the
previous one (in place, NGSolve keeping the parents of new vertices, or as a new mesh with its
``Level.prolongation``: the multigrid's prolongations, ``solvers.multigrid.Multilevel.refined``).
"""
from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass
from typing import Protocol

import ngsolve as ngs
import numpy as np

from .points import cells, coordinates


@dataclass(frozen=True)
class Level:
    """One mesh of a sequence: its index (0 = coarsest), the mesh and h (the largest element
    diameter, ``mesh_size``). A nested sequence either refines one mesh object in place (a
    level's mesh is then valid until the next level is produced; NGSolve keeps the parents of
    its new vertices) or makes each level a new mesh that refines the previous one, with
    ``prolongation``: the P1 prolongation from the previous level's vertices, a sparse
    (nv, nv_previous) matrix (SciPy), whose first nv_previous rows are the identity (the
    previous vertices keep their numbers). ``degrees``: on an hp mesh (``mesh.hp``), the
    polynomial degree of each element (None: every element has the methods' order)."""

    index: int
    mesh: ngs.Mesh
    h: float
    prolongation: object = None
    degrees: np.ndarray | None = None


class LevelSequence(Protocol):
    """What a study needs of the meshes of one chain (``MeshStrategy.sequence`` makes one)."""

    name: str
    nested: bool        # each mesh refines the previous one (multigrid prolongations; ``Level``)
    adaptive: bool      # the next level needs ``observe(indicators)`` of this level's solve
    budgeted: bool      # the chain stops at the uniform chain's number of elements (graded, adaptive)

    def levels(self, count: int) -> Iterator[Level]:
        """The first ``count`` levels, coarse to fine."""

    def observe(self, indicators) -> None:
        """The error indicators of the level just solved, one per element (numpy array), before
        the next level is asked for; a sequence that is not ``adaptive`` ignores them."""


def coarse_mesh(case) -> ngs.Mesh:
    return ngs.Mesh(case.geometry.GenerateMesh(maxh=case.maxh))


def boundary_labels(mesh: ngs.Mesh) -> set[str]:
    return set(mesh.GetBoundaries())


def mesh_hierarchy(case, levels: int):
    """Yield (level, mesh) for level = 0..levels-1 by uniform red refinement.

    netgen's own Refine() splits every triangle into four similar ones, so h halves exactly
    and shape regularity is kept (in 3D every tetrahedron into eight, Bey's red refinement:
    every edge is halved, and the shapes stay in finitely many classes) (NGSolve's Mesh.Refine() bisects and does not halve h).
    The mesh is one object refined in place, so that NGSolve keeps the parents of new vertices
    (the multigrid's prolongations): a level's mesh is valid until the next level is yielded.
    """
    mesh = coarse_mesh(case)
    for level in range(levels):
        if level:
            mesh.ngmesh.Refine()
        yield level, mesh


def mesh_size(mesh: ngs.Mesh) -> float:
    """h of the paper: the largest element diameter (longest element edge)."""
    p = coordinates(mesh)[cells(mesh)]
    corners = p.shape[1]
    sides = np.stack([p[:, j] - p[:, i] for i in range(corners) for j in range(i + 1, corners)], axis=1)
    return float(np.sqrt((sides**2).sum(axis=2)).max())



class UniformRefinement:
    """The paper's meshes: a netgen mesh of the case's geometry (``maxh``), refined uniformly.
    Red refinement halves every edge, so h is measured once on level 0 and halved per level
    (exactly: the same numbers as measuring it)."""

    name = "uniform"
    nested = True
    adaptive = False
    budgeted = False

    def __init__(self, case):
        self.case = case

    def observe(self, indicators) -> None:
        pass

    def levels(self, count: int) -> Iterator[Level]:
        h = None
        for index, mesh in mesh_hierarchy(self.case, count):
            h = mesh_size(mesh) if h is None else h / 2
            yield Level(index, mesh, h)
