"""`python -m harness bench`: the contact solve against one linear solve, the textbook PDAS and a
generic QP solver, on the same discrete problems (transition-r32, both models).

Every measurement of one (model, size) runs in its own fresh process, so that peak memory
(ru_maxrss) belongs to that measurement alone and earlier sizes leave nothing behind. Times
are of the solve only: assembly and the change of variables are shared by all methods. Short
solves are repeated and the fastest run kept (``fastest``).
"""
from __future__ import annotations

import dataclasses
import resource
import time

import numpy as np
import pandas as pd

from .common import (
    FAIR_COLUMNS,
    fair_columns,
    fair_goals,
    fastest,
    in_fresh_process,
    linear_multigrid_seconds,
    own_seconds,
    timed,
)

BENCH_CASE = "transition-r32"


# (coarse maxh, level): 9.2e3 and 3.6e4 dofs on the case's own hierarchy, about 1.9e5 (where
# the goal against a generic QP solver is set), then 1.0e6 and 4.1e6 dofs on finer coarse meshes.
DEFAULT_SIZES = ((0.25, 3), (0.25, 4), (0.22, 5), (0.2, 6), (0.2, 7))


TEXTBOOK_MAX_NDOF = 3_000_000


QP_MAX_NDOF = 200_000


COLUMNS = ["method", "ndof", "t_contact", "t_linear", "t_textbook", "t_qp", "ratio_linear", "speedup_textbook",
           "speedup_qp", "iterations", "kkt_residual", "peak_rss_mb", "contact_cg_iterations", "t_linear_multigrid",
           "multigrid_iterations", "t_linear_cholesky", "t_linear_ngsolve_multigrid", "ngsolve_multigrid_iterations",
           *FAIR_COLUMNS]


# NGSolve's own CG is stopped where its residual is as small, relative to the load, as the
# contact solve's KKT stationarity (<= 1e-10, docs/mathematics.md §5).
NGSOLVE_MULTIGRID_TOLERANCE = 1e-12


def cone_problem(model_name: str, level: int, coarse_maxh: float | None, case_name: str = BENCH_CASE):
    """The discrete problem of ``level`` on the study's hierarchy, with what nested iteration
    brings from ``level - 1`` (solved by the harness's solver): predicted active set, start."""
    from ..fem.assembly import discretise
    from ..fem.cones import contact_qp
    from ..fem.nested import nested_start, p1_values
    from ..mesh.levels import UniformRefinement
    from ..methods import get_method
    from ..problem.case import load_case
    from ..solvers.bound_constraints import solve_contact_qp
    from ..solvers.multigrid import Multilevel

    case = load_case(case_name)
    case = dataclasses.replace(case, maxh=coarse_maxh or case.maxh)
    method = get_method(model_name)
    multilevel, previous, start = None, None, None
    for lev, mesh in ((step.index, step.mesh) for step in UniformRefinement(case).levels(level + 1)):
        multilevel = Multilevel(mesh, case.physics) if multilevel is None else multilevel.refined(mesh)
        if lev < level - 1:
            continue
        problem = discretise(case, mesh, method.order)
        qp = contact_qp(case, problem, method.cone, take_stiffness=True)
        if lev == level - 1:
            coarse = solve_contact_qp(qp, multilevel=multilevel)
            u = qp.to_u(coarse.z)
            previous = qp.trace_function(u, coarse.active)
            vertex_values = p1_values(problem, u)
        elif level > 0:
            start = nested_start(multilevel, vertex_values, problem)
    return qp, qp.predicted_active(previous), multilevel, start


def weak_problem(method_name: str, level: int, coarse_maxh: float | None, case_name: str = BENCH_CASE):
    """A contact law's system of ``level`` on the study's hierarchy (vector P1 for an elastic
    case) and its nested start (the coarser level solved by the same method): (system, start,
    predicted branch, multilevel)."""
    from ..fem.assembly import discretise
    from ..mesh.levels import UniformRefinement
    from ..methods import get_method
    from ..methods.protocol import nested_guess
    from ..problem.case import load_case
    from ..solvers.multigrid import Multilevel

    case = load_case(case_name)
    case = dataclasses.replace(case, maxh=coarse_maxh or case.maxh)
    method = get_method(method_name)
    multilevel, carry = None, None
    for lev, mesh in ((step.index, step.mesh) for step in UniformRefinement(case).levels(level + 1)):
        multilevel = Multilevel(mesh, case.physics) if multilevel is None else multilevel.refined(mesh)
        if lev < level - 1:
            continue
        problem = discretise(case, mesh, method.order)
        if lev == level - 1:
            carry = method.solve(case, problem, None, multilevel, take_stiffness=True).carry
    system = method.system(case, problem, take_stiffness=True)
    start, predicted = nested_guess(system, carry, multilevel)
    return system, start, predicted, multilevel


