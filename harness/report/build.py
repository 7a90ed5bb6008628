"""`make report`: the study of a profile (computed, or reused, by ``study.planning.cache``: results of a
case are reused while the computing code, the case file and the settings are unchanged), its
rates (the plan, ``plan.plan_report``), figures and the document (Markdown and HTML), whose
sections (``sections.SECTIONS``) each write their part from the plan.
"""
from __future__ import annotations

import datetime
import hashlib
import json
import sys
import time
from pathlib import Path

from ..methods import DEGREES, SWEPT, get_method, methods_named, with_role
from ..methods import known as known_methods
from ..problem.case import registered_cases
from ..study import InProcess
from ..study.chain import PROFILES
from ..study.planning.cache import compute, provenance
from ..study.planning.timing import Timings
from ..study.storage.files import ensure_writable, write_atomic, write_csv
from ..study.storage.folder import all_owned
from ..study.storage.merge import read_rows
from ..study.storage.store import merge_into
from .document import Document
from .figure_jobs import FIGURE_WORKERS
from .latex import write_tables
from .plan import ReportPlan, in_profile, plan_report
from .plots import method_styles
from .sections import SECTIONS, figure_pool, queue_figures
from .sections.provenance import left_out_text  # noqa: F401  (a name of this module's before the sections)
from .vtk import VtkWriter


def build_document(plan: ReportPlan) -> Document:
    """The report of a study: each section of ``sections.SECTIONS`` in turn writes its part from
    ``plan`` (what was run, the verdicts at a glance, the problem and methods, the rates against
    the theorems, then the sections a study's cases call for, and each case in full)."""
    doc = Document("The Signorini problem in P2 and P1: measured against the theorems")
    for section in SECTIONS:
        section.write(doc, plan)
    return doc


def computed_since(cases, store: Path, since: datetime.datetime) -> list[str]:
    """The cases whose stored results (``study.planning.cache``) were written by this run."""
    def date(case):
        meta = store / f"{case.name}.json"
        return datetime.datetime.fromisoformat(json.loads(meta.read_text())["date"]) if meta.is_file() else None
    return [case.name for case in cases if (d := date(case)) is not None and d >= since]


def make_report(profile: str = "default", results_dir: Path = Path("results"), report_dir: Path = Path("report"),
                case_names=None, show_progress: bool = True, levels: int | None = None, methods=("all",),
                engine=None, check_memory: bool = True, vtk: bool = False) -> Path:
    """Run (or reuse) the study of a profile, its sweeps, rates and figures, and write the report;
    ``engine``: where the jobs run (``execution``; default this process). Where the time went is
    written to ``results_dir/report_profile.csv`` (``timing``). ``vtk``: also write every level's
    solutions of the studies as ParaView files under ``results_dir/vtk`` (``vtk``; a stored case
    without them is run again)."""
    if profile not in PROFILES:
        raise ValueError(f"unknown profile {profile!r}; expected one of: {', '.join(PROFILES)}")
    known = registered_cases()
    cases = (in_profile(known.values(), profile) if not case_names
             else [known[n] if n in known else _unknown(n, known) for n in case_names])
    everything = methods == "all" or tuple(methods) == ("all",)
    methods = methods_named(methods)                # names, groups, files, modules, Method objects
    # the degree study: the methods of the role DEGREES, and (named) any of order > 2
    studied = {m.name for m in with_role(DEGREES, methods)}
    degree = [m.name for m in methods if m.name in studied or not everything and m.order > 2]
    if everything:                                  # "all": the methods of the profile's orders
        methods = [m for m in methods if m.order in PROFILES[profile]["orders"]]
    settings = {"profile": profile, "methods": [m.name for m in methods], **PROFILES[profile],
                "degree_methods": degree if any(get_method(name).order > 2 for name in degree) else []}
    if case_names:
        settings["cases_given"] = True          # the degree study too runs the named cases only
    files = method_files(methods)
    if files:
        settings["method_files"] = files         # a method of your own: its results change with its file
    if levels is not None:
        settings["levels"], settings["stop_when_asymptotic"], settings["levels_given"] = levels, False, True
        settings["mesh_levels"] = min(settings["mesh_levels"], levels)
        settings["mesh_levels_3d"] = min(settings["mesh_levels_3d"], levels)
        settings["degree_levels"] = min(settings["degree_levels"], levels)
        settings["hp_levels"] = min(settings["hp_levels"], levels)
    results_dir, report_dir = Path(results_dir), Path(report_dir)
    with all_owned([results_dir, report_dir]):
        read_rows(results_dir / "results.csv")      # refused before the study if it is not a results CSV
        with known_methods(methods):                # the study and the document find them by name
            return _build(cases, known, settings, results_dir, report_dir, show_progress, engine, check_memory, vtk)


