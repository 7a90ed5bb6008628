"""Cattaneo and Mindlin (issue 76, item 3): the closed forms of ``harness.problem.closed_forms``
against known values and their own resultants, the case contract's friction predictions, and
the Cattaneo line cases' rows against the closed form at the rows' computed P and Q."""
from math import pi
from pathlib import Path

import numpy as np
import pytest
from scipy.integrate import quad

import harness
from harness.problem import closed_forms
from harness.problem.case import CaseError, load_case

CASES = Path(__file__).resolve().parent.parent / "cases"
MU = 0.3


@pytest.mark.parametrize("ratio, dimension, expected", [(0.3, 2, 0.83666), (0.7, 2, 0.54772),
                                                        (0.3, 3, 0.88790), (0.7, 3, 0.66943)])
def test_the_stick_ratio_is_cattaneos_square_root_and_mindlins_cube_root(ratio, dimension, expected):
    assert closed_forms.stick_ratio(ratio, dimension) == pytest.approx(expected, abs=5e-6)


@pytest.mark.parametrize("ratio", [0.0, 0.3, 0.7, 0.99])
def test_cattaneos_traction_integrates_to_its_tangential_force(ratio):
    """int_{-a}^{a} q dx = mu P (1 - c^2/a^2) = Q: the stick zone's c is the one of Q."""
    force = 8.6e-3
    theory = closed_forms.cattaneo_line(force, ratio * MU * force, MU, 1.0, closed_forms.contact_modulus(1.0, 0.3))
    a, c = theory["a"], theory["c"]
    q = lambda s: float(closed_forms.cattaneo_traction(s, a, theory["p0"], c, MU))     # noqa: E731
    total = quad(q, -a, a, points=[-c, c], limit=200, epsabs=1e-14)[0]
    assert total == pytest.approx(MU * force * (1 - c * c / (a * a)), rel=1e-8)
    assert total == pytest.approx(ratio * MU * force, rel=1e-8, abs=1e-15)


@pytest.mark.parametrize("ratio", [0.0, 0.3, 0.7, 0.99])
def test_mindlins_traction_integrates_to_its_tangential_force(ratio):
    """int_0^a 2 pi r q dr = mu P (1 - c^3/a^3) = Q."""
    force = 1.6e-3
    theory = closed_forms.mindlin_sphere(force, ratio * MU * force, MU, 1.0, closed_forms.contact_modulus(1.0, 0.3))
    a, c = theory["a"], theory["c"]
    q = lambda r: 2 * pi * r * float(closed_forms.cattaneo_traction(r, a, theory["p0"], c, MU))     # noqa: E731
    total = quad(q, 0.0, a, points=[c], limit=200, epsabs=1e-16)[0]
    assert total == pytest.approx(MU * force * (1 - (c / a) ** 3), rel=1e-8)
    assert total == pytest.approx(ratio * MU * force, rel=1e-8, abs=1e-16)


@pytest.mark.parametrize("hertz, dimension", [(closed_forms.hertz_line, 2), (closed_forms.hertz_sphere, 3)])
def test_hertz_pressure_integrates_to_the_force(hertz, dimension):
    force = 5e-3
    a, p0 = hertz(force, 1.0, closed_forms.contact_modulus(1.0, 0.3))
    weight = (lambda r: 2.0) if dimension == 2 else (lambda r: 2 * pi * r)
    total = quad(lambda r: weight(r) * float(closed_forms.hertz_pressure(r, a, p0)), 0.0, a)[0]
    assert total == pytest.approx(force, rel=1e-9)


@pytest.mark.parametrize("poisson, beta", [(0.3, 0.4 / 1.4), (0.45, 0.1 / 1.1), (0.47, 0.06 / 1.06), (0.5, 0.0)])
def test_dundurs_beta_of_a_rigid_indenter(poisson, beta):
    assert closed_forms.rigid_dundurs_beta(poisson) == pytest.approx(beta, abs=1e-15)


def test_hertz_line_keeps_its_formulas():
    """The case's ``hertz`` is the shared closed form: a = 0.1 at F = pi a^2 E* / (4 R)."""
    case = load_case(str(CASES / "hertz_line.py"))
    force = pi * 0.01 * closed_forms.contact_modulus(1.0, 0.3) / 4
    assert case.predicted_quantities(force)["qoi_contact_measure"] == pytest.approx(0.2, rel=1e-12)


@pytest.mark.parametrize("change, message", [
    ("for key in ('friction', 'history'):\n    del declared[key]\n", "needs a Coulomb friction law"),
    ("declared['predicted_friction'] = 3\n", "must be a function"),
    ("del declared['prediction']\n", "needs prediction")])
