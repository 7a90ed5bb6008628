"""Nested iteration in one home (``harness.fem.nested``): the predictions every method family
takes from the coarser level, and the guarded nested start."""
from types import SimpleNamespace

import numpy as np
from conftest import problem_with_hierarchy

from harness.fem.nested import mortar_prediction, nearest_status, nested_start, p1_values, start_from
from harness.fem.p1_embedding import ContactEdges


def _carry(points, active, vertex_rows):
    return SimpleNamespace(points=np.asarray(points, float), active=np.asarray(active, bool), vertex_rows=vertex_rows)


def test_the_mortar_prediction_follows_the_one_body_cones():
    """An edge row from its parent edge's row, a vertex row from the row at its point, a new P1
    vertex active when both coarse neighbours are, beyond the ends the end's status."""
    coarse = _carry([0.0, 1.0, 0.5], [False, False, True], 2)
    assert mortar_prediction(coarse, np.array([0.0, 0.5, 1.0, 0.25, 0.75]), 3).tolist() == [False, True, False, True, True]
    p1 = _carry([0.0, 0.5, 1.0], [False, True, True], 3)
    assert mortar_prediction(p1, np.array([0.0, 0.25, 0.5, 0.75, 1.0]), 5).tolist() == [False, False, True, True, True]
    assert mortar_prediction(p1, np.array([-0.1, 1.1]), 2).tolist() == [False, True]
    assert mortar_prediction(None, np.zeros(3), 3) is None


def test_a_gauss_point_takes_the_branch_of_the_nearest_coarse_one():
    coarse = np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]])
    assert nearest_status(coarse, np.array([True, False, True]), np.array([[0.1, 0.0], [1.4, 0.0], [1.9, 0.0]])).tolist() \
        == [True, False, True]


def test_the_guarded_start_is_the_nested_start_when_both_levels_are_there():
    """``start_from``: None without a coarser level or a hierarchy, else ``nested_start`` of the
    carried vertex values, in the model's variables or NGSolve's own."""
    problem, multilevel = problem_with_hierarchy("transition-r32", 2)
    coarse = problem_with_hierarchy("transition-r32", 1)[0]
    carry = SimpleNamespace(p1=p1_values(coarse, np.random.default_rng(1).random(coarse.ndof)))
    assert start_from(None, multilevel, problem) is None and start_from(carry, None, problem) is None
    assert np.array_equal(start_from(carry, multilevel, problem), nested_start(multilevel, carry.p1, problem))
    own = nested_start(multilevel, carry.p1, problem, ContactEdges.of(problem, model=False))
    assert np.array_equal(start_from(carry, multilevel, problem, model=False), own)
