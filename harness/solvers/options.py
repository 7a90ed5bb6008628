"""The solvers' settings as data: tolerances, the gains of the loose (inexact) solves, and
iteration caps, one frozen value passed from a method (``methods.method.Method.solver``) down to
every solver it calls. The defaults are the harness's; each is explained where it is used
(named in its comment)."""
from __future__ import annotations

import math
from dataclasses import dataclass, field, fields


@dataclass(frozen=True)
class SolverOptions:
    # the relative KKT residual of the active set methods and the relative residual of Newton
    # (``pdas.KKT``, ``newton``)
    tolerance: float = 1e-10
    # linear solves go this fraction of ``tolerance`` deep, so that the stationarity they leave
    # never decides the KKT check (``pdas.primal_dual_active_set``, ``newton``)
    linear_depth: float = 0.1
    # a stationarity residual this small relative to ||K|| ||z|| + ||b|| is round-off
    # (``pdas.KKT.converged``; Newton's backward error alike)
    roundoff_backward_error: float = 1e-13
    # the forcing term: a set that is new is solved to this fraction of the current residual,
    # when that is at least ``loose_gain`` times shallower than the full depth (the CG iterations
    # it saves outweigh the extra step it may cost; ``pdas.loose_depth``)
    forcing: float = 1e-3
    loose_gain: float = 1e3
    # the general-constraint solver's gain: its iterative system's new set is solved to
    # ``forcing`` times the current residual whenever that is shallower than the full depth (the
    # bound solver asks 3 decades, ``loose_gain``): there a set costs an exact factorisation of
    # Gamma_C's block (``projected_multigrid``), and a full-depth solve of a set that then changes is
    # wasted; both reach the same KKT point (``python -m harness bench --only 3d`` counts the sets
    # and CG iterations of `mean` on transition-line-3d)
    loose_gain_general: float = 1.0
    # a pin set needing more new bordered columns is refactorised (``bound_constraints.FactorisedSystem``):
    # ~ the cost of a factorisation in solves, at 1e5-1e6 dofs
    refactor_above: int = 24
    # two bodies: the dual mortar QP of this many dofs (both bodies) or more is solved on their
    # coupled multigrid (``two_body_multigrid``), a smaller one on sparse Cholesky, which is as fast
    # there (measured, 0.10.2: the same time at 8e3 dofs, multigrid 3 times faster at 3e4 and
    # 10 times at 2e6; ``python -m harness bench --only mortar`` times both)
    mortar_multigrid_from: int = 20_000
    # the saddle systems' regularisation, times the block's scale (``general_constraints``)
    regularisation: float = 1e-14
    # steps of iterative refinement of each saddle solve (``general_constraints.SaddleSystem``)
    refinement_steps: int = 2
    # the shift of B B^T and the refinement steps of its solves (``row_projection.RowProjection``)
    projection_shift: float = 1e-10
    projection_refinements: int = 2
    # iteration caps: active sets of the bound solver, of the general-constraint solver, Newton
    # steps, steps without a new best residual before Newton stops as stalled (``newton``), and
    # CG iterations of one linear solve (``multigrid.pcg``)
    active_set_iterations: int = field(default=500, metadata={"least": 1})
    general_iterations: int = field(default=200, metadata={"least": 1})
    newton_iterations: int = 60
    stall_steps: int = 12
    cg_iterations: int = 500

    def __post_init__(self):
        for item in fields(self):
            value = getattr(self, item.name)
            if isinstance(item.default, int):
                _check_count(item.name, value, item.metadata.get("least", 0))
            else:
                _check_number(item.name, value)
                object.__setattr__(self, item.name, float(value))     # 0 and 0.0: one value, one repr

    def as_dict(self) -> dict:
        """Every setting by name, as a plain float or int (for provenance)."""
        return {item.name: type(item.default)(getattr(self, item.name)) for item in fields(self)}


def _check_count(name: str, value, least: int) -> None:
    """A count is an integer >= ``least`` (1 for the active set loops, which report on their
    last iterate; 0 elsewhere: e.g. ``refactor_above`` = 0 refactorises at every set)."""
    if isinstance(value, bool) or not isinstance(value, int) or value < least:
        raise ValueError(f"solver option {name} must be an integer >= {least}, got {value!r}")


def _check_number(name: str, value) -> None:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not (math.isfinite(value) and value >= 0):
        raise ValueError(f"solver option {name} must be a finite non-negative number, got {value!r}")
