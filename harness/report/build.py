"""`make report`: the study of a profile (computed, or reused, by ``study.planning.cache``: results of a
case are reused while the computing code, the case file and the settings are unchanged), its
rates, figures and the document (Markdown and HTML), from the tables of ``tables`` and the
sentences of ``prose``.
"""
from __future__ import annotations

import datetime
import hashlib
import json
import sys
import time
from pathlib import Path

import numpy as np
import pandas as pd

from ..measure.efficiency import efficiency_table, quantity_efficiency_table, verdicts
from ..measure.quantities import QUANTITY_COLUMNS
from ..measure.rates import rate_table
from ..measure.richardson import quantity_table
from ..methods import DEGREES, METHODS, SWEPT, get_method, methods_named, with_role
from ..methods import known as known_methods
from ..problem.case import REPORT_PROFILES, Case, fraction, registered_cases
from ..study import InProcess
from ..study.chain import PROFILES
from ..study.planning.cache import case_settings, compute, provenance
from ..study.planning.mesh_study import PICTURE_METHOD
from ..study.planning.timing import Timings
from ..study.storage.files import ensure_writable, write_atomic, write_csv
from ..study.storage.folder import all_owned
from ..study.storage.merge import read_rows
from ..study.storage.store import merge_into
from .degree_section import add_degree_section
from .document import Document, anchor
from .figure_jobs import FIGURE_WORKERS, FigurePool
from .latex import write_tables
from .mesh_section import add_mesh_section, mesh_rows
from .plots import method_styles, theorem_label, verdict_cells
from .prediction_section import add_prediction_section
from .prose import (
    EFFICIENCY_NOTE,
    ELASTICITY_NOTE,
    GAMMA_C_NOTE,
    INTRO,
    MATRIX_NOTE,
    RATES_NOTE,
    REGULARITY_NOTE,
    SWEEP_NOTE,
    THREE_D_NOTE,
    TWO_BODY_NOTE,
    belief_finding,
    reference_sentence,
    which_bound,
)
from .quantity_section import add_quantity_section
from .tables import (
    efficiency_view,
    elasticity_view,
    gamma_c_view,
    level_table,
    normalised_view,
    regularity_view,
    summary_table,
    sweep_view,
    three_d_view,
    two_body_view,
)
from .vtk import VtkWriter


def build_document(cases: list[Case], results: pd.DataFrame, rates: pd.DataFrame, efficiency: pd.DataFrame,
                   figs: dict, meta: dict, sweeps: dict | None = None, meshes: pd.DataFrame | None = None,
                   quantities: pd.DataFrame | None = None, quantity_costs: pd.DataFrame | None = None,
                   degrees: pd.DataFrame | None = None) -> Document:
    """The report of a study: what was run, the verdicts at a glance, the problem and methods,
    the rates against the theorems, then the sections a study's cases call for (the cost at
    equal accuracy, quantities, parameter sweeps, meshes, the degree, elasticity, two bodies,
    3D), and each case in full."""
    doc = Document("The Signorini problem in P2 and P1: measured against the theorems")
    settings = meta["settings"]
    _provenance_paragraph(doc, cases, meta)
    doc.contents()
    _glance_section(doc, rates, figs)
    methods = methods_named(settings["methods"])
    _methods_section(doc, methods)
    _summary_section(doc, rates, results, figs)
    _efficiency_section(doc, cases, efficiency, rates, methods)
    if quantities is not None:
        add_quantity_section(doc, quantities, quantity_costs)
    add_prediction_section(doc, cases, results)
    if sweeps:
        _sweep_section(doc, sweeps, figs)
    if meshes is not None and not meshes.empty:
        add_mesh_section(doc, results, meshes, figs)
    if degrees is not None:
        add_degree_section(doc, degrees, figs)
    if any(case.physics.elastic for case in cases):
        _elasticity_section(doc, cases, rates)
    if any(case.bodies == 2 for case in cases):
        _two_body_section(doc, cases, rates, results, figs)
    if any(case.dimension == 3 for case in cases):
        _three_d_section(doc, cases, rates, results, settings)
    _cases_section(doc, cases, results, rates, figs)
    return doc


