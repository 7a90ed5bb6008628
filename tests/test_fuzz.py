"""Property-based tests (Hypothesis) of the inputs a user writes: case modules, method specs and
command lines. Each malformed input is refused by a CaseError/ValueError of one line (on the
command line: exit 2, one line on stderr, no traceback, nothing written). Sizes: see
``EXAMPLES``; they run in `make test`, derandomized (the same inputs on every run: CI does not
flicker; a new input found by hand goes into the strategies)."""
import math
import tempfile
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from harness import cli
from harness.fem.contact_laws.builtin import THETAS
from harness.methods import ContactLawMethod, methods_named
from harness.problem.case import REQUIRED, CaseError, load_case
from harness.problem.validate import validate_case

EXAMPLES = {"case modules": 150, "case files on the command line": 60, "method specs": 300, "command lines": 200}

# a valid exact case (transition-r32 made small); every mutation below breaks one thing
VALID = {
    "name": "'fuzzed'", "description": "'generated'", "theorem": "'4.1 ii'", "nu": "2.5", "expected_rate": "1.5",
    "maxh": "0.5", "geometry": "contact_strip(breaks=[0.0])",
    "u": "-sqrt(x * x + y * y) ** 1.5 * sin(1.5 * atan2(y, x))", "f": "0", "singular_points": "[(0.0, 0.0)]",
}
HEADER = ("from ngsolve import atan2, sin, sqrt, x, y\nfrom harness.problem.geometry import contact_strip, polygon\n"
          "from harness.problem.bodies import MirrorBody\n")
BAD = {
    "name": ["3", "None", "''", "['a']"],
    "description": ["None", "1.0"],
    "theorem": ["4.1", "None"],
    "maxh": ["'0.25'", "None", "float('nan')", "float('inf')", "-0.1", "0", "[0.25]", "True"],
    "nu": ["'2.5'", "None", "float('nan')", "0.5", "-1", "[2]"],
    "expected_rate": ["'1.5'", "float('nan')", "float('inf')", "-1", "None"],
    "geometry": ["0", "'strip'", "None"],
    "u": ["'x'", "float('nan')", "float('inf')", "None", "[x, y]"],
    "f": ["'zero'", "float('nan')", "[0]"],
    "singular_points": ["[(0.0,)]", "'origin'", "[(float('nan'), 0.0)]", "5"],
    "gap": ["float('inf')", "'alpha'"],
    "expected_log_exponent": ["'1/4'", "float('nan')"],
    "reference_levels": ["0", "-1", "1.5"],
    "asymptotic_levels": ["2", "0", "6.0", "True", "'6'"],
    "asymptotic_levels_p1": ["2", "6.0", "False", "'7'"],
    "report_profile": ["'weekly'", "None", "1", "['fine']"],
    "physics": ["'plasticity'", "3"],
    # a two-body case: not a MirrorBody, a bad mesh size or geometry, a lower body whose Gamma_C
    # is not the upper one's
    "second_body": ["(contact_strip(), 0.2)", "'lower'", "MirrorBody(contact_strip(), 0)", "MirrorBody(0, 0.2)",
                    "MirrorBody(contact_strip(), float('nan'))",
                    "MirrorBody(polygon([(-1, 0), (0.5, 0), (1, 0), (1, 1), (-1, 1)], "
                    "['contact', 'neumann', 'neumann', 'dirichlet', 'neumann']), 0.3)"],
}
mutations = st.one_of(
    st.sampled_from(REQUIRED).map(lambda key: ("missing", key, None)),
    st.sampled_from(sorted(BAD)).flatmap(lambda key: st.sampled_from(BAD[key]).map(lambda value: ("bad", key, value))),
)


def module_text(mutation) -> str:
    kind, key, value = mutation
    fields = dict(VALID)
    if kind == "missing":
        del fields[key]
    else:
        fields[key] = value
    return HEADER + "".join(f"{k} = {v}\n" for k, v in fields.items())


def refused_in_one_line(text: str) -> str:
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "fuzzed_case.py"
        path.write_text(text)
        with pytest.raises(CaseError) as refused:
            validate_case(load_case(str(path)))
    message = str(refused.value)
    assert message and "\n" not in message
    return message


def test_the_unmutated_case_is_valid(tmp_path):
    path = tmp_path / "fuzzed_case.py"
    path.write_text(HEADER + "".join(f"{k} = {v}\n" for k, v in VALID.items()))
    validate_case(load_case(str(path)))


