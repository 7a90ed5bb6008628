"""`make report`: the default study, its rates, figures and report (Markdown and HTML).

Results of a case are reused when the code, the case file and the settings that produced them
are unchanged (a hash of all three is stored beside them); `make clean` forgets them.
"""
from __future__ import annotations

import datetime
import hashlib
import json
import os
import platform
import subprocess
import time
from pathlib import Path

import ngsolve as ngs
import numpy as np
import pandas as pd

from . import __version__, figures
from .case import Case, fraction, registered_cases
from .document import Document
from .models import MODELS
from .rates import normalised_errors, pairwise_rates, rate_table
from .results import ensure_writable, write_atomic, write_csv
from .snapshots import SnapshotCollector, load_snapshots
from .study import PROFILES, progress_bar, run_study

PACKAGE = Path(__file__).resolve().parent
REPOSITORY = PACKAGE.parent


def git_commit() -> str:
    try:
        commit = subprocess.run(["git", "rev-parse", "HEAD"], cwd=REPOSITORY, capture_output=True, text=True, check=True).stdout.strip()
        dirty = subprocess.run(["git", "status", "--porcelain", "--", "harness", "cases"], cwd=REPOSITORY,
                               capture_output=True, text=True).stdout.strip()
        return commit + ("+dirty" if dirty else "")
    except (OSError, subprocess.CalledProcessError):
        return "unknown"


def provenance(settings: dict) -> dict:
    return {
        "harness_version": __version__, "git_commit": git_commit(), "ngsolve_version": ngs.__version__,
        "date": datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds"),
        "machine": {"node": platform.node(), "platform": platform.platform(), "processor": platform.machine(),
                    "cpus": os.cpu_count(), "python": platform.python_version()},
        "settings": settings,
    }


def cache_key(case: Case, settings: dict) -> str:
    """Hash of the harness source, the case file and the settings."""
    digest = hashlib.sha256()
    for path in sorted(PACKAGE.glob("*.py")):
        digest.update(path.read_bytes())
    digest.update(Path(case.source).read_bytes())
    digest.update(json.dumps(settings, sort_keys=True).encode())
    digest.update(ngs.__version__.encode())
    return digest.hexdigest()


def _stored(store: Path, case: Case, key: str) -> bool:
    meta_path = store / f"{case.name}.json"
    return all((store / f"{case.name}.{ext}").is_file() for ext in ("json", "csv", "npz")) and \
        json.loads(meta_path.read_text()).get("cache_key") == key


def run_or_reuse(cases: list[Case], settings: dict, results_dir: Path, show_progress: bool = True) -> pd.DataFrame:
    store = ensure_writable(results_dir / "cases")
    keys = {case.name: cache_key(case, settings) for case in cases}
    todo = [case for case in cases if not _stored(store, case, keys[case.name])]
    for case in cases:
        if case not in todo:
            print(f"{case.name}: reusing results computed with the same code and settings")
    models = [MODELS[m] for m in settings["models"]]
    progress = progress_bar(len(todo) * len(models) * settings["levels"], show_progress and bool(todo))
    frames = []
    for case in cases:
        meta_path, csv_path, npz_path = (store / f"{case.name}.{ext}" for ext in ("json", "csv", "npz"))
        if case not in todo:
            frames.append(pd.read_csv(csv_path))
            continue
        collector = SnapshotCollector(settings["levels"])
        frame = run_study([case], models, settings["levels"], on_level=collector, progress=progress)
        write_csv(frame, csv_path)
        collector.save(case.name, npz_path)
        meta = provenance(settings) | {"cache_key": keys[case.name], "case": case.name,
                                       "wall_seconds": frame.attrs["wall_seconds"]}
        write_atomic(meta_path, json.dumps(meta, indent=2))
        frames.append(frame)
    progress.close()
    return pd.concat(frames, ignore_index=True)


def _fmt(value, spec=".3e"):
    return "" if value is None or (isinstance(value, float) and not np.isfinite(value)) else format(value, spec)


def level_table(case: Case, group: pd.DataFrame) -> pd.DataFrame:
    group = group.sort_values("level")
    rates = np.concatenate([[np.nan], pairwise_rates(group.h, group.err_h1)])
    normalised = normalised_errors(group.h, group.err_h1, case.expected_rate, case.expected_log_exponent)
    return pd.DataFrame({
        "level": group.level, "h": [_fmt(v, ".4f") for v in group.h], "ndof": group.ndof,
        "err_h1": [_fmt(v) for v in group.err_h1], "rate": [_fmt(v, ".3f") for v in rates],
        f"err / {case.expected_bound}": [_fmt(v) for v in normalised],
        "err_l2": [_fmt(v) for v in group.err_l2],
        "max penetration": [_fmt(v, ".2e") for v in group.max_penetration],
        "active / constraints": [f"{a} / {n}" for a, n in zip(group.active_constraints, group.n_contact_constraints)],
        "iterations": group.solver_iterations, "KKT residual": [_fmt(v, ".1e") for v in group.kkt_residual],
        "solve s": [_fmt(v, ".2f") for v in group.solve_seconds],
    })


def summary_table(rates: pd.DataFrame) -> pd.DataFrame:
    return pd.DataFrame({
        "case": rates.case, "model": rates.model, "theorem": rates.theorem,
        "expected": [f"h^{fraction(p)}" + (f" |log h|^{fraction(q)}" if q else "") for p, q in zip(rates.expected_rate, rates.expected_log_exponent)],
        "fitted rate": [f"{p:.3f} ± {se:.3f}" for p, se in zip(rates.fitted_rate, rates.fitted_rate_se)],
        "pairwise rates": rates.pairwise_rates, "verdict": rates.verdict,
    })


