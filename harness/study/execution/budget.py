"""What a study will cost, known before it starts: the size of every level from the coarse mesh
alone, and from it each job's peak memory and time, with per-triangle and per-dof figures
fitted to runs of this harness (``PEAK_*``, ``SECONDS_*``). A study whose largest job would not
fit in the memory of the machine (or of a Dask worker) is refused before anything is allocated.
"""
from __future__ import annotations

import os
from dataclasses import dataclass

from ...mesh.levels import coarse_mesh
from ...problem.bodies import lower_body
from ...solvers.krylov import KRYLOV_BYTES_PER_DOF
from ..chain.rows import study_levels
from ..chain.run import chain_levels, chain_methods, is_reference

MB = 2.0**20

# Peak resident memory of a job, in bytes:
#   PEAK_BASE + PEAK_PER_TRIANGLE * triangles of its finest mesh
#             + PEAK_PER_DOF * dofs of each order's finest problem (a job of P1 and P2 methods holds both)
#             + PEAK_PER_REFERENCE_DOF * the same again when errors are measured against a
#               reference (its norm matrices, the prolongations, the kept solutions).
# A least-squares fit of peak RSS (2 cores) over transition-r32 with 6 and 7 levels (nodal
# alone, p1 alone, all methods in one process) and smooth-obstacle with 6 (nodal, p1, all),
# rounded up so that every one of those estimates is at or above its peak; the reference term
# also covers smooth-obstacle with 6 and 7 levels, every method measured against nodal's one
# reference. The finest mesh dominates: a P1 job holds a mesh 4 times as fine as a P2 job with
# as many dofs. (``python -m harness bench --only report`` reports the peaks of a report.)
PEAK_BASE = 280 * MB
PEAK_PER_TRIANGLE = 550.0
PEAK_PER_DOF = 250.0
PEAK_PER_REFERENCE_DOF = 620.0
# 3D vector P2 couples each dof with about 100 others (scalar 2D P2: 12): its matrices and the
# vector multigrid's levels hold more per dof. Fitted to elastic-transition-3d on 4 levels (every
# cone and p1 in one process, 2 cores): the bytes per dof beside the terms above, rounded up.
# 2D vector P2 (plane strain), fitted to the elastic reference case hertz-line (nodal, p1 and
# both; 3, 4 and 5 levels with its reference level; one thread), whose peaks the scalar figure
# underestimates: the bytes per dof beside the reference's, rounded up.
PEAK_PER_DOF_BY_KIND = {(3, "elasticity"): 1150.0, (2, "elasticity"): 400.0}
# Two bodies (the mortar's interface operator, the coupled multigrid's levels, Coulomb's load
# steps): the bytes per dof beside the terms above, fitted to cattaneo-two-body-q03 and -q07 on
# the fine profile's 5 levels with their reference (mortar-nodal and mortar-p1 in one process,
# peaks 3.51 and 3.57 GB of 2^30 bytes), rounded up; a frictionless pair is overestimated, on the safe side.
PEAK_PER_TWO_BODY_DOF = 400.0
# Coulomb friction on one body (its nonsymmetric Newton systems go to restarted GMRES,
# ``solvers.krylov``): the basis at full length, KRYLOV_BYTES_PER_DOF (1.6 kB) per dof. Tresca's
# systems are symmetric (CG), and two bodies' Coulomb is a fixed point over symmetric Tresca
# problems (``solvers.coulomb_cones``): neither builds it.
# Seconds of a job, for the ETA's weights, the order in which jobs are submitted and the estimate
# a refusal prints. Each level costs its shared work (mesh refinement, the multigrid's P1
# hierarchy, assembly, best approximation, errors: SHARED_SECONDS_PER_ELEMENT x its elements,
# spread over the methods solving it) and each method's solve (SOLVE_SECONDS_PER_DOF x its
# dofs). Fitted (least squares, one figure per group) to the profile of one default report in
# one process on 2 cores (`bench --only report` writes it); the report's parameter sweeps,
# whose Nitsche runs past theta = 1's coercivity bound take many Newton steps with an LU
# factorisation each, have their own figure (``SWEEP_SECONDS_PER_DOF``).
# 3D elasticity (by the vector multigrid): fitted to elastic-transition-3d's studies on 3 levels
# (one thread) and on 4.
SHARED_SECONDS_PER_ELEMENT = {(2, "scalar"): 6.2e-6, (2, "elasticity"): 1.8e-5, (3, "scalar"): 1.2e-5,
                              (3, "elasticity"): 1.1e-4}
