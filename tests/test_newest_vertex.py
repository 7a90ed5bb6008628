"""Newest vertex bisection on arrays (``harness.mesh.newest_vertex``): the meshes NGSolve's own
bisection makes, conforming and oriented, with the P1 prolongation exact."""
from __future__ import annotations

import ngsolve as ngs
import numpy as np
import pytest
from netgen.geom2d import SplineGeometry

from harness.mesh.bisection import ArrayBisection, InPlaceBisection, bisection, refine_marked
from harness.mesh.newest_vertex import TriangleMesh, straight_polygon
from harness.mesh.points import cells, coordinates
from harness.problem.case import load_case
from harness.problem.geometry import split_strip

CASES = ["corner-r12", "transition-r32"]


def _triangles_by_coordinates(points: np.ndarray, triangles: np.ndarray) -> np.ndarray:
    """Each triangle as its sorted corner coordinates, rows sorted: a mesh up to numbering."""
    corners = np.round(points[triangles], 12)
    order = np.lexsort((corners[:, :, 1], corners[:, :, 0]), axis=1)
    corners = np.take_along_axis(corners, order[:, :, None], axis=1).reshape(len(triangles), -1)
    return corners[np.lexsort(corners.T[::-1])]


@pytest.mark.parametrize("case_name", CASES)
def test_array_bisection_makes_the_meshes_ngsolves_bisection_makes(case_name):
    """Independent cross-check: the same marked elements bisected by NGSolve's Mesh.Refine (in
    place) and on arrays give the same triangles, level after level (p1afem's refineNVB with
    longest-edge labels is what netgen's 2D bisection does)."""
    case = load_case(case_name)
    rng = np.random.default_rng(7)
    reference = InPlaceBisection(ngs.Mesh(case.geometry.GenerateMesh(maxh=case.maxh)))
    arrays = ArrayBisection(ngs.Mesh(case.geometry.GenerateMesh(maxh=case.maxh)))
    for index in range(1, 5):
        ours = _triangles_by_coordinates(arrays.arrays.points, arrays.arrays.triangles)
        assert np.array_equal(ours, _triangles_by_coordinates(coordinates(reference.mesh), cells(reference.mesh)))
        centroids = arrays.element_sizes()[1]
        marked = (rng.random(arrays.ne) < 0.15) | (np.linalg.norm(centroids, axis=1) < 0.3)
        # the same elements marked in both numberings
        order = _element_order(arrays, reference)
        arrays.refine(marked)
        reference.refine(marked[order])
        level = arrays.level(index)
        # NGSolve numbers the new mesh's elements and vertices as the arrays do
        assert np.array_equal(cells(level.mesh), arrays.arrays.triangles)
        assert np.array_equal(coordinates(level.mesh), arrays.arrays.points)
    assert arrays.ne == reference.ne


def _element_order(arrays, reference) -> np.ndarray:
    """For each NGSolve element of ``reference``, the arrays' element with the same corners."""
    def keys(points, triangles):
        corners = np.round(points[triangles], 12)
        return [tuple(sorted(map(tuple, c))) for c in corners]
    ours = {key: k for k, key in enumerate(keys(arrays.arrays.points, arrays.arrays.triangles))}
    return np.array([ours[key] for key in keys(coordinates(reference.mesh), cells(reference.mesh))])


def _refined_twice(geometry, maxh: float = 0.3, share: float = 0.3):
    rng = np.random.default_rng(3)
    coarse = TriangleMesh.of(ngs.Mesh(geometry.GenerateMesh(maxh=maxh)))
    middle, first = coarse.refine(rng.random(coarse.ne) < share)
    fine, second = middle.refine(rng.random(middle.ne) < share)
    return coarse, fine, second @ first


