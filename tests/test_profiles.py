"""Every report profile plans its work before running any of it: its studies, sweeps and mesh
study, from its settings alone (the fine profile's mesh study failed to plan for a whole minor
version while only the default one was ever run by a test)."""
import pytest

import harness.study.planning.cache as cache
from harness.methods import GROUPS, SWEPT, methods_named, with_role
from harness.problem.case import registered_cases
from harness.report.build import in_profile
from harness.study.chain import PROFILES
from harness.study.planning.degree_study import degree_config


@pytest.mark.parametrize("profile", [p if p == "default" else pytest.param(p, marks=pytest.mark.slow) for p in PROFILES])     # fine: 2.3 s
def test_every_profile_plans_its_studies_sweeps_and_mesh_study(profile, tmp_path, monkeypatch):
    monkeypatch.setattr(cache, "validate_case", lambda case: None)        # the cases' own checks: tests/test_validation.py
    methods = methods_named(["all"])
    settings = {"profile": profile, "methods": [m.name for m in methods], **PROFILES[profile]}
    cases = in_profile(registered_cases().values(), profile)
    stores, work = cache.Stores.under(tmp_path), cache.Work()
    cache.plan_studies(work, cases, settings, stores, None, None)
    cache.plan_sweeps(work, {}, cases if with_role(SWEPT, methods) else [], cache.sweep_config(settings["levels"]), stores)
    cache.plan_mesh_studies(work, cases, cache.mesh_config(settings), stores)
    cache.plan_degree_studies(work, cases, degree_config(settings | {"degree_methods": list(GROUPS["degrees"])}), stores)
    tags = {job.tag for job in work.jobs}
    assert tags == {"study", "sweep", "mesh", "degree"}
    assert {job.case.name for job in work.jobs if job.tag == "study"} == {case.name for case in cases}
    # every stored name has its jobs, and every job's solves are on the progress bar
    assert set(work.pending) == {job.scope + job.case.name for job in work.jobs}
    assert work.weights and all(weight > 0 for weight in work.weights.values())
