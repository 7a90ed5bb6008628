"""What the report draws besides the error table: u_h and the contact pressure along Gamma_C on
the finest level (in 3D over Gamma_C, a face of the body), and u_h on Omega (2D) on a level
fine enough to look smooth. Collected during the
study through its ``on_level`` hook and stored as .npz beside the results."""
from __future__ import annotations

import io
from pathlib import Path

import numpy as np

from ...mesh.points import evaluate
from ...methods import REFERENCE, with_role
from ..storage.files import write_atomic
from .rows import study_levels

PICTURE_LEVEL = 3
# two bodies: the level whose meshes the report draws at the interface (coarse enough to see them
# not match)
INTERFACE_LEVEL = 1
SAMPLES_PER_EDGE = 9


def contact_snapshot(case, problem, trace_u, pressure) -> dict:
    """The contact variable of u_h and of u, its obstacle and the pressures along Gamma_C
    (u_h, u, alpha, d_n u - g_C; in elasticity -u_h . n, -u . n, -alpha, -(sigma_n - g_n):
    ``physics``), ordered by the coordinate along it."""
    trace = problem.trace
    t = np.linspace(0.0, 1.0, SAMPLES_PER_EDGE)
    points = trace.points(t)
    start, end = trace.vertex_points.min(axis=0), trace.vertex_points.max(axis=0)
    direction = (end - start) / np.linalg.norm(end - start)
    # the coordinate along Gamma_C's direction (x itself for a horizontal Gamma_C)
    s = (points @ direction).ravel()
    order = np.argsort(s, kind="stable")
    if case.u is None:          # a reference case: nothing exact to draw
        exact_u = exact_pressure = np.full(points.shape[:-1], np.nan)
    else:
        normals = np.broadcast_to(trace.normals[:, None, :], points.shape)
        exact_u = case.physics.contact_value(case, problem.mesh, points, normals)
        exact_pressure = case.physics.pressure(case, problem.mesh, points, normals)
    edge_s = trace.midpoints @ direction
    edge_order = np.argsort(edge_s)
    along = {"s": s, "u_h": trace_u.at(t), "u": exact_u,
             "gap": evaluate(case.obstacle, problem.mesh, points) if case.obstacle is not None else np.zeros(points.shape[:-1]),
             "exact_pressure": exact_pressure}
    return {
        **{key: np.ravel(value)[order] for key, value in along.items()},
        "edge_s": edge_s[edge_order], "edge_lengths": trace.lengths[edge_order],
        "pressure": pressure[edge_order],
    }


def friction_snapshot(case, problem, u: np.ndarray, previous: np.ndarray | None = None) -> dict:
    """An elastic 2D friction case's fields along Gamma_C, in ``contact_snapshot``'s order: the
    slip of u_h (of its last load step: less ``previous``) and of u along tau = (-n_y, n_x), and
    the discrete friction force per edge (``friction_force_per_edge``) beside the exact one at
    the points (NaN without u)."""
    trace = problem.trace
    t = np.linspace(0.0, 1.0, SAMPLES_PER_EDGE)
    points = trace.points(t)
    start, end = trace.vertex_points.min(axis=0), trace.vertex_points.max(axis=0)
    direction = (end - start) / np.linalg.norm(end - start)
    order = np.argsort((points @ direction).ravel(), kind="stable")
    flat = points.reshape(-1, 2)
    normals = np.repeat(trace.normals, len(t), axis=0)
    tangents = np.stack([-normals[:, 1], normals[:, 0]], axis=1)
    moved = u if previous is None else u - previous
    slip = (evaluate(problem.gridfunction(moved), problem.mesh, flat).reshape(-1, 2) * tangents).sum(axis=1)
    if case.u is None:
        exact_slip = exact_force = np.full(len(flat), np.nan)
    else:
        exact_slip = (evaluate(case.u, problem.mesh, flat).reshape(-1, 2) * tangents).sum(axis=1)
        exact_force = (case.physics.tangential_traction(case, problem.mesh, flat, normals) * tangents).sum(axis=1)
    return {"slip": slip[order], "exact_slip": exact_slip[order], "exact_friction_force": exact_force[order],
            "friction_force": friction_force_per_edge(problem, u, direction)}