def test_the_contract_checks_the_friction_predictions(tmp_path, change, message):
    path = tmp_path / "broken.py"
    path.write_text("from harness.problem import cattaneo_line_case\nname = 'broken'\ndescription = 'd'\n"
                    "declared = cattaneo_line_case(0.3, 0.3, 0.002)\n" + change + "globals().update(declared)\n")
    with pytest.raises(CaseError, match=message):
        load_case(str(path))


def stick_deviation(rows, poisson: float) -> np.ndarray:
    """c_h / c - 1 of each row at its own P and Q (c_h = qoi_stick_measure / 2)."""
    theory = [closed_forms.cattaneo_line(p, q, MU, 1.0, closed_forms.contact_modulus(1.0, poisson))["c"]
              for p, q in zip(rows.qoi_force, rows.qoi_tangential_force)]
    return rows.qoi_stick_measure.to_numpy() / 2 / np.array(theory) - 1


def test_the_nu_03_block_shows_the_couplings_share():
    """nu = 0.3 against a rigid cylinder (beta = 0.286): converged two-step rows whose stick zone
    stays far below Cattaneo's, c_h / c about 0.63 on levels 1-4 (measured; the coupling, not the
    mesh: the levels agree to 1 %), and an O(1) traction error (the normal step's shear)."""
    rows = harness.run(str(CASES / "cattaneo_line_q03.py"), methods=["nitsche"], levels=2, show_progress=False)
    assert (rows.kkt_residual <= 1e-10).all() and (rows.load_steps == 2).all() and (rows.status == "converged").all()
    ratio = rows.qoi_tangential_force / (MU * rows.qoi_force)
    assert ratio.between(0.25, 0.35).all()
    assert (stick_deviation(rows, 0.3) < -0.3).all()
    assert (rows.err_traction_prediction > 1.0).all()


@pytest.mark.slow
def test_the_near_incompressible_block_approaches_cattaneo():
    """nu = 0.47 (beta = 0.057), Q/(mu_F P) = 0.72: c_h / c = 0.9825 on level 2 (measured; 0.9877 on
    level 3), so within 2.5 %, below 1 by the remaining coupling; the traction error 0.098
    (0.082 on level 3), below 0.12."""
    rows = harness.run(str(CASES / "cattaneo_line_q07_nu47.py"), methods=["nitsche"], levels=3, show_progress=False)
    assert (rows.kkt_residual <= 1e-10).all() and (rows.load_steps == 2).all() and (rows.status == "converged").all()
    finest = rows[rows.level == 2]
    assert abs(stick_deviation(finest, 0.47)[0]) < 0.025
    assert float(finest.err_traction_prediction.iloc[0]) < 0.12


@pytest.mark.slow
def test_two_identical_bodies_approach_cattaneo():
    """Two identical blocks on non-matching meshes (beta = 0 exactly, in finite blocks too:
    docs/theory/coulomb.md), levels 0-2, the dual mortar's nodal P2 and the master-slave Nitsche
    P2: every row converged in both load steps; c_h / c within the issue's 2 % on every level
    (measured: mortar-nodal 0.9894, 1.0075, 0.9994; mortar-nitsche 0.9893, 1.0192, 1.0061) at
    the rows' own P and Q (the case's ``predicted_friction``), and the shear traction's error
    against Cattaneo's q falling level by level to below 0.1 (mortar-nodal 0.21, 0.083, 0.067,
    levels 3 and 4 reaching 0.015 and 0.013; mortar-nitsche 0.126, 0.077, 0.034): no coupling
    holds it up, as the rigid indenter's beta = 0.286 holds it above 1 (measured 2.2;
    test_the_nu_03_block_shows_the_couplings_share). The fall is not a steady rate: the error is
    dominated by where the stick zone's edge c falls between the nodes. (One study for both: one
    reference solve.)"""
    case = load_case(str(CASES / "cattaneo_two_body_q03.py"))
    study = harness.run(case, methods=["mortar-nodal", "mortar-nitsche"], levels=3, show_progress=False)
    for method, rows in study.sort_values("level").groupby("method"):
        assert len(rows) == 3 and (rows.kkt_residual <= 1e-10).all() and (rows.load_steps == 2).all(), method
        assert (rows.status == "converged").all(), method
        stick = np.array([case.predicted_friction(p, q)["qoi_stick_measure"] for p, q in zip(rows.qoi_force, rows.qoi_tangential_force)])
        assert np.abs(rows.qoi_stick_measure.to_numpy() / stick - 1).max() < 0.02, method
        error = rows.err_traction_prediction.to_numpy()
        assert (np.diff(error) < 0).all() and error[-1] < 0.1, (method, error)