@settings(max_examples=EXAMPLES["case modules"], deadline=None, derandomize=True)
@given(mutation=mutations)
def test_a_case_module_with_a_missing_wrong_typed_non_finite_or_wrong_signed_field_is_refused_in_one_line(mutation):
    message = refused_in_one_line(module_text(mutation))
    assert mutation[1] in message or "lacks" in message or "violates" in message or "failed to import" in message, message


@settings(max_examples=EXAMPLES["case files on the command line"], deadline=None, derandomize=True,
          suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(mutation=mutations)
def test_a_malformed_case_file_on_the_command_line_exits_2_in_one_line_and_writes_nothing(mutation, capsys):
    with tempfile.TemporaryDirectory() as folder:
        path, out = Path(folder) / "fuzzed_case.py", Path(folder) / "out"
        path.write_text(module_text(mutation))
        code = cli.main(["run", "--case", str(path), "--levels", "1", "--out", str(out), "--quiet"])
        err = capsys.readouterr().err
        assert code == 2 and len(err.strip().splitlines()) == 1 and "Traceback" not in err, err
        assert not out.exists()


specs = st.one_of(
    st.text(alphabet="nitschepalymodP1:=,.-+0123456789einfa", max_size=30),
    st.builds(lambda base, key, value: f"{base}:{key}={value}",
              st.sampled_from(["nitsche", "penalty", "nitsche-p1", "penalty-p1", "mean", "p1"]),
              st.sampled_from(["gamma0", "theta", "epsilon0", "alpha", ""]),
              st.one_of(st.floats(allow_nan=True, allow_infinity=True).map(repr), st.text(max_size=5))),
)


@settings(max_examples=EXAMPLES["method specs"], deadline=None, derandomize=True)
@given(spec=specs)
def test_a_method_spec_is_a_valid_method_or_refused_in_one_line(spec):
    try:
        methods = methods_named([spec])
    except ValueError as refused:
        assert str(refused) and "\n" not in str(refused)
        return
    for method in methods:
        if isinstance(method, ContactLawMethod):
            values = method.parameters
            assert values.get("theta", 1.0) in THETAS
            assert all(math.isfinite(v) and v > 0 for k, v in values.items() if k != "theta")


RUN_OPTIONS = [option for action in cli.build_parser()._subparsers._group_actions[0].choices["run"]._actions
               for option in action.option_strings]
def _positive_integer(text: str) -> bool:
    try:
        return int(text) > 0
    except ValueError:
        return False


not_a_positive_integer = st.text(max_size=6).filter(lambda t: not _positive_integer(t))
command_lines = st.one_of(
    st.builds(lambda v: ["run", "--case", "transition-r32", "--levels", v], not_a_positive_integer),
    st.builds(lambda v: ["run", "--case", "transition-r32", "--reference-levels", v], not_a_positive_integer),
    st.builds(lambda v: ["report", "--levels", v], not_a_positive_integer),
    st.builds(lambda v: ["run", "--case", v], st.text(alphabet="abcxyz-_./", min_size=1, max_size=12)
              .filter(lambda t: t not in ("transition-r32",))),
    st.builds(lambda v: ["run", "--case", "transition-r32", f"--{v}"], st.text(alphabet="abcdefgh-", min_size=1, max_size=8)
              .filter(lambda t: not any(option.startswith(f"--{t}") for option in RUN_OPTIONS))),   # argparse abbreviations
    st.builds(lambda v: [v], st.text(alphabet="abcdefghijklmnopqrstuvwxyz", min_size=1, max_size=8)
              .filter(lambda t: t not in ("run", "sweep", "cases", "methods", "rates", "report", "bench"))),
)


@settings(max_examples=EXAMPLES["command lines"], deadline=None, derandomize=True,
          suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(argv=command_lines)
def test_a_malformed_command_line_exits_2_in_one_line_and_writes_nothing(argv, capsys):
    with tempfile.TemporaryDirectory() as folder:
        out = Path(folder) / "out"
        extra = ["--out", str(out)] if argv[0] == "run" else (["--results", str(out), "--report", str(out)]
                                                              if argv[0] == "report" else [])
        code = cli.main(argv + extra + ["--quiet"] if argv[0] in ("run", "report") else argv)
        err = capsys.readouterr().err
        assert code == 2 and len(err.strip().splitlines()) == 1 and "Traceback" not in err, (argv, err)
        assert not out.exists()