# Keyed by the cost model a method declares (``methods.Method.cost_model``: "active-set", the cones' and
# the mortar methods' exact QP solves; "newton", penalty and Nitsche), physics and dimension; a
# method that declares a number is its own seconds per dof.
SOLVE_SECONDS_PER_DOF = {("active-set", "scalar", 2): 1.4e-6, ("newton", "scalar", 2): 2.2e-6,
                         ("active-set", "elasticity", 2): 5.7e-6, ("active-set", "scalar", 3): 8.6e-6,
                         ("active-set", "elasticity", 3): 5.1e-5}
SWEEP_SECONDS_PER_DOF = 2.5e-5
# A reference chain's levels past the studied ones (``chain.chain_levels``): the reference
# solve and the measurement against it (numbering, prolongations, norm matrices, the norms of
# every kept solution), per dof of those levels, on top of the shared work and the cone's solve.
# Fitted to smooth-obstacle (every method, p1, the paper's; 6 and 7 levels, one process,
# 2 cores).
REFERENCE_SECONDS_PER_DOF = 1.4e-5


class BudgetError(ValueError):
    """A study that cannot fit: one line naming the job, the level and the estimate."""


@dataclass(frozen=True)
class LevelSizes:
    """Vertices, edges and elements (``triangles``: triangles, or tetrahedra in 3D) of each
    level of a case's red-refined hierarchy."""

    vertices: tuple
    edges: tuple
    triangles: tuple

    @classmethod
    def of(cls, case, levels: int) -> "LevelSizes":
        """From the coarse mesh alone: red refinement adds a vertex per edge, splits each edge in
        two and adds three edges and three triangles inside each triangle (V' = V + E,
        E' = 2E + 3T, T' = 4T), so nothing finer is ever built. In 3D it also splits each face
        into four (three new edges each) and each tetrahedron into eight around one new interior
        edge and eight new faces: V' = V + E, E' = 2E + 3F + T, F' = 4F + 8T, T' = 8T."""
        v, e, f, t = (list(counts) for counts in _coarse_counts(case))
        for _ in range(1, levels):
            v.append(v[-1] + e[-1])
            if case.dimension == 3:
                e.append(2 * e[-1] + 3 * f[-1] + t[-1])
                f.append(4 * f[-1] + 8 * t[-1])
                t.append(8 * t[-1])
            else:
                e.append(2 * e[-1] + 3 * t[-1])
                t.append(4 * t[-1])
        return cls(tuple(v), tuple(e), tuple(t))

    def ndof(self, level: int, order: int, components: int = 1) -> int:
        """Dofs of P1 (vertices) or P2 (vertices and edges) on ``level``, Dirichlet ones included,
        times the unknowns per node (2 for a displacement). (The per-dof figures below were
        fitted on scalar problems; an elastic dof has about twice the matrix entries, which the
        margins of PEAK_PER_DOF do not cover at every size: elastic estimates are rougher.)"""
        return (self.vertices[level] + (self.edges[level] if order == 2 else 0)) * components


_COARSE: dict = {}


def _coarse_counts(case) -> tuple:
    """(vertices,), (edges,), (faces,), (elements,) of a case's coarse mesh (faces counted in 3D
    only; a two-body case: both bodies' meshes, each refined on its own, ``problem.bodies``), made
    once per case file, name and maxh in a process (a study asks for them once per job)."""
    key = (case.source, case.name, case.maxh)
    if key not in _COARSE:
        meshes = [coarse_mesh(body) for body in ((case,) if case.second_body is None else (case, lower_body(case)))]
        _COARSE[key] = ((sum(m.nv for m in meshes),), (sum(m.nedge for m in meshes),),
                        (sum(m.nface if m.dim == 3 else 0 for m in meshes),), (sum(m.ne for m in meshes),))
    return _COARSE[key]


@dataclass(frozen=True)
class JobEstimate:
    """A job's largest level (the finest of its chains) and its estimated peak memory and time."""

    case: str
    methods: tuple
    level: int
    ndof: int
    peak_bytes: float
    seconds: float

    def describe(self) -> str:
        return (f"{self.case} ({', '.join(self.methods)}): level {self.level} has {self.ndof:.3g} dofs; "
                f"estimated peak memory {_size(self.peak_bytes)}, time {_duration(self.seconds)}")


