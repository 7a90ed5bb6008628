"""The report's Friction section (``report.sections.friction``): its tables and stick/slip
figures for a small friction study, nothing without a friction case, the friction quantities
where the rows have them, and "n/a" with the reason in the verdict matrix."""
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pandas as pd
import pytest

from harness.methods import methods_named
from harness.problem.case import load_case
from harness.report.build import make_report
from harness.report.document import Document
from harness.report.sections import SECTIONS, cases, friction, glance, three_d

FRICTION_CASE = "tresca-r32"
FRICTION_METHODS = ["nodal", "mean", "p1"]


@pytest.fixture(scope="module")
def report(tmp_path_factory):
    root = tmp_path_factory.mktemp("friction")
    html = make_report("default", root / "results", root / "report", [FRICTION_CASE], show_progress=False,
                       levels=3, methods=FRICTION_METHODS)
    return root, html


def test_friction_section_comes_after_three_d_and_before_each_case_in_full():
    assert SECTIONS.index(three_d) < SECTIONS.index(friction) < SECTIONS.index(cases)


def test_friction_section_writes_its_rates_and_the_stick_slip_figure(report):
    root, html = report
    markdown = (root / "report" / "report.md").read_text()
    section = markdown.split("## Tresca friction", 1)[1].split("\n## ", 1)[0]
    for method in FRICTION_METHODS:
        assert f"| {FRICTION_CASE} | {method} |" in section
    assert f"figures/{FRICTION_CASE}_stick_slip.png" in section
    for fmt in ("png", "pdf"):
        assert (root / "report" / "figures" / f"{FRICTION_CASE}_stick_slip.{fmt}").stat().st_size > 0
    # the case's own section shows the same picture as its contact figure, with its caption
    assert "Stick and slip, finest level" in markdown.split("## Cases", 1)[1]


@pytest.mark.parametrize("name", ["transition-r32", "corner-r12"])
def test_friction_section_writes_nothing_without_a_friction_case(name):
    doc = Document("t")
    friction.write(doc, SimpleNamespace(cases=[load_case(name)]))
    assert doc.blocks == []


def test_friction_quantities_are_tabulated_when_the_rows_have_them():
    h = 0.5 ** np.arange(4)
    rows = pd.DataFrame({"case": "c", "method": "nodal", "level": range(4), "h": h, "ndof": 4.0 ** np.arange(4),
                         "mesh": "uniform", "qoi_slip_measure": 1.0 + h ** 1.5, "qoi_slip_measure_exact": 1.0,
                         "err_friction_l2": 0.3 * h ** 2})
    view = friction.friction_quantity_view(rows)
    assert list(view.columns) == ["case", "method", "qoi_slip_measure", "err_friction_l2"]
    assert "(p 1.50)" in view.qoi_slip_measure[0] and "error 4.4e-02" in view.qoi_slip_measure[0]
    assert "(rate 2.00)" in view.err_friction_l2[0]
    assert friction.friction_quantity_view(rows.drop(columns=["qoi_slip_measure", "err_friction_l2"])).empty


def test_a_method_that_leaves_a_case_out_shows_not_applicable_with_its_reason():
    cells = pd.DataFrame({"nodal": ["1.50 / 1.50"], "mean-edges": [""]}, index=pd.Index([FRICTION_CASE], name="case"))
    cells.attrs["verdicts"] = pd.DataFrame({"nodal": ["meets"], "mean-edges": [""]}, index=cells.index)
    reasons = glance.mark_not_applicable(cells, [load_case(FRICTION_CASE)], methods_named(["nodal", "mean-edges"]))
    assert cells.loc[FRICTION_CASE, "mean-edges"] == "n/a"
    assert cells.attrs["verdicts"].loc[FRICTION_CASE, "mean-edges"] == "not applicable"
    assert [cases for (method, _), cases in reasons.items() if method == "mean-edges"] == [[FRICTION_CASE]]


def test_stick_slip_figure_is_not_drawn_from_snapshots_without_the_slip(tmp_path):
    case = SimpleNamespace(physics=SimpleNamespace(elastic=True))
    assert friction.stick_slip(case, {"nodal": {"s": np.zeros(2)}}, Path(tmp_path)) is None


