"""Two bodies on graded and adaptive meshes (issue 53, item 4): each body meshed on its own, one
Dörfler marking over both bodies' elements, the mortar coupling assembled on each level's pair
of meshes, the two-body residual estimator (``measure.two_body_estimator``)."""
import dataclasses

import numpy as np
import pytest
from conftest import trace_values

from harness.fem.assembly import discretise
from harness.fem.mortar import TraceElements, intersection
from harness.fem.two_body import TwoBodyProblem
from harness.measure.rates import fit_ndof_rate
from harness.measure.two_body_estimator import Interface
from harness.mesh.levels import coarse_mesh
from harness.mesh.strategies import MeshStrategy, element_budget, refusal
from harness.mesh.two_body_levels import AdaptivePair
from harness.methods import METHODS, Mortar, methods_named
from harness.problem.bodies import lower_body
from harness.problem.case import registered_cases
from harness.study.chain import run_chain
from harness.study.execution.refusals import skipped_meshes

MORTAR = [name for name, method in METHODS.items() if isinstance(method, Mortar)]
# the contact laws between two bodies (no rows: Gauss points)
TWO_BODY_LAWS = [name for name, method in METHODS.items() if 2 in method.bodies and name not in MORTAR]
MESHES = ["graded", "adaptive"]


@pytest.fixture(scope="module")
def case():
    return registered_cases()["two-body-transition-r32"]


def bodies_of(case):
    return case, lower_body(case)


def coarse_problem(case, order: int) -> TwoBodyProblem:
    return TwoBodyProblem(*(discretise(body, coarse_mesh(body), order) for body in bodies_of(case)))


def level_facts(case, method, level, problem, solve):
    """What a level's coupling was assembled on, read while its meshes are current."""
    slave_nodes = len(problem.upper.trace.vertices) + (len(problem.upper.trace.edges) if problem.order == 2 else 0)
    segments = intersection(*(TraceElements.of(body) for body in problem.bodies))
    return {"elements": (problem.upper.mesh.ne, problem.lower.mesh.ne), "slave_nodes": slave_nodes,
            "trace_edges": (len(problem.upper.trace.edges), len(problem.lower.trace.edges)), "segments": len(segments)}


# the uniform levels whose budget of elements the chains get: graded P2 meshes have about 4
# times the elements of the uniform one at level 1, so 2 levels' budget would leave them one level
BUDGET_LEVELS = {"graded": 3, "adaptive": 2}


@pytest.fixture(scope="module")
def chains(case):
    """Every mortar method's chain on graded and adaptive meshes, small budgets (seconds)."""
    out = {}
    for mesh in MESHES:
        for name in MORTAR:
            output = run_chain(case, methods_named([name]), BUDGET_LEVELS[mesh], on_level=level_facts, mesh=MeshStrategy(mesh))
            out[mesh, name] = output
    return out


@pytest.mark.parametrize("mesh", MESHES)
@pytest.mark.parametrize("method", MORTAR)
def test_each_level_couples_its_own_non_matching_pair_and_solves_to_a_kkt_residual_below_1e_10(chains, mesh, method):
    """The mortar rows of every level are the slave nodes of that level's mesh (the coupling is
    rebuilt per level), the two traces stay non-matching (more intersection segments than either
    body's trace edges), both meshes are refined along the chain, every solve converges."""
    output = chains[mesh, method]
    facts = [output.kept[(method, row["level"])] for row in output.rows]
    assert len(output.rows) >= 2
    for row, fact in zip(output.rows, facts):
        assert row["mesh"] == mesh and row["status"] == "converged"
        assert row["kkt_residual"] <= 1e-10
        assert row["n_contact_constraints"] == fact["slave_nodes"]
        assert fact["segments"] > max(fact["trace_edges"])
        assert np.isfinite(row["estimator"]) and np.isfinite(row["effectivity"])
    rows = [fact["slave_nodes"] for fact in facts]
    assert rows == sorted(rows) and rows[-1] > rows[0]
    first, last = facts[0]["elements"], facts[-1]["elements"]
    assert last[0] > first[0] and last[1] > first[1]


@pytest.mark.parametrize("mesh", MESHES)
@pytest.mark.parametrize("method", TWO_BODY_LAWS)
def test_a_contact_law_between_two_bodies_solves_every_graded_and_adaptive_level(case, mesh, method):
    """The two-body Nitsche methods on the same non-matching graded and adaptive pairs (no joint
    hierarchy: the joint Jacobian factorised): every level converged to a Newton residual <= 1e-10,
    its estimator finite, the slave's trace refined along the chain."""
    output = run_chain(case, methods_named([method]), BUDGET_LEVELS[mesh], on_level=level_facts, mesh=MeshStrategy(mesh))
    facts = [output.kept[(method, row["level"])] for row in output.rows]
    assert len(output.rows) >= 2
    for row in output.rows:
        assert row["mesh"] == mesh and row["status"] == "converged" and row["kkt_residual"] <= 1e-10
        assert np.isfinite(row["estimator"]) and np.isfinite(row["effectivity"])
    assert facts[-1]["trace_edges"][0] > facts[0]["trace_edges"][0]


