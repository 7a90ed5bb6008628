"""The report's sections, one module each, in the order the document shows them (``SECTIONS``).

A section module holds everything of its part of the report but what it computes: its text and
tables, ``write(doc, plan)`` (from the plan, ``report.plan.ReportPlan``; a section the study does
not call for writes nothing), and, where it has figures, their jobs,
``queue_figures(pool, plan, known, results_dir)`` (``report.figure_jobs.FigurePool.job``: which
function draws what, in a worker; its figures come back in the plan's ``figs``, under the section's
``GROUP`` if it declares one). What a section shows is computed by the study's planning
(``study.planning``: ``mesh_study`` for ``meshes``, ``degree_study`` for ``degrees``, ``sweep``
for ``sweeps``, ``cache`` for every case's rows), which each module names; the report imports
the study, never the reverse. ``report.build.build_document`` walks ``SECTIONS``.
"""
from __future__ import annotations

from pathlib import Path

from ..figure_jobs import FIGURE_WORKERS, FigurePool
from . import (
    cases,
    codes,
    coulomb,
    degrees,
    efficiency,
    elasticity,
    friction,
    glance,
    meshes,
    methods,
    prediction,
    provenance,
    quantities,
    summary,
    sweeps,
    three_d,
    two_bodies,
)

# the document's order: what was run, the verdicts at a glance, the problem and methods, the
# rates against the theorems, then the sections a study's cases call for (the cost at equal
# accuracy, quantities, closed-form theories, parameter sweeps, meshes, the degree, elasticity,
# two bodies, 3D, Tresca friction, Coulomb friction, other codes), and each case in full
SECTIONS = (provenance, glance, methods, summary, efficiency, quantities, prediction, sweeps, meshes, degrees,
            elasticity, two_bodies, three_d, friction, coulomb, codes, cases)


def figure_groups() -> tuple[str, ...]:
    """The groups the sections' figures are collected under (``GROUP`` of a section)."""
    return tuple(section.GROUP for section in SECTIONS if hasattr(section, "GROUP"))


def figure_pool(methods, folder: Path, store: Path | None = None, workers: int = FIGURE_WORKERS) -> FigurePool:
    """The pool that draws the report's figures (``report.figure_jobs.FigurePool``): a case's
    figures queued as soon as it is stored (``cases.queue_case_figures``), every section's
    group collected."""
    return FigurePool(methods, folder, workers=workers, store=store, groups=figure_groups(),
                      on_stored=cases.queue_case_figures)


def queue_figures(pool: FigurePool, plan, known: dict, results_dir: Path) -> None:
    """Every section's figures drawn from the finished study (``queue_figures`` of a section),
    in the document's order."""
    for section in SECTIONS:
        if hasattr(section, "queue_figures"):
            section.queue_figures(pool, plan, known, results_dir)
