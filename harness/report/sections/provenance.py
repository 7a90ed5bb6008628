"""The report's opening: what it was computed with and how (versions, machine, profile, the
levels of its cases, the cases a profile leaves out, its methods, how the study was obtained), and
the table of contents. The levels each case runs are the planning's
(``study.planning.cache.case_settings``); whether the study was computed or reused, its cache's
(``study.planning.cache``)."""
from __future__ import annotations

from ...problem.case import Case, registered_cases
from ...study.planning.cache import case_settings
from ..document import Document
from ..plan import ReportPlan, in_profile


def write(doc: Document, plan: ReportPlan) -> None:
    """What the report was computed with and how: a reader can tell whether two reports are
    comparable; then the contents."""
    cases, meta, settings = plan.cases, plan.meta, plan.settings
    doc.paragraph(
        f"Belhachmi and Ben Belgacem, Math. Comp. 72 (2003). Harness {meta['harness_version']} "
        f"(commit {meta['git_commit'][:12]}), NGSolve {meta['ngsolve_version']}, {meta['date']}, "
        f"{meta['machine']['node']} ({meta['machine']['cpus']} cpus); profile {settings['profile']}, "
        f"{levels_text(cases, settings)}{left_out_text(cases, settings)}; methods {', '.join(settings['methods'])}; "
        + study_sentence(meta), css="meta")
    doc.contents()


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