def _provenance_paragraph(doc: Document, cases: list[Case], meta: dict) -> None:
    """What the report was computed with and how (versions, machine, profile, levels, methods):
    a reader can tell whether two reports are comparable."""
    settings = meta["settings"]
    doc.paragraph(
        f"Belhachmi and Ben Belgacem, Math. Comp. 72 (2003). Harness {meta['harness_version']} "
        f"(commit {meta['git_commit'][:12]}), NGSolve {meta['ngsolve_version']}, {meta['date']}, "
        f"{meta['machine']['node']} ({meta['machine']['cpus']} cpus); profile {settings['profile']}, "
        f"{levels_text(cases, settings)}{left_out_text(cases, settings)}; methods {', '.join(settings['methods'])}; "
        + study_sentence(meta), css="meta")


def _glance_section(doc: Document, rates: pd.DataFrame, figs: dict) -> None:
    """Every verdict in one matrix, first: the answer before the detail."""
    doc.heading("At a glance: every case × method")
    cells = verdict_cells(rates)
    doc.paragraph(MATRIX_NOTE + " " + verdict_counts(rates) + ".")
    doc.matrix(cells, cells.attrs["verdicts"])
    with doc.details("The same as a figure (report/figures/verdict_matrix.pdf, for a paper)", "verdict-matrix-figure"):
        doc.figures([(figs["summary"]["matrix"]["png"], "Fitted / expected H¹ rate, coloured by verdict.")], wide=True)


def _methods_section(doc: Document, methods) -> None:
    """The problem and each method studied, with its order, contact condition and reference
    (and where a method of your own comes from)."""
    doc.heading("Problem and methods")
    doc.paragraph(INTRO)
    own = own_methods_sentence(methods)
    if own:
        doc.paragraph(own)
    doc.table(pd.DataFrame([{"method": m.name, "order": m.order, "contact condition": m.contact,
                             "parameters": m.parameter_text, "reference": m.reference}
                            for m in methods]))


def _summary_section(doc: Document, rates: pd.DataFrame, results: pd.DataFrame, figs: dict) -> None:
    """The fitted rates against the theorems' (figure, and every row on demand), then the
    regularity check by the best approximation when the study measured it."""
    doc.heading("Summary: fitted against expected rates")
    doc.paragraph(RATES_NOTE)
    doc.figures([(figs["summary"]["rates"]["png"], "Fitted against theory rates; grey band: ±0.1; the points outside it named.")],
                wide=True)
    with doc.details(f"Every case × method: both theories, fitted rate ± standard error, pairwise rates, L² rate "
                     f"({len(rates)} rows)", "summary-table"):
        doc.table(summary_table(rates), verdict_column="verdict")
    if "fitted_rate_best" in rates and rates.fitted_rate_best.notna().any():
        doc.heading("Regularity check: best approximation")
        doc.paragraph(REGULARITY_NOTE)
        doc.table(regularity_view(rates, results), verdict_column="verdict")
        doc.heading("Errors on Γ_C")
        doc.paragraph(GAMMA_C_NOTE)


def _sweep_section(doc: Document, sweeps: dict, figs: dict) -> None:
    """Penalty's and Nitsche's errors over their parameter: where it is safe to choose."""
    doc.heading("Penalty and Nitsche: where their parameter is safe")
    doc.paragraph(SWEEP_NOTE)
    for name, frame in sweeps.items():
        doc.figures([(figs["sweeps"][name]["png"], f"{name}: H¹ error and largest penetration against ε₀ / γ₀.")],
                    wide=True)
        doc.table(sweep_view(frame))


def _elasticity_section(doc: Document, cases: list[Case], rates: pd.DataFrame) -> None:
    """The elastic cases' rates in one table, apart from the scalar cases' (Remark 2.3)."""
    doc.heading("Unilateral contact in linear elasticity (Remark 2.3)")
    doc.paragraph(ELASTICITY_NOTE)
    doc.table(elasticity_view(cases, rates))


