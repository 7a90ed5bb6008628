"""Polygonal netgen geometries with the three boundary labels of the case contract.

The paper (Section 3) works on polygons meshed by straight triangles whose vertices
include the end points of Gamma_C and Gamma_u; a polygon whose corners include every
transition point and every label change gives exactly that.
"""
from __future__ import annotations

import numpy as np
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


def contact_strip(breaks=(0.0,)):
    """Omega = (-1, 1) x (0, 1) with Gamma_C the bottom side, Gamma_g the two vertical sides and
    Gamma_u the top; ``breaks`` are extra corners on Gamma_C (transition points), so that every
    mesh has a vertex there."""
    bottom = [(-1.0, 0.0)] + [(float(x), 0.0) for x in sorted(breaks)] + [(1.0, 0.0)]
    points = bottom + [(1.0, 1.0), (-1.0, 1.0)]
    labels = ["contact"] * (len(bottom) - 1) + ["neumann", "dirichlet", "neumann"]
    return polygon(points, labels)


def split_strip(at: float = 0.0):
    """``contact_strip(breaks=[at])`` cut in two by the interior line x = ``at`` (labelled
    'interior', no boundary condition): every mesh then has edges along it, so a solution
    whose derivatives jump across that line (a transition at (at, 0) continued into the body)
    is smooth on every element, and the element quadratures see no kink inside an element."""
    geo = SplineGeometry()
    ids = [geo.AppendPoint(float(px), float(py)) for px, py in
           [(-1.0, 0.0), (at, 0.0), (1.0, 0.0), (1.0, 1.0), (at, 1.0), (-1.0, 1.0)]]
    left, right = 1, 2
    sides = [(0, 1, "contact", left), (1, 2, "contact", right), (2, 3, "neumann", right), (3, 4, "dirichlet", right),
             (4, 5, "dirichlet", left), (5, 0, "neumann", left)]
    for a, b, label, domain in sides:
        geo.Append(["line", ids[a], ids[b]], bc=label, leftdomain=domain, rightdomain=0)
    geo.Append(["line", ids[1], ids[4]], bc="interior", leftdomain=left, rightdomain=right)
    return geo


def geometry_dimension(geometry) -> int:
    """2 for a polygon (netgen's SplineGeometry), 3 for a solid (OCC or CSG)."""
    return 2 if isinstance(geometry, SplineGeometry) else 3


def _labelled_box(x0: float, x1: float, interior=(), bottom: str = "contact"):
    """The box (x0, x1) x (-1, 1) x (0, 1) with the bottom face z = 0 labelled ``bottom``
    (Gamma_C by default), Gamma_u the top, Gamma_g the sides; the faces named in ``interior``
    ('xmin', 'xmax') lie inside the body."""
    from netgen.occ import Box, Pnt, X, Z
    box = Box(Pnt(x0, -1.0, 0.0), Pnt(x1, 1.0, 1.0))
    box.faces.name = "neumann"
    box.faces.Min(Z).name = bottom
    box.faces.Max(Z).name = "dirichlet"
    for side in interior:
        (box.faces.Min(X) if side == "xmin" else box.faces.Max(X)).name = "interior"
    return box


def contact_box(split_at: float | list[float] | None = None, bottom: list[str] | None = None):
    """Omega = (-1, 1) x (-1, 1) x (0, 1), the 3D counterpart of ``contact_strip``: Gamma_C the
    bottom face (n = -e_z), Gamma_u the top, Gamma_g the four sides. ``split_at``: the box is
    boxes glued along the planes x = a for each a given (faces labelled 'interior'), so that
    every mesh has edges along the lines {x = a, z = 0} of the bottom (a straight transition or
    junction line) and faces along the planes. ``bottom``: the labels of the pieces' bottom
    faces from left to right (default all 'contact'; 'neumann' makes that piece of the bottom
    Gamma_g: a junction of Gamma_C and Gamma_g along the line between them)."""
    from netgen.occ import Glue, OCCGeometry
    cuts = [] if split_at is None else sorted(float(a) for a in np.atleast_1d(split_at))
    if any(not -1.0 < a < 1.0 for a in cuts) or len(set(cuts)) < len(cuts):
        raise ValueError(f"contact_box: split planes must be distinct and inside (-1, 1), got {cuts}")
    bounds = [-1.0, *cuts, 1.0]
    bottom = ["contact"] * (len(bounds) - 1) if bottom is None else list(bottom)
    if len(bottom) != len(bounds) - 1 or any(label not in LABELS for label in bottom):
        raise ValueError(f"contact_box: need one label of {LABELS} per piece ({len(bounds) - 1}), got {bottom}")
    pieces = [_labelled_box(x0, x1, ["xmin"] * (k > 0) + ["xmax"] * (k < len(bottom) - 1), bottom[k])
              for k, (x0, x1) in enumerate(zip(bounds[:-1], bounds[1:]))]
    return OCCGeometry(pieces[0] if len(pieces) == 1 else Glue(pieces))


