"""Quantities of interest and their Richardson bands (issue 54, items 1, 2 and 5).

The verifier is verified where the answers are known without the harness: Celik et al.'s
procedure on synthetic chains whose limits and orders are given, and transition-r32's
quantities in closed form (u = -r^{3/2} sin(3 theta/2) on (-1, 1) x (0, 1), Gamma_C the bottom):
lambda = (3/2) sqrt(x) on (0, 1), so the force is 1, the contact zone (0, 1) has length 1, the
peak pressure is 3/2 at x = 1, and |grad u|^2 = (9/4) r gives the energy
(9/4) (sqrt 2 + asinh 1) / 3."""
import math

import numpy as np
import pandas as pd
import pytest

from harness.fem.assembly import discretise
from harness.measure.quantities import QUANTITY_COLUMNS, exact_column, exact_quantities, quantities
from harness.measure.rates import fit_rate
from harness.measure.richardson import coverage, observed_order, quantity_table, richardson
from harness.mesh.levels import mesh_hierarchy
from harness.methods import METHODS
from harness.problem.case import registered_cases
from harness.study.chain import run_chain

TRANSITION_R32 = {"qoi_force": 1.0, "qoi_contact_measure": 1.0, "qoi_peak_pressure": 1.5,
                  "qoi_energy": 9 / 4 * (math.sqrt(2) + math.asinh(1)) / 3}


def chain(limit, constant, order, h):
    return [limit + constant * x**order for x in h]


@pytest.mark.parametrize("h", [[0.4, 0.2, 0.1, 0.05], [1.0, 0.6, 0.3, 0.2]], ids=["ratio 2", "ratios 1.67, 2, 1.5"])
@pytest.mark.parametrize("order", [1.0, 1.5, 2.0])
def test_richardson_recovers_the_order_and_the_limit_of_an_exact_power_law(h, order):
    found = richardson(chain(3.0, -0.7, order, h), h)
    assert found["observed_order"] == pytest.approx(order, rel=1e-9)
    assert found["order_previous"] == pytest.approx(order, rel=1e-9)
    assert found["extrapolated"] == pytest.approx(3.0, rel=1e-12)
    assert found["convergence"] == "monotone" and found["asymptotic"]
    finest = chain(3.0, -0.7, order, h)[-1]
    # the band holds the limit: the GCI is 1.25 times the extrapolation's own error estimate
    assert abs(finest - 3.0) <= found["gci"] == pytest.approx(1.25 * abs(finest - 3.0), rel=1e-9)


def test_observed_order_solves_celik_et_al_equation_with_unequal_ratios():
    h = np.array([0.2, 0.3, 0.6])       # finest first
    phi = 1.0 + 2.0 * h**1.7
    p, s = observed_order(phi, h)
    assert s == 1.0 and p == pytest.approx(1.7, rel=1e-10)


def test_oscillating_divergent_and_settled_chains_are_named_and_not_asymptotic():
    h = [0.4, 0.2, 0.1, 0.05]
    oscillating = [1.0 + (-1) ** k * 0.3 * x**2 for k, x in enumerate(h)]
    assert richardson(oscillating, h)["convergence"] == "oscillatory"
    assert not richardson(oscillating, h)["asymptotic"]
    divergent = [1.0, 1.1, 1.3, 1.7]
    assert richardson(divergent, h)["convergence"] == "divergent" and not richardson(divergent, h)["asymptotic"]
    assert math.isnan(richardson(divergent, h)["gci"])          # no limit, no band
    settled = richardson([2.0, 2.0, 2.0, 2.0], h)
    assert settled["convergence"] == "settled" and settled["extrapolated"] == 2.0 and settled["gci"] < 1e-11


def test_orders_that_disagree_over_four_levels_are_not_the_asymptotic_range():
    h = [0.4, 0.2, 0.1, 0.05]
    values = [1.0 + 0.5 * h[0] ** 1.0, 1.0 + 0.5 * h[1] ** 1.0, 1.0 + 0.5 * h[1] * (h[2] / h[1]) ** 2, 0.0]
    values[3] = 1.0 + (values[2] - 1.0) * (h[3] / h[2]) ** 2
    found = richardson(values, h)
    assert found["observed_order"] == pytest.approx(2.0) and found["order_previous"] < 1.8
    assert found["convergence"] == "monotone" and not found["asymptotic"]


