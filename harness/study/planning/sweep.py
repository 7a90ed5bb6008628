"""Parameter sensitivity: a penalty or Nitsche method over a range of its parameter (eps0 or
gamma0, the scale of eps = gamma0 h) on one case, at one level, beside a cone method (the
reference method, ``measure.reference``) as the reference -- where each is robust, where penalty
locks or loses accuracy, where Nitsche with theta = 1 loses coercivity. The report sweeps the
methods that declare the role SWEPT (``Method.roles``); its section: ``report.sections.sweeps``."""
from __future__ import annotations

import numpy as np
import pandas as pd

from ...fem.contact_laws.builtin import THETAS
from ...measure.reference import REFERENCE_METHOD
from ...methods import SWEPT, Method, methods_named, with_role
from ..chain.rows import study_levels
from ..execution.budget import solve_weights
from ..execution.engines import run_study

# eps0 / gamma0 values: four decades around the defaults (0.05) and past theta = 1's bound
# (gamma0 < 0.145 for P2 on every registered case, ``methods/nitsche.py``)
SWEEP_VALUES = (1e-4, 1e-3, 1e-2, 0.05, 0.1, 0.3, 1.0, 3.0, 10.0)


def swept_specs(methods) -> tuple[str, ...]:
    """What the report sweeps of ``methods``: each that declares the role SWEPT, and, for one
    with a parameter theta, the same at each other theta of ``fem.contact_laws.builtin.THETAS``."""
    specs = []
    for method in with_role(SWEPT, methods):
        specs.append(method.name)
        theta = method.parameters.get("theta")
        specs += [f"{method.name}:theta={value:g}" for value in THETAS if theta is not None and value != theta]
    return tuple(specs)


# what the report sweeps: every theta of Nitsche and the penalty method (the registered methods
# that declare SWEPT), P2, on level 3 (about 9e3 dofs) of the cases where contact meets a
# corner singularity and a transition, beside the reference method. The parameters scale with h
# (eps = value h): level 4 draws the same map, converged and failed at the same values but one
# (corner-r12, Nitsche theta = 1, gamma0 = 10), at more than twice the cost. elastic-transition-r32:
# the same map in plane strain (its level 3 has 3.8e3 dofs), where theta = 1's bound is that of
# eps = gamma0 h / (lambda + 2 mu) (``fem.contact_laws.builtin``).
REPORT_SWEEP = {"cases": ("transition-r32", "corner-r12", "elastic-transition-r32"), "level": 3,
                "methods": swept_specs(None), "values": SWEEP_VALUES, "reference": (REFERENCE_METHOD,)}
SWEEP_COLUMNS = ["sweep_method", "sweep_parameter", "sweep_value"]


def swept(spec: str, values) -> list[tuple[Method, str, float]]:
    """(method, its parameter's name, value) for each value of the first parameter of ``spec``
    (its other parameters as given: nitsche:theta=-1 sweeps gamma0 with theta = -1)."""
    (method,) = methods_named([spec])
    if not method.parameters:
        raise ValueError(f"method {spec!r} has no parameter to sweep")
    name = next(iter(method.parameters))
    assignments = spec.partition(":")[2]
    given = {k: method.parameters[k] for k in (item.partition("=")[0].strip() for item in assignments.split(",") if item)
             if k != name}
    return [(method.with_parameters(**given, **{name: float(v)}), name, float(v)) for v in values]


def sweep_plan(specs, values, reference=(REFERENCE_METHOD,)) -> tuple[list, list]:
    """(runs, methods) of a sweep: ``runs`` = (method, spec, parameter name, value) of every
    swept value, ``methods`` = those methods and the ``reference`` methods."""
    values = list(values)
    if not values or any(not v > 0 for v in values):
        raise ValueError(f"sweep values must be positive numbers, got {values}")
    runs = [(m, spec, name, v) for spec in specs for m, name, v in swept(spec, values)]
    references = methods_named(list(reference)) if reference else []
    return runs, [m for m, *_ in runs] + references


def sweep_weights(case, specs, values, level: int, reference=(REFERENCE_METHOD,)) -> dict:
    """The progress bar's weights of a sweep (``study.execution.budget.solve_weights``)."""
    return solve_weights(case, sweep_plan(specs, values, reference)[1], level + 1)


def run_sweep(case, specs, values, level: int, reference=(REFERENCE_METHOD,), show_progress: bool = True,
              progress=None, engine=None) -> pd.DataFrame:
    """The rows of level ``level`` (P1 methods: their level with about the same dofs) of every
    swept method and of the ``reference`` methods, with the swept parameter and value."""
    if level < 0:
        raise ValueError(f"level must be >= 0, got {level}")
    runs, methods = sweep_plan(specs, values, reference)
    frame = run_study([case], methods, level + 1, show_progress=show_progress, progress=progress, engine=engine)
    return label_sweep(frame, runs, methods, level)


def label_sweep(frame: pd.DataFrame, runs, methods, level: int) -> pd.DataFrame:
    """A sweep study's rows of ``level`` (``sweep_plan``'s runs and methods), each with its swept
    method, parameter and value (empty for the reference methods)."""
    finest = {m.name: study_levels(m, level + 1) - 1 for m in methods}
    frame = frame[frame.level == frame.method.map(finest)].copy()
    label = {m.name: (spec, name, v) for m, spec, name, v in runs} | {m.name: (m.name, "", np.nan) for m in methods[len(runs):]}
    for column, k in zip(SWEEP_COLUMNS, range(3)):
        frame[column] = [label[m][k] for m in frame.method]
    return frame.reset_index(drop=True)
