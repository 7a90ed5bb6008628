"""Error measurement: the per-element quadrature is as accurate as a much finer one, the load
quadrature is converged, and the penetration is seen between nodes."""
import dataclasses
import math

import ngsolve as ngs
import numpy as np
import pytest
from conftest import MODEL_NAMES, MODELS

from harness.fem import assembly as discrete
from harness.fem.assembly import ContactTraceFunction, discretise, load_vector
from harness.fem.element_quadrature import ElementQuadrature
from harness.fem.penetration import max_penetration
from harness.measure.errors import NORMS, error_norms
from harness.mesh.levels import mesh_hierarchy
from harness.mesh.points import evaluate
from harness.methods import METHODS, methods_for
from harness.problem.bodies import lower_body
from harness.problem.case import registered_cases
from harness.study.chain import PROFILES, run_chain
from harness.study.planning.degree_study import PLAN

# cases measured against u (a reference case's errors are exact matrix norms: tests/test_reference.py)
EXACT_CASES = [name for name, case in registered_cases(dimension=2).items() if case.exact]     # 3D: test_three_d.py

DEFAULT = PROFILES["default"]
FINEST_DEFAULT_LEVEL = DEFAULT["levels"] - 1
# the degrees the default report's main study runs (1 and 2) end on FINEST_DEFAULT_LEVEL; those
# beyond (P3, P4) only in its degree study, on uniform levels up to FINEST_DEGREE_LEVEL of the
# degree study's cases
FINEST_DEGREE_LEVEL = DEFAULT["degree_levels"] - 1
DEGREE_CASES = [name for name, meshes in PLAN["cases"].items() if "uniform" in meshes]
# `make test` checks the error integration on a small level (the same rule, elements of every
# kind: near the singular points and away; level 2, 2-4 s per case) for the case whose rule is the
# hardest (a singular load beside a corner); the other kinds (a corner singularity, an elastic body,
# two bodies) and every exact case on level 2 and 3 and on the finest level of `make report` (10-50
# s per case) are checked by `make test-full`
SMALL_LEVEL = 2
SMALL_CASES = {"borderline-h2"}
# level 3 and the finest level of `make report` are checked for the cases it runs (``report_profile``
# "default"); the fine profile's on level 2 (their singularities are the default cases' kinds)
IN_DEFAULT_REPORT = [name for name in EXACT_CASES if registered_cases()[name].report_profile == "default"]
# the finest level of `make report`: the cases with a singular point the graded rule grades toward
# (smooth, u in H^{7/2}, has none: Gauss order 6 on every element, checked on levels 2 and 3 and
# across its derivative jump by tests/test_rates.py; its finest level cost CI 70 s)
REPORT_FINEST = [name for name in IN_DEFAULT_REPORT if name != "smooth"]
# (case, level, which methods): every method on the small level; one method of each order of the
# main study on level 3 (what the rule integrates depends on the method only through u_h's degree,
# ``one_of_each_order``: every method there cost CI 4 minutes and checked no other rule) and on
# `make report`'s finest level; of the degree study's orders on that study's finest (which may be
# level 3 too: the kind is said, not read from the level)
ERROR_LEVELS = [pytest.param(name, level, which, id=f"{name}-{level}{'' if which == 'every' else '-' + which}",
                             marks=() if (name, level) in {(c, SMALL_LEVEL) for c in SMALL_CASES} else pytest.mark.slow)
                for level, which, names in ((SMALL_LEVEL, "every", EXACT_CASES), (3, "report", IN_DEFAULT_REPORT),
                                            (FINEST_DEFAULT_LEVEL, "report", REPORT_FINEST),
                                            (FINEST_DEGREE_LEVEL, "degree", DEGREE_CASES))
                for name in names]
REFERENCE_ORDER, REFERENCE_DEPTH = 20, 22


def reference_quadrature(case, mesh) -> ElementQuadrature:
    """Graded at every point of the geometry (not only the case's declared singular points),
    8 more levels of grading and Gauss order 20 on the leaves."""
    return ElementQuadrature.of(dataclasses.replace(case, singular_points=None), mesh,
                                depth=REFERENCE_DEPTH, order=REFERENCE_ORDER)