def test_a_bisected_mesh_is_conforming_oriented_and_keeps_its_domains_and_boundaries():
    """Every interior edge in two triangles, every boundary edge in one triangle and one
    segment; areas positive (orientation kept) summing to the domain's; each domain's area and
    each boundary label's length unchanged."""
    geometry = split_strip(0.25)
    coarse, fine, _ = _refined_twice(geometry)
    p = fine.points[fine.triangles]
    area = 0.5 * ((p[:, 1, 0] - p[:, 0, 0]) * (p[:, 2, 1] - p[:, 0, 1]) - (p[:, 1, 1] - p[:, 0, 1]) * (p[:, 2, 0] - p[:, 0, 0]))
    assert area.min() > 0 and np.isclose(area.sum(), 2.0)
    edges = np.sort(fine.triangles[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2), axis=1)
    keys, counts = np.unique(edges[:, 0] * len(fine.points) + edges[:, 1], return_counts=True)
    outer = keys[counts == 1]
    segments = np.sort(fine.segments, axis=1)
    segment_keys = segments[:, 0] * len(fine.points) + segments[:, 1]
    assert counts.max() == 2 and set(outer) <= set(segment_keys)
    meshes = [ngs.Mesh(geometry.GenerateMesh(maxh=0.3)), fine.ngsolve_mesh()]
    for label in ["contact", "neumann", "dirichlet", "interior"]:
        lengths = [ngs.Integrate(1.0 + ngs.x, m, ngs.BND, definedon=m.Boundaries(label)) for m in meshes]
        assert lengths[1] == pytest.approx(lengths[0], rel=1e-12)
    left = [ngs.Integrate(ngs.IfPos(0.25 - ngs.x, 1.0, 0.0) * (1 + ngs.y), m, element_wise=True) for m in meshes]
    assert sum(left[1]) == pytest.approx(sum(left[0]), rel=1e-12)
    assert meshes[1].GetMaterials() == meshes[0].GetMaterials()


def test_the_prolongation_of_a_bisection_interpolates_p1_functions_exactly():
    """P c at the fine vertices is the coarse P1 function with vertex values c there (two
    refinements: the product of their prolongations)."""
    geometry = split_strip(0.25)
    coarse, fine, prolongation = _refined_twice(geometry)
    coarse_mesh = coarse.ngsolve_mesh()
    u = ngs.GridFunction(ngs.H1(coarse_mesh, order=1))
    values = np.random.default_rng(0).standard_normal(len(coarse.points))
    u.vec.FV().NumPy()[:] = values
    at_fine = np.array([u(coarse_mesh(*point)) for point in fine.points])
    assert prolongation.shape == (len(fine.points), len(coarse.points))
    assert np.abs(prolongation @ values - at_fine).max() < 1e-12


def test_polygons_are_bisected_on_arrays_and_curved_geometries_by_ngsolve():
    """A new boundary vertex must lie on the boundary: a chord's midpoint does only on a
    straight side."""
    assert isinstance(bisection(load_case("corner-r12")), ArrayBisection)
    assert isinstance(bisection(load_case("transition-line-3d")), InPlaceBisection)
    geometry = SplineGeometry()
    ids = [geometry.AppendPoint(*point) for point in [(0, 0), (1, 0), (1, 1)]]
    geometry.Append(["line", ids[0], ids[1]])
    geometry.Append(["spline3", ids[1], ids[2], ids[0]])
    assert not straight_polygon(geometry) and straight_polygon(split_strip(0.0))


def test_refinement_flags_must_match_the_elements():
    arrays = TriangleMesh.of(ngs.Mesh(split_strip(0.0).GenerateMesh(maxh=0.5)))
    with pytest.raises(ValueError, match="refinement flags"):
        arrays.refine(np.ones(arrays.ne + 1, dtype=bool))
    mesh = ngs.Mesh(split_strip(0.0).GenerateMesh(maxh=0.5))
    with pytest.raises(ValueError, match="refinement flags"):
        refine_marked(mesh, np.ones(mesh.ne + 1, dtype=bool))


def test_the_adaptive_bench_replays_the_loop_by_both_bisections_on_the_same_meshes():
    """`bench --only adaptive` on a small budget: the replay finds the same elements in both
    bisections' meshes at every level (else it raises), and every figure is filled."""
    from harness.bench.adaptive import ADAPTIVE_COLUMNS, adaptive_goals, run_adaptive_bench

    frame = run_adaptive_bench(["p1"], levels=3, progress=lambda line: None)
    assert list(frame.columns) == ADAPTIVE_COLUMNS and len(frame) == 1
    row = frame.iloc[0]
    assert row.levels >= 3 and row.kkt_residual <= 1e-10
    assert row.t_refine_arrays > 0 and row.t_refine_in_place > 0 and row.t_chain >= row.t_chain_solves > 0
    assert {goal for goal, _, _ in adaptive_goals(frame)} >= {"adaptive chain, P1: total <= 3.0x its solves"}
