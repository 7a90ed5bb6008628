"""Refuse a case whose exact solution does not satisfy the Signorini conditions (2.4).

With gap alpha and contact load g_C the conditions read, on Gamma_C,
    u - alpha >= 0,   du/dn - g_C >= 0,   (u - alpha)(du/dn - g_C) = 0,
which is what makes u the solution of the variational inequality (2.5) with the data the
harness derives from it. They are sampled densely on the coarse contact trace.
"""
from __future__ import annotations

import numpy as np

from .case import CaseError
from .geometry import LABELS
from .mesh import boundary_labels, coarse_mesh, contact_trace, evaluate

SAMPLES_PER_EDGE = 64
RELATIVE_TOLERANCE = 1e-8


def contact_samples(case, mesh):
    """Points strictly inside the coarse contact edges, their normals, u - alpha and du/dn - g_C."""
    trace = contact_trace(mesh)
    t = (np.arange(SAMPLES_PER_EDGE) + 0.5) / SAMPLES_PER_EDGE
    points = trace.points(t)
    normals = np.broadcast_to(trace.normals[:, None, :], points.shape)
    excess = evaluate(case.u - case.gap_or_zero, mesh, points)
    flux = (evaluate(case.grad_u, mesh, points) * normals).sum(axis=-1) - evaluate(case.load_or_zero, mesh, points)
    return points.reshape(-1, 2), excess.ravel(), flux.ravel()


def validate_case(case) -> None:
    mesh = coarse_mesh(case)
    missing = [label for label in LABELS if label not in boundary_labels(mesh)]
    if missing:
        raise CaseError(f"case {case.name!r}: geometry has no boundary labelled {', '.join(missing)}")
    points, excess, flux = contact_samples(case, mesh)
    if not (np.all(np.isfinite(excess)) and np.all(np.isfinite(flux))):
        bad = points[~(np.isfinite(excess) & np.isfinite(flux))][0]
        raise CaseError(f"case {case.name!r}: u or du/dn is not finite on Gamma_C at ({bad[0]:.4g}, {bad[1]:.4g})")
    tol_u = RELATIVE_TOLERANCE * max(np.abs(excess).max(), 1e-300)
    tol_flux = RELATIVE_TOLERANCE * max(np.abs(flux).max(), 1e-300)
    checks = [
        ("u - gap >= 0", excess < -tol_u, excess),
        ("du/dn - contact_load >= 0", flux < -tol_flux, flux),
        ("(u - gap)(du/dn - contact_load) = 0",
         (np.abs(excess) > tol_u) & (np.abs(flux) > tol_flux), excess * flux),
    ]
    for condition, violated, value in checks:
        if violated.any():
            k = int(np.argmax(violated))
            x, y = points[k]
            raise CaseError(
                f"case {case.name!r} violates the Signorini condition {condition} on Gamma_C "
                f"at ({x:.4g}, {y:.4g}): value {value[k]:.3e} ({int(violated.sum())} of {len(points)} samples)"
            )