class ReferenceErrors:
    """on_level hook: the errors of every solution on ``level``, by the reference integration,
    computed while that level's mesh is the current one."""

    def __init__(self, level):
        self.level, self.errors, self.quadrature = level, {}, None

    def __call__(self, case, method, level, problem, solve):
        if level != self.level:
            return
        if case.bodies == 2:        # each body by its own reference rule, combined as the study does
            self.quadrature = self.quadrature or [reference_quadrature(body, part.mesh)
                                                  for body, part in zip((case, lower_body(case)), problem.bodies)]
            parts = [error_norms(body, [part.gridfunction(u)], quadrature, order=REFERENCE_ORDER)[0]
                     for body, part, u, quadrature in zip((case, lower_body(case)), problem.bodies,
                                                           problem.split(solve.u), self.quadrature)]
            self.errors[method.name] = {norm: math.hypot(parts[0][norm], parts[1][norm]) for norm in parts[0]}
            return
        self.quadrature = self.quadrature or reference_quadrature(case, problem.mesh)
        (self.errors[method.name],) = error_norms(case, [problem.gridfunction(solve.u)], self.quadrature,
                                                  order=REFERENCE_ORDER)


def one_of_each_order(methods) -> list:
    """The first of ``methods`` of each polynomial order: what the error rule integrates,
    |grad(u - u_h)|^2 on an element, depends on the method only through u_h's degree."""
    firsts = {}
    for method in methods:
        firsts.setdefault(method.order, method)
    return list(firsts.values())


@pytest.mark.parametrize("case_name, level, which", ERROR_LEVELS)
def test_errors_agree_with_a_much_finer_integration(case_name, level, which):
    """Issue 12's accuracy proof: the study's errors (graded rule at the declared singular
    points, Gauss order 6 elsewhere) against grading at every geometry point, depth 22 and
    order 20 everywhere, to 0.1%, on a P2 level (P1 ends one level later, on a mesh of the same
    dofs): a small one for every method, and level 3 and the finest of `make report` for one
    method of each order it runs there (`make test-full`; every method there cost 10 minutes of
    CI): orders 1 and 2 on the main study's finest level, P3 and P4 on the degree study's (P3/P4
    on the main study's finest level, which no report row reaches, cost CI 12 minutes)."""
    case = registered_cases()[case_name]
    methods = methods_for(case, METHODS.values())
    if which == "report":
        methods = [m for m in one_of_each_order(methods) if m.order in DEFAULT["orders"]]
    elif which == "degree":
        methods = [m for m in one_of_each_order(methods) if m.order not in DEFAULT["orders"]]
    if which == "report" and case.asymptotic_levels is not None:
        # a case that declares its levels ends `make report` there (elastic-tresca-r32,
        # elastic-coulomb-r32: five), not on the profile's seventh (1.2e6 elastic dofs)
        level = min(level, case.asymptotic_levels - 1)
    if case.bodies == 2:
        # the finest level of `make report` for two bodies is their own (asymptotic_levels); level
        # 6 would put mortar-standard's SuperLU saddle at 2e6 dofs (past 19 GB)
        level = min(level, (case.asymptotic_levels or DEFAULT["levels_two_body"]) - 1)
    reference = ReferenceErrors(level)
    with ngs.TaskManager():
        rows = run_chain(case, methods, level + 1, on_level=reference).rows
    # P4 ends a level earlier (``methods.method.EXTRA_LEVELS``)
    assert set(reference.errors) == {m.name for m in methods if level + 1 + m.extra_levels > level}
    for name, ref in reference.errors.items():
        (row,) = [r for r in rows if r["method"] == name and r["level"] == level]
        for norm in NORMS:
            assert abs(row[norm] - ref[norm]) <= 1e-3 * ref[norm], (name, norm, row[norm], ref[norm])


# `make test` checks the load quadrature on the case whose f is singular (f ~ r^-1 |log r|^-beta,
# the graded rule's hardest load); the elastic cases (4 s), the corner singularities (corner-r12,
# wedge-r23), the oscillating boundary data (oscillating-r34, 7-9 s each) and the smooth loads
# (3-4 s each) in `make test-full`
ROUGH_LOADS = {"borderline-h2"}
LOAD_CASES = [name if name in ROUGH_LOADS else pytest.param(name, marks=pytest.mark.slow) for name in EXACT_CASES]


