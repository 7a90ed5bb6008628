"""What the report's document is written from: the plan (``ReportPlan``), built by one function
(``plan_report``) from the study's rows (``study.planning.cache.compute``) and the tables the
measure stage derives from them; ``report.build`` completes it with the provenance and the
drawn figures, and every section (``report.sections``) reads what it shows from it. Also which
cases a report of a profile runs (``in_profile``).
"""
from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field

import pandas as pd

from ..measure.efficiency import efficiency_table, quantity_efficiency_table
from ..measure.quantities import QUANTITY_COLUMNS
from ..measure.rates import rate_table
from ..measure.richardson import quantity_table
from ..methods import methods_named
from ..problem.case import REPORT_PROFILES, Case


@dataclass(frozen=True)
class ReportPlan:
    """Everything the document shows: the cases, the study's rows (``results``; the sweeps by
    case, the mesh study's and the degree study's rows), the rates, the cost at equal accuracy,
    the quantities of interest with their costs, the provenance (``meta``, whose ``settings`` are
    the report's) and the drawn figures (``figs``, by name: a case's, "summary", and the groups
    "sweeps", "meshes", "degree_study" by case)."""

    cases: list[Case]
    results: pd.DataFrame
    rates: pd.DataFrame
    efficiency: pd.DataFrame
    sweeps: dict | None = None
    meshes: pd.DataFrame | None = None
    quantities: pd.DataFrame | None = None
    quantity_costs: pd.DataFrame | None = None
    degrees: pd.DataFrame | None = None
    meta: dict = field(default_factory=dict)
    figs: dict = field(default_factory=dict)

    @property
    def settings(self) -> dict:
        """The report's settings (profile, levels, methods, ...), as stored in its provenance."""
        return self.meta["settings"]

    @property
    def methods(self) -> list:
        """The report's methods (``methods.method.Method``), in the report's order."""
        return methods_named(self.settings["methods"])

    def completed(self, meta: dict, figs: dict) -> "ReportPlan":
        """This plan with the report's provenance and its drawn figures."""
        return dataclasses.replace(self, meta=meta, figs=figs)


def plan_report(cases: list[Case], results: pd.DataFrame, sweeps: dict, meshes: pd.DataFrame,
                degrees: pd.DataFrame, methods) -> ReportPlan:
    """The plan of a report of ``cases`` and ``methods``: the study's rows and their rates
    (``measure.rates.rate_table``), the cost at equal accuracy (``measure.efficiency``), the
    quantities of interest with their error bars (``measure.richardson.quantity_table``, the mesh
    study's rows included) and their costs."""
    return ReportPlan(
        cases=cases, results=results, rates=rate_table(results),
        efficiency=efficiency_table(results, methods=methods), sweeps=sweeps, meshes=meshes,
        quantities=quantity_table(pd.concat([results, meshes], ignore_index=True) if not meshes.empty else results),
        quantity_costs=quantity_efficiency_table(results, QUANTITY_COLUMNS, methods=methods), degrees=degrees)


def in_profile(cases, profile: str) -> list[Case]:
    """The cases a report of ``profile`` runs: those whose ``report_profile`` is that one or a
    cheaper one (``REPORT_PROFILES``)."""
    rank = REPORT_PROFILES.index(profile)
    return [case for case in cases if REPORT_PROFILES.index(case.report_profile) <= rank]
