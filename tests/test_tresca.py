"""Tresca friction as a case's friction law (``harness.problem.friction``) and the cones' friction
analogues (``fem.friction``): what a case may declare, what validation refuses, the quadratures
of j_h, and that the P2 and P_k discretisations converge to the exact solutions."""
import dataclasses

import ngsolve as ngs
import numpy as np
import pytest

from harness import rates, run
from harness.fem.friction import interpolatory_weights
from harness.fem.polynomials import lobatto_points
from harness.methods import get_method
from harness.methods.cones import sub_edge_means
from harness.problem import Tresca
from harness.problem.case import CaseError, case_groups, load_case
from harness.problem.validate import validate_case

TRESCA_CASES = ["tresca-r32", "tresca-r72"]


def _case_file(tmp_path, body: str):
    path = tmp_path / "case.py"
    path.write_text("from ngsolve import x, y, sqrt, cos, sin\n"
                    "from harness.problem import Tresca, contact_strip, polar\n"
                    "name = 'probe'\ndescription = 'probe'\ntheorem = ''\nnu = 2.5\nexpected_rate = 1.5\n"
                    "geometry = contact_strip(breaks=[0.0])\nmaxh = 0.5\n" + body)
    return str(path)


def test_the_friction_cases_form_a_group_of_their_own():
    assert set(TRESCA_CASES) <= set(case_groups()["friction"])
    assert all(load_case(name).frictional for name in TRESCA_CASES)
    assert not load_case("transition-r32").frictional


@pytest.mark.parametrize("threshold", [0.0, -1.0, float("nan"), "1", True])
def test_a_threshold_that_is_not_positive_is_refused(threshold):
    with pytest.raises(ValueError, match="Tresca threshold must be a number > 0"):
        Tresca(threshold=threshold)


def test_a_friction_that_is_not_a_law_is_refused_in_one_line(tmp_path):
    with pytest.raises(CaseError, match="friction must be harness.problem.Tresca"):
        load_case(_case_file(tmp_path, "u = y\nfriction = 'tresca'\n"))


def test_a_stick_zone_whose_force_exceeds_the_threshold_is_refused(tmp_path):
    """c = 2 > 4 s / 3: on the stick side d_n u = -s + (3/2) c |x|^{1/2} leaves [-s, s] near x = -1."""
    body = ("r, theta = polar(0.0)\nu = y + 2.0 * r ** 1.5 * cos(1.5 * theta)\nf = 0\nfriction = Tresca(threshold=1.0)\n")
    with pytest.raises(CaseError, match=r"Tresca condition \|du/dn - g_C\| <= s on Gamma_C at \(-"):
        validate_case(load_case(_case_file(tmp_path, body)))


def test_a_slip_against_the_force_is_refused(tmp_path):
    """u = -y: d_n u = +s where u = 0 ... and u = -x^3 < 0 on x > 0 slips against d_n u = -s."""
    body = ("from ngsolve import IfPos\nu = y - IfPos(x, x * x * x, 0.0)\nfriction = Tresca(threshold=1.0)\n"
            "singular_points = []\nderivative_jumps = [((0.0, 0.0), (0.0, 1.0))]\n")
    with pytest.raises(CaseError, match=r"du/dn - g_C = -s u/\|u\| where u != 0"):
        validate_case(load_case(_case_file(tmp_path, body)))


@pytest.mark.parametrize("degree", [2, 3, 4])
def test_the_nodal_analogue_weighs_its_nodes_by_gauss_lobatto(degree):
    rules = tuple(((float(t), 1.0),) for t in lobatto_points(degree)[1:-1])
    t = lobatto_points(degree)
    # the Gauss-Lobatto weights: positive, and the interpolatory rule on these nodes is exact
    # to degree 2k - 1 (not only k)
    weights = interpolatory_weights(rules)
    assert weights.shape == t.shape and (weights > 0).all()
    nodes = np.concatenate([[0.0, 1.0], t[1:-1]])
    for p in range(2 * degree - 1):
        assert weights @ nodes ** p == pytest.approx(1.0 / (p + 1), rel=1e-12)


@pytest.mark.parametrize("degree", [2, 3, 4])
def test_the_mean_analogue_weighs_its_sub_edges_equally_and_its_vertices_not(degree):
    weights = interpolatory_weights(sub_edge_means(degree))
    pieces = max(degree - 1, 1)
    assert weights[:2] == pytest.approx([0.0, 0.0], abs=1e-12)
    assert weights[2:] == pytest.approx(np.full(pieces, 1.0 / pieces), rel=1e-12)


