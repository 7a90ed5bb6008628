"""The results page: what the last `make report` measured, generated from its CSVs with the
report's own table views (``harness.report``), so the page and report.html show the same numbers.

Its sections are what the prose pages (guide/findings.md, the theory pages) point to for figures:
"Verdicts on uniform meshes", "Cost at equal accuracy", "Meshes that fit the singularity",
"Beyond one H¹ number", "Quantities of interest with error bars".
"""
from __future__ import annotations

import json
from pathlib import Path

import pandas as pd
from tables import markdown_table, stamp

PLACEHOLDER = ("No results were found when these pages were built: run `make report`, then `make docs`, "
               "and this page shows the rates, verdicts and costs of that report.\n")


def _read(folder: Path, name: str) -> pd.DataFrame:
    path = folder / name
    return pd.read_csv(path) if path.is_file() else pd.DataFrame()


def verdict_section(rates: pd.DataFrame) -> list[str]:
    from harness.report.tables import summary_table
    uniform = rates[rates["mesh"] == "uniform"] if "mesh" in rates else rates
    counts = uniform.verdict.value_counts()
    return ["## Verdicts on uniform meshes\n",
            "Every case × method: the fitted H¹ rate (with its standard error and the pairwise rates) against "
            "the method's theory (the report's summary table names each theorem) and, for the cones, Drouet & "
            "Hild's sharper bound. Counts: "
            + ", ".join(f"{n} {v}" for v, n in counts.items()) + ".\n",
            markdown_table(summary_table(uniform.reset_index(drop=True)).drop(columns=["theory"]))]


def cost_section(efficiency: pd.DataFrame) -> list[str]:
    from harness.report.tables import efficiency_view
    if efficiency.empty:
        return []
    return ["## Cost at equal accuracy\n",
            "Per case, each method's dofs and seconds interpolated at a common target H¹ error, and P1's "
            "over P2's (`efficiency.csv`).\n",
            markdown_table(efficiency_view(efficiency))]


def mesh_section(results: pd.DataFrame, meshes: pd.DataFrame) -> list[str]:
    from harness.measure.rates import rate_table
    from harness.report.sections.meshes import effectivity_view, mesh_rows, ndof_rates_view
    if meshes.empty:
        return []
    frame = mesh_rows(results, meshes)
    return ["## Meshes that fit the singularity\n",
            "The report's mesh study: rates fitted against N on uniform, graded and adaptive meshes, the "
            "estimator's rate and its effectivity η / ‖u − u_h‖ₐ (`meshes.csv`).\n",
            markdown_table(ndof_rates_view(rate_table(frame))),
            "\nThe effectivity over the levels of each chain:\n",
            markdown_table(effectivity_view(frame[frame.mesh != "uniform"]))]


def regularity_section(rates: pd.DataFrame, results: pd.DataFrame) -> list[str]:
    from harness.report.tables import regularity_view
    view = regularity_view(rates[rates["mesh"] == "uniform"] if "mesh" in rates else rates, results)
    if view.empty:
        return []
    return ["## Beyond one H¹ number\n",
            "The best approximation R_h u of each order: its fitted rate against min(ν − 1, k) (an independent "
            "check of each case's declared regularity) and what each contact discretisation costs beyond it, "
            "err / best on the finest level.\n",
            markdown_table(view)]


def quantity_section(quantities: pd.DataFrame) -> list[str]:
    from harness.report.sections.quantities import coverage_misses, coverage_sentence, miss_reason
    if quantities.empty:
        return []
    misses = coverage_misses(quantities)
    return ["## Quantities of interest with error bars\n",
            "Each chain's contact force, contact zone, peak pressure, energy and penetration with Richardson's "
            "extrapolation and the grid convergence index (`quantities.csv`). " + coverage_sentence(quantities) + "\n",
            *([f"\nWhere the band misses the exact value in the asymptotic range{miss_reason(quantities)}:\n",
               markdown_table(misses)]
              if not misses.empty else [])]


def results_page(folder: Path) -> str:
    """The page for the report whose results folder is ``folder``, stamped with its provenance;
    what to run where there is none."""
    rates_path, provenance_path = folder / "rates.csv", folder / "provenance.json"
    if not rates_path.is_file() or not provenance_path.is_file():
        return PLACEHOLDER
    provenance = json.loads(provenance_path.read_text())
    rates, results = pd.read_csv(rates_path), _read(folder, "results.csv")
    text = [f"Generated from `{folder}` of the report computed by {stamp(provenance)}.\n"]
    text += verdict_section(rates)
    text += cost_section(_read(folder, "efficiency.csv"))
    if not results.empty:
        text += mesh_section(results, _read(folder, "meshes.csv"))
        text += regularity_section(rates, results)
    text += quantity_section(_read(folder, "quantities.csv"))
    return "\n".join(text)