def _two_body_section(doc: Document, cases: list[Case], rates: pd.DataFrame, results: pd.DataFrame, figs: dict) -> None:
    """The two-body cases (the paper's Section 6 names them as the next step), with the first
    one's non-matching meshes at the interface."""
    doc.heading("Two bodies, non-matching meshes (Section 6)")
    doc.paragraph(TWO_BODY_NOTE)
    doc.table(two_body_view(cases, rates, results), verdict_column="verdict")
    first = next(case for case in cases if case.bodies == 2)
    if figs.get(first.name, {}).get("interface") is not None:
        doc.figures([(figs[first.name]["interface"]["png"], f"{first.name}: the two meshes at the interface on level 1.")],
                    wide=True)


def _three_d_section(doc: Document, cases: list[Case], rates: pd.DataFrame, results: pd.DataFrame, settings: dict) -> None:
    """The 3D cases (the paper's Section 6 names 3D as open), with their own number of levels."""
    doc.heading("Three dimensions (Section 6)")
    doc.paragraph(THREE_D_NOTE + f" Levels: {settings.get('levels_3d', settings['levels'])} per 3D case.")
    doc.table(three_d_view(cases, rates, results), verdict_column="verdict")


def _cases_section(doc: Document, cases: list[Case], results: pd.DataFrame, rates: pd.DataFrame, figs: dict) -> None:
    """Each case in full, collapsed under its verdicts: the report stays navigable with many."""
    doc.heading("Cases")
    doc.paragraph("Each case in full (click to open): its regime and bound, every method's fitted rates against "
                  "both theories, the errors on Γ_C, the figures, and every level of every method.")
    for case in cases:
        with doc.details(f"{case.name}: P2 {theorem_label(case.theorem)}", anchor(case.name),
                         verdict_counts(rates[rates.case == case.name]), listed=case.name):
            _case_section(doc, case, results, rates, figs)


def _efficiency_section(doc: Document, cases: list[Case], efficiency: pd.DataFrame, rates: pd.DataFrame, methods) -> None:
    claims = verdicts(efficiency, rates, methods=methods)
    if claims:
        doc.heading("Is P2 worth it? Cost at equal accuracy")
        doc.paragraph(EFFICIENCY_NOTE)
        for case in cases:
            if case.name in claims:
                doc.paragraph(f"{case.name}: {claims[case.name]}")
        doc.table(efficiency_view(efficiency))


def own_methods_sentence(methods) -> str:
    """A sentence naming the methods of the report that are not the harness's own (from a file,
    a module, an installed package or Python), and where each comes from; "" if none."""
    own = [m for m in methods if METHODS.get(m.name.split(":")[0]) is None]
    if not own:
        return ""
    described = "; ".join(f"`{m.name}` (P{m.order}: {m.contact}; {m.reference}"
                          + (f"; from {m.source}" if m.source else "") + ")" for m in own)
    return (f"Beside the harness's methods, this report studies {'a method' if len(own) == 1 else 'methods'} "
            f"of your own: {described}. Every table, figure and verdict below treats "
            f"{'it' if len(own) == 1 else 'them'} as the harness's own.")


def in_profile(cases, profile: str) -> list[Case]:
    """The cases a report of ``profile`` runs: those whose ``report_profile`` is that one or a
    cheaper one (``REPORT_PROFILES``)."""
    rank = REPORT_PROFILES.index(profile)
    return [case for case in cases if REPORT_PROFILES.index(case.report_profile) <= rank]


def left_out_text(cases: list[Case], settings: dict) -> str:
    """The registered cases a full report of this profile leaves out for their cost (nothing
    for a report of chosen cases, ``--case``)."""
    names = {case.name for case in cases}
    registered = registered_cases().values()
    if not all(case.name in names for case in in_profile(registered, settings["profile"])):
        return ""
    left = [case.name for case in registered if case.name not in names]
    return (f"; left out of this profile for their cost: {', '.join(left)} (make report-fine, or report --case NAME)"
            if left else "")


