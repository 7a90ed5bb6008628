"""Quantities of interest of a discrete solution: what an engineer reads off a contact
computation, measured for every method from u_h alone (so for cases with and without u):

* ``force``: the total contact force int_{Gamma_C} lambda_h, lambda_h the discrete pressure
  (``errors.DiscretePressure``: the Riesz representative of a(u_h, .) - L(.) on Gamma_C). The
  integral is that functional applied to a function with trace 1, so it is the same number
  whether a method's pressure comes from the cones' multipliers, Nitsche's or the penalty's
  contact term: the force the solution exerts, by Green's formula int lambda v = a(u, v) - L(v);
* ``contact_measure``: the length (2D) or area (3D) of the contact zone, the set where the
  argument of the contact law lambda = [lambda - (c(u) - alpha) / eps]_+ is positive (Chouly &
  Hild's form of the Signorini conditions, SIAM J. Numer. Anal. 51 (2013) eq. (2.3); with
  eps = h / E, E the physics' modulus): for u it is exactly where lambda > 0 or the gap is
  closed, for u_h it needs no threshold (a cone's active vertices, a weak method's penetrating
  points and the mean model's points between its vertices all count), integrated by the
  pressure's Gauss rule; a transition point is found to within O(h);
* ``peak_pressure``: max over Gamma_C of lambda_h (at its Gauss points and the vertices);
* ``energy``: the strain energy a(u_h, u_h) / 2;
* ``penetration``: max over Gamma_C of (alpha - u_h)_+, the rows' ``max_penetration``
  (exact value 0 on every case: u is feasible).

On a friction case (``problem.friction``; the friction force lambda_h and the slip u_t,h of
``errors.DiscreteTraction``: u_h itself in the scalar model, u_h . tau in 2D elasticity, the
2-vector u_t in 3D), two more:

* ``slip_measure``: the length (3D: area) of the slip zone, by the device of the contact measure:
  Tresca's law in Chouly & Hild's form, lambda = P_s(lambda - u_t / eps) with P_s the projection
  onto [-s, s] (3D: the disc of radius s) and eps = h / E (the Nitsche form of the law of
  Chouly, J. Math. Anal. Appl. 411 (2014), as issue 74's notes state it; the paper not read here), and the zone is where
  the projection's argument lies outside the set, |lambda - (E / h) u_t| > s. For u it is exactly
  where u_t != 0: there lambda = -s u_t / |u_t|, so the argument has length s + (E / h)|u_t| > s;
  where u_t = 0, |lambda| <= s. The set {|lambda| = s} would be wrong: a stick point may carry the
  threshold force (tresca-r72's lambda = -s + |x|^3 reaches -s at the stick-slip point). For
  u_h it needs no threshold on u_h;
* ``stick_measure`` (Coulomb): the length (3D: area) of the stick zone, the contact zone less the
  slip zone, by the same rule (Cattaneo's 2c, Mindlin's pi c^2);
* ``tangential_force`` (Coulomb): Q = int_{Gamma_C} -lambda_t, the friction force the body exerts
  on the obstacle, positive in the sense of the applied shear (2D: signed along tau; 3D: the
  resultant's length), the same functional for every method as the force is;
* ``err_traction_prediction`` (Coulomb cases declaring ``predicted_traction``): the relative
  L2(Gamma_C) error of -lambda_t against the predicted shear traction at the row's P and Q
  (``traction_prediction``);
* ``stick_slip_point`` (2D): the position of the first stick-slip point from Gamma_C's start,
  found as the first change of state between consecutive Gauss points ordered along a flat
  Gamma_C (their midpoint: within O(h) of the transition); the position is the coordinate
  along tau = (-n_y, n_x), the x of a horizontal Gamma_C below the body, whose start is its
  left end. NaN where Gamma_C is all stick or all slip, or not flat. Under Coulomb a point out of
  contact neither sticks nor slips: the transition is sought among the points in contact (where
  the body separates first, Cattaneo's -a, is no stick-slip point; -c is).

The frictionless quantities on a friction case: ``force`` is the total flux int lambda_h, the
total friction force in the scalar model and the total normal reaction of the bilateral
contact in elasticity; ``energy`` is unchanged. The scalar model has no unilateral condition, so
its ``contact_measure``, ``peak_pressure`` (and the method's ``max_penetration``) are NaN, not
numbers of a contact that is not there; a bilateral elastic body is in contact on all of
Gamma_C by its condition, so its ``contact_measure`` is NaN, while the normal reaction's
largest value stays its ``peak_pressure``.

Every column comes from one ``Interface`` (the pressure, the gap, the law's 1 / eps, the friction
force and the slip at the pressure's Gauss points) by ``interface_columns``: one body's here
(``one_body_interface``), two bodies' from the jumps between them (``two_body_quantities``).

For a case with u the rows also carry each quantity's exact value (``exact_quantities``), from
the declared u on the level's mesh with rules far finer than the discrete ones (the graded rule
at singular points; the slip zone's and the stick-slip point's from the same rule): the rates stage fits each quantity's error and judges the Richardson
bands against it (``richardson``). The contact measure's and the peak pressure's exact values are
2D only (in 3D the transition curves cross the triangles and the largest pressure lies between
the points of any rule of the level's mesh: no rule of it resolves them to the accuracy an exact
value needs).
"""
from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import ngsolve as ngs
import numpy as np

