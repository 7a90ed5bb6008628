"""What every benchmark shares: a measurement in a fresh process (its peak memory its own),
short solves repeated and the fastest kept, the CSV written beside the results with what
measured it (``write_bench``)."""
from __future__ import annotations

import multiprocessing as mp
import os
import time
from pathlib import Path

import numpy as np
import pandas as pd

# A solve shorter than this is repeated (at most REPEATS times, on the same data, as timeit
# does) and its fastest run kept: a single run of a few milliseconds measures the machine's
# noise and first-touch page faults more than the solver.
SHORT_SECONDS = 1.0


REPEATS = 5


def fastest(solve) -> tuple[float, object]:
    """(seconds, result) of the fastest of repeated calls of ``solve``, which returns
    (seconds, result); repeated only while the runs are short."""
    best, result, total = np.inf, None, 0.0
    for _ in range(REPEATS):
        seconds, out = solve()
        if seconds < best:
            best, result = seconds, out
        total += seconds
        if total >= SHORT_SECONDS:
            break
    return best, result


def timed(function, *args, **kwargs) -> tuple[float, object]:
    start = time.perf_counter()
    out = function(*args, **kwargs)
    return time.perf_counter() - start, out


def own_seconds(solution) -> tuple[float, object]:
    """(seconds, solution) of a contact solution, which times itself."""
    return solution.seconds, solution


def linear_multigrid_seconds(qp, multilevel, start=None) -> tuple[float, object]:
    """(seconds, the MultigridSystem) of one unconstrained solve of ``qp``'s matrix by the
    contact solver's multigrid CG, from ``start`` (default zero), as deep as its linear solves go
    (fastest of repeats)."""
    from ..fem.p1_embedding import ContactEdges
    from ..solvers.bound_constraints import ActiveSetSolver, MultigridSystem
    system = MultigridSystem(qp.K_ngs, qp.b, multilevel, ContactEdges.of(qp.problem))
    load_scale = ActiveSetSolver(qp.K, qp.b, qp.free, qp.C, qp.alpha, lift=qp.lift, system=system).load_scale
    return linear_seconds(system, qp, load_scale, start)


def linear_seconds(system, qp, load_scale: float, start=None) -> tuple[float, object]:
    """(seconds, ``system``) of one solve of ``qp``'s matrix without constraints by ``system``,
    from ``start`` (default zero) to the contact solver's linear tolerance; ``system``'s
    ``cg_iterations`` then counts that solve's iterations (each one fine-level V-cycle)."""
    from ..solvers.bound_constraints import DEFAULT_TOLERANCE

    def linear():
        system.cg_iterations = 0
        return timed(system.solve, ~qp.free, qp.lift, start, tol=0.1 * DEFAULT_TOLERANCE * load_scale)
    return fastest(linear)[0], system


FAIR_COLUMNS = ["t_linear_nested", "nested_iterations", "ratio_nested", "contact_vcycles", "work_units"]


def fair_columns(t_contact: float, contact_cg_iterations: int, t_linear: float, linear_iterations: int,
                 t_nested: float, nested_iterations: int) -> dict:
    """The fair comparison of a contact solve started from the coarser level's solution (nested
    iteration): against the linear solve of the same matrix by the same multigrid CG from the
    same start to the same tolerance (``ratio_nested``), and its cost in fine-level V-cycles:
    the CG iterations it did (``contact_vcycles``; each applies one V-cycle) and its time in
    work units, one unit the time of one CG iteration of the linear solve from zero
    (``work_units``). Multilevel solvers of variational inequalities quote their work that way
    against full multigrid for the linear problem (Bueler & Farrell, SIAM J. Sci. Comput. 2024)."""
    unit = t_linear / max(linear_iterations, 1)
    return {"t_linear_nested": t_nested, "nested_iterations": nested_iterations, "ratio_nested": t_contact / t_nested,
            "contact_vcycles": contact_cg_iterations, "work_units": t_contact / unit}


def in_fresh_process(target, args: tuple, what: str) -> dict:
    ctx = mp.get_context("spawn")
    receiver, sender = ctx.Pipe(duplex=False)
    process = ctx.Process(target=target, args=(*args, sender))
    process.start()
    sender.close()
    try:
        result = receiver.recv()
    except EOFError:
        raise RuntimeError(f"bench process for {what} died (out of memory?)") from None
    process.join()
    return result