def levels_text(cases: list[Case], settings: dict) -> str:
    """How many P2 levels the 2D cases ran: the profile's, fewer for the cases whose fits are
    asymptotic earlier (``Case.asymptotic_levels``) and for those whose levels cost more than the
    profile allows (``Case.report_levels``; ``study.planning.cache.case_settings``)."""
    fewer: dict[int, list[str]] = {}
    budget: dict[int, list[str]] = {}
    for case in cases:
        levels = case_settings(case, settings)["levels"]
        if case.dimension == 2 and levels < settings["levels"]:
            capped = dict(case.report_levels or ()).get(settings.get("profile")) == levels
            (budget if capped else fewer).setdefault(levels, []).append(case.name)
    text = f"{settings['levels']} P2 levels"
    if fewer:
        text += " (" + "; ".join(f"{n} for {', '.join(names)}" for n, names in sorted(fewer.items())) + \
            ": their fitted H¹ rates are asymptotic by then, one level more moved none by more than 0.01)"
    if budget:
        text += " (" + "; ".join(f"{n} for {', '.join(names)}" for n, names in sorted(budget.items())) + \
            ": their levels cost more, the profile's budget stops them there)"
    with_p2 = [case.name for case in cases if case_settings(case, settings).get("p1_extra_levels") == 0]
    text += ", P1 one level more (to P2's finest number of dofs)"
    if with_p2:
        text += (f" except for {', '.join(with_p2)}, where P1 stops with P2: its fitted H¹ rates are asymptotic "
                 "by then, the extra level moved none by more than 0.01")
    return text


def verdict_counts(rates: pd.DataFrame) -> str:
    """"5 meet, 1 above, 1 no theory": the verdicts of some rate rows."""
    counts = rates.verdict.value_counts()
    return ", ".join(f"{n} {'meet' if v == 'meets' and n > 1 else v}" for v, n in counts.items())


def _case_section(doc: Document, case: Case, results: pd.DataFrame, rates: pd.DataFrame, figs: dict) -> None:
    """One case's part of the report."""
    if case.physics.elastic:
        doc.paragraph(f"Physics: {case.physics.describe()}.")
    doc.paragraph(f"{case.description}. Regime {case.regime or '-'}, "
                  + (f"ν = {fraction(case.nu)}; " if np.isfinite(case.nu) else "ν not declared; ")
                  + (f"the authors believe (no theorem) the P2 H¹ error behaves like {case.expected_bound}."
                     if case.conjectured else f"the paper bounds the P2 H¹ error by C {case.expected_bound}."))
    against = reference_sentence(case, results)
    if against:
        doc.paragraph(against)
    doc.table(summary_table(rates[rates.case == case.name]), verdict_column="verdict")
    if case.conjectured:
        doc.paragraph(belief_finding(case, rates))
    sentences = "" if case.conjectured else which_bound(case, rates, results)   # no bound to follow
    if sentences:
        doc.paragraph(sentences)
    if case.expected_log_exponent:
        view = normalised_view(case, results)
        if view is not None:
            doc.table(view)
    if "err_trace_l2" in results:
        doc.paragraph("On Γ_C, finest level (the paper's Section 5 remark; the measures are defined "
                      "under 'Errors on Γ_C' above):")
        doc.table(gamma_c_view(rates, results, case.name))
    f = figs[case.name]
    doc.figures([(f["convergence"]["png"], "H¹ error against h; dashed: each theory's bound through the coarsest point."),
                 (f["contact"]["png"], _contact_caption(case))])
    if f.get("interface") is not None:
        doc.figures([(f["interface"]["png"], "The two bodies' meshes at the interface on level 1: independent, not matching on Γ_C.")],
                    wide=True)
    doc.figures([(f["efficiency"]["png"], "H¹ error against ndof and against seconds summed over the levels; dotted: the target.")],
                wide=True)
    if f["solution"] is not None:
        doc.figures([(f["solution"]["png"], "Deformed shape: the mesh moved by u_h (magnified), coloured by |u_h|; grey: the body at rest."
                      if case.physics.elastic else "u_h on Ω.")])
    for method, group in results[results.case == case.name].groupby("method", sort=False):
        doc.heading(f"{case.name}: method {method}", level=3, key=f"{anchor(case.name)}-{method}")
        doc.table(level_table(group, energy=case.physics.elastic))


def _contact_caption(case: Case) -> str:
    if case.bodies == 2:
        return ("Finest level along Γ_C: the opening [u_h] - 2α of the interface (sampled on the intersection of the two "
                "trace meshes) and the mortar pressure per slave edge; shaded: exact contact zone.")
    if case.dimension == 2:
        return "Finest level along Γ_C: u_h - α and the discrete contact pressure; shaded: exact contact zone."
    return "Γ_C from below, finest level: u_h - α and the discrete pressure per triangle."