def friction_force_per_edge(problem, u: np.ndarray, direction: np.ndarray) -> np.ndarray:
    """The discrete friction force of u_h per edge of Gamma_C: the mean over each edge of
    ``measure.errors.DiscreteTraction`` (sigma_t,h - g_t along tau), the edges ordered by their
    midpoints' coordinate along ``direction`` (``contact_snapshot``'s edge order)."""
    from ...measure.errors import DiscreteTraction
    trace = problem.trace
    traction = DiscreteTraction.of(problem)
    q = traction.quadrature
    force = traction.at_points(u)[0][:, 0]
    per_edge = np.bincount(q.edge, weights=q.weights * force, minlength=len(trace.lengths)) / \
        np.bincount(q.edge, weights=q.weights, minlength=len(trace.lengths))
    return per_edge[np.argsort(trace.midpoints @ direction)]


def contact_face_snapshot(case, problem, trace_u, pressure) -> dict:
    """3D: Gamma_C seen as its triangles, each split into four at its edge midpoints: the
    points (x, y), those sub-triangles, u_h - alpha and u - alpha at the points (u_h at the
    midpoints from its quadratic trace, so that a dip of u_h between the vertices shows) and
    the discrete pressure per triangle (``fem.cones.contact_pressure``)."""
    trace = problem.trace
    corners = trace.faces.corners(trace)                         # (f, 3, 3)
    sides = trace.faces.edges                                    # (f, 3): side k from corner k to k+1
    points = np.concatenate([trace.vertex_points, trace.midpoints])
    nv = len(trace.vertices)
    c = np.searchsorted(trace.vertices, trace.faces.vertices)    # corner index in points
    m = nv + sides                                               # side midpoint index in points
    triangles = np.concatenate([np.stack([c[:, 0], m[:, 0], m[:, 2]], 1), np.stack([m[:, 0], c[:, 1], m[:, 1]], 1),
                                np.stack([m[:, 2], m[:, 1], c[:, 2]], 1), np.stack([m[:, 0], m[:, 1], m[:, 2]], 1)])
    u_h = np.concatenate([problem_vertex_values(problem, trace_u), trace_u.at(np.array([0.5]))[:, 0]])
    gap = evaluate(case.obstacle, problem.mesh, points) if case.obstacle is not None else np.zeros(len(points))
    exact = evaluate(case.u, problem.mesh, points) if case.u is not None else np.full(len(points), np.nan)
    return {"faces": np.array(True), "points": points[:, :2], "triangles": triangles, "face_corners": corners[:, :, :2],
            "u_h": u_h, "u": exact, "gap": gap, "pressure": pressure}


def problem_vertex_values(problem, trace_u) -> np.ndarray:
    """u_h at the vertices of Gamma_C (``problem.trace.vertices`` order), from the edge end values."""
    values = np.empty(len(problem.trace.vertices))
    index = np.searchsorted(problem.trace.vertices, problem.trace.edge_vertices)
    values[index[:, 0]], values[index[:, 1]] = trace_u.va, trace_u.vb
    return values


def domain_snapshot(case, problem, u: np.ndarray) -> dict:
    """Vertices, triangles and vertex values of u_h (vertex dofs are nodal values; (nv, 2)
    Cartesian displacements in elasticity). Copies: netgen hands out views of a mesh that the
    next level refines in place."""
    ngmesh = problem.mesh.ngmesh
    coords = np.array(ngmesh.Coordinates()[:, :2], copy=True)
    triangles = np.array(ngmesh.Elements2D().NumPy()["nodes"][:, :3], dtype=np.int64) - 1
    return {"points": coords, "triangles": triangles, "values": case.physics.displacement_at_vertices(problem, u)}


