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