from ..fem.contact_quadrature import contact_quadrature, exact_pressure
from ..fem.element_quadrature import singular_vertices
from ..mesh.points import evaluate
from .errors import CONTACT_ERROR_POINTS, DiscretePressure, DiscreteTraction, exact_friction, point_tangents

# quantity -> its column in results.csv (the penetration column predates the quantities)
QUANTITY_COLUMNS = {"force": "qoi_force", "contact_measure": "qoi_contact_measure", "peak_pressure": "qoi_peak_pressure",
                    "energy": "qoi_energy", "penetration": "max_penetration",
                    "slip_measure": "qoi_slip_measure", "stick_slip_point": "qoi_stick_slip_point"}
QUANTITY_MEANINGS = {
    "force": "the total contact force ∫_{Γ_C} λ_h",
    "contact_measure": "the length (3D: area) of the contact zone",
    "peak_pressure": "the largest contact pressure max λ_h",
    "energy": "the strain energy a(u_h, u_h)/2",
    "penetration": "the largest penetration max (α − u_h)_+ (exact: 0)",
    "slip_measure": "the length (3D: area) of the slip zone (friction cases)",
    "stick_slip_point": "the position along Γ_C of its first stick–slip point (2D friction cases)",
}
# the quantities of friction cases only (NaN on a frictionless one)
FRICTION_QUANTITIES = ("slip_measure", "stick_slip_point")
# the quantities a friction case's model leaves without meaning (module docstring): the scalar
# model has no unilateral condition, a bilateral elastic body no contact zone of its own
MEANINGLESS = {False: ("qoi_contact_measure", "qoi_peak_pressure"), True: ("qoi_contact_measure",)}
# The exact pressure is unbounded where its largest value on the graded rule (down to 2^-30 h
# from a singular point) exceeds this many times its largest at the pressure's Gauss points: r^{-1/2} at a
# contact/Neumann junction gives 2^15 and more, a bounded pressure about 1
UNBOUNDED_FACTOR = 10.0
# Gauss points per contact edge of the exact values (graded at singular points): the pressure's
# own rule (degree 15 on the edges away from singular points)
EXACT_POINTS = CONTACT_ERROR_POINTS


def exact_column(column: str) -> str:
    return f"{column}_exact"


@dataclass(frozen=True)
class Interface:
    """What the quantities on Gamma_C are read from, at the points of the pressure's Gauss rule
    ``q`` (``errors.DiscretePressure.quadrature``): the discrete pressure there and at the
    vertices, the gap c(u_h) - alpha (two bodies: the opening less 2 alpha,
    ``two_body_quantities``), the contact law's 1 / eps (one body: E / h), and on a friction
    case the friction force and the slip over the last load step, each (q, d - 1)."""

    q: object
    pressure: np.ndarray
    vertices: np.ndarray
    gap: np.ndarray
    stiffness: np.ndarray
    force: np.ndarray | None = None
    slip: np.ndarray | None = None


