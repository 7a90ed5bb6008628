"""The adaptive rows of `bench`: on corner-r12's adaptive meshes (SOLVE -> ESTIMATE -> MARK ->
REFINE), the contact solve on the finest mesh against one linear solve of the same matrix by the
same multigrid CG (its hierarchy: the bisection levels of the adaptive loop), how the cost per
level grows with N, what the whole chain costs against its solves (the study's own chain,
``total_seconds`` over ``solve_seconds``), and the loop's refinements replayed by the two
bisections (``mesh.bisection``): on arrays, as the study refines a polygon, and NGSolve's in
place."""
from __future__ import annotations

import numpy as np
import pandas as pd

from .common import fastest, own_seconds

ADAPTIVE_CASE = "corner-r12"
ADAPTIVE_LEVELS = 7            # the budget of uniform level 6: about 5.8e5 P2 dofs
ADAPTIVE_GOAL = 1.5            # contact solve / one linear solve of the same matrix
CHAIN_GOAL = 3.0               # the P1 chain's total seconds / its solves' seconds

ADAPTIVE_COLUMNS = ["case", "method", "levels", "ndof", "t_contact", "t_linear", "ratio_linear", "iterations",
                    "cg_iterations", "linear_cg_iterations", "kkt_residual", "cost_exponent", "multigrid_levels",
                    "t_chain", "t_chain_solves", "ratio_chain", "t_refine_arrays", "t_refine_in_place", "ratio_refine"]


def _adaptive_row(method_name: str, levels: int) -> dict:
    import ngsolve as ngs

    from ..fem.assembly import discretise
    from ..fem.cones import contact_qp
    from ..fem.nested import nested_start
    from ..measure.estimator import ResidualEstimator
    from ..mesh.bisection import dorfler
    from ..mesh.strategies import MeshStrategy, element_budget
    from ..methods import get_method
    from ..problem.case import load_case
    from ..solvers.bound_constraints import solve_contact_qp
    from ..solvers.multigrid import Multilevel
    from .three_d import linear_multigrid_seconds

    case, method = load_case(ADAPTIVE_CASE), get_method(method_name)
    sequence = MeshStrategy("adaptive").sequence(case, method.order)
    budget = element_budget(case, levels, method.extra_levels)
    sequence.limit_elements(budget)
    multilevel, carry, ndofs, seconds, marked = None, None, [], [], []
    for level in sequence.levels(60):
        mesh = level.mesh
        if level.index and mesh.ne > budget:
            break
        multilevel = Multilevel(mesh) if multilevel is None else multilevel.refined(mesh, level.prolongation)
        with ngs.TaskManager():
            problem = discretise(case, mesh, method.order)
            estimator = ResidualEstimator(case, problem)
            qp = contact_qp(case, problem, method.cone)
            previous, coarse = carry or (None, None)
            start = nested_start(multilevel, coarse, problem) if coarse is not None else None
            predicted = qp.predicted_active(previous)
            t_contact, solution = fastest(lambda: own_seconds(solve_contact_qp(qp, predicted, multilevel=multilevel, start=start)))
            u = qp.to_u(solution.z)
            carry = (qp.trace_function(u, solution.active), u[:mesh.nv].copy())
            indicators = estimator.indicators(u)
            sequence.observe(indicators)
            marked.append(dorfler(indicators, sequence.theta))
        ndofs.append(problem.ndof)
        seconds.append(t_contact)
        last = (qp, solution, t_contact, len(multilevel.matrices))
    qp, solution, t_contact, stored = last
    with ngs.TaskManager():
        t_linear, system = linear_multigrid_seconds(qp, multilevel)
    # the cost per level against N over the finer half of the levels: t ~ N^a
    half = len(ndofs) // 2
    exponent = float(np.polyfit(np.log(ndofs[half:]), np.log(seconds[half:]), 1)[0])
    return {"case": ADAPTIVE_CASE, "method": method_name, "levels": len(ndofs), "ndof": qp.problem.ndof,
            "t_contact": t_contact, "t_linear": t_linear, "ratio_linear": t_contact / t_linear,
            "iterations": solution.iterations, "cg_iterations": solution.work.get("cg_iterations"),
            "linear_cg_iterations": system.cg_iterations, "kkt_residual": solution.kkt.residual,
            "cost_exponent": exponent, "multigrid_levels": stored,
            **_chain_costs(case, method, levels), **_refinement_costs(case, marked[:len(ndofs) - 1])}


