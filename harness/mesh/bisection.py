"""Meshes that fit the singularity: graded a priori (Remark 4.4) and adaptive (SOLVE -> ESTIMATE
-> MARK -> REFINE), both by bisection of marked elements, so that each level refines the
previous one (nested: the multigrid's prolongations and the nested iteration work as on
uniform meshes, ``solvers.multigrid.Multilevel``). Polygons are bisected on arrays, each level
a new mesh (``newest_vertex``: the cost of a sweep grows with the marked elements); solids and
curved 2D geometries by NGSolve, in place (``InPlaceBisection``).

Both are ``mesh.levels.LevelSequence`` implementations; ``strategies`` names them.
"""
from __future__ import annotations

from collections.abc import Iterator

import ngsolve as ngs
import numpy as np

from .levels import Level, coarse_mesh, mesh_size
from .newest_vertex import TriangleMesh, straight_polygon
from .points import cells, coordinates

# Graded meshes: the size function h(r) = H (r / R)^(1 - mu) holds within GRADING_RADIUS of a
# singular point or line (h = H beyond). A fixed length of the cases' scale (their domains are about 2 x 1):
# it changes the constant of N(H), not the rate.
GRADING_RADIUS = 0.5
# mu = GRADING_MARGIN * lambda / k: strictly inside Apel's condition mu < lambda / k (at equality
# the rate keeps a log factor), close to it so that the smallest elements, of size ~ H^(1/mu),
# stay as large as the theory allows.
GRADING_MARGIN = 0.9
# Level 0 grades with H = GRADED_START x maxh: away from the singular points the case's own mesh
# is then fine enough already, and the refinement goes where it pays; each level halves H.
GRADED_START = 4.0
# a bound on the bisection sweeps of one level (each at least halves the area of every marked
# element; a graded level needs about 2/mu of them): a size function that cannot be met is an error
MAX_SWEEPS = 400


def element_sizes(mesh: ngs.Mesh) -> tuple[np.ndarray, np.ndarray]:
    """(h_T, centroid) of every element: its longest edge and its centre of mass."""
    p = coordinates(mesh)[cells(mesh)]
    corners = p.shape[1]
    sides = np.stack([p[:, j] - p[:, i] for i in range(corners) for j in range(i + 1, corners)], axis=1)
    return np.sqrt((sides**2).sum(axis=2)).max(axis=1), p.mean(axis=1)


def refine_marked(mesh: ngs.Mesh, marked: np.ndarray) -> None:
    """Bisect the marked elements (and what conformity asks besides), in place: NGSolve's
    ``ngsolve.Mesh.Refine`` with refinement flags, which records every new vertex's parents."""
    if len(marked) != mesh.ne:
        raise ValueError(f"{len(marked)} refinement flags for a mesh of {mesh.ne} elements")
    mesh.SetRefinementFlags([bool(m) for m in marked])
    mesh.Refine()


class InPlaceBisection:
    """NGSolve's bisection of the marked elements of one mesh, in place (``refine_marked``):
    tetrahedra, and triangles of a geometry with curved sides (NGSolve puts a new boundary
    vertex on the curve)."""

    def __init__(self, mesh: ngs.Mesh):
        self.mesh = mesh

    @property
    def ne(self) -> int:
        return self.mesh.ne

    def element_sizes(self) -> tuple[np.ndarray, np.ndarray]:
        return element_sizes(self.mesh)

    def refine(self, marked: np.ndarray) -> None:
        refine_marked(self.mesh, marked)

    def level(self, index: int) -> Level:
        return Level(index, self.mesh, mesh_size(self.mesh))


class ArrayBisection:
    """Newest vertex bisection on arrays (``newest_vertex.TriangleMesh``): sweeps refine the
    arrays; ``level`` builds the NGSolve mesh, with the prolongation of all sweeps since the
    last level (their product)."""

    def __init__(self, mesh: ngs.Mesh):
        self.mesh, self.arrays, self.pending = mesh, TriangleMesh.of(mesh), None

    @property
    def ne(self) -> int:
        return self.arrays.ne

    def element_sizes(self) -> tuple[np.ndarray, np.ndarray]:
        return self.arrays.element_sizes()

    def refine(self, marked: np.ndarray) -> None:
        self.arrays, prolongation = self.arrays.refine(marked)
        self.pending = prolongation if self.pending is None else prolongation @ self.pending

    def level(self, index: int) -> Level:
        prolongation, self.pending = self.pending, None
        if prolongation is not None:
            self.mesh = self.arrays.ngsolve_mesh()
        return Level(index, self.mesh, float(self.arrays.element_sizes()[0].max()), prolongation)


