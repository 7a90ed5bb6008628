"""The generated pages' tables, from the code that owns what they list (no hand-copied table)."""
import os
from pathlib import Path

from bench_page import performance_page
from layout_table import modules_table, stages_table
from levels_tables import case_levels_table, extra_levels_table, profiles_table
from results_page import results_page
from tables import columns_table, markdown_table


def write_generated(folder: Path) -> None:
    from harness import case_table, method_table
    from harness.measure.efficiency import COLUMN_MEANINGS as EFFICIENCY
    from harness.measure.efficiency import QUANTITY_EFFICIENCY_MEANINGS as QUANTITY_EFFICIENCY
    from harness.measure.rates import COLUMN_MEANINGS as RATES
    from harness.measure.richardson import QUANTITY_TABLE_MEANINGS as QUANTITIES
    from harness.study.chain.rows import COLUMN_MEANINGS as RESULTS
    folder.mkdir(exist_ok=True)
    cases = case_table().drop(columns=["description"]).rename(columns={"expected_log_exponent": "log exponent"})
    pages = {"cases.md": cases, "methods.md": method_table(),
             "results_columns.md": columns_table(RESULTS), "rates_columns.md": columns_table(RATES),
             "efficiency_columns.md": columns_table(EFFICIENCY), "quantities_columns.md": columns_table(QUANTITIES),
             "quantity_efficiency_columns.md": columns_table(QUANTITY_EFFICIENCY),
             "profiles.md": profiles_table(), "extra_levels.md": extra_levels_table(),
             "case_levels.md": case_levels_table(), "stages.md": stages_table(), "modules.md": modules_table()}
    texts = {name: markdown_table(frame) for name, frame in pages.items()}
    texts["results.md"] = results_page(Path(os.environ.get("HARNESS_RESULTS", folder.parent.parent / "results")))
    texts["performance.md"] = performance_page(Path(os.environ.get("HARNESS_RESULTS", folder.parent.parent / "results")))
    for name, text in texts.items():
        path = folder / name
        if not path.exists() or path.read_text() != text:      # unchanged files keep Sphinx's cache
            path.write_text(text)
