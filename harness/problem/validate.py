"""Refuse a case whose exact solution does not satisfy the Signorini conditions (2.4).

With gap alpha and contact load g_C the conditions read, on Gamma_C,
    u - alpha >= 0,   du/dn - g_C >= 0,   (u - alpha)(du/dn - g_C) = 0,
which is what makes u the solution of the variational inequality (2.5) with the data the
harness derives from it. For an elastic case (Remark 2.3; ``physics``) they are
    u . n - alpha <= 0,   sigma_n(u) - g_n <= 0,   (u . n - alpha)(sigma_n(u) - g_n) = 0,
and, frictionless, sigma_t(u) = g_t: checked as the scalar conditions of the contact variable
c(u) = -u . n >= -alpha and the pressure p = -(sigma_n - g_n) >= 0, plus the tangential one. They are sampled densely on the coarse contact trace. A declared
volume load f must equal -Laplace(u) (sampled inside every coarse element), and declared
singular points must be vertices of the mesh (2D: the quadratures are graded there).

A reference case (no u) cannot be checked against (2.4); its data must be finite where they
act: f inside the coarse elements, u_D, g, gap and contact load on their boundaries.
"""
from __future__ import annotations

import dataclasses

import ngsolve as ngs
import numpy as np

from ..mesh.levels import boundary_labels, coarse_mesh
from ..mesh.points import cells, coordinates, evaluate, format_point, vertices_at
from ..mesh.trace import contact_trace
from .case import CaseError
from .friction import FRICTIONLESS
from .geometry import LABELS
from .physics import COORDINATES

SAMPLES_PER_EDGE = 64
# The conditions in words, by physics (elasticity: sigma_n = n . sigma(u) n, compression < 0).
CONDITIONS = {
    "scalar": ("u - gap >= 0", "du/dn - contact_load >= 0", "(u - gap)(du/dn - contact_load) = 0"),
    "elasticity": ("u.n - gap <= 0", "sigma_n(u) - g_n <= 0", "(u.n - gap)(sigma_n(u) - g_n) = 0",
                   "sigma_t(u) = g_t (frictionless)"),
}
RELATIVE_TOLERANCE = 1e-8


def contact_samples(case, mesh):
    """Points strictly inside the coarse contact edges, their normals, the excess c(u) - obstacle
    (u - alpha; alpha - u . n in elasticity) and the pressure (du/dn - g_C; -(sigma_n - g_n))."""
    trace = contact_trace(mesh)
    if trace.faces is None:
        t = (np.arange(SAMPLES_PER_EDGE) + 0.5) / SAMPLES_PER_EDGE
        points = trace.points(t)
        normals = np.broadcast_to(trace.normals[:, None, :], points.shape)
    else:       # 3D: points strictly inside the coarse triangles of Gamma_C
        points = np.einsum("kc,fcd->fkd", _FACE_INTERIOR, trace.faces.corners(trace))
        normals = np.broadcast_to(trace.faces.normals[:, None, :], points.shape)
    excess = case.physics.contact_value(case, mesh, points, normals)
    if case.obstacle is not None:
        excess = excess - evaluate(case.obstacle, mesh, points)
    pressure = case.physics.pressure(case, mesh, points, normals)
    dim = mesh.dim
    return points.reshape(-1, dim), excess.ravel(), pressure.ravel(), normals.reshape(-1, dim)


def _strict_lattice(n: int, corners: int) -> np.ndarray:
    """Barycentric points (k, corners) of the lattice of step 1/n strictly inside the simplex."""
    import itertools
    points = [p for p in itertools.product(range(1, n), repeat=corners - 1) if sum(p) < n]
    return np.array([(*p, n - sum(p)) for p in points], dtype=float) / n


# the points of each coarse triangle of a 3D Gamma_C where the conditions are sampled
_FACE_INTERIOR = _strict_lattice(24, 3)
# barycentric coordinates of the points where a declared f is compared with -Laplace(u)
_INTERIOR = {2: _strict_lattice(5, 3), 3: _strict_lattice(5, 4)}


def interior_samples(mesh) -> np.ndarray:
    """Points strictly inside every element of ``mesh``."""
    return np.einsum("kv,evd->ekd", _INTERIOR[mesh.dim], coordinates(mesh)[cells(mesh)]).reshape(-1, mesh.dim)