def test_functionals_whose_quadrature_has_a_negative_weight_are_refused():
    with pytest.raises(ValueError, match="negative weights"):
        interpolatory_weights((((0.05, 1.0),), ((0.1, 1.0),)))


def test_a_frictionless_method_is_left_out_of_a_tresca_case_with_its_reason():
    assert "frictionless contact, not tresca friction" in get_method("mortar-standard").refusal(load_case("tresca-r32"))


def test_the_nodal_cone_given_by_its_functional_is_the_nodal_model():
    """The P_k path (``fem.friction.rules_friction_qp``) with the midpoint rule on P2 is the
    P2 nodal analogue (``fem.friction.friction_qp``): the same u_h."""
    as_rules = dataclasses.replace(get_method("nodal-p3"), name="nodal-as-rules", order=2, functionals_of=None,
                                   functionals=(((0.5, 1.0),),))
    rows = run("tresca-r32", methods=["nodal", as_rules], levels=2, show_progress=False)
    pivot = rows.pivot(index="level", columns="method", values="err_h1")
    assert np.allclose(pivot["nodal"], pivot["nodal-as-rules"], rtol=1e-9)
    assert (rows.kkt_residual <= 1e-10).all() and (rows.status == "converged").all()


@pytest.mark.slow
@pytest.mark.parametrize("case_name, methods, low", [
    ("tresca-r32", ["nodal", "mean"], 1.4), ("tresca-r32", ["p1"], 0.9),
    ("tresca-r72", ["nodal", "mean"], 1.9), ("tresca-r72", ["nodal-p3"], 2.4)])
def test_the_friction_analogues_converge_at_the_rate_of_the_regularity(case_name, methods, low):
    """The issue's figures: six levels of tresca-r32, P2 within 0.1 of 1.5 and P1 >= 0.9; on
    tresca-r72 P2 >= 1.9 and P3 >= 2.4; every row converged to a residual <= 1e-10."""
    rows = run(case_name, methods=methods, levels=6 if "p3" not in methods[0] else 5, show_progress=False)
    assert (rows.kkt_residual <= 1e-10).all() and (rows.status == "converged").all()
    fitted = rates(rows).set_index("method")
    for method in methods:
        assert fitted.loc[method, "fitted_rate"] >= low, (method, fitted.loc[method])


def test_threshold_may_vary_along_gamma_c(tmp_path):
    """s(x) as a CoefficientFunction: the nodal analogue evaluates it at its nodes."""
    case = dataclasses.replace(load_case("tresca-r72"), friction=Tresca(threshold=ngs.CF(1.0) + 0 * ngs.x))
    rows = run(case, methods=["nodal"], levels=2, show_progress=False)
    constant = run("tresca-r72", methods=["nodal"], levels=2, show_progress=False)
    assert np.allclose(rows.err_h1.to_numpy(), constant.err_h1.to_numpy(), rtol=1e-12)


P2_CONES, WEAK = ["mean", "nodal", "p1"], ["nitsche", "penalty", "nitsche-p1", "penalty-p1"]
DEGREES = ["mean-p3", "nitsche-p3", "nodal-p3", "penalty-p3", "mean-p4", "nitsche-p4", "nodal-p4", "penalty-p4"]


@pytest.mark.parametrize("case_name, expected", [
    ("tresca-r32", P2_CONES + WEAK + DEGREES), ("elastic-tresca-r32", P2_CONES + WEAK + DEGREES),
    ("tresca-reference", P2_CONES + WEAK),            # a reference solution is P2: no P_k, k >= 3
    # 3D: the triangle means are general rows (no mean); the elastic slip's disc is the laws' alone
    ("tresca-line-3d", ["nodal", "p1"] + WEAK + ["nitsche-p3", "penalty-p3", "nitsche-p4", "penalty-p4"]),
    ("elastic-tresca-3d", WEAK + ["nitsche-p3", "penalty-p3", "nitsche-p4", "penalty-p4"]),
    ("two-body-tresca-r32", ["mortar-mean", "mortar-nitsche", "mortar-nodal", "mortar-nitsche-p1", "mortar-p1"])])
def test_every_friction_case_gets_the_methods_that_discretise_tresca(case_name, expected):
    from harness.methods import METHODS
    case = load_case(case_name)
    assert [m.name for m in METHODS.values() if m.supports(case)] == expected
    # the others are left out with a reason of their own
    assert all(m.refusal(case) for m in METHODS.values() if m.name not in expected)