def _measure_weak(method: str, model_name: str, level: int, coarse_maxh) -> dict:
    """`contact`: one penalty/Nitsche solve (semismooth Newton, nested start); `multigrid` and
    `cholesky`: one linear solve with its matrix (no contact term active)."""
    from ..fem.p1_embedding import ContactEdges
    from ..solvers.bound_constraints import DEFAULT_TOLERANCE, Cholesky, MultigridSystem
    from ..solvers.newton import load_scale, solve_semismooth_newton

    system, start, predicted, multilevel = weak_problem(model_name, level, coarse_maxh)
    problem = system.problem
    out = {"ndof": problem.ndof}
    if method == "contact":
        t, solution = fastest(lambda: own_seconds(solve_semismooth_newton(system, start, multilevel, predicted=predicted)))
        out |= {"t": t, "iterations": solution.iterations, "kkt_residual": solution.residual,
                "cg_iterations": solution.linear_iterations}
    elif method == "multigrid":
        linear = MultigridSystem(system.J_ngs, system.rhs, multilevel, ContactEdges.of(problem, model=False))
        tol = 0.1 * DEFAULT_TOLERANCE * load_scale(system)
        def solve():
            linear.cg_iterations = 0
            return timed(linear.solve, ~problem.free, problem.lift, tol=tol)
        out["t"], _ = fastest(solve)
        out["iterations"] = linear.cg_iterations
    elif method == "cholesky":
        rhs = np.where(problem.free, system.rhs - system.J @ problem.lift, 0.0)
        out["t"], _ = fastest(lambda: timed(lambda: Cholesky(system.J_ngs, problem.free).solve(rhs)))
    return out


def _ngsolve_multigrid_solve(level: int, coarse_maxh, order: int = 2) -> dict:
    """One unconstrained solve of the same P2 system by CG with NGSolve's own geometric
    multigrid (P1 prolongation of the vertex dofs, P2 matrices on every level).

    Its setup time is what the assemblies with the preconditioner cost beyond the same
    assemblies without it.
    """
    import ngsolve as ngs

    from ..fem.assembly import discretise
    from ..mesh.levels import coarse_mesh
    from ..problem.case import load_case

    case = dataclasses.replace(load_case(BENCH_CASE), maxh=coarse_maxh)
    mesh = coarse_mesh(case)
    fes = ngs.H1(mesh, order=order, dirichlet="dirichlet")
    u, v = fes.TnT()
    a = ngs.BilinearForm(ngs.grad(u) * ngs.grad(v) * ngs.dx)
    preconditioner = ngs.Preconditioner(a, "multigrid")
    plain = ngs.BilinearForm(ngs.grad(u) * ngs.grad(v) * ngs.dx)
    setup = 0.0
    for lev in range(level + 1):
        if lev:
            mesh.ngmesh.Refine()
            fes.Update()
        start = time.perf_counter()
        a.Assemble()
        setup += time.perf_counter() - start
        start = time.perf_counter()
        plain.Assemble()
        setup -= time.perf_counter() - start
    problem = discretise(case, mesh, order)
    rhs, solution = a.mat.CreateColVector(), a.mat.CreateColVector()
    rhs.FV().NumPy()[:] = np.where(problem.free, problem.b - problem.A @ problem.lift, 0.0)
    solver = ngs.CGSolver(a.mat, preconditioner.mat, tol=NGSOLVE_MULTIGRID_TOLERANCE, maxiter=1000)

    def solve():
        solution.data = solver * rhs
    seconds, _ = fastest(lambda: timed(solve))
    residual = np.where(problem.free, rhs.FV().NumPy() - problem.A @ solution.FV().NumPy(), 0.0)
    relative = np.abs(residual).max() / np.abs(rhs.FV().NumPy()).max()
    if relative > 1e-10:
        raise RuntimeError(f"multigrid CG stopped at relative residual {relative:.1e} > 1e-10")
    return {"t": max(setup, 0.0) + seconds, "iterations": solver.iterations}