def check_declared_f(case, mesh) -> None:
    if case.declared_f is None:
        return
    points = interior_samples(mesh)
    derived = evaluate(case.derived_f, mesh, points).reshape(len(points), -1)
    declared = evaluate(case.f, mesh, points).reshape(len(points), -1)
    # the size of the second derivatives of u (times the largest modulus lambda + 2 mu in elasticity)
    second = max(np.abs(evaluate(case.u.Diff(d).Diff(d), mesh, points)).max() for d in COORDINATES[:mesh.dim])
    modulus = case.physics.modulus
    scale = max(second * modulus, 1e-300)
    wrong = ~(np.abs(declared - derived) <= RELATIVE_TOLERANCE * scale).all(axis=1)
    if wrong.any():
        k = int(np.argmax(wrong))
        raise CaseError(f"case {case.name!r}: declared f is not {case.physics.operator} at {format_point(points[k])}: "
                        f"{declared[k]} against {derived[k]}")


def check_declared_grad_u(case, mesh) -> None:
    """A declared grad_u is the derivative of u, to RELATIVE_TOLERANCE of its size."""
    if case.declared_grad_u is None:
        return
    if case.declared_grad_u.dim != case.derived_grad_u.dim:
        raise CaseError(f"case {case.name!r}: grad_u has {case.declared_grad_u.dim} components, "
                        f"grad u has {case.derived_grad_u.dim}")
    points = interior_samples(mesh)
    derived = evaluate(case.derived_grad_u, mesh, points).reshape(len(points), -1)
    declared = evaluate(case.declared_grad_u, mesh, points).reshape(len(points), -1)
    scale = max(np.abs(derived).max(), 1e-300)
    wrong = ~(np.abs(declared - derived) <= RELATIVE_TOLERANCE * scale).all(axis=1)
    if wrong.any():
        k = int(np.argmax(wrong))
        raise CaseError(f"case {case.name!r}: declared grad_u is not the gradient of u at {format_point(points[k])}: "
                        f"{declared[k]} against {derived[k]}")


def boundary_samples(mesh, label: str) -> np.ndarray:
    """Points strictly inside the coarse boundary cells labelled ``label``: along each edge
    (2D), or on a barycentric grid of each triangle (3D)."""
    t = (np.arange(SAMPLES_PER_EDGE) + 0.5) / SAMPLES_PER_EDGE
    corners = np.array([[mesh[v].point for v in el.vertices] for el in mesh.Elements(ngs.BND) if el.mat == label], dtype=float)
    if mesh.dim == 2:
        return (corners[:, :1, :] + t[None, :, None] * (corners[:, 1:, :] - corners[:, :1, :])).reshape(-1, 2)
    s, r = np.meshgrid(t, t)
    inside = s + r < 1.0
    weights = np.column_stack([1.0 - s[inside] - r[inside], s[inside], r[inside]])       # (k, 3)
    return np.einsum("kc,fcd->fkd", weights, corners).reshape(-1, 3)


def check_reference_data(case, mesh) -> None:
    """The data of a reference case are finite where they act."""
    data = [("f", case.f, interior_samples(mesh)), ("dirichlet", case.dirichlet, boundary_samples(mesh, "dirichlet")),
            ("neumann", case.neumann, boundary_samples(mesh, "neumann"))]
    data += [(name, cf, boundary_samples(mesh, "contact")) for name, cf in (("gap", case.gap), ("contact_load", case.contact_load))
             if cf is not None]
    for name, cf, points in data:
        values = evaluate(cf, mesh, points)
        if not np.all(np.isfinite(values)):
            bad = points[~np.isfinite(values)][0]
            raise CaseError(f"case {case.name!r}: {name} is not finite at {format_point(bad)}")


