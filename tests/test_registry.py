"""The methods' registry: one module per family, listed explicitly (a helper module beside
them is not read), the registry's order and groups as in 0.10.3 (the report's CSVs follow the
order), groups derived from what a method is, roles checked, and what a study leaves out of a
case said with its reason (``harness.methods.left_out``)."""
import ast
import shutil
import subprocess
import sys
from pathlib import Path
from types import SimpleNamespace

import pytest

from harness.core.names import assignments, look_up, split_spec
from harness.methods import FAMILIES, GROUPS, METHODS, Method, OwnSolution, OwnSolve, get_method, left_out, methods_for
from harness.problem.friction import FRICTIONLESS

PACKAGE = Path(__file__).resolve().parent.parent / "harness"

# 0.10.3's registry order and groups (the report's CSVs list methods in this order)
ORDER = ["mean", "mean-edges", "nodal", "p1", "mortar-mean", "mortar-nodal", "mortar-standard", "nitsche", "penalty",
         "mortar-p1", "nitsche-p1", "penalty-p1", "mean-p3", "nitsche-p3", "nodal-p3", "penalty-p3", "mean-p4",
         "nitsche-p4", "nodal-p4", "penalty-p4"]
GROUPS_0_10_3 = {
    "paper": ["mean", "nodal"], "cones": ["mean", "nodal", "p1"], "weak": ["nitsche", "penalty", "nitsche-p1", "penalty-p1"],
    "mortar": ["mortar-mean", "mortar-nodal", "mortar-standard", "mortar-p1"],
    "degrees": ["nodal", "p1", "nitsche", "nitsche-p1", "nitsche-p3", "nodal-p3", "nitsche-p4", "nodal-p4"],
    "high-order": ["nitsche-p3", "nitsche-p4", "penalty-p3", "penalty-p4", "nodal-p3", "nodal-p4", "mean-p3", "mean-p4"],
}


# the methods added since 0.10.3, in registry order, and the groups they joined (0.17.0: the
# two-body Nitsche methods, weak methods between two bodies)
ADDED = {"mortar-nitsche": ("weak", "mortar"), "mortar-nitsche-p1": ("weak", "mortar")}


def test_the_registry_keeps_its_order_and_its_groups():
    """0.10.3's methods keep their order and groups; the methods added since take their place by
    the registry's rule (``registry._place``) and join the groups their kind puts them in."""
    assert [m for m in METHODS if m in ORDER] == ORDER
    assert [m for m in METHODS if m not in ORDER] == list(ADDED)
    assert list(GROUPS) == list(GROUPS_0_10_3)
    for name, members in GROUPS_0_10_3.items():
        # every group in registry order (0.10.3 listed high-order by family; methods_named took registry order)
        joined = [m for m, groups in ADDED.items() if name in groups]
        assert list(GROUPS[name]) == [m for m in METHODS if m in members or m in joined], name


def test_every_method_comes_from_a_family_module_listed_in_the_registry():
    declared = [m.name for family in FAMILIES for m in family.methods]
    assert sorted(declared) == sorted(METHODS)


def test_methods_holds_at_most_twelve_modules_none_a_single_call():
    modules = sorted((PACKAGE / "methods").glob("*.py"))
    assert len(modules) <= 12, [p.name for p in modules]
    for path in modules:
        body = [n for n in ast.parse(path.read_text()).body if not (isinstance(n, ast.Expr) and isinstance(n.value, ast.Constant))]
        statements = [n for n in body if not isinstance(n, (ast.Import, ast.ImportFrom))]
        single_call = len(statements) == 1 and isinstance(statements[0], ast.Assign) and isinstance(statements[0].value, ast.Call)
        assert not single_call, f"{path.name} is a single call"


