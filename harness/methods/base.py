"""What a discretisation ("method") is to the harness, and the family the paper's models and
the P1 baseline belong to.

A method declares its finite element order, how it imposes the contact condition, the paper
or theorem it comes from, and, for a case of regularity nu, the H^1 rate its theory predicts
(``expected``). It solves one level of a study (``solve``) and returns what the study's rows,
the next level (nested iteration) and the report need (``LevelSolve``).
"""
from __future__ import annotations

from contextlib import nullcontext
from dataclasses import dataclass
from typing import Callable

import numpy as np

from ..errors import max_penetration
from ..models import ContactModel, contact_qp
from ..multigrid import nested_start
from ..solver import solve_contact_qp

# P1 on level l+1 has about the dofs of P2 on level l (the vertices of level l+1 are those of
# level l plus one per edge): a study gives order-1 methods one more level, so that every
# method ends at about the same number of dofs.
EXTRA_LEVELS = {1: 1, 2: 0}


@dataclass(frozen=True)
class Expectation:
    """The H^1 bound C h^rate |log h|^log_exponent a theory predicts, and which theory."""

    rate: float
    log_exponent: float
    reference: str


@dataclass
class LevelSolve:
    """One method on one level: the row's solver fields, u_h (NGSolve numbering of its space),
    its trace on Gamma_C, the multipliers on the constrained nodes, and what the next level
    starts from."""

    fields: dict
    u: np.ndarray
    trace_u: object
    solution: object
    carry: tuple


@dataclass(frozen=True)
class Method:
    name: str
    order: int
    contact: str                                  # how the contact condition is imposed
    reference: str                                # where the method comes from
    expected: Callable[[object], Expectation]     # case -> the rate its theory predicts

    @property
    def extra_levels(self) -> int:
        return EXTRA_LEVELS[self.order]

    def solve(self, case, problem, carry, multilevel, take_stiffness: bool = False, phases=None) -> LevelSolve:
        """Solve on ``problem`` (a ``discrete.DiscreteProblem`` of this method's order) from
        ``carry`` (what the coarser level's solve left, or None), on ``multilevel``'s hierarchy.
        ``take_stiffness``: this is the level's last method of its order and may take the
        stiffness matrix's memory. ``phases`` (``study.Phases``) times set-up and solve."""
        raise NotImplementedError


@dataclass(frozen=True)
class BoundConstrained(Method):
    """A cone of nodal functionals (``models.ContactModel``), solved exactly (KKT <= 1e-10) by
    the active set method with the truncated multigrid; nested iteration carries the coarser
    level's trace (active set prediction) and vertex values (CG start) to the next level."""

    cone: ContactModel = ContactModel()

    def solve(self, case, problem, carry, multilevel, take_stiffness: bool = False, phases=None) -> LevelSolve:
        timed = phases or (lambda phase: nullcontext())
        previous, coarse_vertex_values = carry or (None, None)
        with timed("setup"):
            qp = contact_qp(case, problem, self.cone, take_stiffness=take_stiffness)
            start = None
            if multilevel is not None and coarse_vertex_values is not None:
                start = nested_start(multilevel, coarse_vertex_values, problem)
            predicted = qp.predicted_active(previous)
        with timed("solve"):
            solution = solve_contact_qp(qp, predicted, multilevel=multilevel, start=start)
        u = qp.to_u(solution.z)
        trace_u = qp.trace_function(u, solution.active)
        fields = {
            "n_contact_constraints": len(qp.C),
            "max_penetration": max_penetration(case, problem.mesh, trace_u),
            "active_constraints": int(solution.active.sum()),
            "solver_iterations": solution.iterations,
            "kkt_residual": solution.kkt.residual,
            "solve_seconds": solution.seconds,
            "status": solution.status,
        }
        nv = multilevel.nvertices if multilevel is not None else problem.mesh.nv
        return LevelSolve(fields, u, trace_u, solution, (trace_u, u[:nv].copy()))


def paper_theorem(case) -> Expectation:
    """The rate the case declares from the paper's theorems (Theorems 4.1, 4.2, 5.1, 5.2,
    Remark 4.9): the same for both P2 models."""
    return Expectation(case.expected_rate, case.expected_log_exponent,
                       f"Belhachmi & Ben Belgacem 2003, {_theorem_label(case.theorem)}")


def _theorem_label(theorem: str) -> str:
    return theorem if theorem.lower().startswith(("remark", "thm", "theorem")) else f"Thm {theorem}"
