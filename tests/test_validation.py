"""The harness refuses a case whose exact solution breaks the Signorini conditions (2.4)."""
import dataclasses
import math
from pathlib import Path

import ngsolve as ngs
import numpy as np
import pytest

from harness.methods import methods_named
from harness.problem.case import REPORT_PROFILES, CaseError, load_case, registered_cases
from harness.problem.validate import validate_case

DATA = Path(__file__).parent / "data"


# the 2D cases in `make test`; the 3D ones (2-9 s each: the same checks on a 3D quadrature) in
# `make test-full`
VALIDATED = [name if case.dimension == 2 else pytest.param(name, marks=pytest.mark.slow)
             for name, case in registered_cases().items()]


@pytest.mark.parametrize("case_name", VALIDATED)
def test_registered_cases_satisfy_signorini_conditions(case_name):
    validate_case(registered_cases()[case_name])


def test_case_file_outside_repository_runs_by_path():
    case = load_case(str(DATA / "gap_case.py"))
    validate_case(case)
    assert case.gap is not None and case.contact_load is not None


def test_violated_sign_is_refused_with_condition_and_place():
    with pytest.raises(CaseError, match=r"u - gap >= 0 on Gamma_C at \(-"):
        validate_case(load_case(str(DATA / "bad_sign_case.py")))


def test_missing_label_is_refused():
    with pytest.raises(CaseError, match="no boundary labelled dirichlet"):
        validate_case(load_case(str(DATA / "no_dirichlet_case.py")))


def test_unknown_case_lists_known_ones():
    with pytest.raises(CaseError, match="known cases: .*transition-r32"):
        load_case("no-such-case")


@pytest.mark.parametrize("case_name, wrong_f", [("transition-r32", 1.0), ("borderline-h2", 0)])
def test_declared_f_that_is_not_minus_laplacian_is_refused(case_name, wrong_f):
    case = dataclasses.replace(registered_cases()[case_name], declared_f=wrong_f)
    with pytest.raises(CaseError, match=r"declared f is not -Laplace\(u\) at \("):
        validate_case(case)


@pytest.mark.parametrize("wrong", ["swapped", "scaled", "scalar"])
def test_declared_grad_u_that_is_not_the_gradient_of_u_is_refused(wrong):
    """oscillating-r34 declares grad u in closed form (it passes validation: the registered
    cases' test); a swapped, slightly scaled or scalar one is refused."""
    case = registered_cases()["oscillating-r34"]
    declared = case.declared_grad_u
    assert declared is not None
    bad = {"swapped": ngs.CF((declared[1], declared[0])), "scaled": (1 + 1e-6) * declared, "scalar": declared[0]}[wrong]
    with pytest.raises(CaseError, match=r"grad_u (is not the gradient of u at \(|has 1 components)"):
        validate_case(dataclasses.replace(case, declared_grad_u=bad))


def test_singular_point_off_the_mesh_vertices_is_refused():
    case = dataclasses.replace(registered_cases()["transition-r32"], singular_points=((0.3, 0.0),))
    with pytest.raises(CaseError, match=r"\(0.3, 0\) is not a vertex of the mesh"):
        validate_case(case)


def test_a_case_asymptotic_by_six_levels_runs_six_in_the_default_report_and_what_it_is_told_otherwise():
    from harness.study.chain import PROFILES
    from harness.study.planning.cache import case_settings, study_groups
    known = registered_cases()
    default, fine = {"profile": "default", **PROFILES["default"]}, {"profile": "fine", **PROFILES["fine"]}
    assert known["corner-r12"].asymptotic_levels == 6
    assert case_settings(known["corner-r12"], default)["levels"] == 6
    assert case_settings(known["borderline-h2"], default)["levels"] == 7        # not asymptotic by six
    # a case whose levels cost more than the profile's budget stops at its report_levels
    assert case_settings(known["oscillating-r34"], default)["levels"] == 6
    assert case_settings(known["oscillating-r34"], fine)["levels"] == 8
    assert case_settings(known["corner-r12"], fine)["levels"] == 8               # the fine profile runs all
    told = default | {"levels": 5, "stop_when_asymptotic": False, "levels_given": True}   # report --levels 5
    assert {case_settings(case, told)["levels"] for case in known.values() if case.dimension == 2} == {5}
    groups = study_groups([known[n] for n in ("transition-line-3d", "corner-r12", "borderline-h2")], default)
    assert [([c.name for c in group], own["levels"]) for group, own in groups] == \
        [(["corner-r12"], 6), (["borderline-h2"], 7), (["transition-line-3d"], 3)]


