"""Hertz line contact (issue 54, item 3): the registered case against Hertz's formulas, its
declared exponent, and its budget of levels in the reports."""
import importlib.util
import math
from pathlib import Path

import pandas as pd
import pytest

import harness
from harness.problem.case import CaseError, load_case, registered_cases
from harness.study.chain import PROFILES
from harness.study.planning.cache import case_settings

CASE = Path(__file__).resolve().parent.parent / "cases" / "hertz_line.py"


def module(path: Path = CASE):
    """The case file's module (its helpers: ``hertz``, ``setup``)."""
    spec = importlib.util.spec_from_file_location(f"{path.stem}_module", path)
    loaded = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(loaded)
    return loaded


def hertz_errors(rows: pd.DataFrame) -> pd.DataFrame:
    """a_h / a - 1 and p_max / p0 - 1 of each row, at the row's own force (module ``hertz``)."""
    hertz = module().hertz
    a, p0 = zip(*(hertz(force) for force in rows.qoi_force))
    return rows.assign(a_error=rows.qoi_contact_measure / 2 / pd.Series(a, index=rows.index) - 1,
                       p0_error=rows.qoi_peak_pressure / pd.Series(p0, index=rows.index) - 1)


def test_the_corner_exponent_solves_williams_clamped_free_equation():
    """At omega = pi/2, kappa = 3 - 4 nu = 1.8: the least root, 0.7112 (the case's nu - 1)."""
    case = registered_cases()["hertz-line"]
    exponent, kappa = case.nu - 1, 3 - 4 * 0.3
    assert kappa**2 + 1 + 2 * kappa * math.cos(exponent * math.pi) - 4 * exponent**2 == pytest.approx(0.0, abs=1e-12)
    assert exponent == pytest.approx(0.711173, abs=1e-6)


@pytest.fixture(scope="module")
def two_levels():
    return harness.run("hertz-line", methods=["nodal", "p1"], levels=2, show_progress=False)


def test_p2_is_within_one_percent_of_hertz_from_its_second_level(two_levels):
    rows = two_levels
    errors = hertz_errors(rows)
    finest = errors[(errors.method == "nodal") & (errors.level == 1)].iloc[0]
    assert abs(finest.a_error) < 0.01 and abs(finest.p0_error) < 0.01, finest[["a_error", "p0_error"]]
    # P1 at the same dofs is further off, in both
    p1 = errors[(errors.method == "p1") & (errors.ndof == finest.ndof)].iloc[0]
    assert abs(p1.a_error) > abs(finest.a_error) and abs(p1.p0_error) > abs(finest.p0_error)
    assert (rows.kkt_residual <= 1e-10).all()


def test_the_reports_stop_hertz_at_its_budget_and_report_levels_is_checked(tmp_path):
    case = registered_cases()["hertz-line"]
    default, fine = {"profile": "default", **PROFILES["default"]}, {"profile": "fine", **PROFILES["fine"]}
    assert case_settings(case, default)["levels"] == 4 and case_settings(case, fine)["levels"] == 5
    assert case_settings(case, default | {"levels": 6, "levels_given": True})["levels"] == 6      # report --levels 6
    bad = tmp_path / "bad.py"
    bad.write_text(CASE.read_text().replace('report_levels = {"default": 4, "fine": 5}', 'report_levels = {"coarse": 2}'))
    with pytest.raises(CaseError, match="report_levels must map report profiles"):
        load_case(str(bad))


@pytest.mark.slow
def test_the_half_space_is_approached_as_the_block_grows(tmp_path):
    """The finest default level on blocks of 10 a and 20 a (delta found again so that a stays
    about 0.1): the peak pressure's excess over Hertz's falls like (a/L)^2, by about 4."""
    excess = []
    for size, delta in ((1.0, 0.015), (2.0, 0.0186)):
        path = write_scaled(tmp_path / f"hertz_{size:g}.py", size, delta)
        rows = harness.run(str(path), methods=["nodal"], levels=4, show_progress=False)
        excess.append(hertz_errors(rows).p0_error.iloc[-1])
    assert excess[0] > 0 and excess[1] > 0                  # a block is stiffer than the half-space
    assert 3.0 < excess[0] / excess[1] < 5.0, excess