def smallest_slave_edge(case, method, level, problem, solve):
    return float(np.diff(np.sort(problem.upper.trace.vertex_points[:, 0])).min())


def test_standard_multipliers_solve_to_round_off_on_slave_edges_down_to_1e_5():
    """mortar-standard's rows as general constraints, divided by their weights int psi_i
    (``methods.mortar._general``): on the junction's adaptive meshes, undivided, the saddle
    system's regularisation swamped the rows of the shortest slave edges and the active set
    method stalled at KKT residuals of 1e-10 .. 1e-7 from edges of 8e-6 on."""
    case = registered_cases()["two-body-junction"]
    output = run_chain(case, methods_named(["mortar-standard"]), 3, on_level=smallest_slave_edge, mesh=MeshStrategy("adaptive"))
    assert min(output.kept.values()) < 1e-5
    assert all(row["kkt_residual"] <= 1e-10 and row["status"] == "converged" for row in output.rows)


@pytest.mark.parametrize("mesh", MESHES)
def test_a_chain_stops_within_the_uniform_budget_summed_over_both_bodies(case, chains, mesh):
    budget = sum(element_budget(body, BUDGET_LEVELS[mesh]) for body in bodies_of(case))
    output = chains[mesh, "mortar-nodal"]
    assert sum(output.kept[("mortar-nodal", output.rows[-1]["level"])]["elements"]) <= budget
    if mesh == "adaptive":        # runs until the next level would pass it
        assert len(output.rows) > 2


@pytest.mark.parametrize("mesh", MESHES)
def test_the_effectivity_stays_between_1_and_10_on_every_level(chains, mesh):
    """The estimator is an upper bound in practice and not a loose one (measured: 2.8-7 on both
    exact two-body cases; the one-body estimator's band is [0.5, 10])."""
    for method in MORTAR:
        effectivity = np.array([row["effectivity"] for row in chains[mesh, method].rows])
        assert ((effectivity >= 1) & (effectivity <= 10)).all(), (method, effectivity)


def opening_of(problem, upper, lower):
    return np.concatenate([trace_values(problem.upper, upper), trace_values(problem.lower, lower)])


def pressures(problem, value: float):
    """The constant ``value`` in each side's trace basis (``contact_dofs``: vertices, then the P2
    bubbles, whose coefficients vanish for a constant)."""
    return [np.concatenate([np.full(len(body.vertex_dofs), value), np.zeros(len(body.edge_dofs))]) for body in problem.bodies]


@pytest.mark.parametrize("order", [1, 2])
def test_the_interface_terms_vanish_for_an_open_interface_without_pressure(case, order):
    problem = coarse_problem(case, order)
    z = opening_of(problem, lambda x: 0.3 + 0.1 * x, lambda x: 0.2 - 0.05 * x)
    terms = Interface(case, problem).indicators(z, pressures(problem, 0.0))
    assert all(np.abs(t).max() == 0.0 for t in terms)


@pytest.mark.parametrize("order", [1, 2])
def test_the_penetration_term_is_the_negative_opening_squared_over_each_sides_edge(case, order):
    """A constant opening -d < 0 (interpenetration, which no single body sees): the sum over both
    sides is d^2 sum_S |S| (1/(2 h_1) + 1/(2 h_2)), h_k the length of side k's trace edge at S."""
    problem = coarse_problem(case, order)
    d = 0.01
    z = opening_of(problem, lambda x: -0.5 * d + 0.0 * x, lambda x: -0.5 * d + 0.0 * x)
    interface = Interface(case, problem)
    terms = interface.indicators(z, pressures(problem, 0.0))
    sides = [TraceElements.of(body) for body in problem.bodies]
    segments = intersection(*sides)
    middle = segments.mean(axis=1)
    lengths = segments[:, 1] - segments[:, 0]
    expected = sum(0.5 * d**2 * (lengths / (s.right - s.left)[s.locate(middle)]).sum() for s in sides)
    assert sum(t.sum() for t in terms) == pytest.approx(expected, rel=1e-12)


@pytest.mark.parametrize("order", [1, 2])
def test_the_complementarity_term_is_the_pressure_times_the_opening(case, order):
    """lambda_h = 1 on both sides and a constant opening a > 0: a |Gamma_C| (half from each side)."""
    problem = coarse_problem(case, order)
    a = 0.02
    z = opening_of(problem, lambda x: a + 0.0 * x, lambda x: 0.0 * x)
    terms = Interface(case, problem).indicators(z, pressures(problem, 1.0))
    assert sum(t.sum() for t in terms) == pytest.approx(a * 2.0, rel=1e-12)       # Gamma_C = [-1, 1]
    assert all(t.sum() == pytest.approx(a, rel=1e-12) for t in terms)