def validate_case(case) -> None:
    """The case's declarations against its coarse mesh and the Signorini conditions (2.2)-(2.4)
    at samples of Gamma_C; a two-body case (``bodies``) each body's, and that they meet."""
    if case.bodies == 2 and case.friction.name == "coulomb":
        # the mirror solution has no tangential jump (problem.bodies): it satisfies Coulomb's
        # two-body conditions (stick, force sigma_t) exactly when each body's frictionless ones
        # hold (sigma_t = 0, the traction balance of a mirror pair); a body's own u_t is no slip
        case = dataclasses.replace(case, friction=FRICTIONLESS)
    if case.bodies == 2:
        check_two_bodies(case)
    mesh = coarse_mesh(case)
    missing = [label for label in LABELS if label not in boundary_labels(mesh)]
    if missing:
        raise CaseError(f"case {case.name!r}: geometry has no boundary labelled {', '.join(missing)}")
    try:
        # in 2D the quadratures are graded at them; in 3D they only grade meshes (no vertex needed)
        vertices_at(mesh, case.singular_points if case.singular_points and mesh.dim == 2 else ())
    except ValueError as exc:
        raise CaseError(f"case {case.name!r}: singular point {exc}") from None
    if case.u is None:
        check_reference_data(case, mesh)
        return
    check_declared_f(case, mesh)
    check_declared_grad_u(case, mesh)
    points, excess, flux, normals = contact_samples(case, mesh)
    if not (np.all(np.isfinite(excess)) and np.all(np.isfinite(flux))):
        bad = points[~(np.isfinite(excess) & np.isfinite(flux))][0]
        raise CaseError(f"case {case.name!r}: u or its flux is not finite on Gamma_C at {format_point(bad)}")
    if case.frictional:
        FRICTION_CHECKS[case.friction.name](case, mesh, points, excess, flux, normals)
        return
    check_signorini(case, mesh, points, excess, flux, normals)


def check_signorini(case, mesh, points, excess, flux, normals) -> None:
    """The Signorini conditions (2.4) of the contact variable, and frictionless elasticity's
    sigma_t(u) = g_t, at the samples of Gamma_C."""
    checks, _ = signorini_checks(CONDITIONS[case.physics.name], points, excess, flux)
    tangential = case.physics.tangential(case, mesh, points, normals)
    if tangential is not None:
        tol_flux = RELATIVE_TOLERANCE * max(np.abs(flux).max(), 1e-300)
        checks.append((CONDITIONS[case.physics.name][3], np.abs(tangential) > tol_flux, tangential))
    refuse_violated(case, "Signorini", checks, points)


def signorini_checks(names, points, excess, flux) -> tuple[list, float]:
    """The three conditions (2.4) -- excess >= 0, flux (pressure) >= 0, their product 0 -- as
    (name, violated, value) rows, and the tolerance of the excess."""
    # the scale of u - gap: its own, or, where u = gap on all of Gamma_C (its round-off is then
    # all there is), the flux times Gamma_C's extent
    extent = float(np.ptp(points, axis=0).max())
    tol_u = RELATIVE_TOLERANCE * max(np.abs(excess).max(), np.abs(flux).max() * extent, 1e-300)
    tol_flux = RELATIVE_TOLERANCE * max(np.abs(flux).max(), 1e-300)
    return [
        (names[0], excess < -tol_u, excess),
        (names[1], flux < -tol_flux, flux),
        (names[2], (np.abs(excess) > tol_u) & (np.abs(flux) > tol_flux), excess * flux),
    ], tol_u


def refuse_violated(case, law: str, checks, points) -> None:
    """Refuse the case in one line at the first violated row of ``checks`` (name, violated, value):
    the law, the condition, the place, the value and how many samples break it."""
    for condition, violated, value in checks:
        if violated.any():
            k = int(np.argmax(violated))
            raise CaseError(f"case {case.name!r} violates the {law} condition {condition} on Gamma_C at "
                            f"{format_point(points[k])}: value {value[k]:.3e} ({int(violated.sum())} of {len(points)} samples)")


# Tresca's conditions in words (``problem.friction``), by physics
TRESCA_CONDITIONS = {
    "scalar": ("|du/dn - g_C| <= s", "du/dn - g_C = -s u/|u| where u != 0"),
    "elasticity": ("|sigma_t| <= s", "sigma_t = -s u_t/|u_t| where u_t != 0", "u.n = 0 (bilateral)"),
}


def check_tresca(case, mesh, points, excess, flux, normals) -> None:
    """Tresca's conditions (``problem.friction``) at the samples of Gamma_C: the friction force
    (the flux d_n u - g_C, or the tangential traction sigma_t(u) - g_t, a vector in 3D) lies in
    the disc of radius s, and equals -s times the slip direction where u (u_t) does not vanish;
    in elasticity u . n = 0 (bilateral)."""
    s = evaluate(case.friction.threshold_function, mesh, points)
    force, slip = friction_force_and_slip(case, mesh, points, excess, flux, normals)
    names = TRESCA_CONDITIONS[case.physics.name]
    checks, tol_u = threshold_checks(names, points, s, force, slip, excess)
    if case.physics.name != "scalar":
        checks.append((names[2], np.abs(excess) > tol_u, excess))
    refuse_violated(case, "Tresca", checks, points)