def write_scaled(path: Path, size: float, delta: float) -> Path:
    source = CASE.read_text().replace("globals().update(setup())",
                                      f"globals().update(setup(half_width={size}, height={size}, delta={delta}))")
    path.write_text(source.replace('name = "hertz-line"', f'name = "hertz-line-{size:g}"'))
    return path


def test_the_report_sets_every_row_against_hertz_at_its_own_force(two_levels, tmp_path):
    from harness.report.document import Document
    from harness.report.sections.prediction import add_prediction_section, deviations
    case = registered_cases()["hertz-line"]
    rows = two_levels
    table = deviations(case, rows)
    a, p0 = module().hertz(float(rows.qoi_force.iloc[-1]))
    assert table.qoi_peak_pressure_predicted.iloc[-1] == pytest.approx(p0, rel=1e-12)
    assert table.qoi_contact_measure_deviation.iloc[-1] == pytest.approx(rows.qoi_contact_measure.iloc[-1] / (2 * a) - 1)
    doc = Document("t")
    add_prediction_section(doc, [case], rows.assign(mesh="uniform"))
    text = doc.markdown(tmp_path)
    assert "hertz-line against Hertz" in text and "dofs to 1%: peak_pressure" in text and "deviation" in text


def test_a_prediction_that_is_not_a_function_is_refused(tmp_path):
    bad = tmp_path / "bad.py"
    bad.write_text(CASE.read_text() + "\npredicted_quantities = 3\n")
    with pytest.raises(CaseError, match="predicted_quantities must be a function"):
        load_case(str(bad))


# Hertz point contact (3D): the registered hertz-sphere

SPHERE = Path(__file__).resolve().parent.parent / "cases" / "hertz_sphere.py"


def sphere_module():
    return module(SPHERE)


def test_the_sphere_formulas_integrate_to_the_force_they_were_given():
    """int over the disc of p0 sqrt(1 - r^2/a^2) = (2/3) pi a^2 p0 = F, and delta = a^2/R is
    Johnson's approach (9 F^2 / (16 R E*^2))^{1/3}: the case's formulas hold together."""
    hertz = sphere_module()
    for force in (1e-4, 1.6e-3, 0.3):
        a, p0 = hertz.hertz(force)
        assert 2 / 3 * math.pi * a * a * p0 == pytest.approx(force, rel=1e-14)
        assert a * a / hertz.RADIUS == pytest.approx((9 * force**2 / (16 * hertz.RADIUS * hertz.E_STAR**2)) ** (1 / 3), rel=1e-14)
    assert registered_cases()["hertz-sphere"].report_profile == "fine"


@pytest.mark.slow
def test_sphere_p2_is_within_two_percent_of_hertz_on_its_second_level():
    """nodal P2 on level 1 (1.8e5 dofs): the contact radius sqrt(area / pi) and the peak
    pressure within 2 % of Hertz at the computed force (the fine profile's finest studied level),
    and closer than on level 0; solved without the reference (1.4e6 dofs one level finer)."""
    from harness.fem.assembly import discretise
    from harness.measure.quantities import quantities
    from harness.mesh.levels import UniformRefinement
    from harness.methods import get_method
    from harness.solvers.multigrid import Multilevel

    case, method, hertz = load_case("hertz-sphere"), get_method("nodal"), sphere_module().hertz
    multilevel, carry, deviations = None, None, []
    for step in UniformRefinement(case).levels(2):
        multilevel = Multilevel(step.mesh, case.physics) if multilevel is None else multilevel.refined(step.mesh)
        problem = discretise(case, step.mesh, method.order)
        solved = method.solve(case, problem, carry, multilevel)
        carry = solved.carry
        assert solved.fields["kkt_residual"] <= 1e-10
        q = quantities(case, problem, solved.u)
        a, p0 = hertz(q["qoi_force"])
        deviations.append((math.sqrt(q["qoi_contact_measure"] / math.pi) / a - 1, q["qoi_peak_pressure"] / p0 - 1))
    (a0, p00), (a1, p01) = deviations
    assert abs(a1) < 0.02 and abs(p01) < 0.02, deviations
    assert abs(a1) < abs(a0) and abs(p01) < abs(p00)