def bisection(case):
    """The bisection of ``case``'s coarse mesh: on arrays for a polygon, else NGSolve's in place."""
    mesh = coarse_mesh(case)
    if mesh.dim == 2 and straight_polygon(case.geometry):
        return ArrayBisection(mesh)
    return InPlaceBisection(mesh)


def dorfler(indicators: np.ndarray, theta: float) -> np.ndarray:
    """Dörfler's marking (SIAM J. Numer. Anal. 33 (1996), the bulk criterion): the smallest set M
    of elements with sum_{T in M} eta_T^2 >= theta sum_T eta_T^2, taken largest first.
    ``indicators``: eta_T^2 per element."""
    eta2 = np.asarray(indicators, dtype=float)
    order = np.argsort(-eta2, kind="stable")
    total = eta2.sum()
    marked = np.zeros(len(eta2), dtype=bool)
    if not total > 0:
        return marked
    count = int(np.searchsorted(np.cumsum(eta2[order]), theta * total * (1 - 1e-12))) + 1
    marked[order[:min(count, len(eta2))]] = True
    return marked


def grading_exponent(lam: float, order: int) -> float:
    """mu of the graded mesh h_T ~ H r^(1 - mu) for P_order near a point where u ~ r^lam.

    T. Apel, A.-M. Sändig and J. R. Whiteman, Math. Methods Appl. Sci. 19 (1996) 63-85: on such
    meshes P_k reaches the error of a smooth solution, ||u - u_h||_1 <= C H^k = C N^(-k/2) (in 3D
    near an edge the same condition gives N^(-k/3), ``GradedRefinement``),
    for mu < lam / k (their Theorem for k = 1 with mu < lam; the same local interpolation
    argument for P_k, Apel's survey "Anisotropic finite elements", Teubner 1999, Section 3);
    equivalently radial meshes r_i = R (i/n)^beta with beta = 1/mu > k / lam. mu = 1 is
    the uniform mesh (nothing to grade: lam >= k)."""
    if not (lam > 0):
        raise ValueError(f"the singular exponent lambda = nu - 1 must be positive to grade a mesh, got {lam}")
    return min(1.0, GRADING_MARGIN * lam / order)


def distance_to_segments(points: np.ndarray, segments: np.ndarray) -> np.ndarray:
    """The distance of each of ``points`` (n, d) to the nearest of ``segments`` (m, 2, d), a
    segment from ``[k, 0]`` to ``[k, 1]`` (a point where the two coincide); inf if m = 0.
    One segment at a time: O(n) memory for the polylines of curved singular lines too."""
    nearest = np.full(len(points), np.inf)
    for a, b in np.asarray(segments, dtype=float):
        direction = b - a
        length2 = float(direction @ direction)
        t = np.zeros(len(points)) if length2 == 0 else np.clip((points - a) @ direction / length2, 0.0, 1.0)
        np.minimum(nearest, np.linalg.norm(points - a - t[:, None] * direction, axis=1), out=nearest)
    return nearest