@pytest.fixture(scope="module")
def transition_rows():
    case = registered_cases()["transition-r32"]
    return pd.DataFrame(run_chain(case, [METHODS["nodal"], METHODS["p1"]], 4).rows)


def test_exact_quantities_of_transition_r32_are_its_closed_forms(transition_rows):
    finest = transition_rows.iloc[-1]
    for column, value in TRANSITION_R32.items():
        assert finest[exact_column(column)] == pytest.approx(value, rel=1e-9, abs=1e-12), column


@pytest.mark.parametrize("method", ["nodal", "p1"])
def test_discrete_quantities_of_transition_r32_converge_to_its_closed_forms(transition_rows, method):
    """Each quantity at least at first order in h (the contact zone: within an element of
    (0, 1); P1 finds it exactly, its vertex at the transition point)."""
    rows = transition_rows[transition_rows.method == method]
    h = rows.h.to_numpy()
    for column, value in TRANSITION_R32.items():
        errors = np.abs(rows[column].to_numpy() - value)
        if column == "qoi_contact_measure":
            assert (errors <= h).all(), errors
        else:
            assert fit_rate(h, errors)[0] >= 0.9, (column, errors)
    table = quantity_table(transition_rows[transition_rows.method == method])
    # each band that claims the asymptotic range holds the closed form, not only the harness's exact value
    for _, row in table[table.asymptotic.astype(bool)].iterrows():
        column = QUANTITY_COLUMNS[row.quantity]
        closed = TRANSITION_R32.get(column, 0.0)
        assert abs(row.value - closed) <= row.gci + 1e-14, row.quantity


def test_every_band_of_transition_r32_in_the_asymptotic_range_holds_the_exact_value(transition_rows):
    judged = coverage(quantity_table(transition_rows))
    assert judged["judged"] >= 6 and judged["fraction"] == 1.0


@pytest.fixture(scope="module")
def solved():
    """transition-r32's second level solved by nodal and by Nitsche, with an intact stiffness
    matrix for the cross-checks."""
    case = registered_cases()["transition-r32"]
    *_, (_, mesh) = mesh_hierarchy(case, 2)
    out = {}
    for name in ("nodal", "nitsche"):
        problem = discretise(case, mesh, 2)
        solve = METHODS[name].solve(case, problem, None, None)
        out[name] = (case, problem, solve.u)
    return out


@pytest.mark.parametrize("method", ["nodal", "nitsche"])
def test_contact_force_is_the_residual_summed_over_the_contact_vertices(solved, method):
    """int lambda_h = (a(u_h, .) - L(.)) applied to a function with trace 1: the hats of the
    Gamma_C vertices sum to 1 there and the bubbles vanish; no mass matrix involved."""
    case, problem, u = solved[method]
    residual = problem.contact_residual(u)[:len(problem.vertex_dofs)]
    assert quantities(case, problem, u)["qoi_force"] == pytest.approx(residual.sum(), rel=1e-10)


@pytest.mark.parametrize("method", ["nodal", "nitsche"])
def test_energy_is_half_the_stiffness_form_of_the_solution(solved, method):
    case, problem, u = solved[method]
    full = problem.cartesian(u)
    A = problem.A
    assert quantities(case, problem, u)["qoi_energy"] == pytest.approx(0.5 * full @ (A @ full), rel=1e-10)


def test_a_pressure_unbounded_at_a_junction_has_an_infinite_peak():
    """corner-r12: lambda ~ r^{-1/2} where Gamma_C meets Gamma_g; its force stays finite."""
    case = registered_cases()["corner-r12"]
    *_, (_, mesh) = mesh_hierarchy(case, 1)
    problem = discretise(case, mesh, 2)
    exact = exact_quantities(case, problem)
    assert exact[exact_column("qoi_peak_pressure")] == math.inf
    assert math.isfinite(exact[exact_column("qoi_force")])


def test_the_report_section_states_the_coverage_and_lists_every_chain(transition_rows, tmp_path):
    from harness.report.document import Document
    from harness.report.sections.quantities import add_quantity_section
    table = quantity_table(transition_rows)
    doc = Document("t")
    add_quantity_section(doc, table)
    text = doc.markdown(tmp_path)
    judged = coverage(table)
    assert f"the band holds the exact value in {judged['covered']} of them" in text
    assert all(f"| {method} " in text for method in ("nodal", "p1"))