def solve_weights(case, methods, levels: int, sizes: LevelSizes | None = None, per_dof: float | None = None,
                  per_level_reference: bool = False) -> dict:
    """(case, method, level) -> estimated seconds of that solve with its share of the level's
    shared work: the weights of the progress bar (its ETA is then weighted by the size of each
    level, not by the count of solves). ``per_dof``: the solve's seconds per dof, if not the
    figure of the method's cost model (``solve_seconds_per_dof``). ``per_level_reference``: a
    case without u on graded or adaptive meshes, where each studied level has its own reference
    (``measure.level_reference``, 4^K times the level's P2 dofs) in place of the reference chain's
    finer levels, which are then never solved."""
    methods = chain_methods(case, methods)
    chains = {m.name: chain_levels(case, m, levels, methods) for m in methods}
    if per_level_reference:
        chains = {m.name: study_levels(m, levels) for m in methods}
    sizes = sizes or LevelSizes.of(case, max(chains.values()))
    physics, dim, components = case.physics.name, case.dimension, case.physics.components
    shared = SHARED_SECONDS_PER_ELEMENT.get((dim, physics), max(SHARED_SECONDS_PER_ELEMENT.values()))
    weights = {}
    for level in range(max(chains.values())):
        solving = [m for m in methods if level < chains[m.name]]
        own_reference = (REFERENCE_SECONDS_PER_DOF * 4**case.reference_levels * sizes.ndof(level, 2, components) / len(solving)
                         if per_level_reference else 0.0)
        for m in solving:
            solve = per_dof or solve_seconds_per_dof(m, physics, dim)
            ndof = sizes.ndof(level, m.order, components)
            reference = REFERENCE_SECONDS_PER_DOF * ndof if is_reference(case, m, methods) and level >= study_levels(m, levels) else 0.0
            weights[(case.name, m.name, level)] = shared * sizes.triangles[level] / len(solving) + solve * ndof + reference + own_reference
    return weights


def solve_seconds_per_dof(method, physics: str, dimension: int) -> float:
    """A solve's seconds per dof by the cost model ``method`` declares (``methods.method.Method.cost_model``):
    its own number, or the figure of its model, physics and dimension (``SOLVE_SECONDS_PER_DOF``;
    the largest for a combination not measured)."""
    model = getattr(method, "cost_model", None)
    if isinstance(model, (int, float)) and not isinstance(model, bool):
        return float(model)
    return SOLVE_SECONDS_PER_DOF.get((model, physics, dimension), max(SOLVE_SECONDS_PER_DOF.values()))


def estimate(case, methods, levels: int, sizes: LevelSizes | None = None, per_dof: float | None = None) -> JobEstimate:
    """Peak memory and time of one job: ``methods`` on ``case`` (one process, shared levels)."""
    methods = chain_methods(case, methods)
    chains = {m.name: chain_levels(case, m, levels, methods) for m in methods}
    last = max(chains.values())
    sizes = sizes or LevelSizes.of(case, last)
    finest = {}                                  # order -> (level, ndof) of its finest problem
    for m in methods:
        level = chains[m.name] - 1
        finest[m.order] = max(finest.get(m.order, (0, 0)), (level, sizes.ndof(level, m.order, case.physics.components)))
    bytes_per_dof = (PEAK_PER_DOF_BY_KIND.get((case.dimension, case.physics.name), PEAK_PER_DOF)
                     + (0.0 if case.exact else PEAK_PER_REFERENCE_DOF) + (0.0 if case.bodies == 1 else PEAK_PER_TWO_BODY_DOF)
                     + (KRYLOV_BYTES_PER_DOF if case.bodies == 1 and case.friction.name == "coulomb" else 0.0))
    peak = PEAK_BASE + PEAK_PER_TRIANGLE * sizes.triangles[last - 1] + bytes_per_dof * sum(n for _, n in finest.values())
    seconds = sum(solve_weights(case, methods, levels, sizes, per_dof).values())
    level, ndof = max(finest.values())
    return JobEstimate(case.name, tuple(m.name for m in methods), level, ndof, peak, seconds)


def machine_memory() -> float:
    """Physical memory of this machine, in bytes."""
    return float(os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES"))


def check_fits(estimates: list[JobEstimate], limit: float, where: str) -> None:
    """BudgetError naming the largest job if it would need more than ``limit`` bytes."""
    worst = max(estimates, key=lambda e: e.peak_bytes)
    if worst.peak_bytes > limit:
        raise BudgetError(f"{worst.describe()}: more than the {_size(limit)} of {where}; "
                          f"use fewer levels, or --skip-memory-check to run it anyway")


def _size(nbytes: float) -> str:
    for unit, scale in (("TB", 2.0**40), ("GB", 2.0**30), ("MB", MB)):
        if nbytes >= scale:
            return f"{nbytes / scale:.4g} {unit}"
    return f"{nbytes:.0f} B"


def _duration(seconds: float) -> str:
    if seconds >= 86400:
        return f"{seconds / 86400:.3g} days"
    if seconds >= 3600:
        return f"{seconds / 3600:.3g} h"
    return f"{seconds / 60:.3g} min" if seconds >= 60 else f"{seconds:.2g} s"