def load_check_method(case):
    """``nodal`` solves ``discretise(case)`` of every exact case (a two-body case's too, as one
    problem on the union mesh); on a Coulomb case Nitsche's Newton method (two steps where the
    cone's fixed point solves twenty Tresca problems: the load check is the same)."""
    return METHODS["nitsche"] if case.friction.name == "coulomb" else METHODS["nodal"]


@pytest.mark.parametrize("case_name", LOAD_CASES)
def test_load_quadrature_changes_no_error_by_more_than_1e_4(case_name, monkeypatch):
    """The load f v (derived f = -Laplace(u), also for cases that declare f) with the study's
    quadrature and with a much finer one give the same H^1 error (order 2 would not: 1.8% on
    borderline-h2, where f ~ r^{-1} |log r|^{-0.6})."""
    case = registered_cases()[case_name]
    derived = dataclasses.replace(case, declared_f=None)
    *_, (_, mesh) = mesh_hierarchy(case, 5)
    with ngs.TaskManager():
        problem = discretise(case, mesh)
        reference = reference_quadrature(case, mesh)
        monkeypatch.setattr(discrete, "LOAD_ORDER", dict.fromkeys(discrete.ORDERS, 14))
        fine_load = load_vector(derived, problem.fes, reference)
        if case.contact_load is not None:       # g_C on Gamma_C: the study's graded rule, as before
            fine_load += discrete.contact_load_vector(case, problem)
        errors = []
        for b in (problem.b, fine_load):
            variant = dataclasses.replace(problem, b=b)
            solve = load_check_method(case).solve(case, variant, None, None)
            errors.append(error_norms(case, [variant.gridfunction(solve.u)], problem.quadrature)[0]["err_h1"])
    assert abs(errors[0] - errors[1]) <= 1e-4 * errors[1], errors


def test_one_pass_integration_equals_integrals_component_by_component(small_problem):
    """``integrate`` swaps the near elements' Gauss share for the graded one: the same as
    integrating each component with the two measures."""
    mesh = small_problem.mesh
    r = ngs.sqrt(ngs.x * ngs.x + ngs.y * ngs.y)
    components = (r ** -0.5, ngs.x * ngs.x * ngs.y, ngs.exp(ngs.x + ngs.y))
    quadrature = small_problem.quadrature
    assert sum(quadrature.near) > 0
    one_pass = quadrature.integrate(ngs.CF(components), order=6)
    plain, near = quadrature.measures(6)
    separate = [ngs.Integrate(c * plain, mesh) + ngs.Integrate(c * near, mesh) for c in components]
    np.testing.assert_allclose(one_pass, separate, rtol=1e-12)


def test_graded_rule_integrates_the_corner_singularity():
    """The integral over the reference triangle of r^{-1} about the vertex (0,0) is
    int_0^{pi/2} dt / (cos t + sin t) = sqrt(2) log(1 + sqrt(2)): the graded rule gets it to
    1e-6, a plain Gauss rule of the same order misses by 0.6%."""
    from harness.fem.element_quadrature import graded_rule
    exact = np.sqrt(2) * np.log(1 + np.sqrt(2))
    rule = graded_rule()
    graded = sum(w / np.hypot(*p[:2]) for p, w in zip(rule.points, rule.weights))
    plain_rule = ngs.IntegrationRule(ngs.TRIG, 12)
    plain = sum(w / np.hypot(*p[:2]) for p, w in zip(plain_rule.points, plain_rule.weights))
    assert abs(graded - exact) <= 1e-6 * exact
    assert abs(plain - exact) > 1e-3 * exact


def test_penetration_sees_the_dip_between_nodes(small_problem):
    """A P2 trace with zero vertex values and a positive bubble dips to -c/8 at midpoints."""
    u = np.zeros(small_problem.ndof)
    u[small_problem.edge_dofs[3]] = 2.0
    trace_u = ContactTraceFunction.of(small_problem, u)
    case = registered_cases()["transition-r32"]
    assert max_penetration(case, small_problem.mesh, trace_u) == pytest.approx(2.0 / 8, rel=1e-12)