def quantities(case, problem, u: np.ndarray, previous: np.ndarray | None = None) -> dict:
    """The quantities of ``u`` (a solution on ``problem``), as results.csv columns; the
    penetration is the method's own column. ``previous``: u_h at the end of the load step before
    the last (``problem.friction.LoadHistory``), from which the last step's slip is measured."""
    return interface_columns(case, problem, one_body_interface(case, problem, u, previous), strain_energy(problem, u))


def one_body_interface(case, problem, u: np.ndarray, previous: np.ndarray | None = None) -> Interface:
    """``Interface`` of one body's u_h against its obstacle: c(u_h) - alpha and its own slip u_t,h."""
    pressure = DiscretePressure.of(problem)
    coefficients = pressure.coefficients(u)
    q = pressure.quadrature
    gap = q.T @ u - obstacle_at(case, problem, q.points)
    interface = Interface(q, pressure.at_points(coefficients), coefficients[:len(problem.vertex_dofs)],   # vertex dofs are nodal values
                          gap, problem.physics.modulus / q.h)
    if not case.frictional:
        return interface
    traction = DiscreteTraction.of(problem)
    force, slip = traction.at_points(u)
    if previous is not None:
        slip = slip - traction.at_points(previous)[1]
    return dataclasses.replace(interface, force=force, slip=slip)


def interface_columns(case, problem, interface: Interface, energy: float) -> dict:
    """The columns of ``interface`` (one body's or two bodies', ``Interface``) with the strain
    energy ``energy``: the force, the contact measure, the peak pressure and, on a friction
    case, the slip zone's (``friction_quantities``) and Coulomb's Q (``coulomb_quantities``).
    ``problem``: the body whose rule ``interface.q`` is (its mesh holds a Tresca threshold)."""
    q, at_points = interface.q, interface.pressure
    contact = contact_zone(at_points, interface.gap, interface.stiffness)
    columns = {"qoi_force": float(q.weights @ at_points),
               "qoi_contact_measure": float(q.weights @ contact),
               "qoi_peak_pressure": float(max(at_points.max(initial=-np.inf), interface.vertices.max(initial=-np.inf))),
               "qoi_energy": energy}
    if not case.frictional:
        return columns
    columns |= friction_quantities(case, problem, q, interface.force, interface.slip, pressure=at_points, contact=contact,
                                   stiffness=interface.stiffness) | meaningless(case)
    if case.friction.name == "coulomb":
        columns |= coulomb_quantities(case, q, interface.force, columns)
    return columns


