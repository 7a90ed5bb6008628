"""The sides of a 2D mesh as arrays: for every triangle its three sides (vertices, outward
normal, length), and every interior edge as the pair of (triangle, side) that share it. What a
residual estimator's flux jumps need, made from the vertex and cell tables in numpy, without a
loop over NGSolve's element objects."""
from __future__ import annotations

from collections import OrderedDict
from dataclasses import dataclass

import ngsolve as ngs
import numpy as np

from .points import cells, coordinates, mesh_key, mesh_points

# side s of a triangle joins its local vertices s and s + 1 (mod 3)
SIDE_ENDS = np.array([[0, 1], [1, 2], [2, 0]])
_MADE: OrderedDict = OrderedDict()
_KEPT = 2


@dataclass(frozen=True)
class MeshSides:
    """Sides of the triangles of one 2D mesh."""

    cells: np.ndarray          # (ne, 3) vertex numbers, NGSolve's order
    corners: np.ndarray        # (ne, 3, 2) vertex coordinates
    area: np.ndarray           # (ne,)
    normals: np.ndarray        # (ne, 3, 2) outward unit normal of each side
    lengths: np.ndarray        # (ne, 3)
    interior: np.ndarray       # (k, 2, 2) the two (element, side) of each interior edge
    boundary: np.ndarray       # (b, 2) the (element, side) of each boundary edge

    @classmethod
    def of(cls, mesh: ngs.Mesh) -> "MeshSides":
        """The sides of ``mesh`` (made once for the problems of both orders on one mesh: the
        last few are kept, keyed as ``points`` keys its point sets)."""
        key = mesh_key(mesh)
        hit = _MADE.get(key)
        if hit is not None and hit[0] is mesh:
            return hit[1]
        made = cls._make(mesh)
        _MADE[key] = (mesh, made)
        while len(_MADE) > _KEPT:
            _MADE.popitem(last=False)
        return made

    @classmethod
    def _make(cls, mesh: ngs.Mesh) -> "MeshSides":
        if mesh.dim != 2:
            raise ValueError("MeshSides is for 2D meshes")
        table, xy = cells(mesh), coordinates(mesh)
        # the coordinates as (ne, 3) planes, x and y apart: one-dimensional gathers and
        # elementwise arithmetic are faster than on (ne, 3, 2) arrays
        X, Y = xy[:, 0][table], xy[:, 1][table]
        ends = table[:, SIDE_ENDS]                                            # (ne, 3, 2)
        following, opposite = [1, 2, 0], [2, 0, 1]
        tx, ty = X[:, following] - X, Y[:, following] - Y                      # side s: x_{s+1} - x_s
        lengths = np.hypot(tx, ty)
        nx, ny = ty / lengths, -tx / lengths
        # outward: away from the vertex opposite the side (local vertex s + 2)
        inward = nx * (X[:, opposite] - X) + ny * (Y[:, opposite] - Y) > 0
        nx[inward] *= -1
        ny[inward] *= -1
        area = 0.5 * np.abs((X[:, 1] - X[:, 0]) * (Y[:, 2] - Y[:, 0]) - (Y[:, 1] - Y[:, 0]) * (X[:, 2] - X[:, 0]))
        corners, normals = np.stack([X, Y], axis=2), np.stack([nx, ny], axis=2)
        key = (np.minimum(ends[..., 0], ends[..., 1]) * mesh.nv + np.maximum(ends[..., 0], ends[..., 1])).ravel()
        order = np.argsort(key, kind="stable")
        sorted_key = key[order]
        paired = np.flatnonzero(sorted_key[1:] == sorted_key[:-1])
        single = np.ones(len(key), bool)
        single[paired] = single[paired + 1] = False
        pairs = np.stack([order[paired], order[paired + 1]], axis=1)          # flat (element * 3 + side)
        lone = order[single]
        return cls(table, corners, area, normals, lengths,
                   np.stack([pairs // 3, pairs % 3], axis=2), np.stack([lone // 3, lone % 3], axis=1))

    def side_vertices(self, elements: np.ndarray, sides: np.ndarray) -> np.ndarray:
        """(..., 2) vertex numbers at the two ends of side ``sides`` of ``elements``."""
        return self.cells[elements[..., None], SIDE_ENDS[sides]]

    def vertex_points(self, mesh: ngs.Mesh) -> np.ndarray:
        """NGSolve mesh points at the three vertices of every triangle (element e's vertex k at
        index 3e + k; local coordinates (1, 0), (0, 1), (0, 0) in NGSolve's reference triangle),
        for evaluating volume functions -- gradients included -- there without a search."""
        ne = len(self.cells)
        points = mesh_points(mesh, 3 * ne)
        points["x"] = np.tile([1.0, 0.0, 0.0], ne)
        points["y"] = np.tile([0.0, 1.0, 0.0], ne)
        points["nr"] = np.repeat(np.arange(ne), 3)
        return points