@pytest.mark.parametrize("model_name", MODEL_NAMES)
def test_discrete_solutions_are_nonconforming_only_between_nodes(small_problem, model_name):
    case = registered_cases()["transition-r32"]
    solve = METHODS[model_name].solve(case, small_problem, None, None)
    # nodes satisfy the constraints, so any penetration is between them and small
    assert (MODELS[model_name].constraint_values(small_problem, solve.u) >= -1e-12).all()
    assert solve.fields["max_penetration"] >= -1e-14
    assert solve.fields["max_penetration"] < 0.1 * np.abs(solve.u).max()


def test_p1_solution_is_conforming_on_the_whole_contact_boundary():
    """P1's cone is exact: nonnegative vertex values make a linear trace nonnegative everywhere."""
    from conftest import problem_at
    case = registered_cases()["transition-r32"]
    problem = problem_at("transition-r32", 3, order=1)
    solve = METHODS["p1"].solve(case, problem, None, None)
    assert solve.fields["status"] == "converged" and solve.fields["kkt_residual"] <= 1e-10
    assert solve.fields["max_penetration"] <= 1e-14 * np.abs(solve.u).max()


@pytest.mark.parametrize("case_name", ["wedge-r23", "transition-r32"])
def test_red_refinement_halves_h_exactly(case_name):
    """The study measures h on level 0 and halves it per level: netgen's red refinement splits
    every edge in two."""
    from harness.mesh.levels import mesh_size
    sizes = [mesh_size(mesh) for _, mesh in mesh_hierarchy(registered_cases()[case_name], 5)]
    np.testing.assert_allclose(sizes, sizes[0] / 2.0 ** np.arange(5), rtol=1e-12)




@pytest.mark.parametrize("case_name, level", [("transition-r32", 1), ("transition-r32", 3), ("transition-r32", 4), ("smooth-3d", 1)])
def test_gamma_c_points_located_without_search_are_netgens_points(case_name, level, rng):
    """``mesh.in_elements``: the points of the Gamma_C rules are made from the element on each
    contact edge (2D) or face (3D), not searched for; values and gradients of a random P2
    function there, and of u, are those at the points netgen's search finds. (transition-r32's
    u has its branch cut on Gamma_C: on level 3, before the local coordinates were kept inside
    the element, Gauss points mapped to y = -1e-17 took u of the other sign.)"""
    from conftest import problem_at

    import harness.mesh.points as harness_mesh
    from harness.fem.contact_quadrature import contact_quadrature
    problem = problem_at(case_name, level)
    quadrature = contact_quadrature(problem)          # makes its points known (located)
    gfu = problem.gridfunction(rng.standard_normal(problem.ndof))
    for cf in (gfu, ngs.grad(gfu), registered_cases()[case_name].u):
        direct = evaluate(cf, problem.mesh, quadrature.points)
        harness_mesh._LOCATED.clear()
        searched = evaluate(cf, problem.mesh, quadrature.points)
        np.testing.assert_allclose(direct, searched, rtol=1e-12, atol=1e-12 * np.abs(searched).max())
        contact_quadrature(problem)


def test_the_trace_of_u_on_a_bisected_mesh_has_no_branch_cut_on_gamma_c():
    """transition-r32's u = |x|^{3/2} on the free part of Gamma_C (x < 0) and 0 on the binding
    part: at the Gamma_C Gauss points of a graded (bisected) mesh, which NGSolve's element map
    may put at y = -1e-17, the case's u has those values (written with atan2(y, x), it had the
    opposite sign there, and the trace error of graded and adaptive rows was 1e3 times too large)."""
    from harness.fem.contact_quadrature import contact_quadrature
    from harness.measure.errors import CONTACT_ERROR_POINTS
    from harness.mesh.strategies import MeshStrategy
    from harness.problem.case import load_case
    case = load_case("transition-r32")
    for level in MeshStrategy("graded").sequence(case, 2).levels(2):
        mesh = level.mesh
    problem = discretise(case, mesh, 2)
    q = contact_quadrature(problem, CONTACT_ERROR_POINTS)         # the error measurement's points
    values = case.physics.contact_value(case, mesh, q.points, q.normals)
    x = q.points[:, 0]
    assert np.allclose(values, np.where(x < 0, np.abs(x) ** 1.5, 0.0), atol=1e-12)
