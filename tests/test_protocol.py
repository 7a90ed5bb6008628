"""The method protocol's second and third levels (issue 51): a weak method given by its contact
law, solved by the harness's semismooth Newton method, and a method with a solve of its own.
Each example of ``examples/methods`` is checked against the built-in method it re-expresses
(the protocol adds nothing of its own), and a law or a solve that breaks its promises is
refused in one line."""
import importlib.util
import math
import shutil
from dataclasses import replace
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

import harness
from harness.methods import METHODS, LawError, MethodError, OwnSolution, check_method, methods_named

ROOT = Path(__file__).resolve().parent.parent
EXAMPLES = ROOT / "examples" / "methods"


def example(name: str):
    spec = importlib.util.spec_from_file_location(f"example_{name}", EXAMPLES / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.fixture(scope="module")
def laws():
    return example("contact_laws")


@pytest.fixture(scope="module")
def own():
    return example("own_newton")


def study(methods, case="transition-r32", levels=3, **options) -> pd.DataFrame:
    rows = harness.run([case], methods, levels=levels, show_progress=False, **options)
    return rows.set_index(["method", "level"]).sort_index()


def assert_same_rows(rows: pd.DataFrame, mine: str, builtin: str, rtol: float):
    a, b = rows.loc[mine], rows.loc[builtin]
    assert (a.ndof == b.ndof).all()
    np.testing.assert_allclose(a.err_h1, b.err_h1, rtol=rtol)
    np.testing.assert_allclose(a.max_penetration, b.max_penetration, rtol=rtol, atol=1e-14)


# (3D: the law from outside the repository runs there in make test, below; beside the built-in here in test-full)
@pytest.mark.parametrize("case, levels", [("transition-r32", 3), ("corner-r12", 3), ("elastic-transition-r32", 3),
                                          pytest.param("elastic-transition-3d", 2, marks=pytest.mark.slow)])
def test_nitsche_written_as_a_contact_law_gives_the_builtin_nitsche_rows(laws, case, levels):
    """The example's law is written in elasticity's terms (CHR 2015 eq. (10)); on the scalar
    problem and on plane-strain and 3D elasticity it is the built-in law to round-off."""
    rows = study([laws.nitsche_law, "nitsche"], case, levels)
    assert (rows.status == "converged").all() and (rows.kkt_residual <= 1e-10).all()
    # the same discrete problem solved by the same Newton method: equal to the solver's tolerance
    assert_same_rows(rows, "nitsche-law", "nitsche", rtol=1e-8)
    assert (rows.loc["nitsche-law"].solver_iterations == rows.loc["nitsche"].solver_iterations).all()


@pytest.mark.parametrize("case", ["transition-r32", "elastic-transition-r32"])
def test_a_method_with_its_own_solve_gives_the_builtin_penalty_rows(own, case):
    rows = study([own.method, "penalty"], case)
    assert (rows.status == "converged").all()
    mine = rows.loc["penalty-own-newton"]
    assert (mine.kkt_residual <= 1e-10).all()              # its own residual, recorded
    assert (mine.max_penetration > 0).all()                # the harness's own feasibility measure
    assert_same_rows(rows, "penalty-own-newton", "penalty", rtol=1e-8)


def test_a_law_without_a_declared_theory_is_measured_with_no_expected_rate(laws):
    rows = study([laws.penalty_h2], levels=4)
    assert (rows.status == "converged").all() and (rows.kkt_residual <= 1e-10).all()
    assert rows.expected_rate.isna().all() and (rows.reference == "no theory declared").all()
    rates = harness.rates(rows.reset_index())
    assert rates.verdict.eq("no theory").all(), rates.verdict.tolist()


def test_a_law_parameter_is_set_by_name_and_names_the_method(laws):
    stiffer = laws.penalty_h2.with_parameters(epsilon0=0.01)
    assert stiffer.name == "penalty-h2:epsilon0=0.01" and stiffer.law.epsilon0 == 0.01
    with pytest.raises(ValueError, match="has parameters epsilon0"):
        laws.penalty_h2.with_parameters(gamma0=1)


class WrongSlope:
    """A penalty whose derivative is not its term's (a sign error a user might make)."""

    def branch(self, at):
        return at.gap - at.u > 0

    def term(self, at, branch):
        return np.where(branch, (at.gap - at.u) / at.h, 0.0), 0.0

    def derivative(self, at, branch):
        return np.where(branch, 1.0 / at.h, 0.0), 0.0, 0.0, 0.0


class NotAffine(WrongSlope):
    def term(self, at, branch):
        return np.where(branch, (at.gap - at.u) ** 3, 0.0), 0.0


@pytest.mark.parametrize("law, broken", [(WrongSlope(), "pressure on the branch 'in contact' is not affine"),
                                         (NotAffine(), "not affine")])
def test_a_law_that_breaks_its_promises_is_refused_in_one_line(laws, law, broken):
    """Found on the law's first level: the study stops (``StudyFailed``, its cause the law's
    ``LawError``), in one line."""
    with pytest.raises(harness.StudyFailed, match=broken) as refused:
        study([replace(laws.penalty_h2, name="broken", law=law)], levels=1)
    assert isinstance(refused.value.__cause__, LawError) and "\n" not in str(refused.value)


def test_a_law_or_a_solve_that_is_not_one_is_refused_when_checked(laws, own):
    with pytest.raises(MethodError, match="no branch, term and derivative"):
        check_method(replace(laws.penalty_h2, law=object()), "here")
    with pytest.raises(MethodError, match="solve_level"):
        check_method(replace(own.method, solve_level=None), "here")


@pytest.mark.parametrize("answer, refusal", [
    (lambda level: np.zeros(3), "not an OwnSolution"),
    (lambda level: OwnSolution(np.zeros(3), 0.0), "the level has"),
    (lambda level: OwnSolution(np.full(level.ndof, math.nan), 0.0), "non-finite"),
    (lambda level: OwnSolution(np.where(level.free, 0.0, level.lift + 1.0), 0.0), "Dirichlet values"),
])
def test_an_own_solve_returning_no_solution_of_the_level_is_refused_in_one_line(own, answer, refusal):
    with pytest.raises(harness.StudyFailed, match=refusal) as refused:
        study([replace(own.method, solve_level=answer)], levels=1)
    assert isinstance(refused.value.__cause__, ValueError) and "\n" not in str(refused.value)


@pytest.mark.slow          # 7 s: every example on every mesh, two workers
def test_the_protocol_examples_run_from_outside_on_every_mesh_and_two_workers(tmp_path):
    """A method at each protocol level (a cone by its functionals, a law, an own solve), each by
    its path from a folder outside the repository,
    on uniform, graded and adaptive meshes, in two worker processes (by value: their classes
    and functions live in no importable module)."""
    for path in EXAMPLES.glob("*.py"):
        shutil.copy(path, tmp_path / path.name)
    from tests.test_plugins import harness_cli
    specs = ["quarter_points.py", "contact_laws.py:penalty_h2", "own_newton.py"]
    done = harness_cli("run", "--case", "corner-r12", *[a for spec in specs for a in ("--method", spec)], "--mesh", "all",
                       "--levels", "3", "--workers", "2", "--out", "out", "--quiet", cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    rows = pd.read_csv(tmp_path / "out" / "results.csv")
    assert (rows.status == "converged").all() and (rows.kkt_residual <= 1e-10).all()
    assert set(rows.method) == {methods_named([str(tmp_path / spec)])[0].name for spec in specs}
    assert set(map(tuple, rows[["method", "mesh"]].drop_duplicates().values)) == \
        {(m, mesh) for m in set(rows.method) for mesh in ("uniform", "graded", "adaptive")}
    assert rows.effectivity.notna().all()


def test_the_case_example_runs_by_path_and_its_cones_meet_the_paper_rate():
    """`examples/cases/transition_off_vertex.py`: a transition inside a contact edge on every
    level; the paper's theorems do not ask for a vertex there, and the rates meet them."""
    rows = harness.run([str(ROOT / "examples" / "cases" / "transition_off_vertex.py")], ["paper", "p1"], levels=5,
                       show_progress=False)
    assert (rows.status == "converged").all() and (rows.kkt_residual <= 1e-10).all()
    rates = harness.rates(rows).set_index("method")
    assert rates.verdict.eq("meets").all(), rates[["fitted_rate", "verdict"]]


@pytest.mark.slow          # 7 s: 2D and 3D elastic studies
def test_a_law_written_for_elasticity_runs_from_outside_on_2d_and_3d_elastic_cases(tmp_path):
    """The elastic Nitsche law of ``examples/methods/contact_laws.py``, by its path from a folder
    outside the repository, beside the built-in on plane strain and 3D elasticity."""
    shutil.copy(EXAMPLES / "contact_laws.py", tmp_path / "contact_laws.py")
    from tests.test_plugins import harness_cli
    done = harness_cli("run", "--case", "elastic-transition-r32", "--case", "elastic-transition-3d", "--method",
                       "contact_laws.py:nitsche_law", "--method", "nitsche", "--levels", "2", "--out", "out", "--quiet",
                       cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    rows = pd.read_csv(tmp_path / "out" / "results.csv").set_index(["case", "method", "level"]).sort_index()
    assert (rows.status == "converged").all() and (rows.kkt_residual <= 1e-10).all()
    for case in ("elastic-transition-r32", "elastic-transition-3d"):
        np.testing.assert_allclose(rows.loc[(case, "nitsche-law")].err_h1, rows.loc[(case, "nitsche")].err_h1, rtol=1e-8)


def test_a_solve_of_ones_own_runs_at_degree_3_and_agrees_with_penalty_p3(own):
    """The method protocol's third level at any degree (issue 63): the example's own Newton
    penalty solve, given order 3, hands back the u_h of the built-in penalty-p3 (the same
    discrete problem), its own residual recorded."""
    from dataclasses import replace
    rows = study([replace(own.method, name="own-p3", order=3), METHODS["penalty-p3"]], levels=2)
    assert (rows.loc["own-p3"].kkt_residual <= 1e-10).all() and (rows.loc["own-p3"].status == "converged").all()
    assert_same_rows(rows, "own-p3", "penalty-p3", 1e-8)
