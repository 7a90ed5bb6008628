"""Quantities of a Tresca solution (issue 74, item 5): the slip zone's measure, the first
stick-slip point and the friction force's L2 error on Gamma_C (``measure.quantities``,
``measure.errors.DiscreteTraction``).

The answers are known without the harness: on tresca-r32 and tresca-r72 (scalar, Gamma_C =
(-1, 1) x {0}) the stick zone is [-1, 0) and the slip zone (0, 1], so the slip measure is 1 and
the first stick-slip point from Gamma_C's left end is x = 0; lambda = d_n u is -1 on the slip
zone and -1 + (3/2)|x|^{1/2} (r32), -1 + |x|^3 (r72) on the stick zone, so the total friction
force is -1 + 1 - 1 = -1 (r32) and -1 + 1/4 - 1 = -7/4 (r72). Two elastic fields built here give
the elastic path closed-form answers too: one slipping on all of Gamma_C with sigma_t = -s, one
sticking on all of it.
"""
import types

import numpy as np
import pytest
from ngsolve import CF, x, y

import harness
from harness.measure.quantities import QUANTITY_COLUMNS
from harness.measure.rates import fit_rate
from harness.problem import Elasticity, Tresca, contact_strip
from harness.problem.case import case_from_module

LEVELS = 4
# the exact friction force of each case (module docstring)
FORCE = {"tresca-r32": -1.0, "tresca-r72": -1.75}


@pytest.fixture(scope="module", params=["tresca-r32", "tresca-r72"])
def scalar_rows(request):
    rows = harness.run(request.param, methods=["nodal", "p1"], levels=LEVELS, show_progress=False)
    assert (rows.kkt_residual <= 1e-10).all()
    return rows


def test_the_exact_slip_zone_is_0_1_and_the_stick_slip_point_is_x_0(scalar_rows):
    case = scalar_rows.case.iloc[0]
    assert np.allclose(scalar_rows.qoi_slip_measure_exact, 1.0, atol=1e-12)
    assert np.allclose(scalar_rows.qoi_stick_slip_point_exact, 0.0, atol=1e-9)     # graded rule: 2^-30 h from 0
    assert np.allclose(scalar_rows.qoi_force_exact, FORCE[case], rtol=1e-10)


@pytest.mark.parametrize("method", ["nodal", "p1"])
def test_slip_measure_and_stick_slip_point_converge_within_h(scalar_rows, method):
    """Each level within one element diameter of the exact values, the finest at least three
    times nearer than the coarsest; on tresca-r32 level by level (tresca-r72's transition is
    degenerate on both sides, |x|^3: its discrete zone's ends move by a fraction of an edge)."""
    rows = scalar_rows[scalar_rows.method == method].sort_values("level")
    for column in ("qoi_slip_measure", "qoi_stick_slip_point"):
        error = (rows[column] - rows[f"{column}_exact"]).abs().to_numpy()
        assert (error <= rows.h.to_numpy()).all(), (column, error)
        assert error[-1] <= error[0] / 3, (column, error)
        if rows.case.iloc[0] == "tresca-r32":
            assert (np.diff(error) <= 1e-14).all(), (column, error)


@pytest.mark.parametrize("method", ["nodal", "p1"])
def test_friction_force_error_decreases_and_is_the_pressure_error_of_the_scalar_model(scalar_rows, method):
    rows = scalar_rows[scalar_rows.method == method].sort_values("level")
    error = rows.err_friction_l2.to_numpy()
    assert (np.diff(error) < 0).all(), error
    # lambda is -1 + (3/2)|x|^{1/2} on r32's stick side, in H^{1-eps}: L2 rate 1 at best
    assert fit_rate(rows.h.to_numpy(), error)[0] > 0.9
    assert np.array_equal(error, rows.err_pressure_l2.to_numpy())


def test_frictionless_quantities_without_meaning_are_nan_in_the_scalar_model(scalar_rows):
    for column in ("qoi_contact_measure", "qoi_peak_pressure", "qoi_contact_measure_exact", "qoi_peak_pressure_exact",
                   "max_penetration"):
        assert scalar_rows[column].isna().all(), column
    # the total flux is the total friction force
    assert np.allclose(scalar_rows.qoi_force, FORCE[scalar_rows.case.iloc[0]], atol=0.01)


