"""Errors against a reference per level: graded and adaptive chains of a case without u.

On uniform meshes every method is measured against one reference, the nodal P2 solution k levels
finer than P2's finest studied level (``reference.ReferenceErrors``). A graded or adaptive chain
has no such nested uniform hierarchy above its levels (its meshes are bisections, and an
adaptive chain's next mesh is not known before its solves), so each of its levels gets its
own reference by the same rule: the reference method (``reference_method``: nodal P2) solved on
the level's mesh refined uniformly so that the reference has 4^k times the level's dofs (k = the
case's ``reference_levels``, as on uniform meshes, where the one reference has 4^k times the
dofs of every method's finest level): k refinements of a P2 level, k - 1 of a P1 one (P2 has
about 4 times P1's dofs on one mesh; at least one refinement), and every method's u_h of the
level measured against it.

How, per level, after every method has solved it (``end_level``):

1. a copy of the level's netgen mesh (``netgen.meshing.Mesh.Copy``: the chain's own mesh, which the next
   graded or adaptive level bisects in place, is not touched), with the same vertex numbers
   (checked, with the coordinates);
2. red refinement of the copy k (P1: k - 1) times (netgen's ``Refine``, as ``mesh.levels.mesh_hierarchy``):
   every refined copy is nested in the level's mesh, so every u_h of the level is exactly a
   function of the reference space, through the hierarchical-basis prolongation of
   ``reference.prolongation`` (the level's numbering is read on the chain's mesh, whose P2 dofs
   u_h is written in; the copies' parents from their cells);
3. the reference method solved on the copy and its k refinements by nested iteration, on the
   multigrid hierarchy of those meshes (where the physics has one), as a uniform reference
   chain is solved; the last solve is the reference, with 4^k times the dofs of the level
   (k = 2: 16);
4. ``reference.ReferenceErrors`` on that little chain (the level as its studied level 0, the
   reference on the last) completes every row of the level: the same norms, exact matrix norms
   of u_R - P u_h, as on uniform meshes; then the reference columns and the effectivity
   estimator / err_energy against the reference.

Galerkin orthogonality with nested spaces (``reference`` module): against a reference k levels
finer the energy error of a P2 method converging like h^p near its worst elements is
underestimated by about sqrt(1 - 4^{-pk}); per level, not only on the finest (a uniform
reference is more than k levels finer than the coarser studied levels).

Cost: a level's reference chain solves about (1 + 1/4 + 1/16) 16 = 21 times the level's dofs
(k = 2), so an adaptive chain's references cost a few times its finest reference, which has
about the dofs of the uniform chain's reference (the chain stops at the uniform budget of
elements).
"""
from __future__ import annotations

import contextlib
import time

import ngsolve as ngs
import numpy as np

from ..fem.assembly import discretise
from ..fem.element_quadrature import ElementQuadrature
from ..mesh.points import coordinates
from ..solvers.multigrid import Multilevel
from .reference import ReferenceErrors


def refinable_copy(mesh: ngs.Mesh) -> ngs.Mesh:
    """A copy of ``mesh`` to refine without touching it: the same vertices, numbered alike
    (RuntimeError otherwise: u_h's vertex dofs would not be the copy's)."""
    copy = ngs.Mesh(mesh.ngmesh.Copy())
    if copy.nv != mesh.nv or copy.ne != mesh.ne or not np.array_equal(coordinates(copy), coordinates(mesh)):
        raise RuntimeError("the copy of the level's mesh numbers its vertices differently")
    return copy