def test_a_helper_module_in_methods_does_not_break_the_import(tmp_path):
    """A plain module beside the families (no ``methods``, no ``method``) is not read: the
    registry lists its families."""
    copy = tmp_path / "harness"
    shutil.copytree(PACKAGE, copy, ignore=shutil.ignore_patterns("__pycache__"))
    (copy / "methods" / "helpers.py").write_text('"""Shared helpers of two families."""\n\n\ndef twice(x):\n    return 2 * x\n')
    code = "import harness, harness.methods as m; assert harness.__file__.startswith(%r); print(len(m.METHODS))" % str(tmp_path)
    out = subprocess.run([sys.executable, "-c", code], cwd=tmp_path, capture_output=True, text=True,
                         env={"PYTHONPATH": str(tmp_path), "PATH": "/usr/bin:/bin"})
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip() == str(len(METHODS))


def test_an_unknown_role_is_refused_in_one_line():
    with pytest.raises(ValueError, match="unknown role.*papr"):
        Method(name="x", order=2, contact="", reference="", expected=None, roles=frozenset({"papr"}))


def _case(physics="scalar", dimension=2, bodies=1, exact=True):
    return SimpleNamespace(physics=SimpleNamespace(name=physics), dimension=dimension, bodies=bodies, exact=exact,
                           friction=FRICTIONLESS, frictional=False)


def _own(**declared):
    return OwnSolve(name="own", order=2, contact="", reference="", expected=None,
                    solve_level=lambda level: OwnSolution(level.b, 0.0), **declared)


def test_an_own_solve_runs_in_every_physics_and_dimension_as_the_protocol_page_says():
    own = _own()
    assert all(own.supports(_case(p, d)) for p in ("scalar", "elasticity") for d in (2, 3))
    assert not own.supports(_case(bodies=2))


def test_what_a_study_leaves_out_of_a_case_is_named_with_its_reason():
    elastic = _case("elasticity")
    scalar_only = _own(physics=("scalar",))
    methods = [scalar_only, get_method("nitsche"), get_method("mortar-nodal"), get_method("mean-edges")]
    assert [m.name for m in methods_for(elastic, methods)] == ["nitsche"]
    out = dict(left_out(elastic, methods))
    assert list(out) == ["own", "mortar-nodal", "mean-edges"]
    assert "elasticity" in out["own"] and "2" in out["mortar-nodal"] and "3D" in out["mean-edges"]
    assert "exact" in dict(left_out(_case(exact=False), [get_method("nodal-p3")]))["nodal-p3"]


def test_specs_and_names_are_read_one_way():
    assert split_spec("nitsche:gamma0=0.5,theta=-1") == ("nitsche", "gamma0=0.5,theta=-1")
    assert assignments(" gamma0=0.5,theta,") == [("gamma0", "0.5"), ("theta", None)]
    assert look_up({"a": 1}, "a", "thing") == 1
    with pytest.raises(KeyError, match="unknown thing 'b'; known things: a"):
        look_up({"a": 1}, "b", "thing", KeyError)


def test_a_method_file_is_loaded_without_entering_a_lower_stage():
    """``--method path.py``: from ``methods_named`` to the registry the loader calls the methods
    stage and the foundation (``core.plugins``) only, never a function of mesh/, problem/ or
    solvers/, and of fem/ only the cone's own check of its functionals
    (``fem.edge_functionals.check_rules``, run when the record is made, here when the loader
    stamps its source on it). What the user's file itself calls while it runs is its own."""
    from harness.methods import methods_named
    path = Path(__file__).parents[1] / "examples" / "methods" / "quarter_points.py"
    called = set()

    def by_the_file(frame) -> bool:
        while frame is not None:
            if frame.f_code.co_filename == str(path):
                return True
            frame = frame.f_back
        return False

    def profile(frame, event, arg):
        module = frame.f_globals.get("__name__", "")
        if event == "call" and module.startswith("harness.") and frame.f_code.co_name != "<module>" \
                and not by_the_file(frame):
            caller = frame
            while caller is not None and caller.f_code.co_name != "check_rules":
                caller = caller.f_back
            called.add("fem.check_rules" if caller is not None else module.split(".")[1])
    sys.setprofile(profile)
    try:
        loaded = methods_named(str(path))
    finally:
        sys.setprofile(None)
    assert [m.name for m in loaded] == ["quarter-points"] and called <= {"core", "methods", "fem.check_rules"}, called