class GradedRefinement:
    """Remark 4.4's meshes: level l satisfies h_T <= H_l min(1, r_T / R)^(1 - mu) on every element
    T (r_T: the distance of its centroid to the nearest singular point or singular line,
    R = GRADING_RADIUS), with H_l = GRADED_START maxh 2^-l, so that N grows by about 2^d per level
    as on uniform meshes in d dimensions. N ~ H^-d int h(r)^-d dV is finite for mu > 0 about a
    point; about a line (3D: dV ~ r dr) for 3 (1 - mu) < 2, i.e. mu > 1/3 (else N ~ H^(-1/mu),
    the smallest elements ~ H^(1/mu) across dominating). Made by bisecting the violating elements
    until none is left, from the previous level: nested.

    In 3D the singular sets of a case are lines, an edge singularity u ~ r^lam in the distance
    r to the line, smooth along it: isotropic grading h_T ~ H r^(1 - mu) with mu < lam / k gives
    P_k the optimal N^(-k/3) (Apel & Nicaise, Math. Methods Appl. Sci. 21 (1998); uniform meshes:
    h^lam = N^(-lam/3)); the same ``grading_exponent`` as in 2D.

    ``lam``: the exponent of the case's leading singularity (nu - 1); ``order``: the method's k;
    ``points`` (p, d) and ``lines`` (m, 2, d, segments): the singular sets; ``mu``: the grading
    exponent, if not ``grading_exponent(lam, order)``.
    """

    name = "graded"
    nested = True
    adaptive = False
    budgeted = True

    def observe(self, indicators) -> None:
        pass

    def __init__(self, case, lam: float, order: int, points: np.ndarray, lines: np.ndarray = (), mu: float | None = None):
        self.case, self.order = case, order
        self.mu = grading_exponent(lam, order) if mu is None else float(mu)
        dim = case.dimension
        points = np.asarray(points, dtype=float).reshape(-1, dim)
        lines = np.asarray(lines, dtype=float).reshape(-1, 2, dim)
        # a point is a segment of length 0
        self.segments = np.concatenate([np.stack([points, points], axis=1), lines])

    def distance(self, centroids: np.ndarray) -> np.ndarray:
        """r: the distance of each centroid to the nearest singular point or line."""
        return distance_to_segments(centroids, self.segments)

    def target(self, H: float, centroids: np.ndarray) -> np.ndarray:
        if not len(self.segments) or self.mu >= 1.0:
            return np.full(len(centroids), H)
        return H * np.minimum(1.0, self.distance(centroids) / GRADING_RADIUS) ** (1.0 - self.mu)

    def grade(self, refiner, H: float, limit: float = np.inf) -> int | None:
        """Bisect until h(r) holds (``refiner``: ``ArrayBisection`` or ``InPlaceBisection``);
        the number of sweeps it took, or None once the mesh has more than ``limit`` elements
        (the level is abandoned half made)."""
        for sweep in range(MAX_SWEEPS):
            sizes, centroids = refiner.element_sizes()
            marked = sizes > self.target(H, centroids) * (1 + 1e-9)
            if not marked.any():
                return sweep
            if refiner.ne > limit:
                return None
            refiner.refine(marked)
        raise RuntimeError(f"graded mesh of {self.case.name}: {MAX_SWEEPS} bisection sweeps did not meet h(r) at H = {H:g}")

    def levels(self, count: int) -> Iterator[Level]:
        """Levels 0..count-1, but none past the uniform level count - 1's number of elements
        (2^d times the coarse mesh's per level): the study's budget (``study.chain.one_body``), which
        would drop such a level; its bisection stops as soon as it has more (in 3D, where mu < 1/3
        makes N ~ H^(-1/mu), the level past the budget could be ten times it)."""
        refiner = bisection(self.case)
        limit = refiner.ne * (2 ** self.case.dimension) ** (count - 1)
        H = GRADED_START * self.case.maxh
        index = 0
        while index < count:
            sweeps = self.grade(refiner, H, limit if index else np.inf)
            if sweeps is None:
                return
            # an H the mesh already meets (the coarse mesh, at the first halvings) is no new level
            if sweeps or index == 0:
                yield refiner.level(index)
                index += 1
            H /= 2


class AdaptiveRefinement:
    """SOLVE -> ESTIMATE -> MARK -> REFINE: level 0 is the case's coarse mesh; after each level's
    solve the study hands the error indicators eta_T^2 to ``observe``; the next level bisects
    Dörfler's set for ``theta`` (``dorfler``) once. One method's solutions drive its own
    meshes: a sequence serves one method."""

    name = "adaptive"
    nested = True
    adaptive = True
    budgeted = True

    def __init__(self, case, theta: float = 0.5):
        if not (0 < theta <= 1):
            raise ValueError(f"adaptive: theta must be in (0, 1], got {theta}")
        self.case, self.theta = case, theta
        self._indicators = None
        self.element_limit = np.inf

    def limit_elements(self, limit: float) -> None:
        """The study's budget of elements (``study.chain.one_body``): a level it would drop is not made."""
        self.element_limit = limit

    def observe(self, indicators: np.ndarray) -> None:
        """eta_T^2 of the solve on the last level yielded (one per element)."""
        self._indicators = np.asarray(indicators, dtype=float)

    def levels(self, count: int) -> Iterator[Level]:
        refiner = bisection(self.case)
        for index in range(count):
            if index:
                if self._indicators is None or len(self._indicators) != refiner.ne:
                    raise RuntimeError("adaptive refinement: observe() the level's indicators before asking for the next level")
                marked = dorfler(self._indicators, self.theta)
                self._indicators = None
                # each marked element is bisected at least once: past the budget already, the
                # level would be made only to be dropped (in 3D it can need more memory than the
                # whole chain before it)
                if refiner.ne + marked.sum() > self.element_limit:
                    return
                refiner.refine(marked)
            yield refiner.level(index)
