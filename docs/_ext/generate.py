"""The generated pages' tables, from the code that owns what they list (no hand-copied table)."""
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
    for name, frame in pages.items():
        text = markdown_table(frame)
        path = folder / name
        if not path.exists() or path.read_text() != text:      # unchanged files keep Sphinx's cache
            path.write_text(text)
