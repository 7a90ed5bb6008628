import numpy as np
import pytest

from harness.case import load_case
from harness.discrete import discretise
from harness.mesh import mesh_hierarchy
from harness.models import MODELS

MODEL_NAMES = list(MODELS)


def problem_at(case_name: str, level: int):
    for lev, mesh in mesh_hierarchy(load_case(case_name), level + 1):
        if lev == level:
            return discretise(load_case(case_name), mesh)


@pytest.fixture(scope="session")
def small_problem():
    """transition-r32 on level 1 (609 dofs)."""
    return problem_at("transition-r32", 1)


@pytest.fixture
def rng():
    return np.random.default_rng(20031)