@pytest.mark.parametrize("mesh", MESHES)
def test_elastic_bodies_are_meshed_and_estimated_too(mesh):
    """two-body-elastic-transition (the tangential traction term of each side): the solves
    converge, the estimator is finite and above the energy error."""
    case = registered_cases()["two-body-elastic-transition"]
    rows = run_chain(case, methods_named(["mortar-nodal"]), BUDGET_LEVELS[mesh], mesh=MeshStrategy(mesh)).rows
    assert len(rows) >= 2
    for row in rows:
        assert row["status"] == "converged" and row["kkt_residual"] <= 1e-10
        assert 1 <= row["effectivity"] <= 10, row["effectivity"]


def test_one_dorfler_marking_ranks_both_bodies_elements_together(case):
    """All of the estimate on the lower body: only the lower body is refined, the upper keeps
    its mesh; then all on the upper body: the reverse."""
    pair = AdaptivePair(bodies_of(case), theta=0.5)
    levels = pair.levels(3)
    first = next(levels)
    upper, lower = first.mesh
    sizes = (upper.ne, lower.ne)
    pair.observe(np.concatenate([np.zeros(upper.ne), np.ones(lower.ne)]))
    second = next(levels)
    assert second.mesh[0].ne == sizes[0] and second.mesh[1].ne > sizes[1]
    sizes = (second.mesh[0].ne, second.mesh[1].ne)
    pair.observe(np.concatenate([np.ones(sizes[0]), np.zeros(sizes[1])]))
    third = next(levels)
    assert third.mesh[0].ne > sizes[0] and third.mesh[1].ne == sizes[1]


def test_what_two_bodies_cannot_be_meshed_for_is_refused_in_one_line(case):
    for mesh in MESHES:
        assert MeshStrategy(mesh).applies_to(case) is None
    without_u = dataclasses.replace(case, reference_levels=2)
    reason = MeshStrategy("adaptive").applies_to(without_u)
    assert reason is not None and "\n" not in reason
    with pytest.raises(ValueError, match="one method"):
        run_chain(case, methods_named(["mortar-nodal", "mortar-mean"]), 2, mesh=MeshStrategy("adaptive"))


class OneBodyGrading:
    """A strategy of one's own: it makes one body's level sequence."""

    label = "mine"

    def applies_to(self, case):
        return None

    def group_key(self, method):
        return None

    def sequence(self, case, order):
        raise AssertionError("a two-body study must not ask it for a sequence")


def test_a_strategy_of_ones_own_is_skipped_on_two_bodies_before_any_solve(case):
    mine = OneBodyGrading()
    assert refusal(mine, case) == "two bodies are meshed by the package's strategies only (uniform, graded, adaptive)"
    assert refusal(mine, registered_cases()["transition-r32"]) is None
    assert skipped_meshes([case], [mine]) == [f"{case.name}: mine meshes skipped: {refusal(mine, case)}"]


@pytest.mark.slow
@pytest.mark.parametrize("mesh", MESHES)
def test_on_graded_and_adaptive_meshes_mortar_p2_and_p1_reach_their_optimal_rate_in_n_on_the_junction(mesh):
    """two-body-junction (r^{1/2}: uniform meshes give N^{-1/4} for every order): the H^1 error over
    both bodies falls as N^{-r}, r >= 0.9 for mortar P2 and r >= 0.45 for mortar P1 (optimal:
    1 and 1/2), fitted as ``harness rates`` fits it."""
    case = registered_cases()["two-body-junction"]
    goals = {"mortar-nodal": 0.9, "mortar-p1": 0.45}
    for name, goal in goals.items():
        rows = run_chain(case, methods_named([name]), 5, mesh=MeshStrategy(mesh)).rows
        rate = fit_ndof_rate(np.array([r["ndof"] for r in rows]), np.array([r["err_h1"] for r in rows]))
        assert rate >= goal, (name, rate)


def test_uniform_two_body_rows_carry_the_estimator_and_its_effectivity(case):
    """The two-body estimator on uniform meshes too (it was left NaN there): every row has
    eta > 0 and an effectivity in the same band as on graded and adaptive meshes."""
    for name in MORTAR:
        rows = run_chain(case, methods_named([name]), 2).rows
        assert all(row["mesh"] == "uniform" for row in rows)
        effectivity = np.array([row["effectivity"] for row in rows])
        assert all(row["estimator"] > 0 for row in rows)
        assert ((effectivity >= 1) & (effectivity <= 10)).all(), (name, effectivity)