def two_body_snapshot(case, problem, solve) -> dict:
    """``contact_snapshot``'s fields for two bodies (``fem.two_body``): along Gamma_C the opening
    c_1 + c_2 of u_h and of u (twice the one-body contact value; NaN without u), twice the
    obstacle, the pressures (the mortar pressure per slave edge, ``methods.mortar``)."""
    from ...fem.two_body import opening
    x, values = opening(problem, solve.u, SAMPLES_PER_EDGE)
    points = np.stack([x, np.zeros_like(x)], axis=-1)
    upper = problem.upper
    normals = np.broadcast_to(np.array([0.0, -1.0]), points.shape)
    order = np.argsort(x.ravel(), kind="stable")
    along = {"s": x, "u_h": values,
             "gap": 2.0 * evaluate(case.obstacle, upper.mesh, points) if case.obstacle is not None else np.zeros(x.shape)}
    if case.u is None:          # a reference case: no exact opening or pressure to draw
        along |= {"u": np.full(x.shape, np.nan), "exact_pressure": np.full(x.shape, np.nan)}
    else:
        along |= {"u": 2.0 * case.physics.contact_value(case, upper.mesh, points, normals),
                  "exact_pressure": case.physics.pressure(case, upper.mesh, points, normals)}
    edge_s = upper.trace.midpoints[:, 0]
    edge_order = np.argsort(edge_s)
    return {**{key: np.ravel(value)[order] for key, value in along.items()},
            "edge_s": edge_s[edge_order], "edge_lengths": upper.trace.lengths[edge_order],
            "pressure": solve.pressure[edge_order], "two_bodies": np.array(True)}


def two_body_friction_snapshot(problem, s: np.ndarray, u: np.ndarray, previous: np.ndarray | None = None) -> dict:
    """``friction_snapshot``'s fields for two elastic bodies in 2D at ``two_body_snapshot``'s
    points ``s`` (x on Gamma_C, y = 0 in both frames): the slip is the tangential jump t_1 - t_2
    between the bodies over the last load step (of u_h less ``previous``), as the quantities read
    it (``measure.two_body_quantities.tangential_jump``; each body's trace by ``MasterTrace``:
    both traces are continuous, so a point shared by two segments has one value), and the
    friction force the upper (slave) body's per edge (``friction_force_per_edge``, its edges in
    ``two_body_snapshot``'s order). No exact ones (NaN): a mirror pair's u has no jump, and its
    slip zone none either (``measure.two_body_quantities.COULOMB_EXACT_NAN``)."""
    from ...measure.two_body_quantities import MasterTrace, tangential_jump
    moved = u if previous is None else u - previous
    upper, lower = (MasterTrace.at(body, s) for body in problem.bodies)
    slip = tangential_jump(problem, lower, moved, upper.values(problem.split(moved)[0], tangential=True)[:, None])[:, 0]
    nan = np.full(len(s), np.nan)
    return {"slip": slip, "exact_slip": nan, "exact_friction_force": nan,
            "friction_force": friction_force_per_edge(problem.upper, problem.split(u)[0], np.array([1.0, 0.0]))}


def two_body_domain_snapshot(case, problem, z: np.ndarray) -> dict:
    """Both bodies as one picture: the lower body mirrored back to y < 0 (its triangles after
    the upper one's), its values those of the real u_2 (``problem.bodies``: -w for the scalar
    variable, (u_x, -u_y) for a displacement), and ``body`` (0, 1) per triangle."""
    parts = [domain_snapshot(case, body, u) for body, u in zip(problem.bodies, problem.split(z))]
    upper, lower = parts
    lower["points"] = lower["points"] * np.array([1.0, -1.0])
    values = lower["values"]
    lower["values"] = values * np.array([1.0, -1.0]) if values.ndim == 2 else -values
    return {"points": np.concatenate([upper["points"], lower["points"]]),
            "triangles": np.concatenate([upper["triangles"], lower["triangles"] + len(upper["points"])]),
            "values": np.concatenate([upper["values"], lower["values"]]),
            "body": np.repeat([0, 1], [len(upper["triangles"]), len(lower["triangles"])])}


