"""The level chain of a two-body case (``problem.bodies``): each body's mesh hierarchy refined
uniformly on its own (the meshes stay non-matching on Gamma_C), each level's two discrete
problems coupled by a mortar method (``methods._mortar``), each body's errors measured as a
one-body chain measures them (``measure.errors.ExactErrors``, the lower body against the same
u in its mirrored frame) and combined over the two bodies:

    err^2 = err_upper^2 + err_lower^2      for every norm (H^1, L^2, energy, best approximation,
                                           trace and pressure on Gamma_C),

so that ``err_h1`` is the H^1 error over both bodies and ``err_h1_over_best`` the ratio of the
combined errors. One row per (method, level), with the columns of a one-body chain; ``ndof`` the
two bodies' together, ``h`` the coarser body's mesh size.

Not yet: checkpoints (a killed two-body chain starts again from its first level), graded and
adaptive meshes, the multigrid (each body's R_h u and the mortar QP are solved by sparse
Cholesky).
"""
from __future__ import annotations

import math
import time

from ..fem.assembly import discretise
from ..fem.element_quadrature import ElementQuadrature
from ..fem.two_body import TwoBodyProblem
from ..measure.errors import ExactErrors
from ..mesh.levels import UniformRefinement
from ..methods import methods_for
from ..problem.bodies import lower_body
from . import threads
from .rows import ChainOutput, Phases, keep, level_row, study_levels
from .threads import p2_size

# the error columns combined over the bodies as the root of the sum of squares
COMBINED = ("err_h1", "err_h1_semi", "err_l2", "err_energy", "err_best_h1", "err_best_h1_semi", "err_best_energy",
            "err_trace_l2", "err_pressure_l2", "err_pressure_h12")


def combine(upper: dict, lower: dict) -> dict:
    """The error columns of both bodies' rows as one: sqrt(a^2 + b^2) per norm, and the ratio to
    the best approximation of the combined errors."""
    out = {key: math.hypot(upper[key], lower[key]) for key in COMBINED if key in upper and key in lower}
    out["err_h1_over_best"] = out["err_h1"] / out["err_best_h1"]
    return out


def run_two_body_chain(case, methods, levels: int, progress=None, phases=None, on_level=None):
    """The rows of ``methods`` (those that couple two bodies) on the two-body ``case``, levels
    0 .. ``levels`` - 1 (+ the methods' extra levels, P1's), sharing each level's meshes and
    each order's pair of discrete problems. ``on_level(case, method, level, problem, solve)`` as
    in ``chain.run_chain``, with ``problem`` a ``fem.two_body.TwoBodyProblem``; what it returns
    is kept by (method, level). Returns ``chain.ChainOutput``."""
    phases = phases or Phases()
    methods = methods_for(case, methods)
    if not case.exact:
        raise ValueError(f"case {case.name}: a two-body case needs its exact u")
    bodies = (case, lower_body(case))
    studied = {m.name: study_levels(m, levels) for m in methods}
    last_level = max(studied.values(), default=0)
    measures = [ExactErrors(body, phases, {m.name: m.order for m in methods}) for body in bodies]
    walks = [UniformRefinement(body).levels(last_level) for body in bodies]
    carry = {m.name: None for m in methods}
    rows, kept = [], {}
    for level in range(last_level):
        clock = time.perf_counter()
        with phases("mesh"):
            steps = [next(walk) for walk in walks]
        with threads.level(p2_size(*(step.mesh for step in steps))):
            active = [m for m in methods if level < studied[m.name]]
            with phases("mesh"):
                quadratures = [ElementQuadrature.of(body, step.mesh) for body, step in zip(bodies, steps)]
            mesh_seconds = time.perf_counter() - clock
            problems, assembly_seconds = {}, {}
            for order in sorted({m.order for m in active}, reverse=True):
                clock = time.perf_counter()
                with phases("assembly"):
                    problems[order] = TwoBodyProblem(*(discretise(body, step.mesh, order, quadrature)
                                                       for body, step, quadrature in zip(bodies, steps, quadratures)))
                assembly_seconds[order] = time.perf_counter() - clock
            for k, (measure, step, quadrature) in enumerate(zip(measures, steps, quadratures)):
                measure.begin_level(level, step.mesh, {order: pair.bodies[k] for order, pair in problems.items()},
                                    quadrature, None)
            level_rows = []
            for method in active:
                problem = problems[method.order]
                if progress is not None:
                    progress.solving(case.name, method.name, level, problem.ndof, "")
                clock = time.perf_counter()
                solve = method.solve(case, problem, carry[method.name], None, phases=phases)
                own_seconds = time.perf_counter() - clock
                carry[method.name] = solve.carry
                row = level_row(case, method, "uniform", level, max(step.h for step in steps), problem.ndof, solve.fields,
                                mesh_seconds + assembly_seconds[method.order] + own_seconds, float("nan"),
                                method.expected(case), method.sharper(case))
                body_rows = [{}, {}]
                with phases("errors"):
                    for k, (measure, u) in enumerate(zip(measures, problem.split(solve.u))):
                        body_rows[k].update(measure.solved(method, level, problem.bodies[k], u, body_rows[k]))
                level_rows.append((row, body_rows))
                keep(on_level, phases, kept, case, method, level, problem, solve)
                if progress is not None:
                    progress.solved(case.name, method.name, level)
            with phases("errors"):
                for measure in measures:
                    measure.end_level()
            for row, (upper, lower) in level_rows:
                row.update(combine(upper, lower))
                row["effectivity"] = float("nan")
                rows.append(row)
    order = {m.name: k for k, m in enumerate(methods)}
    rows.sort(key=lambda r: (r["level"], order[r["method"]]))
    return ChainOutput(rows, kept, phases.as_dict(), {m.name: 0 for m in methods})
