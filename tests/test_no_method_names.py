"""No method name outside ``harness/methods/`` (issue 51, item 3): the code elsewhere asks for
the methods that declare a role (``Method.roles``: the paper's P2 models, the P1 baseline, the
reference method, ...), so that a method of your own appears everywhere the harness's do and can
take any role."""
import ast
import dataclasses
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from harness.measure.efficiency import baseline_name, efficiency_table
from harness.measure.reference import REFERENCE_METHOD, reference_method
from harness.methods import (
    BASELINE,
    GROUPS,
    MESH_STUDY,
    METHODS,
    PAPER,
    REFERENCE,
    ROLES,
    SWEPT,
    known,
    methods_named,
    names_with_role,
    role_names,
    with_role,
)
from harness.report.plots import method_styles
from harness.study.execution.budget import SOLVE_SECONDS_PER_DOF, solve_seconds_per_dof
from harness.study.planning.sweep import REPORT_SWEEP

PACKAGE = Path(__file__).resolve().parent.parent / "harness"
NAMES = set(METHODS) | set(GROUPS)
# strings that are method names by coincidence, each with why it may stay
ALLOWED = {("fem/cones.py", "mean"): "the 0.3 name of the edge-mean rule (ContactModel), deprecated until 0.5"}


def outside_methods() -> list[Path]:
    return sorted(p for p in PACKAGE.rglob("*.py") if p.relative_to(PACKAGE).parts[0] != "methods")


def docstrings(tree: ast.AST) -> set[int]:
    """The ids of the string constants that are docstrings (a module's, class's or function's
    first statement)."""
    found = set()
    for node in ast.walk(tree):
        if isinstance(node, (ast.Module, ast.ClassDef, ast.FunctionDef, ast.AsyncFunctionDef)) and node.body:
            first = node.body[0]
            if isinstance(first, ast.Expr) and isinstance(first.value, ast.Constant) and isinstance(first.value.value, str):
                found.add(id(first.value))
    return found


def method_names_in(path: Path) -> list[str]:
    """'line: string' for every string constant of ``path`` (docstrings aside) that is a method
    or group name, or a method with parameters ('name:...')."""
    tree = ast.parse(path.read_text())
    skip = docstrings(tree)
    return [f"{node.lineno}: {node.value!r}" for node in ast.walk(tree)
            if isinstance(node, ast.Constant) and isinstance(node.value, str) and id(node) not in skip
            and (node.value in NAMES or node.value.partition(":")[0] in NAMES and ":" in node.value)]


def test_the_scan_finds_what_it_looks_for(tmp_path):
    sample = tmp_path / "sample.py"
    sample.write_text('"""nodal in a docstring is fine."""\nA = "nodal"\nB = ("paper", "nitsche:theta=0", "nodal-ish")\n'
                      'def f():\n    """p1 too."""\n    return f"{A}: p1"\n')
    assert method_names_in(sample) == ["2: 'nodal'", "3: 'paper'", "3: 'nitsche:theta=0'"]


@pytest.mark.parametrize("path", outside_methods(), ids=lambda p: str(p.relative_to(PACKAGE)))
def test_no_method_or_group_name_is_written_in_the_code_outside_methods(path):
    where = str(path.relative_to(PACKAGE))
    assert not [s for s in method_names_in(path) if (where, ast.literal_eval(s.split(": ", 1)[1])) not in ALLOWED], f"{path.relative_to(PACKAGE.parent)} names methods: use a role (harness.methods.with_role)"


def test_the_registered_methods_declare_the_roles_the_report_gave_them_by_name():
    assert role_names(PAPER) == ["mean", "nodal"] == list(GROUPS[PAPER])
    assert role_names(BASELINE) == ["p1"]
    # nitsche: the reference of the cases nodal does not discretise (3D Coulomb: ``measure.reference.reference_method``)
    assert REFERENCE_METHOD == "nodal" and role_names(REFERENCE) == ["nodal", "mortar-nodal", "nitsche"]
    assert role_names(SWEPT) == ["nitsche", "penalty"]
    assert role_names(MESH_STUDY) == ["nodal", "p1", "mortar-nodal", "nitsche", "mortar-p1"]
    assert REPORT_SWEEP["methods"] == ("nitsche", "nitsche:theta=0", "nitsche:theta=-1", "penalty")
    assert REPORT_SWEEP["reference"] == ("nodal",)
    assert all(set(m.roles) <= set(ROLES) for m in METHODS.values())
    # other parameter values make another method, without the roles
    assert not methods_named("nitsche:theta=-1")[0].roles