def test_p1_stops_with_p2_in_the_default_report_where_the_case_says_its_fits_are_asymptotic():
    from harness.study.chain import PROFILES, study_levels
    from harness.study.planning.cache import case_settings, study_methods
    known = registered_cases()
    default, fine = {"methods": ["all"], **PROFILES["default"]}, {"methods": ["all"], **PROFILES["fine"]}

    def levels(case, settings):
        own = case_settings(known[case], settings)
        return {m.name: study_levels(m, own["levels"]) for m in study_methods(own) if m.name in ("nodal", "p1", "penalty-p1")}
    assert levels("smooth", default) == {"nodal": 7, "p1": 7, "penalty-p1": 7}
    assert levels("corner-r12", default) == {"nodal": 6, "p1": 6, "penalty-p1": 6}
    assert levels("oscillating-r34", default) == {"nodal": 7, "p1": 8, "penalty-p1": 8}     # P1 not asymptotic a level early
    assert levels("smooth", fine) == {"nodal": 8, "p1": 9, "penalty-p1": 9}                 # the fine profile runs all
    # the method is the same method, only its levels differ
    p1 = next(m for m in study_methods(case_settings(known["smooth"], default)) if m.name == "p1")
    assert p1.extra_levels == 0 and p1.with_extra_levels(1) == methods_named(["p1"])[0].with_extra_levels(1)


@pytest.mark.parametrize("p2, p1", [(6, 5), (6, 8)])
def test_p1_levels_other_than_p2s_or_one_more_are_refused(tmp_path, p2, p1):
    source = Path(registered_cases()["corner-r12"].source).read_text()
    path = tmp_path / "case.py"
    path.write_text(source.replace("asymptotic_levels_p1 = 6", f"asymptotic_levels_p1 = {p1}").replace(
        "asymptotic_levels = 6", f"asymptotic_levels = {p2}"))
    with pytest.raises(CaseError, match="asymptotic_levels_p1 must be asymptotic_levels"):
        load_case(str(path))


@pytest.mark.parametrize("side", ["right", "left"])
def test_the_transitions_closed_form_gradient_is_its_derived_one(side):
    """``transition_gradient`` against NGSolve's derivative of ``transition`` (an offset x0, both
    binding sides), in the L^2 norm over a strip above Gamma_C."""
    from harness.problem.functions import transition, transition_gradient
    from harness.problem.geometry import contact_strip
    mesh = ngs.Mesh(contact_strip(breaks=[0.2]).GenerateMesh(maxh=0.2))
    g = transition(0.2, binding_side=side)
    derived = ngs.CF((g.Diff(ngs.x), g.Diff(ngs.y)))
    closed = ngs.CF(transition_gradient(0.2, binding_side=side))
    error = ngs.Integrate(ngs.InnerProduct(closed - derived, closed - derived), mesh, order=8)
    assert error <= 1e-24 * ngs.Integrate(ngs.InnerProduct(derived, derived), mesh, order=8)


@pytest.mark.parametrize("options", [dict(), dict(x0=0.2, mirrored=True), dict(x0=0.2, angle=0.3),
                                     dict(x0=0.2, mirrored=True, angle=-0.4)])
@pytest.mark.parametrize("exponent, omega", [(0.5, math.pi), (1.5, math.pi), (0.544483736782464, 3 * math.pi / 4)])
def test_the_roller_modes_closed_form_gradient_is_its_derived_one(exponent, omega, options):
    """``roller_free_mode(..., with_gradient=True)`` (the derivatives of its ``PolarSeries``):
    the Jacobian equals NGSolve's derivative of u for an offset, a mirrored and a turned mode,
    to 1e-12 relative in L^2 over a strip above Gamma_C; its u is the mode's."""
    from harness.problem.functions import roller_free_mode
    from harness.problem.geometry import contact_strip
    from harness.problem.physics import Elasticity, gradient
    mesh = ngs.Mesh(contact_strip(breaks=[0.2]).GenerateMesh(maxh=0.2))
    material = Elasticity(1.0, 0.3)
    u, closed = roller_free_mode(exponent, omega, material, with_gradient=True, **options)
    derived = gradient(roller_free_mode(exponent, omega, material, **options), 2)
    size = ngs.Integrate(ngs.InnerProduct(derived, derived), mesh, order=8)
    assert ngs.Integrate(ngs.InnerProduct(closed - derived, closed - derived), mesh, order=8) <= 1e-24 * size
    plain = roller_free_mode(exponent, omega, material, **options)
    assert ngs.Integrate(ngs.InnerProduct(u - plain, u - plain), mesh, order=8) == 0.0


def test_the_3d_roller_modes_closed_form_gradient_is_its_derived_one():
    """The same in the (x, z) plane of a 3D body (coordinates 'xz'): a 3 x 3 Jacobian with zero
    y-row and y-column."""
    from harness.problem.functions import roller_free_mode
    from harness.problem.geometry import contact_box
    from harness.problem.physics import Elasticity, gradient
    mesh = ngs.Mesh(contact_box(split_at=0.2).GenerateMesh(maxh=0.5))
    material = Elasticity(1.0, 0.3, dim=3)
    _, closed = roller_free_mode(1.5, math.pi, material, x0=0.2, mirrored=True, coordinates="xz", with_gradient=True)
    derived = gradient(roller_free_mode(1.5, math.pi, material, x0=0.2, mirrored=True, coordinates="xz"), 3)
    size = ngs.Integrate(ngs.InnerProduct(derived, derived), mesh, order=6)
    assert ngs.Integrate(ngs.InnerProduct(closed - derived, closed - derived), mesh, order=6) <= 1e-24 * size


