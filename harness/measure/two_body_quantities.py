"""Quantities of interest of a two-body solution (``fem.two_body.TwoBodyProblem``), measured
from u_h alone, the same for every method, as the one-body ones are (``quantities``, whose
module docstring defines each): the interface's state is read from the *pointwise* jumps
between the bodies, not from any method's projection of them.

Both bodies' frames have Gamma_C on y = 0 with n = -e_y (``problem.bodies``: the lower body
solves the upper body's problem in its mirrored frame (x, y') = (x, -y)), and the mirror map
fixes Gamma_C's points. So at each Gauss point (x, 0) of the upper (slave) body's pressure rule
(``errors.DiscretePressure.quadrature``) both bodies' traces are evaluated, the lower body's on
its own mesh (its trace elements and basis, ``fem.mortar.TraceElements``):

* the opening less the gap, [c_h] - 2 alpha = (c_1 - alpha) + (c_2 - alpha), c_k each body's
  contact variable in its frame: the mortar rows impose int psi_i (c_1 + c_2) >= int psi_i
  2 alpha (``fem.mortar.mortar_coupling``);
* the slip over the last load step, the tangential jump less the previous step's: in
  elasticity [u_t] = t_1 - t_2, t_k = u_k . tau with tau = e_x in both frames (the mirror map
  keeps u_x, so t_2 is the lower body's u_x: t_1 - t_2 is the upper body's motion relative to
  the lower one, what the one-body slip u_t is relative to the rigid obstacle); in the scalar
  model [u] = u_1 - u_2 = c_1 + c_2 (the lower body's variable is -u_2, ``problem.bodies``);
* the pressure, its vertex values, the friction force and Q: the upper body's
  (``errors.DiscretePressure``, ``errors.DiscreteTraction``; the lower body's balance them);
* the contact law's eps (the contact and slip zones' device, Chouly & Hild's form): the two
  bodies' compliances in series, eps = h_1 / E_1 + h_2 / E_2, h_k the length of body k's trace
  edge holding the point. For the exact solution any eps > 0 gives the same zones; for u_h on
  a matching mirror pair (h_1 = h_2, c_2 = c_1, t_2 = -t_1) the argument
  lambda - [c_h - 2 alpha] / eps = lambda - (c_1 - alpha) E / h is the one body's, so the two-body
  columns are the one-body ones (tests/test_two_body_quantities.py).

On non-matching meshes a slave edge whose nodes all stick has zero *dual projection* of the
slip (the method's variables), not zero pointwise slip: the master's trace is not in the slave's
space, and what remains is the master's trace less its projection. The device reads it as the
slip it is.

The exact values (``two_body_exact_quantities``) of a two-body case with u (a mirror pair): the
opening is twice the upper body's gap and the pressure the same, so the contact zone, the
force and the peak pressure are the upper body's one-body exact values; the scalar model's jump
is 2 u, whose slip zone is u's, the upper body's exact Tresca values. Under Coulomb the mirror
pair's tangential jump is 0 and its friction force too (mirroring flips sigma_xy's sign, action
and reaction need the same): no slip zone and no stick-slip point, nothing a measured zone
converges to. Those exact columns are NaN.
"""
from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from ..fem.mortar import trace_at
from .errors import DiscreteTraction
from .quantities import (
    Interface,
    exact_column,
    exact_quantities,
    interface_columns,
    obstacle_at,
    one_body_interface,
    strain_energy,
)

# the columns of a Coulomb mirror pair whose exact values have no meaning (module docstring)
COULOMB_EXACT_NAN = ("qoi_slip_measure", "qoi_stick_slip_point")


@dataclass(frozen=True)
class MasterTrace:
    """The lower (master) body's trace at points (x, 0) of Gamma_C: its trace element of each
    point (``fem.mortar.TraceElements``), the element's contact dofs and basis there, and the
    element's length h_2."""

    problem: object
    dofs: np.ndarray        # (q, k + 1) the contact variable's dofs of each point's element
    basis: np.ndarray       # (q, k + 1) their trace basis at the point
    h: np.ndarray           # (q,)

    @classmethod
    def at(cls, problem, x: np.ndarray) -> "MasterTrace":
        return cls(problem, *trace_at(problem, x))

    def values(self, u: np.ndarray, tangential: bool = False) -> np.ndarray:
        """The contact variable of ``u`` (the lower body's dofs) at the points; ``tangential``
        (elasticity): u . tau, whose block comes one before the normal one
        (``fem.assembly.DiscreteProblem.tangential_dofs``)."""
        dofs = self.dofs - self.problem.ndof // 2 if tangential else self.dofs
        return np.einsum("qj,qj->q", self.basis, u[dofs])


def two_body_interface(bodies: tuple, problem, u: np.ndarray, previous: np.ndarray | None = None) -> Interface:
    """``quantities.Interface`` of a two-body u_h (joint dofs; ``previous`` the previous load
    step's) at the upper body's Gauss points: the opening and the slip are the jumps between
    the bodies (module docstring)."""
    upper_case, lower_case = bodies
    u_1, u_2 = problem.split(u)
    own = one_body_interface(upper_case, problem.upper, u_1)
    q = own.q
    master = MasterTrace.at(problem.lower, q.points[:, 0])
    gap = own.gap + (master.values(u_2) - obstacle_at(lower_case, problem.lower, q.points))
    stiffness = 1.0 / (q.h / problem.upper.physics.modulus + master.h / problem.lower.physics.modulus)
    interface = dataclasses.replace(own, gap=gap, stiffness=stiffness)
    if not upper_case.frictional:
        return interface
    slip = tangential_jump(problem, master, u, own.slip)
    if previous is not None:
        slip = slip - tangential_jump(problem, master, previous)
    return dataclasses.replace(interface, slip=slip)


def tangential_jump(problem, master: MasterTrace, u: np.ndarray, own: np.ndarray | None = None) -> np.ndarray:
    """The jump the friction acts on at the upper body's Gauss points, (q, 1): t_1 - t_2 in
    elasticity, c_1 + c_2 in the scalar model (module docstring); ``own``: the upper body's
    slip variable t_1 (``errors.DiscreteTraction``), if already evaluated."""
    u_1, u_2 = problem.split(u)
    own = DiscreteTraction.of(problem.upper).at_points(u_1)[1] if own is None else own
    if problem.upper.physics.rotated_frame:
        return own - master.values(u_2, tangential=True)[:, None]
    return own + master.values(u_2)[:, None]


def two_body_quantities(bodies: tuple, problem, u: np.ndarray, previous: np.ndarray | None = None) -> dict:
    """The columns of a two-body u_h (``quantities.interface_columns`` of ``two_body_interface``),
    with the strain energy of both bodies."""
    u_1, u_2 = problem.split(u)
    energy = strain_energy(problem.upper, u_1) + strain_energy(problem.lower, u_2)
    return interface_columns(bodies[0], problem.upper, two_body_interface(bodies, problem, u, previous), energy)


def two_body_exact_quantities(bodies: tuple, problem) -> dict:
    """The exact columns of a mirror pair (module docstring): the upper body's one-body exact
    values, NaN for Coulomb's slip zone and stick-slip point (its energy is both bodies',
    ``study.chain.two_body.combine``)."""
    case = bodies[0]
    columns = exact_quantities(case, problem.upper)
    if case.frictional and case.friction.name == "coulomb":
        columns |= {exact_column(c): float("nan") for c in COULOMB_EXACT_NAN}
    return columns
