"""The `study` rows of `bench`: the default profile's 2D study, without the report, wall time
against the sum of its contact solves."""
from __future__ import annotations

import resource

import pandas as pd

from .common import in_fresh_process


def _measure_study(methods: str, connection):
    """The default profile's study of every registered 2D case with ``methods`` (the paper's
    group, PAPER, or 'all', as `make report` runs it), without the report: wall time, the sum
    of its contact solves, where the rest goes."""
    from ..methods import methods_named
    from ..problem.case import registered_cases
    from ..study import run_study
    from ..study.chain import PROFILES

    # one body: the row's cases (two bodies have no `paper` method, and their
    # factorised solves would move the ratio of the multigrid path it measures)
    cases = [case for case in registered_cases(dimension=2).values() if case.bodies == 1]
    frame = run_study(cases, methods_named(methods), PROFILES["default"]["levels"], show_progress=False)
    # every contact solve the study makes: its rows', and the reference chains' (smooth-obstacle's
    # reference solve alone is the largest of the study, and no row holds it)
    wall, reference = frame.attrs["wall_seconds"], frame.attrs["reference_solve_seconds"]
    solves = float(frame.solve_seconds.sum()) + reference
    phases = frame.attrs["phase_seconds"]
    connection.send({
        "methods": methods, "levels": PROFILES["default"]["levels"], "rows": len(frame),
        "finest_ndof": int(frame.ndof.max()),
        "wall_seconds": wall, "solve_seconds": solves, "reference_solve_seconds": reference, "ratio": wall / solves,
        **{f"share_{phase}": seconds / wall for phase, seconds in phases.items()},
        "max_kkt_residual": float(frame.kkt_residual.max()),
        "peak_rss_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024,
    })
    connection.close()


def measure_study() -> pd.DataFrame:
    """The `study` rows: the default profile with the paper's two methods (whose ratio the goal
    judges) and with every method (`make report`), each in a fresh process. The contact solves
    are all of them, the reference chains' included (``reference_solve_seconds``)."""
    from ..methods import PAPER
    return pd.DataFrame([in_fresh_process(_measure_study, (methods,), f"the default study ({methods})")
                         for methods in (PAPER, "all")])


def study_goals(study: pd.DataFrame) -> list[tuple[str, bool, str]]:
    """The goal, set for the paper's methods: a study costs at most 2.5x its contact solves.
    With P1 the ratio is shown, not judged: P1's extra level is a mesh four times larger, whose
    refinement, assembly and error integration cost per element while its solve is cheap."""
    from ..methods import PAPER
    out = []
    for row in study.to_dict("records"):
        shares = ", ".join(f"{k[len('share_'):]} {v:.0%}" for k, v in row.items() if k.startswith("share_"))
        figure = (f"{row['wall_seconds']:.1f} s / {row['solve_seconds']:.1f} s = {row['ratio']:.2f}x "
                  f"(of the solves {row.get('reference_solve_seconds', 0.0):.1f} s in reference chains; {shares})")
        if row["methods"] == PAPER:
            out.append(("default study, paper methods: wall <= 2.5x the sum of its contact solves", row["ratio"] <= 2.5, figure))
        else:
            out.append((f"default study, methods {row['methods']}: wall / contact solves (shown)", True, figure))
        out.append((f"KKT residual <= 1e-10 in every row of the study ({row['methods']})", row["max_kkt_residual"] <= 1e-10,
                    f"max {row['max_kkt_residual']:.1e}"))
    return out