def _chain_costs(case, method, levels: int) -> dict:
    """The study's adaptive chain of ``method`` (``study.chain.run_chain``): what its levels cost
    a user (the rows' ``total_seconds``: refinement, assembly, set-up, solve, ESTIMATE and MARK)
    against its solves alone."""
    from ..mesh.strategies import MeshStrategy
    from ..study.chain import run_chain
    rows = run_chain(case, [method], levels, mesh=MeshStrategy("adaptive")).rows
    total, solves = sum(r["total_seconds"] for r in rows), sum(r["solve_seconds"] for r in rows)
    return {"t_chain": total, "t_chain_solves": solves, "ratio_chain": total / solves}


def _refinement_costs(case, marked: list) -> dict:
    """The loop's refinements (``marked``: each level's Dörfler flags, in the study's numbering)
    replayed by both bisections, levels included (the arrays' NGSolve mesh, the in-place mesh's
    h). The same triangles come out (``tests/test_newest_vertex.py``), numbered differently: the
    flags are carried over by the elements' centroids, untimed."""
    import time

    from ..mesh.bisection import ArrayBisection, InPlaceBisection
    from ..mesh.levels import coarse_mesh
    arrays, in_place = ArrayBisection(coarse_mesh(case)), InPlaceBisection(coarse_mesh(case))
    seconds = [0.0, 0.0]
    for index, flags in enumerate(marked, start=1):
        order = _same_elements(arrays, in_place)
        for k, (refiner, own) in enumerate(((arrays, flags), (in_place, flags[order]))):
            start = time.perf_counter()
            refiner.refine(own)
            refiner.level(index)
            seconds[k] += time.perf_counter() - start
    return {"t_refine_arrays": seconds[0], "t_refine_in_place": seconds[1], "ratio_refine": seconds[1] / seconds[0]}


def _same_elements(arrays, in_place) -> np.ndarray:
    """For each element of ``in_place``, the element of ``arrays`` with the same centroid."""
    ours, theirs = arrays.element_sizes()[1], in_place.element_sizes()[1]
    rank = [np.lexsort(np.round(c, 12).T[::-1]) for c in (ours, theirs)]
    order = np.empty(len(theirs), dtype=np.int64)
    order[rank[1]] = rank[0]
    if not np.allclose(ours[order], theirs, atol=1e-12):
        raise RuntimeError("the two bisections made different meshes")
    return order


def run_adaptive_bench(methods=None, levels: int = ADAPTIVE_LEVELS, progress=print) -> pd.DataFrame:
    """Each method's row (default: the paper's and the P1 baseline, the methods that declare
    the roles PAPER and BASELINE)."""
    from ..methods import BASELINE, PAPER, role_names
    methods = methods or [*role_names(PAPER), *role_names(BASELINE)]
    rows = []
    for name in methods:
        rows.append(_adaptive_row(name, levels))
        row = rows[-1]
        progress(f"adaptive {name:5s} ndof {row['ndof']:>8d} contact {row['t_contact']:.3f} s linear {row['t_linear']:.3f} s "
                 f"ratio {row['ratio_linear']:.2f}")
    return pd.DataFrame(rows, columns=ADAPTIVE_COLUMNS)


def p1_baselines() -> list[str]:
    """The P1 methods the chain goal judges: the role BASELINE's."""
    from ..methods import BASELINE, role_names
    return role_names(BASELINE)


def adaptive_goals(frame: pd.DataFrame) -> list[tuple[str, bool, str]]:
    """Exact on every adaptive level's finest mesh; the contact solve against one linear solve."""
    exact = bool((frame.kkt_residual <= 1e-10).all())
    return [("adaptive meshes: KKT <= 1e-10 on the finest mesh", exact, f"max {frame.kkt_residual.max():.1e}"),
            # the goal: the nested iteration across bisection levels as good as across red ones
            (f"adaptive meshes: contact solve <= {ADAPTIVE_GOAL}x one linear solve on the finest mesh",
             bool((frame.ratio_linear <= ADAPTIVE_GOAL).all()),
             ", ".join(f"{m} {r:.2f}" for m, r in zip(frame.method, frame.ratio_linear))),
            ("adaptive meshes: cost per level ~ N^a (shown)", True,
             ", ".join(f"{m} a = {a:.2f}" for m, a in zip(frame.method, frame.cost_exponent))),
            (f"adaptive chain, P1: total <= {CHAIN_GOAL}x its solves",
             bool((frame[frame.method.isin(p1_baselines())].ratio_chain <= CHAIN_GOAL).all()),
             ", ".join(f"{m} {r:.2f}" for m, r in zip(frame.method, frame.ratio_chain))),
            ("adaptive refinement: NGSolve in place / on arrays (shown)", True,
             ", ".join(f"{m} {r:.2f}" for m, r in zip(frame.method, frame.ratio_refine)))]