def test_a_fine_only_case_is_left_out_of_the_default_report_and_named_there():
    """``report_profile = "fine"`` (elastic-transition-circle-3d: its study is more than the
    default report's five minutes allow): the default profile's cases leave it out and the
    report's meta line names it and how to run it; the fine profile, and a report of chosen
    cases, run it; the profiles a case may name are the study's."""
    from harness.report.build import in_profile, left_out_text
    from harness.study.chain import PROFILES
    known = registered_cases()
    assert known["elastic-transition-circle-3d"].report_profile == "fine"
    default, fine = in_profile(known.values(), "default"), in_profile(known.values(), "fine")
    assert [c.name for c in fine] == list(known)
    assert {c.name for c in fine} - {c.name for c in default} == {
        "elastic-transition-circle-3d", "hertz-sphere", "smooth-quintic", "tresca-r72", "tresca-corner-r12",
        "tresca-reference", "tresca-line-3d", "elastic-tresca-3d", "two-body-tresca-r32", "elastic-coulomb-3d",
        "cattaneo-line-q03", "cattaneo-line-q07", "cattaneo-line-q03-nu47", "cattaneo-line-q07-nu47", "mindlin-sphere",
        "transition-circle-3d", "smooth-3d", "elastic-junction-3d", "cattaneo-two-body-q03",
        "cattaneo-two-body-q07"}
    text = left_out_text(default, {"profile": "default"})
    assert "elastic-transition-circle-3d" in text and "report-fine" in text
    assert left_out_text(fine, {"profile": "fine"}) == ""
    assert left_out_text([known["smooth"]], {"profile": "default"}) == ""      # report --case smooth
    assert tuple(PROFILES) == REPORT_PROFILES


def test_an_unknown_report_profile_is_refused(tmp_path):
    source = Path(registered_cases()["corner-r12"].source).read_text()
    path = tmp_path / "case.py"
    path.write_text(source + "\nreport_profile = 'weekly'\n")
    with pytest.raises(CaseError, match="report_profile must be one of default, fine, got 'weekly'"):
        load_case(str(path))


@pytest.mark.parametrize("jumps", ["[((0.0, 0.0), (0.0, 0.0))]", "[((0.0, 0.0), (0.0, float('nan')))]",
                                   "[((0.0, 0.0, 0.0), (0.0, 1.0, 0.0))]", "[((0.0, 0.0),)]", "[(0.0, 1.0)]",
                                   "0.5", "'x = 0'"])
def test_a_malformed_derivative_jump_is_refused_in_one_line(tmp_path, jumps):
    """``derivative_jumps``: segments ((x0, y0), (x1, y1)) of finite numbers with distinct ends;
    anything else (a point, a 3D segment, NaN, a number, a string) is refused when the case is
    loaded, in one line."""
    source = Path(registered_cases()["smooth"].source).read_text()
    path = tmp_path / "case.py"
    path.write_text(source + f"\nderivative_jumps = {jumps}\n")
    with pytest.raises(CaseError, match=r"derivative_jumps must be a list of segments \(\(x0, y0\), \(x1, y1\)\)") as error:
        load_case(str(path))
    assert "\n" not in str(error.value)


def test_derivative_jumps_are_2d_only_and_select_the_elements_they_cross(tmp_path):
    """A 3D case's derivative_jumps are refused in one line. smooth's x = 0 crosses the elements
    whose vertices lie on both sides of it, and no other: not those that only touch it at (0, 0)."""
    from harness.fem.element_quadrature import crossed_elements
    from harness.mesh.levels import coarse_mesh
    from harness.mesh.points import cells, coordinates
    source = Path(registered_cases()["smooth-3d"].source).read_text()
    path = tmp_path / "case.py"
    path.write_text(source + "\nderivative_jumps = [((0.0, 0.0), (0.0, 1.0))]\n")
    with pytest.raises(CaseError, match="derivative_jumps are 2D only") as error:
        load_case(str(path))
    assert "\n" not in str(error.value)
    case = registered_cases()["smooth"]
    assert case.derivative_jumps == (((0.0, 0.0), (0.0, 1.0)),)
    mesh = coarse_mesh(case)
    x = coordinates(mesh)[cells(mesh)][..., 0]
    straddling = np.flatnonzero((x.min(axis=1) < -1e-12) & (x.max(axis=1) > 1e-12))
    np.testing.assert_array_equal(crossed_elements(case, mesh), straddling)
    assert len(crossed_elements(dataclasses.replace(case, derivative_jumps=()), mesh)) == 0