INTRO = (
    "The Poisson-Signorini problem (2.1)-(2.4): -Δu = f in Ω, u = u_D on Γ_u, ∂u/∂n = g on Γ_g and "
    "u ≥ 0, ∂u/∂n ≥ 0, u ∂u/∂n = 0 on Γ_C (with a gap α and a contact load g_C where a case "
    "declares them). P2 finite elements (NGSolve) on uniformly refined meshes; h halves per level. "
    "Two nonconforming discrete cones: `mean` (K_h, Section 3: vertex values and edge means ≥ 0, the "
    "degrees of freedom of J_h) and `nodal` (K̃_h, Section 5: vertex and midpoint values ≥ 0, the "
    "degrees of freedom of I_h); K̃_h ⊂ K_h by Simpson's rule. Each discrete inequality is solved "
    "exactly: every row's KKT residual is listed. Max penetration is max over Γ_C of α - u_h, "
    "between nodes included: the nonconformity of the cones."
)
RATES_NOTE = (
    "Fitted rate: least squares of log e = log C + p log h + q log|log h| over the last three "
    "levels, q fixed to the theorem's log exponent, with its standard error. Verdict: meets if "
    "within 0.1 of the theorem rate; above/below otherwise. The theorems give upper bounds, so "
    "'above' is consistent with them; 'below' would contradict them."
)


def build_document(cases: list[Case], results: pd.DataFrame, rates: pd.DataFrame, figs: dict,
                   meta: dict) -> Document:
    doc = Document("Quadratic finite elements for the Signorini problem: measured against the theorems")
    doc.paragraph(
        f"Belhachmi and Ben Belgacem, Math. Comp. 72 (2003). Harness {meta['harness_version']} "
        f"(commit {meta['git_commit'][:12]}), NGSolve {meta['ngsolve_version']}, {meta['date']}, "
        f"{meta['machine']['node']} ({meta['machine']['cpus']} cpus); profile {meta['settings']['profile']}, "
        f"{meta['settings']['levels']} levels; study wall time {meta['wall_seconds']:.0f} s.", css="meta")
    doc.heading("Problem and contact models")
    doc.paragraph(INTRO)
    doc.heading("Summary: every case x model")
    doc.paragraph(RATES_NOTE)
    doc.table(summary_table(rates), verdict_column="verdict")
    doc.figures([(figs["summary"]["png"], "Fitted against theorem rates; grey band: ±0.1.")])
    for case in cases:
        doc.heading(f"{case.name}: Theorem {case.theorem}")
        doc.paragraph(f"{case.description}. Regime {case.regime or '-'}, ν = {fraction(case.nu)}; "
                      f"the theorem bounds the H¹ error by C {case.expected_bound}.")
        doc.table(summary_table(rates[rates.case == case.name]), verdict_column="verdict")
        f = figs[case.name]
        doc.figures([(f["convergence"]["png"], "H¹ error against h; dashed: the theorem's bound through the finest point."),
                     (f["contact"]["png"], "Finest level along Γ_C: u_h - α and the discrete contact pressure; shaded: exact contact zone."),
                     (f["solution"]["png"], "u_h on Ω.")])
        for model, group in results[results.case == case.name].groupby("model", sort=False):
            doc.heading(f"model {model}", level=3)
            doc.table(level_table(case, group))
    return doc


def make_report(profile: str = "default", results_dir: Path = Path("results"), report_dir: Path = Path("report"),
                case_names=None, show_progress: bool = True, levels: int | None = None) -> Path:
    if profile not in PROFILES:
        raise ValueError(f"unknown profile {profile!r}; expected one of: {', '.join(PROFILES)}")
    known = registered_cases()
    cases = list(known.values()) if not case_names else [known[n] if n in known else _unknown(n, known) for n in case_names]
    settings = {"profile": profile, "models": list(MODELS), **PROFILES[profile]}
    if levels is not None:
        settings["levels"] = levels
    ensure_writable(report_dir / "figures")
    start = time.perf_counter()
    results = run_or_reuse(cases, settings, Path(results_dir), show_progress)
    rates = rate_table(results, known)
    write_csv(results, Path(results_dir) / "results.csv")
    write_csv(rates, Path(results_dir) / "rates.csv")
    meta = provenance(settings) | {"wall_seconds": time.perf_counter() - start, "cases": [c.name for c in cases]}
    write_atomic(Path(results_dir) / "provenance.json", json.dumps(meta, indent=2))

    figure_dir = Path(report_dir) / "figures"
    figs = {"summary": figures.summary(rates, figure_dir)}
    for case in cases:
        contact, domain = load_snapshots(Path(results_dir) / "cases" / f"{case.name}.npz")
        figs[case.name] = {
            "convergence": figures.convergence(case, results[results.case == case.name], figure_dir),
            "contact": figures.contact(case, contact, figure_dir),
            "solution": figures.domain(case, domain, figure_dir),
        }
    doc = build_document(cases, results, rates, figs, meta)
    write_atomic(Path(report_dir) / "report.md", doc.markdown(Path(report_dir)))
    html_path = write_atomic(Path(report_dir) / "report.html", doc.html())
    return html_path


def _unknown(name, known):
    raise ValueError(f"unknown case {name!r}; known cases: {', '.join(known)}")