def method_files(methods) -> dict[str, str]:
    """{name: sha256 of its file} of the methods defined outside the package (``methods.method.Method.source``):
    in the settings, whose hash keys the cached results (``study.planning.cache``), so that a changed file
    runs its method again."""
    files = {}
    for m in methods:
        if m.source and Path(m.source).is_file():
            files[m.name] = hashlib.sha256(Path(m.source).read_bytes()).hexdigest()
    return files


def _build(cases, known, settings, results_dir: Path, report_dir: Path, show_progress, engine, check_memory, vtk) -> Path:
    """``make_report``'s work, in folders this process owns."""
    ensure_writable(report_dir / "figures")
    timings = Timings()
    start = time.perf_counter()
    run_started = datetime.datetime.now(datetime.timezone.utc).replace(microsecond=0)
    methods = methods_named(settings["methods"])
    sweep_cases = cases if with_role(SWEPT, methods) else []
    writer = VtkWriter(results_dir / "vtk") if vtk else None
    # the figures are drawn as the cases are stored, on the cores the study leaves free
    drawn = methods + [m for m in methods_named(settings.get("degree_methods") or []) if m not in methods]
    with figure_pool(method_styles(drawn), Path(report_dir) / "figures", store=results_dir / "cases") as pool:
        results, sweeps, meshes, degrees = compute(cases, settings, results_dir, sweep_cases, show_progress, engine,
                                                   check_memory, timings, writer, listener=pool)
        with timings("rates"):
            plan = plan_report(cases, results, sweeps, meshes, degrees, methods)
        with timings("writing", "results"):
            _write_results(plan, results_dir)
        meta = provenance(settings, methods) | {"wall_seconds": time.perf_counter() - start, "cases": [c.name for c in cases],
                                       "engine": (engine or InProcess()).describe(),
                                       "computed": computed_since(cases, results_dir / "cases", run_started)}
        write_atomic(results_dir / "provenance.json", json.dumps(meta, indent=2))
        with timings("figures", f"drawn in {FIGURE_WORKERS} processes (after the study)"):
            queue_figures(pool, plan, known, results_dir)
            figs, seconds = pool.collect()
    for name, spent in seconds.items():
        timings.add("figures (in workers)", name, "", spent)
    with timings("document"):
        doc = build_document(plan.completed(meta, figs))
    with timings("writing", "report"):
        write_tables(results, plan.rates, plan.efficiency, Path(report_dir) / "tables")
        write_atomic(Path(report_dir) / "report.md", doc.markdown(Path(report_dir)))
        html_path = write_atomic(Path(report_dir) / "report.html", doc.html())
    timings.add("total", "wall", "", time.perf_counter() - start)
    write_csv(timings.frame(), results_dir / "report_profile.csv")
    return html_path


def _write_results(plan: ReportPlan, results_dir: Path) -> None:
    """The study's rows merged into ``results_dir/results.csv`` and the tables of the plan beside them."""
    stored = merge_into(results_dir, plan.results)
    if stored.merged.kept:
        print(stored.summary(), file=sys.stderr)
    if not plan.meshes.empty:
        write_csv(plan.meshes, results_dir / "meshes.csv")
    if not plan.degrees.empty:
        write_csv(plan.degrees, results_dir / "degrees.csv")
    write_csv(plan.rates, results_dir / "rates.csv")
    write_csv(plan.efficiency, results_dir / "efficiency.csv")
    write_csv(plan.quantities, results_dir / "quantities.csv")
    write_csv(plan.quantity_costs, results_dir / "quantity_efficiency.csv")


def _unknown(name, known):
    raise ValueError(f"unknown case {name!r}; known cases: {', '.join(known)}")