def _measure(method: str, model_name: str, level: int, coarse_maxh, connection):
    import ngsolve as ngs

    from ..solvers.bound_constraints import Cholesky, solve_contact_qp

    ngs.ngsglobals.msg_level = 0
    with ngs.TaskManager():
        if method == "ngsolve_multigrid":
            from ..methods import get_method
            out = _ngsolve_multigrid_solve(level, coarse_maxh, get_method(model_name).order)
            out["peak_rss_mb"] = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
            connection.send(out)
            connection.close()
            return
        from ..methods import BoundConstrained, get_method
        if not isinstance(get_method(model_name), BoundConstrained):
            out = _measure_weak(method, model_name, level, coarse_maxh)
            out["peak_rss_mb"] = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
            connection.send(out)
            connection.close()
            return
        qp, predicted, multilevel, start_vector = cone_problem(model_name, level, coarse_maxh)
        out = {"ndof": qp.problem.ndof}
        if method == "contact":
            t, solution = fastest(lambda: own_seconds(solve_contact_qp(qp, predicted, multilevel=multilevel,
                                                                     start=start_vector)))
            out |= {"t": t, "iterations": solution.iterations, "kkt_residual": solution.kkt.residual,
                    "cg_iterations": solution.work["cg_iterations"]}
        elif method == "multigrid":
            # the contact solver's own back end, the same matrix K, no contact constraints, as
            # deep as the contact solver's linear solves: from zero, and from the contact solve's
            # nested start (the fair comparison, ``common.fair_columns``); a fresh V-cycle each
            (out["t"], zero), (out["t_nested"], nested) = (linear_multigrid_seconds(qp, multilevel, s)
                                                          for s in (None, start_vector))
            out["iterations"], out["nested_iterations"] = zero.cg_iterations, nested.cg_iterations
        elif method == "cholesky":
            # the same matrix K, no constraints
            rhs = np.where(qp.free, qp.b - qp.K @ qp.lift, 0.0)
            out["t"], _ = fastest(lambda: timed(lambda: Cholesky(qp.K_ngs, qp.free).solve(rhs)))
        elif method == "textbook":
            t, solution = fastest(lambda: own_seconds(solve_contact_qp(qp, textbook=True)))
            out |= {"t": t, "textbook_iterations": solution.iterations}
        elif method == "qp":
            import scipy.sparse as sp
            from qpsolvers import solve_qp
            free = np.flatnonzero(qp.free)
            position = np.cumsum(qp.free) - 1
            K = sp.csc_matrix(qp.K[free][:, free])
            q = -(qp.b - qp.K @ qp.lift)[free]
            G = sp.csc_matrix((-np.ones(len(qp.C)), (np.arange(len(qp.C)), position[qp.C])), shape=(len(qp.C), len(free)))
            out["t"], _ = fastest(lambda: timed(solve_qp, K, q, G=G, h=-qp.alpha, solver="clarabel"))
    out["peak_rss_mb"] = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    connection.send(out)
    connection.close()


def measure(method: str, model_name: str, level: int, coarse_maxh=None) -> dict:
    return in_fresh_process(_measure, (method, model_name, level, coarse_maxh), f"{method}/{model_name}/level {level}")


def run_bench(sizes=DEFAULT_SIZES, models=None, qp_max_ndof=QP_MAX_NDOF,
              textbook_max_ndof=TEXTBOOK_MAX_NDOF, progress=print) -> pd.DataFrame:
    """Each (model, size)'s row (default: the paper's models, the methods that declare the role
    PAPER)."""
    from ..methods import PAPER, BoundConstrained, get_method, role_names
    models = models or role_names(PAPER)
    rows = []
    for coarse_maxh, level in sizes:
        for model in models:
            contact = measure("contact", model, level, coarse_maxh)
            ndof = contact["ndof"]
            multigrid = measure("multigrid", model, level, coarse_maxh)
            cholesky = measure("cholesky", model, level, coarse_maxh)
            ngsolve_multigrid = measure("ngsolve_multigrid", model, level, coarse_maxh)
            # the textbook PDAS and a QP solver exist for the cones only
            cone = isinstance(get_method(model), BoundConstrained)
            textbook = measure("textbook", model, level, coarse_maxh) if cone and ndof <= textbook_max_ndof else {}
            qp = measure("qp", model, level, coarse_maxh) if cone and ndof <= qp_max_ndof else {}
            row = {
                # one linear solve with the fastest back end at this size
                "method": model, "ndof": ndof, "t_contact": contact["t"],
                "t_linear": min(multigrid["t"], cholesky["t"], ngsolve_multigrid["t"]),
                "t_linear_multigrid": multigrid["t"], "multigrid_iterations": multigrid["iterations"],
                "t_linear_cholesky": cholesky["t"], "t_linear_ngsolve_multigrid": ngsolve_multigrid["t"],
                "ngsolve_multigrid_iterations": ngsolve_multigrid["iterations"],
                "t_textbook": textbook.get("t", np.nan), "t_qp": qp.get("t", np.nan),
                "iterations": contact["iterations"], "contact_cg_iterations": contact["cg_iterations"],
                "kkt_residual": contact["kkt_residual"], "peak_rss_mb": contact["peak_rss_mb"],
            }
            row["ratio_linear"] = row["t_contact"] / row["t_linear"]
            if "t_nested" in multigrid:
                row |= fair_columns(contact["t"], contact["cg_iterations"], multigrid["t"], multigrid["iterations"],
                                    multigrid["t_nested"], multigrid["nested_iterations"])
            row["speedup_textbook"] = row["t_textbook"] / row["t_contact"]
            row["speedup_qp"] = row["t_qp"] / row["t_contact"]
            rows.append(row)
            progress(f"{model:5s} ndof {ndof:>9d}  contact {row['t_contact']:7.2f} s  linear: multigrid "
                     f"{row['t_linear_multigrid']:7.2f} s (nested start {row.get('t_linear_nested', np.nan):7.2f} s), cholesky {row['t_linear_cholesky']:7.2f} s, ngsolve "
                     f"multigrid {row['t_linear_ngsolve_multigrid']:7.2f} s  "
                     f"textbook {row['t_textbook']:7.2f} s  qp {row['t_qp']:7.2f} s  rss {row['peak_rss_mb']:.0f} MB")
    return pd.DataFrame(rows, columns=COLUMNS)