def fresh_rows(measure, label: str, linear: str, levels, models, progress, columns) -> pd.DataFrame:
    """``measure(model, level, connection)`` for each (level, model), each in a fresh process."""
    rows = []
    for level in levels:
        for model in models:
            row = in_fresh_process(measure, (model, level), f"{label} {model}/level {level}")
            rows.append(row)
            progress(f"{label} {model:5s} ndof {row['ndof']:>9d}  contact {row['t_contact']:7.2f} s  "
                     f"linear ({linear}) {row['t_linear']:7.2f} s  ratio {row['ratio_linear']:.2f}  rss {row['peak_rss_mb']:.0f} MB")
    return pd.DataFrame(rows, columns=columns)


def contact_goals(frame: pd.DataFrame, label: str, bound: float) -> list[tuple[str, bool, str]]:
    """The two goals of a contact-solve table: at its largest size the contact solve costs at
    most ``bound`` linear solves, and every size meets the KKT tolerance."""
    largest = frame[frame.ndof == frame.ndof.max()]
    return fair_goals(frame, label) + [
        (f"{label} contact solve <= {bound:g}x one linear solve at the largest size", bool((largest.ratio_linear <= bound).all()),
         ", ".join(f"{m} {r:.2f} at {n:.2g} dofs" for m, r, n in zip(largest.method, largest.ratio_linear, largest.ndof))),
        (f"{label} KKT residual <= 1e-10 at every size", bool((frame.kkt_residual <= 1e-10).all()), f"max {frame.kkt_residual.max():.1e}"),
    ]


def fair_goals(frame: pd.DataFrame, label: str) -> list[tuple[str, bool, str]]:
    """The fair row at the largest size (shown, not judged): the contact solve against the linear
    solve from the same nested start to the same tolerance, and its work in fine V-cycles."""
    if "ratio_nested" not in frame or frame.ratio_nested.isna().all():
        return []
    largest = frame[frame.ndof == frame.ndof.max()].dropna(subset=["ratio_nested"])
    return [(f"{label} contact solve / linear multigrid solve from the same nested start, same tolerance (shown)", True,
             ", ".join(f"{r.method} {r.ratio_nested:.2f} at {r.ndof:.2g} dofs ({r.work_units:.1f} work units; "
                       f"{int(r.contact_vcycles)} V-cycles against {int(r.nested_iterations)})" for r in largest.itertuples()))]


def cpu_model() -> str | None:
    """The processor's name as Linux reports it (``/proc/cpuinfo``), or None where it does not."""
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return None


def bench_provenance(title: str, goals, wall_seconds: float | None, command: str) -> dict:
    """What a benchmark table was measured with and what it showed: its title, the harness,
    NGSolve, the date and the machine (``study.planning.cache.environment``, here with the cores this
    process may use and the processor's name), the command line, the table's wall seconds and
    the load averages as it is written, and the goals judged on it ((goal, met, figure) each, as
    `bench` prints them)."""
    from ..study.execution.threads import usable_cpus
    from ..study.planning.cache import environment
    meta = {"title": title} | environment()
    meta["machine"] |= {"cpus_usable": usable_cpus(), "cpu_model": cpu_model()}
    # the machine's load averages (1, 5, 15 minutes) as the table is written: NGSolve's threads
    # lose many times over beside a busy process, and a table measured so must say it
    return meta | {"command": command, "wall_seconds": wall_seconds, "load_average": list(os.getloadavg()),
                   "goals": [{"goal": goal, "met": bool(met), "figure": figure} for goal, met, figure in goals]}


def write_bench(frame: pd.DataFrame, path: Path, title: str = "", goals=(), wall_seconds: float | None = None,
                command: str = "") -> Path:
    """``frame`` as the CSV ``path``, then beside it (the suffix .json) its provenance
    (``bench_provenance``) and the SHA-256 of the CSV (``csv_sha256``: a sidecar left from
    another run of the table, or a run killed between the two files, does not match it); each
    file written atomically."""
    import hashlib
    import json

    from ..study.storage.files import ensure_writable, write_atomic, write_csv
    ensure_writable(path.parent)
    write_csv(frame, path)
    meta = bench_provenance(title, goals, wall_seconds, command) | {"csv_sha256": hashlib.sha256(path.read_bytes()).hexdigest()}
    write_atomic(path.with_suffix(".json"), json.dumps(meta, indent=2))
    return path
