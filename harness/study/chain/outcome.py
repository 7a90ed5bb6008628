"""What a study's rows say in words: which solves did not converge (``failures``), and where
the errors of a case without an exact solution come from (``reference_lines``). The command
line prints these lines; a notebook may too."""
from __future__ import annotations

import pandas as pd


def failures(frame: pd.DataFrame) -> list[str]:
    """One line per solve that did not converge: case, method, level and why; and per case whose
    reference solve did not (a case measured against a reference)."""
    lines = [f"case {r.case}, method {r.method}, {_mesh_words(getattr(r, 'mesh', None))}level {r.level}: {r.status}"
             for r in frame[frame["status"] != "converged"].itertuples()]
    measured = frame[(frame["errors_against"] == "reference") & (frame["reference_status"] != "converged")]
    for case, group in measured.groupby("case", sort=False):
        first = group.iloc[0]
        lines.append(f"case {case}, reference ({first.reference_method}'s solution) on level "
                     f"{int(first.reference_level)}: {first.reference_status}")
    return lines


def reference_lines(frame: pd.DataFrame) -> list[str]:
    """One line per reference solve, or per chain of references (graded and adaptive meshes: one
    per level, ``measure.level_reference``): where the errors of a case without u come from."""
    lines = []
    measured = frame[frame["errors_against"] == "reference"]
    for (case, mesh), group in measured.groupby(["case", "mesh"], sort=False, dropna=False):
        first = group.iloc[0]
        whose = f"{first.reference_method}'s solution"
        if group["reference_level"].nunique() == 1:
            lines.append(f"{case}: {_mesh_words(mesh)}errors of every method against {whose} on level "
                         f"{int(first.reference_level)} ({int(first.reference_ndof)} dofs, KKT residual "
                         f"{first.reference_kkt_residual:.1e}, {first.reference_status})")
            continue
        refinements = int(first.reference_level - first.level)
        statuses = ", ".join(sorted(set(group["reference_status"])))
        lines.append(f"{case}: {_mesh_words(mesh)}errors of each level against {whose} on that level's mesh refined "
                     f"uniformly {refinements} times ({int(group.reference_ndof.min())} to "
                     f"{int(group.reference_ndof.max())} dofs, KKT residual <= {group.reference_kkt_residual.max():.1e}, "
                     f"{statuses})")
    return lines


def _mesh_words(mesh) -> str:
    """'graded mesh, ' in a line; nothing for uniform meshes (or an old file's NaN)."""
    return f"{mesh} mesh, " if isinstance(mesh, str) and mesh != "uniform" else ""