def _elastic_pair():
    """two-body-elastic-transition under Coulomb (mu_F = 0.3), both coarse meshes refined once:
    non-matching on Gamma_C (2:3), P2."""
    import dataclasses

    from harness.fem.assembly import discretise
    from harness.fem.two_body import TwoBodyProblem
    from harness.mesh.levels import coarse_mesh
    from harness.problem.bodies import lower_body
    from harness.problem.case import registered_cases
    from harness.problem.friction import Coulomb
    case = dataclasses.replace(registered_cases()["two-body-elastic-transition"], friction=Coulomb(0.3))
    bodies = (case, lower_body(case))
    meshes = [coarse_mesh(body) for body in bodies]
    for mesh in meshes:
        mesh.Refine()
    return bodies, TwoBodyProblem(*(discretise(body, mesh, 2) for body, mesh in zip(bodies, meshes)))


def test_a_two_body_snapshot_slip_is_the_jump_the_quantities_measure():
    """At the upper body's Gauss points the two-body snapshot's slip is the quantities' slip
    (``measure.two_body_quantities.two_body_interface``: t_1 from the upper body's
    ``DiscreteTraction``, t_2 by ``MasterTrace``) for a random u_h less a random previous step,
    to round-off; its per-edge friction force times the edge lengths sums to the quantities'
    Q (the P, Q the dashed closed form is read at); no exact slip or force (NaN)."""
    from harness.measure.two_body_quantities import two_body_interface
    from harness.study.chain.snapshots import two_body_friction_snapshot
    bodies, problem = _elastic_pair()
    rng = np.random.default_rng(3)
    u, previous = rng.standard_normal((2, problem.ndof))
    interface = two_body_interface(bodies, problem, u, previous)
    x = interface.q.points[:, 0]
    snap = two_body_friction_snapshot(problem, x, u, previous)
    np.testing.assert_allclose(snap["slip"], interface.slip[:, 0], rtol=0, atol=1e-12 * np.abs(interface.slip).max())
    trace = problem.upper.trace
    lengths = trace.lengths[np.argsort(trace.midpoints[:, 0])]            # the snapshot's edge order
    assert np.abs(interface.slip).max() > 0.1
    np.testing.assert_allclose(snap["friction_force"] @ lengths, interface.q.weights @ interface.force[:, 0], rtol=1e-12)
    assert np.isnan(snap["exact_slip"]).all() and np.isnan(snap["exact_friction_force"]).all()


TWO_BODY_CASE = "cattaneo-two-body-q03"


@pytest.mark.slow
def test_the_coulomb_section_draws_the_two_body_stick_slip_figure(tmp_path):
    """A two-body Coulomb case (`mortar-nodal`, levels 0-1): the Coulomb section shows its
    stick/slip picture, captioned with the jump between the bodies; the stored snapshot holds
    the slip, zero where Cattaneo's stick zone is (|x| < c, c = 0.084 here: |x| < 0.05) and not in
    its slip zone (0.09 < |x| < 0.1, a = 0.1), and the friction force per edge."""
    html = make_report("default", tmp_path / "results", tmp_path / "report", [TWO_BODY_CASE], show_progress=False,
                       levels=2, methods=["mortar-nodal"])
    markdown = (tmp_path / "report" / "report.md").read_text()
    section = markdown.split("## Coulomb friction", 1)[1].split("\n## ", 1)[0]
    assert f"figures/{TWO_BODY_CASE}_stick_slip.png" in section and "the tangential jump between the bodies" in section
    assert (tmp_path / "report" / "figures" / f"{TWO_BODY_CASE}_stick_slip.png").stat().st_size > 0
    snap = np.load(next((tmp_path / "results").rglob(f"{TWO_BODY_CASE}.npz")))
    s, slip = snap["contact__mortar-nodal__s"], np.abs(snap["contact__mortar-nodal__slip"])
    assert len(snap["contact__mortar-nodal__friction_force"]) == len(snap["contact__mortar-nodal__edge_s"])
    slipping = slip[(np.abs(s) > 0.09) & (np.abs(s) < 0.1)]
    assert slip[np.abs(s) < 0.05].max() <= 1e-2 * slipping.min(), (slip[np.abs(s) < 0.05].max(), slipping.min())
    assert html.exists()
