"""The generated pages' tables, from the code that owns what they list (no hand-copied table)."""
import os
from pathlib import Path

import pandas as pd


def markdown_table(frame: pd.DataFrame) -> str:
    """A DataFrame as a Markdown pipe table (pipes inside cells escaped)."""
    def cell(value) -> str:
        text = "" if pd.isna(value) else str(value)
        return text.replace("|", "\\|").replace("\n", " ")
    lines = ["| " + " | ".join(map(str, frame.columns)) + " |", "|" + "---|" * len(frame.columns)]
    lines += ["| " + " | ".join(cell(v) for v in row) + " |" for row in frame.itertuples(index=False)]
    return "\n".join(lines) + "\n"


def columns_table(meanings: dict[str, str]) -> pd.DataFrame:
    return pd.DataFrame({"column": [f"`{name}`" for name in meanings], "meaning": list(meanings.values())})


def stamp(provenance: dict) -> str:
    """Which harness, commit, date and machine produced a generated page's numbers."""
    machine = provenance.get("machine", {})
    return (f"harness {provenance.get('harness_version', '?')}, commit `{str(provenance.get('git_commit', '?'))[:12]}`, "
            f"NGSolve {provenance.get('ngsolve_version', '?')}, {provenance.get('date', '?')}, "
            f"{machine.get('cpus', '?')} CPUs ({machine.get('platform', '?')}); profile "
            f"{provenance.get('settings', {}).get('profile', '?')}, wall time {provenance.get('wall_seconds', float('nan')):.0f} s")


def results_page(results: Path) -> str:
    """The results page: the verdicts and rates of the last `make report` whose results folder is
    ``results``, stamped with its provenance; what to run where there is none."""
    import json
    rates_path, provenance_path = results / "rates.csv", results / "provenance.json"
    if not rates_path.is_file() or not provenance_path.is_file():
        return ("No results were found when these pages were built: run `make report`, then `make docs`, "
                "and this page shows the rates and verdicts of that report.\n")
    provenance = json.loads(provenance_path.read_text())
    rates = pd.read_csv(rates_path)
    uniform = rates[rates["mesh"] == "uniform"] if "mesh" in rates else rates
    counts = uniform.verdict.value_counts()
    table = uniform[["case", "method", "expected_rate", "fitted_rate", "fitted_rate_se", "verdict"]].round(3)
    text = [f"Generated from `{rates_path}` of the report computed by {stamp(provenance)}.\n",
            "Verdicts on uniform meshes: " + ", ".join(f"{n} {v}" for v, n in counts.items()) + ".\n",
            markdown_table(table)]
    efficiency = results / "efficiency.csv"
    if efficiency.is_file():
        cost = pd.read_csv(efficiency)
        text += ["\n## Cost at equal accuracy\n", markdown_table(cost.round(3))]
    return "\n".join(text)


def write_generated(folder: Path) -> None:
    from harness import case_table, method_table
    from harness.measure.efficiency import COLUMN_MEANINGS as EFFICIENCY
    from harness.measure.rates import COLUMN_MEANINGS as RATES
    from harness.study.rows import COLUMN_MEANINGS as RESULTS
    folder.mkdir(exist_ok=True)
    cases = case_table().drop(columns=["description"]).rename(columns={"expected_log_exponent": "log exponent"})
    pages = {"cases.md": cases, "methods.md": method_table(),
             "results_columns.md": columns_table(RESULTS), "rates_columns.md": columns_table(RATES),
             "efficiency_columns.md": columns_table(EFFICIENCY)}
    texts = {name: markdown_table(frame) for name, frame in pages.items()}
    texts["results.md"] = results_page(Path(os.environ.get("HARNESS_RESULTS", folder.parent.parent / "results")))
    for name, text in texts.items():
        path = folder / name
        if not path.exists() or path.read_text() != text:      # unchanged files keep Sphinx's cache
            path.write_text(text)
