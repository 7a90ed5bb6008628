"""How far a discrete solution's trace dips below the obstacle: every method reports it beside
its KKT or Newton residual (K_h and K~_h constrain only nodes and edge means, the weak methods
nothing pointwise)."""
from __future__ import annotations

import ngsolve as ngs
import numpy as np

from ..mesh.points import evaluate, in_elements
from .assembly import ContactTraceFunction
from .polynomials import barycentric_lattice

PENETRATION_SAMPLES_PER_EDGE = 33

# barycentric points sampled on each triangle of a 3D Gamma_C for max_penetration
FACE_LATTICE = barycentric_lattice(8)


def max_penetration(case, mesh: ngs.Mesh, trace_u: ContactTraceFunction) -> float:
    """max over Gamma_C of (obstacle - c(u_h)): positive where u_h dips below the obstacle
    (c(u_h) = u_h, obstacle alpha; in elasticity u_h . n - alpha, positive where u_h penetrates
    the foundation).

    Sampled densely on every contact edge and at the stationary point of its quadratic, so
    the value between nodes is seen (K_h and K~_h only constrain nodes and edge means).
    """
    dense = np.linspace(0.0, 1.0, PENETRATION_SAMPLES_PER_EDGE)
    t_star = trace_u.minimum_parameters()
    values = np.concatenate([trace_u.at(dense), trace_u.value(np.arange(len(t_star)), t_star)[:, None]], axis=1)
    params = np.concatenate([np.broadcast_to(dense, (len(t_star), len(dense))), t_star[:, None]], axis=1)
    points = trace_u.a[:, None, :] + params[..., None] * (trace_u.b - trace_u.a)[:, None, :]
    if trace_u.volumes is not None and case.obstacle is not None:
        in_elements(mesh, points, trace_u.volumes[:, None])
    excess = [_excess(case, mesh, points, values)]
    if trace_u.face_points is not None:     # 3D: inside the triangles too
        excess.append(_excess(case, mesh, *trace_u.on_faces(FACE_LATTICE)))
    return float(max(e.max() for e in excess))


def _excess(case, mesh, points: np.ndarray, values: np.ndarray) -> np.ndarray:
    obstacle = evaluate(case.obstacle, mesh, points) if case.obstacle is not None else 0.0
    return obstacle - values
