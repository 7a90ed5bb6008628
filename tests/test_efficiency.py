"""Cost at equal accuracy: interpolation between measured levels, never extrapolation."""
import numpy as np
import pandas as pd
import pytest

from harness.measure.efficiency import at_target, efficiency_table, quantity_efficiency_table


def test_cost_at_a_target_interpolates_log_log_between_the_levels_around_it():
    ndof = np.array([1e2, 4e2, 1.6e3, 6.4e3])
    err = 0.3 * ndof ** -0.75                  # rate 3/2 in h
    target = 0.3 * 1000.0 ** -0.75
    assert at_target(err, ndof, target) == pytest.approx(1000.0, rel=1e-12)
    assert np.isnan(at_target(err, ndof, err[-1] / 2))     # not reached: no extrapolation


def synthetic(method, order, c, rate, levels):
    h = 0.5 ** np.arange(levels)
    ndof = (4 if order == 2 else 1) * 16 * 4.0 ** np.arange(levels)
    return pd.DataFrame({"case": "c", "method": method, "order": order, "level": np.arange(levels), "h": h,
                         "ndof": ndof, "err_h1": c * h ** rate, "solve_seconds": 1e-6 * ndof, "total_seconds": 3e-6 * ndof})


def test_p2_with_a_higher_rate_needs_fewer_dofs_and_the_ratios_are_relative_to_p1():
    results = pd.concat([synthetic("nodal", 2, 1.0, 2.0, 5), synthetic("p1", 1, 1.0, 1.0, 6)], ignore_index=True)
    table = efficiency_table(results).set_index("method")
    # the target is P1's finest error, which P1 reaches on its last level
    assert table.target_err_h1.iloc[0] == pytest.approx(0.5 ** 5)
    assert table.loc["p1", "ndof"] == pytest.approx(16 * 4.0 ** 5)
    assert table.loc["p1", "p1_over_ndof"] == pytest.approx(1.0)
    # nodal reaches 2^-5 = h^2 at h = 2^-2.5: ndof 64 * 4^2.5 = 2048
    assert table.loc["nodal", "ndof"] == pytest.approx(2048.0, rel=1e-12)
    assert table.loc["nodal", "p1_over_ndof"] == pytest.approx(16 * 4.0 ** 5 / 2048.0)


@pytest.mark.parametrize("p1_levels", [6, 5])
def test_errors_at_equal_dofs_are_compared_where_both_orders_have_levels(p1_levels):
    """With P1 one level past P2 the comparison is at P2's finest dofs; with P1 stopped with P2
    (a case's ``asymptotic_levels_p1``) at P1's finest, P2's error interpolated there: the same
    ratio when both orders share the rate."""
    results = pd.concat([synthetic("nodal", 2, 1.0, 1.0, 5), synthetic("p1", 1, 3.0, 1.0, p1_levels)], ignore_index=True)
    table = efficiency_table(results).set_index("method")
    # equal rates in h, and P2 on level l has P1's dofs on level l + 1 (h / 2): 3 (h/2) / h = 1.5
    assert table.loc["nodal", "err_ratio_at_equal_ndof"] == pytest.approx(1.5, rel=1e-12)


def test_the_cost_is_read_from_the_level_after_which_the_error_stays_below_the_target():
    """A quantity's error can change sign: small by accident on a level where it crosses zero."""
    ndof = np.array([1e2, 4e2, 1.6e3, 6.4e3, 2.56e4])
    err = np.array([0.5, 0.01, 0.3, 0.1, 0.05])
    assert at_target(err, ndof, 0.1) == pytest.approx(6.4e3)
    assert at_target(err, ndof, 0.2) == pytest.approx(np.exp(np.log(1.6e3) + np.log(0.3 / 0.2) / np.log(3.0) * np.log(4.0)))


def test_quantity_costs_compare_the_methods_at_equal_error_in_each_quantity():
    results = pd.concat([synthetic("nodal", 2, 1.0, 2.0, 5), synthetic("p1", 1, 1.0, 1.0, 6)], ignore_index=True)
    # a force whose error is the H^1 error squared (a functional), exact value 1
    results = results.assign(qoi_force=1.0 + results.err_h1 ** 2, qoi_force_exact=1.0)
    table = quantity_efficiency_table(results, {"force": "qoi_force"}).set_index("method")
    assert table.target_error.iloc[0] == pytest.approx(0.5 ** 10)
    # nodal: h^4 = 2^-10 at h = 2^-2.5, as for the H^1 error above
    assert table.loc["nodal", "ndof"] == pytest.approx(2048.0, rel=1e-9)
    assert table.loc["nodal", "p1_over_ndof"] == pytest.approx(16 * 4.0 ** 5 / 2048.0, rel=1e-9)
