import numpy as np
import pytest

from harness.case import load_case
from harness.discrete import discretise
from harness.mesh import mesh_hierarchy
from harness.models import MODELS
from harness.multigrid import Multilevel

MODEL_NAMES = list(MODELS)


def problem_at(case_name: str, level: int):
    for lev, mesh in mesh_hierarchy(load_case(case_name), level + 1):
        if lev == level:
            return discretise(load_case(case_name), mesh)


def problem_with_hierarchy(case_name: str, level: int):
    """The problem of ``level`` and the multigrid's P1 hierarchy of levels 0..level."""
    case = load_case(case_name)
    multilevel = None
    for lev, mesh in mesh_hierarchy(case, level + 1):
        multilevel = Multilevel(mesh) if multilevel is None else multilevel.refined()
    return discretise(case, mesh), multilevel


@pytest.fixture(scope="session")
def small_problem():
    """transition-r32 on level 1 (609 dofs)."""
    return problem_at("transition-r32", 1)


@pytest.fixture
def rng():
    return np.random.default_rng(20031)