def test_a_method_of_your_own_may_take_a_role():
    mine = dataclasses.replace(METHODS["p1"], name="my-p1", roles=frozenset({BASELINE}))
    assert with_role(BASELINE, [METHODS["nodal"], mine]) == [mine]
    assert not dataclasses.replace(METHODS["p1"], name="a-p1").roles      # a copy renamed takes none unasked
    assert METHODS["p1"].with_extra_levels(2).roles == METHODS["p1"].roles   # the same method, run longer
    assert names_with_role(BASELINE, ["nodal", "my-p1"]) == []             # unknown by name here
    with known([mine]):
        assert names_with_role(BASELINE, ["nodal", "my-p1"]) == ["my-p1"]
        assert methods_named(["my-p1"]) == [mine]
    assert names_with_role(BASELINE, ["nodal", "my-p1"], [mine]) == ["my-p1"]
    reference = dataclasses.replace(METHODS["mean"], name="my-reference", roles=frozenset({REFERENCE}))
    assert reference_method(methods=[reference]) is reference
    assert reference_method() is METHODS["nodal"]


def _levels(method: str, order: int, errors, ndofs) -> list[dict]:
    return [{"case": "c", "method": method, "order": order, "level": k, "err_h1": e, "ndof": n,
             "solve_seconds": 0.1 * n / 1e3, "total_seconds": 0.2 * n / 1e3} for k, (e, n) in enumerate(zip(errors, ndofs))]


def test_the_efficiency_baseline_is_the_method_that_declares_the_role():
    frame = pd.DataFrame(_levels("nodal", 2, [1e-2, 3e-3, 1e-3], [100, 400, 1600])
                         + _levels("my-p1", 1, [2e-2, 1e-2, 5e-3, 2.5e-3], [100, 400, 1600, 6400]))
    mine = dataclasses.replace(METHODS["p1"], name="my-p1").with_roles(BASELINE)
    assert baseline_name(frame.method) is None
    assert efficiency_table(frame).p1_over_ndof.isna().all()             # no baseline: no ratios
    table = efficiency_table(frame, methods=[mine]).set_index("method")
    assert table.loc["my-p1", "p1_over_ndof"] == 1.0 and table.loc["nodal", "p1_over_ndof"] > 1.0
    with known([mine]):
        assert np.allclose(efficiency_table(frame).p1_over_ndof, table.p1_over_ndof)


def test_colours_are_assigned_the_paper_and_the_baseline_first_and_stable():
    every = method_styles(METHODS.values())
    assert [every[m]["color"] for m in ("mean", "nodal", "p1")] == ["tab:blue", "tab:orange", "tab:green"]
    assert [every[m]["marker"] for m in ("mean", "nodal", "p1")] == ["o", "s", "^"]
    assert len({s["color"] for s in every.values()}) == len(every)        # no two methods alike
    mine = dataclasses.replace(METHODS["nitsche"], name="my-nitsche", roles=frozenset())
    alone = method_styles([mine, "p1"])                                    # the roles' places stay theirs
    assert alone["p1"] == every["p1"] and alone["my-nitsche"]["color"] not in {every[m]["color"] for m in ("mean", "nodal", "p1")}
    paper = dataclasses.replace(mine, name="my-paper", roles=frozenset({PAPER}))
    assert list(method_styles([paper]))[:3] == ["mean", "nodal", "my-paper"]


def test_the_budget_takes_the_cost_model_a_method_declares():
    assert METHODS["nitsche"].cost_model == "newton" and METHODS["nodal"].cost_model == "active-set"
    assert solve_seconds_per_dof(METHODS["nitsche"], "scalar", 2) == SOLVE_SECONDS_PER_DOF[("newton", "scalar", 2)]
    assert solve_seconds_per_dof(METHODS["mortar-nodal"], "scalar", 2) == SOLVE_SECONDS_PER_DOF[("active-set", "scalar", 2)]
    own = dataclasses.replace(METHODS["nitsche"], name="slow", cost_model=1e-3)
    assert solve_seconds_per_dof(own, "scalar", 2) == 1e-3
    unknown = dataclasses.replace(own, cost_model="something else")
    assert solve_seconds_per_dof(unknown, "scalar", 2) == max(SOLVE_SECONDS_PER_DOF.values())


@pytest.mark.slow       # one small report (about 35 s: its figure processes, sweep-free, and the mesh study)
def test_a_method_of_your_own_from_a_file_is_in_every_part_of_the_report(tmp_path):
    from harness.report.build import make_report
    source = tmp_path / "outside" / "my_nitsche.py"
    source.parent.mkdir()
    source.write_text('import dataclasses\nimport harness.methods\n'
                      'method = dataclasses.replace(harness.methods.METHODS["nitsche"], name="my-nitsche", roles=frozenset())\n')
    mine = methods_named([str(source)])[0]                      # an object, as from Python
    html = make_report("default", tmp_path / "results", tmp_path / "report", ["transition-r32"], levels=2,
                       methods=[mine, PAPER], show_progress=False)
    for table in ("results.csv", "rates.csv", "efficiency.csv"):
        assert "my-nitsche" in set(pd.read_csv(tmp_path / "results" / table).method), table
    text = Path(html).read_text()
    assert "of your own: <code>my-nitsche</code>" in text and "transition-r32: method my-nitsche" in text
    for tex in ("summary.tex", "efficiency.tex", "transition-r32.tex"):
        assert "my-nitsche" in (tmp_path / "report" / "tables" / tex).read_text(), tex