def computed_since(cases, store: Path, since: datetime.datetime) -> list[str]:
    """The cases whose stored results (``study.planning.cache``) were written by this run."""
    def date(case):
        meta = store / f"{case.name}.json"
        return datetime.datetime.fromisoformat(json.loads(meta.read_text())["date"]) if meta.is_file() else None
    return [case.name for case in cases if (d := date(case)) is not None and d >= since]


def study_sentence(meta: dict) -> str:
    """How the study of this report was obtained: computed now (wall time, engine), reused from
    the results cache, or both."""
    computed, total = len(meta.get("computed", meta["cases"])), len(meta["cases"])
    engine = f" {meta['engine']}" if meta.get("engine") else ""
    if computed == total:
        return f"study wall time {meta['wall_seconds']:.3g} s{engine}."
    if computed == 0:
        return "study reused from results/cases (same computing code, case files and settings)."
    return (f"{computed} of {total} cases computed in this run (wall time {meta['wall_seconds']:.3g} s{engine}), "
            f"the rest reused from results/cases.")


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
    with FigurePool(method_styles(drawn), Path(report_dir) / "figures", store=results_dir / "cases") as pool:
        results, sweeps, meshes, degrees = compute(cases, settings, results_dir, sweep_cases, show_progress, engine,
                                                   check_memory, timings, writer, listener=pool)
        with timings("rates"):
            rates = rate_table(results)
            efficiency = efficiency_table(results, methods=methods)
            quantities = quantity_table(pd.concat([results, meshes], ignore_index=True) if not meshes.empty else results)
            quantity_costs = quantity_efficiency_table(results, QUANTITY_COLUMNS, methods=methods)
        with timings("writing", "results"):
            stored = merge_into(results_dir, results)
            if stored.merged.kept:
                print(stored.summary(), file=sys.stderr)
            if not meshes.empty:
                write_csv(meshes, results_dir / "meshes.csv")
            if not degrees.empty:
                write_csv(degrees, results_dir / "degrees.csv")
            write_csv(rates, results_dir / "rates.csv")
            write_csv(efficiency, results_dir / "efficiency.csv")
            write_csv(quantities, results_dir / "quantities.csv")
            write_csv(quantity_costs, results_dir / "quantity_efficiency.csv")
        meta = provenance(settings, methods) | {"wall_seconds": time.perf_counter() - start, "cases": [c.name for c in cases],
                                       "engine": (engine or InProcess()).describe(),
                                       "computed": computed_since(cases, results_dir / "cases", run_started)}
        write_atomic(results_dir / "provenance.json", json.dumps(meta, indent=2))
        with timings("figures", f"drawn in {FIGURE_WORKERS} processes (after the study)"):
            pool.summary(rates)
            for name, frame in sweeps.items():
                pool.sweep(known[name], frame)
            both = mesh_rows(results, meshes)
            for name in dict.fromkeys(meshes.case) if not meshes.empty else []:
                adaptive = next((p for p in sorted((results_dir / "meshes").glob(f"{name}-adaptive*.npz"))), None)
                pool.meshes_of(known[name], both[both.case == name], adaptive or Path("-"), PICTURE_METHOD)
            for name in dict.fromkeys(degrees.case) if not degrees.empty else []:
                pool.degrees_of(known[name], degrees[degrees.case == name])
            figs, seconds = pool.collect()
    for name, spent in seconds.items():
        timings.add("figures (in workers)", name, "", spent)
    with timings("document"):
        doc = build_document(cases, results, rates, efficiency, figs, meta, sweeps, meshes, quantities, quantity_costs,
                             degrees)
    with timings("writing", "report"):
        write_tables(results, rates, efficiency, Path(report_dir) / "tables")
        write_atomic(Path(report_dir) / "report.md", doc.markdown(Path(report_dir)))
        html_path = write_atomic(Path(report_dir) / "report.html", doc.html())
    timings.add("total", "wall", "", time.perf_counter() - start)
    write_csv(timings.frame(), results_dir / "report_profile.csv")
    return html_path


def _unknown(name, known):
    raise ValueError(f"unknown case {name!r}; known cases: {', '.join(known)}")
