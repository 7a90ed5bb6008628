"""Polygonal netgen geometries with the three boundary labels of the case contract.

The paper (Section 3) works on polygons meshed by straight triangles whose vertices
include the end points of Gamma_C and Gamma_u; a polygon whose corners include every
transition point and every label change gives exactly that.
"""
from __future__ import annotations

from netgen.geom2d import SplineGeometry

LABELS = ("contact", "dirichlet", "neumann")


def polygon(points, labels):
    """Counter-clockwise polygon; side k joins points[k] to points[k+1] and carries labels[k]."""
    if len(points) != len(labels):
        raise ValueError("polygon: need one label per side")
    for label in labels:
        if label not in LABELS:
            raise ValueError(f"polygon: unknown boundary label {label!r}, expected one of {LABELS}")
    geo = SplineGeometry()
    ids = [geo.AppendPoint(float(px), float(py)) for px, py in points]
    for k, label in enumerate(labels):
        geo.Append(["line", ids[k], ids[(k + 1) % len(ids)]], bc=label, leftdomain=1, rightdomain=0)
    return geo