class SnapshotHook:
    """``on_level`` hook of the study: returns the finest contact snapshot of each (case, method)
    and the domain picture of each case (the first one-body method that declares the role
    REFERENCE if one runs, else the first; level PICTURE_LEVEL or the finest; two bodies: the
    same among the two-body methods). The study keeps what it returns (in checkpoints too, and back
    from a worker), so the hook itself holds nothing."""

    def __init__(self, levels: int, methods):
        self.finest = {m.name: study_levels(m, levels) - 1 for m in methods}
        methods = list(methods)
        one = [m for m in methods if 1 in m.bodies]
        self.picture_method = next((m.name for m in with_role(REFERENCE, one)), next(iter(self.finest)))
        # two bodies: the first two-body method that declares REFERENCE, else the first that couples two bodies
        two = [m for m in methods if 2 in m.bodies]
        self.two_body_method = next((m.name for m in with_role(REFERENCE, two) + two), None)
        self.picture_level = min(PICTURE_LEVEL, self.finest[self.picture_method])

    def __call__(self, case, method, level, problem, solve) -> dict | None:
        kept = {}
        if case.bodies == 2:
            if level == self.finest.get(method.name):
                kept["contact"] = two_body_snapshot(case, problem, solve)
                if case.frictional and case.physics.elastic:
                    kept["contact"] |= two_body_friction_snapshot(problem, kept["contact"]["s"], solve.u, solve.previous)
            if method.name == self.two_body_method and level == min(PICTURE_LEVEL, self.finest[method.name]):
                kept["domain"] = two_body_domain_snapshot(case, problem, solve.u) | {"method": np.array(method.name)}
            if method.name == self.two_body_method and level == INTERFACE_LEVEL:
                kept["interface"] = two_body_domain_snapshot(case, problem, solve.u)
            return kept or None
        three_d = problem.trace.faces is not None
        if level == self.finest.get(method.name):
            snapshot = contact_face_snapshot if three_d else contact_snapshot
            kept["contact"] = snapshot(case, problem, solve.trace_u, solve.pressure)
            if case.frictional and case.physics.elastic and not three_d:
                kept["contact"] |= friction_snapshot(case, problem, solve.u, solve.previous)
        if method.name == self.picture_method and level == self.picture_level and not three_d:
            kept["domain"] = domain_snapshot(case, problem, solve.u) | {"method": np.array(method.name)}
        return kept or None


def save_snapshots(kept: dict, path: Path) -> None:
    """The snapshots one case's study kept (by (method, level), from ``SnapshotHook``), as .npz."""
    arrays = {}
    for (method, _level), snaps in kept.items():
        arrays.update({f"contact__{method}__{k}": v for k, v in snaps.get("contact", {}).items()})
        arrays.update({f"domain_{k}": v for k, v in snaps.get("domain", {}).items()})
        arrays.update({f"interface_{k}": v for k, v in snaps.get("interface", {}).items()})
    buffer = io.BytesIO()
    np.savez_compressed(buffer, **arrays)
    write_atomic(path, buffer.getvalue())


def load_snapshots(path: Path) -> tuple[dict, dict]:
    """(contact snapshots by method, domain snapshot) of one case."""
    data = np.load(path)
    contact, domain = {}, {}
    for key in data.files:
        if key.startswith("contact__"):
            _, method, field = key.split("__", 2)
            contact.setdefault(method, {})[field] = data[key]
        elif key.startswith("domain_"):
            domain[key[len("domain_"):]] = data[key]
        elif key.startswith("interface_"):      # two bodies: their meshes at the interface
            domain.setdefault("interface", {})[key[len("interface_"):]] = data[key]
    return contact, domain
