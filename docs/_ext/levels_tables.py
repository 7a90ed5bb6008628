"""The tables of docs/guide/levels.md, from the code that decides how many levels a study runs:
the report profiles (``harness.study.chain.PROFILES``), the levels each order runs past P2's
(``harness.methods.method.EXTRA_LEVELS``) and the level counts the cases declare."""
import pandas as pd

# what each key of a profile means (the keys ``harness.study.planning.cache.case_settings``, the mesh study
# and the degree study read)
PROFILE_MEANINGS = {
    "levels": "P2 levels of a 2D one-body case (levels 0 .. L−1)",
    "levels_3d": "P2 levels of a 3D case",
    "levels_two_body": "at most this many levels for a two-body case",
    "stop_when_asymptotic": "a case that declares asymptotic_levels stops there",
    "weak_3d": "the weak methods (Nitsche, penalty) run on the 3D cases",
    "orders": "the orders of the methods a report of all methods runs",
    "mesh_levels": "graded and adaptive chains (2D): the budget of this many uniform levels",
    "mesh_levels_3d": "the same in 3D",
    "degree_levels": "the degree study: the budget of this many uniform P2 levels",
    "hp_levels": "the degree study on hp meshes: this many layers",
}


def profiles_table() -> pd.DataFrame:
    from harness.study.chain import PROFILES
    keys = [key for key in PROFILE_MEANINGS if all(key in p for p in PROFILES.values())]
    keys += [key for key in next(iter(PROFILES.values())) if key not in keys]
    rows = [{"setting": f"`{key}`", **{name: str(profile.get(key, "")) for name, profile in PROFILES.items()},
             "meaning": PROFILE_MEANINGS.get(key, "")} for key in keys]
    return pd.DataFrame(rows)


def extra_levels_table() -> pd.DataFrame:
    from harness.methods.method import EXTRA_LEVELS
    return pd.DataFrame({"order": list(EXTRA_LEVELS), "levels past P2's": [f"{n:+d}" for n in EXTRA_LEVELS.values()]})


def case_levels_table() -> pd.DataFrame:
    from harness import registered_cases
    rows = [{"case": name, "asymptotic_levels": case.asymptotic_levels or "",
             "asymptotic_levels_p1": case.asymptotic_levels_p1 or "",
             "report_levels": ", ".join(f"{p}: {n}" for p, n in case.report_levels or ()),
             "reference_levels": case.reference_levels or ""}
            for name, case in registered_cases().items()
            if case.asymptotic_levels or case.asymptotic_levels_p1 or case.report_levels or case.reference_levels]
    return pd.DataFrame(rows)
