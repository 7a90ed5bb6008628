"""The report's degree study, "Is P2 the sweet spot?": Nitsche's method (optimal at every degree)
and the nodal cone (the paper's K~_h, at the Gauss-Lobatto points for k >= 3) of degree
k = 1 ... 4, on a case limited by its transition point (transition-r32: uniform meshes saturate
every degree at h^{3/2}, adaptive ones recover N^{-k/2}), a smooth one (smooth-quintic: h^k up
to k = 4) and an elastic one, and Nitsche of base degree k on hp meshes (``mesh.hp``); stored per (case, mesh) under ``results/degree_study`` and reused while
code, case file and settings are unchanged, as the mesh study is (``mesh_study``). Its section of the report: ``report.sections.degrees``.
"""
from __future__ import annotations

from pathlib import Path

import pandas as pd

from ...mesh.strategies import parse_meshes, refusal, serves
from ...methods import methods_named
from .stored import read_stored

PLAN = {
    # (case, the mesh strategies it runs on): adaptive and hp meshes where a singular point limits
    # the uniform rate (hp: the methods of a contact law, ``mesh.strategies.MeshStrategy.serves``),
    # uniform ones everywhere
    "cases": {"transition-r32": ("uniform", "adaptive", "hp"), "smooth-quintic": ("uniform",),
              "elastic-transition-r32": ("uniform",)},
    # the fine profile's too: the junction r^{1/2}, where uniform meshes give every degree h^{1/2}
    "fine_cases": {"corner-r12": ("uniform", "adaptive", "hp")},
}


def degree_config(settings: dict) -> dict:
    """What the report runs across the degree: ``settings["degree_methods"]`` (the report's
    choice, ``report.build.make_report``) on ``PLAN``'s cases with the profile's
    ``degree_levels`` (the budget of dofs: the uniform level's)."""
    fine = settings.get("profile") == "fine"
    cases = dict(PLAN["cases"]) | (dict(PLAN["fine_cases"]) if fine else {})
    return {"cases": {name: list(meshes) for name, meshes in cases.items()},
            "methods": list(settings.get("degree_methods", ())), "levels": settings.get("degree_levels", 5),
            "hp_levels": settings.get("hp_levels", 10), "registry": not settings.get("cases_given", False)}


def levels_of(mesh, config: dict) -> int:
    """The levels a chain of the degree study runs: ``hp_levels`` on hp meshes (a layer each: N
    grows like l^3), else ``levels``."""
    return config["hp_levels"] if getattr(mesh, "name", None) == "hp" else config["levels"]


def degree_jobs_plan(cases, config: dict):
    """(case, mesh strategy, methods) of every chain group the degree study runs: the cases of
    ``config`` among ``cases``, and where the report runs its profile's list, those it lacks
    from the registry (smooth-quintic is the fine profile's case, the degree study's at every
    profile)."""
    from ...problem.case import registered_cases
    methods = methods_named(config["methods"]) if config["methods"] else []
    given = {case.name: case for case in cases}
    known = registered_cases() if config.get("registry", True) else {}
    for name, meshes in config["cases"].items():
        case = given.get(name) or known.get(name)
        own = [m for m in methods if case is not None and m.supports(case)]
        if case is None or not own:
            continue
        for mesh in parse_meshes(meshes):
            served = [m for m in own if serves(mesh, m)]
            if refusal(mesh, case) is None and served:
                yield case, mesh, served


def read_degree_results(store: Path, cases, config: dict) -> pd.DataFrame:
    """Every stored (case, mesh) frame the degree study of ``config`` has (empty if none)."""
    return read_stored(store, degree_jobs_plan(cases, config))