def goals(frame: pd.DataFrame) -> list[tuple[str, bool, str]]:
    """The solver table's goals, each with the measured figure."""
    from ..measure.reference import REFERENCE_METHOD
    out = []
    cones = frame.method.map(_is_cone)
    big = frame[frame.ndof >= 1_000_000]
    weak = big[~cones.loc[big.index]]
    big = big[cones.loc[big.index]]      # the goals are the cones'
    if len(weak):
        out.append(("penalty/Nitsche solve / one linear solve at >= 1M dofs (shown)", True,
                    ", ".join(f"{m} {r:.2f}" for m, r in zip(weak.method, weak.ratio_linear))))
    if len(big):
        worst = big.ratio_linear.max()
        out.append(("contact/linear <= 1.5 at >= 1M dofs", worst <= 1.5, f"worst {worst:.2f}"))
        tb = big.speedup_textbook.dropna()
        if len(tb):
            out.append((">= 5x faster than textbook PDAS at >= 1M dofs", tb.min() >= 5, f"least {tb.min():.1f}x"))
        mem = big.sort_values("ndof").groupby("method").peak_rss_mb.first()
        out.append(("peak memory <= 3 GB at ~1M dofs (smallest size >= 1M)", mem.max() <= 3072, f"max {mem.max():.0f} MB"))
    near = frame.dropna(subset=["speedup_qp"])
    if len(near):
        largest = near[near.ndof == near.ndof.max()]
        out.append((">= 20x faster than Clarabel near 185k dofs", largest.speedup_qp.min() >= 20,
                    f"least {largest.speedup_qp.min():.1f}x at {largest.ndof.max()} dofs"))
    def spread(times):
        per_dof = times / frame.ndof
        return (per_dof.groupby(frame.method).max() / per_dof.groupby(frame.method).min()).max()
    out.append((f"time per dof within 2x over {frame.ndof.min()}..{frame.ndof.max()} dofs", spread(frame.t_contact) <= 2,
                f"spread {spread(frame.t_contact):.2f}x (one linear solve alone: multigrid "
                f"{spread(frame.t_linear_multigrid):.2f}x, cholesky {spread(frame.t_linear_cholesky):.2f}x)"))
    out.append(("KKT (cones) / Newton (weak) residual <= 1e-10 at every size", bool((frame.kkt_residual <= 1e-10).all()),
                f"max {frame.kkt_residual.max():.1e}"))
    out += fair_goals(frame[cones], "2D")
    out += relative_to(REFERENCE_METHOD, frame)
    return out


def _is_cone(name: str) -> bool:
    """Whether the method ``name`` is a cone of bounds (``BoundConstrained``: its solve is the
    active set method the goals are set for)."""
    from ..methods import BoundConstrained, get_method
    return isinstance(get_method(name), BoundConstrained)


def relative_to(reference: str, frame: pd.DataFrame) -> list[tuple[str, bool, str]]:
    """One solve of each other method over one solve of ``reference`` at the same size (shown,
    not judged): the cost of penalty and Nitsche against the paper's nodal model (the reference
    method)."""
    ref = frame[frame.method == reference].set_index("ndof").t_contact
    out = []
    for method, group in frame[frame.method != reference].groupby("method", sort=False):
        ratios = [f"{t / ref[n]:.2f}x at {n:.2g} dofs" for n, t in zip(group.ndof, group.t_contact) if n in ref.index]
        if ratios:
            out.append((f"one {method} solve / one {reference} solve (shown)", True, ", ".join(ratios)))
    return out