class LevelReferenceErrors:
    """The error columns of a graded or adaptive chain of a case without u: each level against
    the reference method's solution on the level's mesh refined uniformly ``refinements`` times,
    4^k times the level's dofs, k = ``case.reference_levels`` (module docstring). The same calls as ``reference.ReferenceErrors`` (the study's level
    loop, ``study.chain.walk``); every row is complete at the end of its level, so nothing is carried
    across levels (``state_of``: nothing to checkpoint).

    ``orders``: the chain's methods' finite element orders by name; ``reference``: the method
    that solves the references (``reference.reference_method``); ``threads(size)``: a context
    for work of ``size`` scalar P2 dofs (``study.execution.threads.level``), the reference's solves run
    under it."""

    def __init__(self, case, orders: dict[str, int], reference, phases=None, threads=None):
        self.case, self.reference, self.phases = case, reference, phases
        # k refinements of a chain with P2 methods; k - 1 (at least one) of one of P1 methods alone
        k = case.reference_levels
        self.refinements = k if max(orders.values()) > 1 else max(1, k - 1)
        self.studied = {name: 1 for name in orders} | {reference.name: 1 if reference.name in orders else 0}
        self.orders = dict(orders) | {reference.name: reference.order}
        self.threads = threads or (lambda size: contextlib.nullcontext())
        self.errors: ReferenceErrors | None = None
        self.mesh, self.level, self.rows = None, None, []
        # per level: (level, the reference's ndof, its seconds: meshes, solves and measurement)
        self.costs: list[tuple[int, int, float]] = []
        self.reference_solve_seconds = 0.0       # the reference solves' own seconds (``solve_seconds``)

    def _phase(self):
        return self.phases("errors") if self.phases is not None else contextlib.nullcontext()

    def begin_level(self, level: int, mesh: ngs.Mesh, problems: dict, quadrature=None, multilevel=None) -> None:
        """The level's numbering and discrete pressures, as the studied level 0 of its reference chain."""
        with self._phase():
            self.errors = ReferenceErrors(self.studied, self.orders, self.reference.name, self.refinements)
            self.errors.begin_level(0, mesh, problems)
            self.mesh, self.level, self.rows = mesh, level, []

    def solved(self, method, level: int, problem, u: np.ndarray, row: dict | None) -> dict:
        if row is not None:
            self.rows.append(row)
        return self.errors.solved(method, 0, problem, u, row)

    def end_level(self) -> None:
        """After every solve of the level: its reference, solved and measured against."""
        if self.errors is None or not self.rows:
            return
        clock = time.perf_counter()
        ndof, fields = self._solve_reference()
        self.errors.end_level()
        for row in self.rows:
            row.update({"reference_level": self.level + self.refinements, "reference_ndof": ndof,
                        "reference_method": self.reference.name, "reference_kkt_residual": fields["kkt_residual"],
                        "reference_status": fields["status"], "effectivity": row["estimator"] / row["err_energy"]})
        self.costs.append((self.level, ndof, time.perf_counter() - clock))
        self.errors, self.mesh, self.rows = None, None, []

    def _solve_reference(self) -> tuple[int, dict]:
        """The reference chain of the level: its mesh copied, refined ``refinements`` times, the
        reference method solved on each by nested iteration; the last solve handed to ``errors``.
        (ndof, fields) of that solve."""
        case, errors = self.case, self.errors
        mesh = refinable_copy(self.mesh)
        last = self.refinements
        with self.threads(4**last * (mesh.nv + mesh.nedge)):
            multilevel = Multilevel(mesh, case.physics) if case.physics.multigrid else None
            carry = None
            for k in range(last + 1):
                if k:
                    mesh.ngmesh.Refine()
                    multilevel = multilevel.refined(mesh) if multilevel is not None else None
                    if k < last:
                        errors.skip_level(k, mesh)
                problem = discretise(case, mesh, self.reference.order, ElementQuadrature.of(case, mesh))
                if k == last:
                    # before the solve takes the stiffness matrix (the reference's norms copy it)
                    errors.begin_level(k, mesh, {self.reference.order: problem})
                solve = self.reference.solve(case, problem, carry, multilevel, take_stiffness=True)
                carry = solve.carry
                self.reference_solve_seconds += solve.fields["solve_seconds"]
            errors.solved(self.reference, last, problem, solve.u, None)
        return problem.ndof, solve.fields

    def skip_level(self, level: int, mesh) -> None:
        """A level no method solves: nothing to measure (no level waits for a later reference)."""

    def state_of(self, method_name: str) -> list:
        return []

    def restore(self, method_name: str, state: list, rows: list[dict]) -> None:
        pass
