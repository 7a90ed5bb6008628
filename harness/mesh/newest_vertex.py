"""Newest vertex bisection of triangles on arrays: local refinement at the cost of the marked
elements, each level a new NGSolve mesh built from the arrays.

``ngsolve.Mesh.Refine`` with refinement flags refines one mesh in place at a cost that grows
with the whole mesh, however few elements are marked, and a graded level is a dozen such sweeps.
Here a sweep touches arrays: the marked elements, their closure and the vertices they create; an
NGSolve mesh is built once per level (netgen's ``AddPoints``/``AddElements``), and the level's
P1 prolongation is the sparse matrix of the new vertices' parents (``solvers.multigrid.Multilevel``
takes it where NGSolve's refinement would have kept them). ``python -m harness bench --only
adaptive`` times both on the same marked sets.

The rule is that of p1afem's ``refineNVB`` (S. Funken, D. Praetorius and P. Wissgott, "Efficient
implementation of adaptive P1-FEM in Matlab", Comput. Methods Appl. Math. 11 (2011) 460-490,
whose abstract was read, not its code: the rule below is checked against NGSolve's bisection,
``tests/test_newest_vertex.py``): every edge of a marked element is marked;
the closure marks the refinement edge of every element with a marked edge; an element is then
bisected on its refinement edge, and its two children on theirs (its other two edges) where
those are marked -- 2, 3 or 4 children, a conforming mesh. Each triangle is stored (a, b, c)
with (a, b) its refinement edge and c its newest vertex; the coarse mesh is labelled by longest
edges. Newest vertex bisection keeps every triangle in finitely many similarity classes of
the coarse ones (Mitchell; Sewell), so the meshes stay shape regular however deep.

Polygons only: a new vertex is the midpoint of its edge, on a straight side where the edge is
a boundary edge (``straight_polygon``; a curved geometry is refined by NGSolve, which projects
onto the curve).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

# the local edges of a stored triangle (a, b, c): the refinement edge first
_EDGES = ((0, 1), (1, 2), (2, 0))


def straight_polygon(geometry) -> bool:
    """Whether a 2D netgen geometry has straight sides only (every spline a line: netgen plots a
    line by its two ends)."""
    try:
        xs = geometry.PlotData()[2]
    except (AttributeError, TypeError, IndexError):
        return False
    return all(len(x) == 2 for x in xs)


@dataclass
class TriangleMesh:
    """A conforming triangulation as arrays, in NGSolve's element and vertex numbering: the
    elements grouped by domain (``ngsolve_mesh`` adds them in this order)."""

    points: np.ndarray          # (n, 2)
    triangles: np.ndarray       # (m, 3) int64: (a, b) the refinement edge, c the newest vertex
    domains: np.ndarray         # (m,) netgen's face descriptor (domain) index, from 1
    segments: np.ndarray        # (s, 2) int64 boundary and interface segments, oriented as netgen's
    segment_index: np.ndarray   # (s,) netgen's segment index (the geometry's line, which has the bc name)
    materials: tuple            # the name of domain k + 1
    boundaries: tuple           # the name of segment index k + 1

    @classmethod
    def of(cls, mesh) -> "TriangleMesh":
        """The arrays of a 2D NGSolve mesh, each triangle turned (cyclically: the orientation is
        kept) so that its longest edge is its refinement edge."""
        ngmesh = mesh.ngmesh
        points = np.array(ngmesh.Coordinates()[:, :2], dtype=float)
        table = ngmesh.Elements2D().NumPy()
        triangles = np.array(table["nodes"][:, :3], dtype=np.int64) - 1
        lengths = np.stack([np.linalg.norm(points[triangles[:, j]] - points[triangles[:, i]], axis=1) for i, j in _EDGES], axis=1)
        turn = lengths.argmax(axis=1)
        triangles = np.take_along_axis(triangles, (turn[:, None] + np.arange(3)) % 3, axis=1)
        segments = ngmesh.Elements1D().NumPy()
        return cls(points, triangles, np.array(table["index"], dtype=np.int32),
                   np.array(segments["nodes"][:, :2], dtype=np.int64) - 1, np.array(segments["index"], dtype=np.int32),
                   tuple(mesh.GetMaterials()), tuple(mesh.GetBoundaries()))

    @property
    def ne(self) -> int:
        return len(self.triangles)

    def element_sizes(self) -> tuple[np.ndarray, np.ndarray]:
        """(h_T, centroid) of every element: its longest edge and its centre of mass."""
        x, y = self.points[:, 0][self.triangles], self.points[:, 1][self.triangles]
        longest = np.zeros(self.ne)
        for i, j in _EDGES:
            np.maximum(longest, (x[:, j] - x[:, i]) ** 2 + (y[:, j] - y[:, i]) ** 2, out=longest)
        return np.sqrt(longest), np.stack([x.mean(axis=1), y.mean(axis=1)], axis=1)

    def refine(self, marked: np.ndarray):
        """(the refined mesh, its P1 prolongation: a sparse (n', n) matrix) after bisecting
        every edge of the ``marked`` elements and the closure's."""
        if len(marked) != self.ne:
            raise ValueError(f"{len(marked)} refinement flags for a mesh of {self.ne} elements")
        n = len(self.points)
        edges = _Edges.of(self.triangles, n)
        split = edges.closure(np.asarray(marked, dtype=bool))
        middle = np.full(len(split), -1, dtype=np.int64)
        middle[split] = n + np.arange(np.count_nonzero(split))
        ends = np.stack([edges.keys[split] // n, edges.keys[split] % n], axis=1)
        points = np.concatenate([self.points, 0.5 * (self.points[ends[:, 0]] + self.points[ends[:, 1]])])
        # the refinement edges (local edge 0), then the children's: (c, a, m)'s is the
        # parent's edge (c, a) (local 2), (b, c, m)'s its edge (b, c) (local 1)
        cut = middle[edges.of_triangle[:, 0]] >= 0
        (first, second), _ = _children(self.triangles[cut], middle[edges.of_triangle[cut, 0]])
        below = np.concatenate([middle[edges.of_triangle[cut, 2]], middle[edges.of_triangle[cut, 1]]])
        grand, kept = _children(np.concatenate([first, second]), below)
        parents_domain = np.tile(self.domains[cut], 2)
        triangles = np.concatenate([self.triangles[~cut], np.concatenate([first, second])[kept], grand[0], grand[1]])
        domains = np.concatenate([self.domains[~cut], parents_domain[kept], parents_domain[~kept], parents_domain[~kept]])
        # by domain (``ngsolve_mesh`` adds a domain at a time), then by lowest vertex: a numbering
        # with locality, in which NGSolve builds its topology a third faster than in this one
        order = np.lexsort((triangles.min(axis=1), domains))
        segments = _split_segments(self.segments, self.segment_index, edges.keys[split], middle[split], n)
        refined = TriangleMesh(points, triangles[order], domains[order], *segments, self.materials, self.boundaries)
        return refined, _prolongation(n, ends)

    def ngsolve_mesh(self):
        """The NGSolve mesh of these arrays, elements and vertices numbered as here."""
        import netgen.meshing as nm
        import ngsolve as ngs

        ngmesh = nm.Mesh(dim=2)
        ngmesh.AddPoints(np.ascontiguousarray(self.points))
        for k, name in enumerate(self.materials):
            ngmesh.Add(nm.FaceDescriptor(surfnr=k + 1, domin=k + 1, bc=k + 1))
            ngmesh.SetMaterial(k + 1, name)
        for k, name in enumerate(self.boundaries):
            ngmesh.SetBCName(k, name)
        for index in np.unique(self.domains):
            ngmesh.AddElements(dim=2, index=int(index), data=self.triangles[self.domains == index].astype(np.int32), base=0)
        for index in np.unique(self.segment_index):
            ngmesh.AddElements(dim=1, index=int(index), data=self.segments[self.segment_index == index].astype(np.int32), base=0)
        return ngs.Mesh(ngmesh)


@dataclass(frozen=True)
class _Edges:
    """The edges of a triangulation: ``keys`` (sorted, min n + max of the ends), the number
    of each triangle's local edge (``of_triangle``, (m, 3)), and the triangles around each
    edge (``owners[starts[e]:starts[e + 1]]``)."""

    keys: np.ndarray
    of_triangle: np.ndarray
    owners: np.ndarray
    starts: np.ndarray

    @classmethod
    def of(cls, triangles: np.ndarray, n: int) -> "_Edges":
        pairs = np.stack([triangles[:, list(e)] for e in _EDGES], axis=1)
        keys = (pairs.min(axis=2) * n + pairs.max(axis=2)).ravel()
        order = np.argsort(keys, kind="stable")
        ordered = keys[order]
        new = np.concatenate([[True], ordered[1:] != ordered[:-1]])
        of_triangle = np.empty(len(keys), dtype=np.int64)
        of_triangle[order] = np.cumsum(new) - 1
        return cls(ordered[new], of_triangle.reshape(-1, 3), order // 3, np.append(np.flatnonzero(new), len(keys)))

    def closure(self, marked: np.ndarray) -> np.ndarray:
        """The edges to bisect: every edge of a marked element, then, until none is left, the
        refinement edge of every element with a bisected edge (else its middle would hang).
        Each pass visits only the elements around the edges the last one added."""
        split = np.zeros(len(self.keys), dtype=bool)
        split[self.of_triangle[marked].ravel()] = True
        fresh = np.flatnonzero(split)
        while len(fresh):
            reference = self.of_triangle[self.owners[_ranges(self.starts[fresh], self.starts[fresh + 1])], 0]
            fresh = np.unique(reference[~split[reference]])
            split[fresh] = True
        return split


def _ranges(first: np.ndarray, stop: np.ndarray) -> np.ndarray:
    """The concatenation of range(first[k], stop[k]) over k, without a Python loop."""
    counts = stop - first
    if counts.sum() == 0:
        return np.zeros(0, dtype=np.int64)
    return np.arange(counts.sum()) + np.repeat(first - np.concatenate([[0], np.cumsum(counts)[:-1]]), counts)


def _children(triangles: np.ndarray, middle: np.ndarray) -> tuple[tuple[np.ndarray, np.ndarray], np.ndarray]:
    """Each triangle (a, b, c) whose refinement edge (a, b) is bisected at m = ``middle`` (-1:
    not bisected) becomes (c, a, m) and (b, c, m): the orientation is kept, the new vertex is
    each child's newest, and the children's refinement edges are the parent's other two edges.
    ((the first children, the second ones), whether each triangle stays whole)."""
    cut = middle >= 0
    a, b, c = triangles[cut].T
    m = middle[cut]
    return (np.stack([c, a, m], axis=1), np.stack([b, c, m], axis=1)), ~cut


def _split_segments(segments: np.ndarray, index: np.ndarray, keys: np.ndarray, middle: np.ndarray,
                    n: int) -> tuple[np.ndarray, np.ndarray]:
    """Each segment (a, b) of a bisected edge (``keys``, sorted, and its ``middle``) becomes
    (a, m) and (m, b), with its index."""
    own = segments.min(axis=1) * n + segments.max(axis=1)
    where = np.minimum(np.searchsorted(keys, own), max(len(keys) - 1, 0))
    cut = keys[where] == own if len(keys) else np.zeros(len(own), dtype=bool)
    a, b = segments[cut].T
    m = middle[where[cut]]
    return (np.concatenate([segments[~cut], np.stack([a, m], axis=1), np.stack([m, b], axis=1)]),
            np.concatenate([index[~cut], index[cut], index[cut]]))


def _prolongation(n: int, ends: np.ndarray):
    """The P1 prolongation of a bisection: identity on the n old vertices, each new vertex the
    mean of its edge's ends (``ends``, in the new vertices' order)."""
    import scipy.sparse as sp

    k = len(ends)
    rows = np.concatenate([np.arange(n), np.repeat(n + np.arange(k), 2)])
    cols = np.concatenate([np.arange(n), ends.ravel()])
    values = np.concatenate([np.ones(n), np.full(2 * k, 0.5)])
    return sp.csr_matrix((values, (rows, cols)), shape=(n + k, n))