def shear(q, force: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The friction force the body exerts on the obstacle, -lambda_t (the sense of the applied
    shear), at the points of ``q`` as (q, d - 1), and its resultant's unit direction in the
    tangent frame (2D: tau itself, so that Q is signed along tau)."""
    sheared = -force
    if sheared.shape[1] == 1:
        return sheared, np.ones(1)
    total = q.weights @ sheared
    length = np.linalg.norm(total)
    return sheared, total / length if length > 0 else np.eye(sheared.shape[1])[0]


def coulomb_quantities(case, q, force: np.ndarray, columns: dict) -> dict:
    """A Coulomb case's tangential force Q = int_{Gamma_C} -lambda_t (2D: along tau, the x of a
    horizontal Gamma_C below the body; 3D: the resultant's length) and, where the case declares
    a predicted shear traction (``Case.predicted_traction``), the relative L2(Gamma_C) error of
    -lambda_t against it at the row's P and Q (``traction_prediction``)."""
    sheared, direction = shear(q, force)
    tangential = float((q.weights @ sheared) @ direction)
    out = {"qoi_tangential_force": tangential, "err_traction_prediction": float("nan")}
    if case.predicted_traction is not None:
        out["err_traction_prediction"] = traction_prediction(case, q, sheared, direction, columns["qoi_force"], tangential)
    return out


def traction_prediction(case, q, sheared: np.ndarray, direction: np.ndarray, force: float, tangential: float) -> float:
    """||t_h - q e||_{L2(Gamma_C)} / ||q||_{L2(Gamma_C)}: t_h = -lambda_t the discrete shear at the
    pressure's Gauss points, q the case's predicted traction at the computed P and Q, e the
    resultant's direction (a shear across it, as Mindlin's slip annulus has, counts as error).
    The rule's points fall on either side of the predicted kinks at c and a: the norms are
    integrated to O(h^{3/2}), below the discretisation error they measure."""
    two_d = sheared.shape[1] == 1
    s = q.points @ point_tangents(q.normals[:1])[0, 0] if two_d else q.points
    predicted = np.asarray(case.predicted_traction(s, force, tangential), float)
    difference = sheared - predicted[:, None] * direction[None, :]
    norm = float(np.sqrt(q.weights @ predicted**2))
    return float(np.sqrt(q.weights @ np.sum(difference**2, axis=1))) / norm if norm > 0 else float("nan")


def meaningless(case, exact: bool = False) -> dict:
    """NaN for the frictionless quantities without meaning on a Tresca case (``MEANINGLESS``;
    Coulomb's contact is unilateral: every frictionless quantity keeps its meaning)."""
    if case.friction.name != "tresca":
        return {}
    return {exact_column(c) if exact else c: float("nan") for c in MEANINGLESS[case.physics.rotated_frame]}


def friction_threshold(case, problem, q, pressure: np.ndarray) -> np.ndarray:
    """The friction threshold at the points of ``q``: Tresca's s, or Coulomb's mu_F times the
    contact pressure ``pressure`` (its positive part: no threshold where the body separates)."""
    if case.friction.name == "coulomb":
        return case.friction.coefficient * np.maximum(pressure, 0.0)
    return evaluate(case.friction.threshold_function, problem.mesh, q.points)


def friction_quantities(case, problem, q, force: np.ndarray, slip: np.ndarray, exact: bool = False,
                        pressure: np.ndarray | None = None, contact: np.ndarray | None = None,
                        stiffness: np.ndarray | None = None) -> dict:
    """The slip zone's measure and the first stick-slip point of a friction force ``force`` and a
    slip ``slip`` ((q, d - 1) at the points of the rule ``q``; for Coulomb the ``pressure``
    there, its threshold's, and the ``contact`` zone, outside which a point neither sticks nor
    slips): the module docstring's, with the law's 1 / eps ``stiffness`` (by default E / h)."""
    stiffness = problem.physics.modulus / q.h if stiffness is None else stiffness
    zone = slip_zone(force, slip, stiffness, friction_threshold(case, problem, q, pressure))
    coulomb = case.friction.name == "coulomb"
    if coulomb:
        zone &= contact
    two_d = problem.trace.faces is None
    columns = {"qoi_slip_measure": float(q.weights @ zone),
               "qoi_stick_slip_point": first_transition(q, zone, contact if coulomb else None) if two_d else float("nan")}
    if coulomb and not exact:      # the stick zone: in contact, not slipping
        columns["qoi_stick_measure"] = float(q.weights @ (contact & ~zone))
    return {exact_column(c): v for c, v in columns.items()} if exact else columns


def slip_zone(force: np.ndarray, slip: np.ndarray, stiffness: np.ndarray, threshold: np.ndarray) -> np.ndarray:
    """At each point: does Tresca's projection P_s(lambda - u_t / eps) act, i.e.
    |lambda - u_t / eps| > s (the module docstring; ``stiffness`` = 1 / eps, E / h for one body)?"""
    argument = force - stiffness[:, None] * slip
    return np.linalg.norm(argument, axis=1) > threshold


def first_transition(q, zone: np.ndarray, among: np.ndarray | None = None) -> float:
    """The midpoint of the first two consecutive points of ``q`` (ordered along a flat 2D
    Gamma_C, by the coordinate along tau = (-n_y, n_x)) whose states ``zone`` differ, counting
    only the points ``among`` (Coulomb: those in contact; None: all); NaN where none do or
    Gamma_C is not flat."""
    if not len(zone) or np.abs(q.normals - q.normals[0]).max() > 1e-12:
        return float("nan")
    position = q.points @ point_tangents(q.normals[:1])[0, 0]
    order = np.argsort(position, kind="stable")
    if among is not None:
        order = order[among[order]]
    changes = np.flatnonzero(zone[order][1:] != zone[order][:-1])
    if not len(changes):
        return float("nan")
    i = changes[0]
    return float(0.5 * (position[order[i]] + position[order[i + 1]]))


def strain_energy(problem, u: np.ndarray) -> float:
    """a(u_h, u_h) / 2, integrated exactly on straight elements (the gradients are polynomials of
    degree k - 1, the energy density of degree 2k - 2)."""
    gfu = problem.gridfunction(u)
    order = 2 * (problem.order - 1)
    return 0.5 * float(ngs.Integrate(problem.physics.energy_density(ngs.Grad(gfu)), problem.mesh, order=order))


def obstacle_at(case, problem, points: np.ndarray) -> np.ndarray | float:
    return evaluate(case.obstacle, problem.mesh, points) if case.obstacle is not None else 0.0


def contact_zone(pressure: np.ndarray, gap: np.ndarray, stiffness: np.ndarray) -> np.ndarray:
    """At each point: is the contact law's argument lambda - (c(u) - alpha) / eps positive
    (module docstring; ``stiffness`` = 1 / eps, E / h for one body)?"""
    return pressure - stiffness * gap > 0


def exact_quantities(case, problem) -> dict:
    """The exact value of each quantity on Gamma_C from the declared u, on ``problem``'s mesh
    (the same for every order of a level: a caller keeps it per level, ``study.chain.one_body``); the
    exact energy comes with the volume errors (``errors.ExactErrors.end_level``)."""
    two_d = problem.trace.faces is None
    q = (contact_quadrature(problem, EXACT_POINTS, graded_at=singular_vertices(case, problem.mesh)) if two_d
         else DiscretePressure.of(problem).quadrature)
    pressure = exact_pressure(case, problem, q)
    gap = case.physics.contact_value(case, problem.mesh, q.points, q.normals) - obstacle_at(case, problem, q.points)
    contact = contact_zone(pressure, gap, case.physics.modulus / q.h)
    columns = {exact_column("qoi_force"): float(q.weights @ pressure),
               exact_column("qoi_contact_measure"): float(q.weights @ contact) if two_d else float("nan"),
               exact_column("qoi_peak_pressure"): exact_peak(case, problem, pressure) if two_d else float("nan")}
    if not case.frictional:
        return columns
    friction = friction_quantities(case, problem, q, *exact_friction(case, problem, q), exact=True, pressure=pressure,
                                   contact=contact)
    if not two_d:       # the slip zone's border crosses the triangles: no rule of the mesh resolves it
        friction = dict.fromkeys(friction, float("nan"))
    return columns | friction | meaningless(case, exact=True)


def exact_peak(case, problem, graded: np.ndarray) -> float:
    """max over Gamma_C of the exact pressure: over the graded rule's points ``graded`` and the
    edges' ends, or infinity where the pressure grows without bound toward a singular point
    (``UNBOUNDED_FACTOR``)."""
    trace = problem.trace
    regular = exact_pressure(case, problem, DiscretePressure.of(problem).quadrature)      # Gauss points, no grading
    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):    # nan, inf: at a singular vertex
        ends = [case.physics.pressure(case, problem.mesh, points, trace.normals) for points in (trace.a, trace.b)]
    bounded = np.nanmax(np.concatenate([regular, *ends]))
    largest = np.nanmax(graded)
    return float("inf") if largest > UNBOUNDED_FACTOR * abs(bounded) else float(max(bounded, largest))