# Coulomb's conditions in words (``problem.friction``; elasticity only): Signorini's, then
# Tresca's with the threshold mu_F p
COULOMB_CONDITIONS = ("u.n - gap <= 0", "p = -(sigma_n(u) - g_n) >= 0", "p (u.n - gap) = 0",
                      "|sigma_t| <= mu_F p", "sigma_t = -mu_F p u_t/|u_t| where u_t != 0")


def check_coulomb(case, mesh, points, excess, flux, normals) -> None:
    """Coulomb's conditions (``problem.friction``) of a static problem at the samples of Gamma_C:
    the unilateral ones of elasticity (Signorini's, without the frictionless sigma_t = g_t),
    and Tresca's with the threshold s = mu_F p, p = ``flux`` the contact pressure."""
    checks, _ = signorini_checks(COULOMB_CONDITIONS, points, excess, flux)
    force, slip = friction_force_and_slip(case, mesh, points, excess, flux, normals)
    checks += threshold_checks(COULOMB_CONDITIONS[3:], points, case.friction.coefficient * flux, force, slip, excess)[0]
    refuse_violated(case, "Coulomb", checks, points)


def friction_force_and_slip(case, mesh, points, excess, flux, normals) -> tuple:
    """(force, slip) at the samples, (k, components): the scalar flux d_n u - g_C and u itself,
    or the tangential traction sigma_t(u) - g_t and the tangential displacement u_t."""
    if case.physics.name == "scalar":
        return flux[:, None], excess[:, None]
    force = case.physics.tangential_traction(case, mesh, points, normals)
    u = evaluate(case.u, mesh, points).reshape(points.shape)
    return force, u - (u * normals).sum(axis=-1)[:, None] * normals


def threshold_checks(names, points, s, force, slip, excess) -> tuple[list, float]:
    """Tresca's two conditions with the threshold s (k,): |force| <= s, and force = -s slip/|slip|
    where the slip exceeds its round-off, as (name, violated, value) rows; and that tolerance."""
    extent = float(np.ptp(points, axis=0).max())
    tol_force = RELATIVE_TOLERANCE * max(np.abs(s).max(), np.abs(force).max(), 1e-300)
    tol_u = RELATIVE_TOLERANCE * max(np.abs(slip).max(), np.abs(excess).max(), tol_force / RELATIVE_TOLERANCE * extent, 1e-300)
    length = np.linalg.norm(slip, axis=-1)
    direction = slip / np.where(length > 0, length, 1.0)[:, None]
    size = np.linalg.norm(force, axis=-1)
    mismatch = np.linalg.norm(force + s[:, None] * direction, axis=-1)
    return [(names[0], size - s > tol_force, size - s),
            (names[1], (length > tol_u) & (mismatch > tol_force), mismatch)], tol_u


# the check of each friction law, by name (``problem.friction``)
FRICTION_CHECKS = {"tresca": check_tresca, "coulomb": check_coulomb}


def check_two_bodies(case) -> None:
    """Both bodies of a two-body case: each a valid one-body case in its frame (the mirror
    solution satisfies the two-body conditions exactly when it does, ``problem.bodies``), and
    their Gamma_C one segment of the line y = 0 with the body above it."""
    from .bodies import lower_body
    lower = lower_body(case)
    validate_case(lower)
    extents = []
    for body in (case, lower):
        trace = contact_trace(coarse_mesh(body))
        ends = np.concatenate([trace.a, trace.b])
        if np.abs(ends[:, 1]).max() > 1e-12 or not np.allclose(trace.normals, [0.0, -1.0]):
            raise CaseError(f"case {case.name!r}: two bodies need Gamma_C on y = 0 below each body (in each body's frame)")
        extents.append((ends[:, 0].min(), ends[:, 0].max()))
    if not np.allclose(extents[0], extents[1], atol=1e-12):
        raise CaseError(f"case {case.name!r}: the two bodies' Gamma_C differ: {extents[0]} and {extents[1]}")
