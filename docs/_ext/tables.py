"""What the generated pages share: a DataFrame as a Markdown table, and the stamp of which
harness, commit, NGSolve, date and machine produced a page's numbers."""
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


def machine_stamp(provenance: dict) -> str:
    """The harness, its commit, NGSolve, the date and the machine of a provenance record
    (``harness.study.planning.cache.environment``); the processor's name and the cores the process could
    use where the record has them (a benchmark's)."""
    machine = provenance.get("machine", {})
    details = [str(machine.get("platform", "?"))]
    if machine.get("cpu_model"):
        details.append(machine["cpu_model"])
    if machine.get("cpus_usable") not in (None, machine.get("cpus")):
        details.append(f"{machine['cpus_usable']} usable")
    return (f"harness {provenance.get('harness_version', '?')}, commit `{str(provenance.get('git_commit', '?'))[:12]}`, "
            f"NGSolve {provenance.get('ngsolve_version', '?')}, {provenance.get('date', '?')}, "
            f"{machine.get('cpus', '?')} CPUs ({'; '.join(details)})")


def wall_time(provenance: dict) -> str:
    return f"wall time {provenance.get('wall_seconds', float('nan')):.0f} s"


def stamp(provenance: dict) -> str:
    """Which harness, commit, date and machine produced a report's numbers, with its profile."""
    return f"{machine_stamp(provenance)}; profile {provenance.get('settings', {}).get('profile', '?')}, {wall_time(provenance)}"