def disc_box(radius: float):
    """``contact_box()`` with the cylinder x^2 + y^2 < radius^2 glued in (its side labelled
    'interior'): the circle x^2 + y^2 = radius^2 of Gamma_C (a curved transition line) is then a
    curve of the geometry, on which every coarse mesh has vertices and edges (chords)."""
    from netgen.occ import Axes, Cylinder, Glue, OCCGeometry, Pnt, X, Z
    box = _labelled_box(-1.0, 1.0)
    cylinder = Cylinder(Axes(Pnt(0, 0, 0), Z, X), radius, 1.0)
    cylinder.faces.name = "interior"
    cylinder.faces.Min(Z).name = "contact"
    cylinder.faces.Max(Z).name = "dirichlet"
    outside = box - cylinder
    for face in outside.faces:
        if face.name not in ("contact", "dirichlet", "neumann"):
            face.name = "interior"
    return OCCGeometry(Glue([outside, cylinder]))


def zone_box(half_width: float, height: float, zone: float, zone_h: float):
    """(-L, L) x (-L, L) x (0, H) with the box (-zone, zone)^2 x (0, zone) glued in at the middle
    of the bottom, meshed at the local size ``zone_h`` (its inner faces labelled 'interior'):
    Gamma_C the whole bottom face (n = -e_z), Gamma_u the top, Gamma_g the four sides. A coarse
    mesh fine where a contact zone lives, which uniform red refinement keeps; flat faces only, so
    the refined meshes stay nested (a reference solution's exact prolongation)."""
    from netgen.occ import Box, Glue, OCCGeometry, Pnt, X, Y, Z
    L = half_width
    inner = Box(Pnt(-zone, -zone, 0.0), Pnt(zone, zone, zone))
    inner.faces.name = "interior"
    inner.faces.Min(Z).name = "contact"
    inner.maxh = zone_h
    outside = Box(Pnt(-L, -L, 0.0), Pnt(L, L, height)) - inner
    for face in outside.faces:
        face.name = "interior"
    outside.faces.Min(Z).name = "contact"
    outside.faces.Max(Z).name = "dirichlet"
    for side in (outside.faces.Min(X), outside.faces.Max(X), outside.faces.Min(Y), outside.faces.Max(Y)):
        side.name = "neumann"
    return OCCGeometry(Glue([outside, inner]))


def zone_rectangle(half_width, height, zone, zone_h=None, corner_h=None):
    """(-L, L) x (0, H): Gamma_C the bottom with corners at +-zone (local mesh size zone_h on
    [-zone, zone]), Gamma_g the sides, Gamma_u the top (local size corner_h at its corners)."""
    L, H = half_width, height
    geo = SplineGeometry()
    bottom = [(-L, 0.0, None)] + ([(-zone, 0.0, zone_h), (zone, 0.0, zone_h)] if zone else []) + [(L, 0.0, None)]
    points = bottom + [(L, H, corner_h), (-L, H, corner_h)]
    ids = [geo.AppendPoint(px, py) if h is None else geo.AppendPoint(px, py, maxh=h) for px, py, h in points]
    labels = ["contact"] * (len(bottom) - 1) + ["neumann", "dirichlet", "neumann"]
    sizes = [None] * len(labels)
    if zone and zone_h:
        sizes[1] = zone_h
    for k, (label, h) in enumerate(zip(labels, sizes)):
        extra = {} if h is None else {"maxh": h}
        geo.Append(["line", ids[k], ids[(k + 1) % len(ids)]], bc=label, leftdomain=1, rightdomain=0, **extra)
    return geo