def test_the_richardson_table_has_the_friction_quantities_with_their_exact_values(scalar_rows):
    table = harness.quantities(scalar_rows)
    for quantity in ("slip_measure", "stick_slip_point"):
        assert quantity in QUANTITY_COLUMNS
        found = table[table.quantity == quantity]
        assert set(found.method) == {"nodal", "p1"}
        assert np.allclose(found.exact, 1.0 if quantity == "slip_measure" else 0.0, atol=1e-9)
        assert np.isfinite(found.error).all()


def elastic_case(name: str, ux, uy, slipping: bool):
    """A plane-strain Tresca case on (-1, 1) x (0, 1) (E = 1, Poisson 0.3, s = 1) with u . n = 0
    on Gamma_C and the contact traction g_C making its law hold: zero normal pressure, and
    sigma_t - g_t = -s (``slipping``: u_x > 0 there) or -sigma_xy(u), of size <= 0.2 mu < s (u = 0
    there: stick)."""
    material = Elasticity(1.0, 0.3)
    grad = CF((ux.Diff(x), ux.Diff(y), uy.Diff(x), uy.Diff(y)), dims=(2, 2))
    sigma = material.stress(grad)
    # n = -e_y: the traction sigma n = -(sigma_xy, sigma_yy), tau = (-n_y, n_x) = e_x
    load = CF((-sigma[0, 1] + (1.0 if slipping else 0.0), -sigma[1, 1]))
    module = types.SimpleNamespace(
        name=name, description=name, physics="elasticity", young=1.0, poisson=0.3, regime="smooth", theorem="none",
        nu=10.0, expected_rate=2.0, geometry=contact_strip(), maxh=0.25, u=CF((ux, uy)), grad_u=grad,
        friction=Tresca(threshold=1.0), contact_load=load)
    return case_from_module(module, f"{name} (tests/test_friction_quantities.py)")


ELASTIC = {
    "slip": (0.1 * (2 + x) * (1 + y), 0.1 * y * x * x, True),
    "stick": (0.1 * y * (1 + x), 0.1 * y * x * x, False),
}


@pytest.mark.parametrize("kind", list(ELASTIC))
def test_elastic_slip_zone_and_tangential_traction(kind):
    ux, uy, slipping = ELASTIC[kind]
    rows = harness.run(elastic_case(f"elastic-tresca-{kind}", ux, uy, slipping), methods=["nodal", "p1"], levels=3,
                       show_progress=False)
    assert (rows.kkt_residual <= 1e-10).all()
    measure = 2.0 if slipping else 0.0
    assert np.allclose(rows.qoi_slip_measure_exact, measure) and np.allclose(rows.qoi_slip_measure, measure)
    assert rows.qoi_stick_slip_point.isna().all() and rows.qoi_stick_slip_point_exact.isna().all()
    assert rows.qoi_contact_measure.isna().all() and rows.qoi_peak_pressure.notna().all()
    for _, chain in rows.groupby("method"):
        error = chain.sort_values("level").err_friction_l2.to_numpy()
        if slipping:
            # every friction bound active: the residual's tangential part is -s times the
            # quadrature weights, whose Riesz representative is the constant -s
            assert (error <= 1e-10).all(), error
        else:
            assert (np.diff(error) < 0).all(), error


def test_under_coulomb_the_stick_slip_point_is_sought_among_the_points_in_contact():
    """Cattaneo's picture along a flat Gamma_C: open beyond |x| > a = 0.5, slip on c < |x| < a
    (c = 0.25), stick inside. Counting every point, the first change of state is the contact
    edge -a (open counts as not slipping); counting only the points in contact it is -c."""
    from harness.measure.quantities import first_transition
    s = np.linspace(-0.99, 0.99, 199)
    q = types.SimpleNamespace(points=np.column_stack([s, np.zeros_like(s)]), normals=np.tile([0.0, -1.0], (len(s), 1)))
    contact, slip = np.abs(s) < 0.5, (np.abs(s) > 0.25) & (np.abs(s) < 0.5)
    assert abs(first_transition(q, slip) + 0.5) <= 0.01
    assert abs(first_transition(q, slip, contact) + 0.25) <= 0.01
    assert np.isnan(first_transition(q, np.zeros_like(slip), contact))
