"""The layout promises of docs/development/architecture.md ("How the code is laid out"): the package reads as the
pipeline, imports run one way, the physics owns the scalar/elastic differences, and every
file a docstring cites exists."""
import ast
import re
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parent.parent / "harness"
REPOSITORY = PACKAGE.parent
# the stages in pipeline order: a module imports only from its own stage and earlier ones
STAGES = ["core", "mesh", "problem", "fem", "solvers", "methods", "measure", "study", "report", "bench"]
# the entry points: import anything (cli_options: the command line's options, which cli.py
# imports per command)
TOP = {"__init__", "__main__", "api", "cli", "cli_options"}


def modules() -> list[Path]:
    return sorted(PACKAGE.rglob("*.py"))


def stage_of(parts: list[str]) -> str:
    return parts[0] if parts else "__init__"


def imported(path: Path) -> set[tuple[str, ...]]:
    """The harness modules ``path`` imports, as parts below ``harness`` (names imported from
    a package count as that package)."""
    here = list(path.relative_to(PACKAGE).with_suffix("").parts)
    package = here[:-1]
    found = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.ImportFrom):
            if node.level:
                base = package[:len(package) - (node.level - 1)] if node.level > 1 else package
                target = base + (node.module.split(".") if node.module else [])
            elif (node.module or "").split(".")[0] == "harness":
                target = node.module.split(".")[1:]
            else:
                continue
            found.add(tuple(target))
        elif isinstance(node, ast.Import):
            found |= {tuple(a.name.split(".")[1:]) for a in node.names if a.name.split(".")[0] == "harness"}
    return found


def test_the_top_level_holds_at_most_eight_modules():
    top = [p.stem for p in PACKAGE.glob("*.py")]
    assert len(top) <= 8, top
    assert {p.name for p in PACKAGE.iterdir() if p.is_dir() and (p / "__init__.py").is_file()} == set(STAGES)


@pytest.mark.parametrize("path", modules(), ids=lambda p: str(p.relative_to(PACKAGE)))
def test_imports_run_from_earlier_stages_to_later_ones(path):
    here = list(path.relative_to(PACKAGE).with_suffix("").parts)
    stage = stage_of(here if len(here) > 1 or here[0] in TOP else here)
    if here[0] in TOP:
        return
    allowed = set(STAGES[:STAGES.index(here[0]) + 1])
    for target in imported(path):
        if not target:              # ``from .. import __version__``: the package's one version
            continue
        assert target[0] in allowed, f"{'/'.join(here)} (stage {stage}) imports {'.'.join(target)}"


def test_only_the_physics_tells_scalar_from_elastic():
    pattern = re.compile(r"components\s*(>|==|<|!=)")
    offenders = [f"{p.relative_to(REPOSITORY)}:{n}" for p in modules() if p.name != "physics.py"
                 for n, line in enumerate(p.read_text().splitlines(), 1) if pattern.search(line)]
    assert not offenders


def test_the_study_takes_h_from_its_level_sequence():
    assert "h / 2" not in (PACKAGE / "study" / "chain" / "run.py").read_text()


# a function longer than this does more than one job (issue 51 item 7; 60 since issue 62)
LONGEST_FUNCTION = 60


def long_functions(folder: Path, limit: int) -> list[str]:
    """Every function of ``folder``'s modules (methods and nested ones too) longer than
    ``limit`` lines, from its ``def`` line to its last line."""
    found = []
    for path in sorted(folder.rglob("*.py")):
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
                lines = node.end_lineno - node.lineno + 1
                if lines > limit:
                    found.append(f"{path.relative_to(folder.parent)}:{node.lineno} {node.name} ({lines} lines)")
    return found


def test_every_function_of_the_package_fits_in_60_lines():
    assert long_functions(PACKAGE, LONGEST_FUNCTION) == []


def test_the_length_check_measures_methods_and_nested_functions(tmp_path):
    def body(lines, indent):
        return "".join(f"{' ' * indent}x{k} = {k}\n" for k in range(lines))
    source = ("def fits():\n" + body(LONGEST_FUNCTION - 1, 4) +
              "class A:\n    def method(self):\n        def nested():\n" + body(LONGEST_FUNCTION, 12) + "        return nested\n")
    (tmp_path / "m.py").write_text(source)
    found = [text.split(" ", 1)[1] for text in long_functions(tmp_path, LONGEST_FUNCTION)]
    # fits: exactly the limit; nested: one line over it; method: nested and its own three lines
    assert found == ["method (63 lines)", "nested (61 lines)"]


def test_every_cited_file_exists():
    cited = re.compile(r"`([\w./-]+\.(?:md|py|pdf))`|(\b[\w-]+/[\w./-]+\.md)\b|\b(MATH\.md)\b")
    missing = []
    for path in modules():
        for match in cited.finditer(path.read_text()):
            name = next(g for g in match.groups() if g)
            if not any((base / name).exists() for base in (REPOSITORY, PACKAGE, path.parent, REPOSITORY / "docs")):
                missing.append(f"{path.relative_to(REPOSITORY)}: {name}")
    assert not missing


def test_no_docstring_or_comment_blames_the_sandbox_for_what_was_not_read():
    """A citation says what was read (the abstract, a secondary source) and what was not checked,
    not where the reading happened."""
    sources = [*modules(), *(REPOSITORY / "cases").glob("*.py")]
    assert not [str(path.relative_to(REPOSITORY)) for path in sources if "sandbox" in path.read_text().lower()]


@pytest.mark.parametrize("old", ["harness.geometry", "harness.functions", "harness.rates", "harness.execution"])
def test_the_import_paths_of_version_0_2_are_gone_as_their_deprecation_said(old):
    """Deprecated in 0.3.0 (harness.problem.geometry, .problem.functions, .measure.rates,
    .study), removed in 0.4.0 (CHANGELOG)."""
    import importlib
    with pytest.raises(ModuleNotFoundError):
        importlib.import_module(old)


def import_graph() -> dict[str, set[str]]:
    """Each module of the package (dotted, below ``harness``) -> the package's modules it imports,
    lazy imports inside functions included; ``from . import x`` is the module x."""
    names = {".".join(p for p in path.relative_to(PACKAGE).with_suffix("").parts if p != "__init__"): path for path in modules()}
    graph = {}
    for key, path in names.items():
        package = [p for p in (key.split(".") if path.name == "__init__.py" else key.split(".")[:-1]) if p]
        found = set()
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.ImportFrom) and (node.level or (node.module or "").split(".")[0] == "harness"):
                base = package[:len(package) - (node.level - 1)] if node.level else []
                target = base + (node.module.split(".") if node.module else []) if node.level else node.module.split(".")[1:]
                for alias in node.names:
                    full = ".".join([*target, alias.name])
                    found.add(full if full in names else ".".join(target))
            elif isinstance(node, ast.Import):
                found |= {".".join(a.name.split(".")[1:]) for a in node.names if a.name.split(".")[0] == "harness"}
        graph[key] = {m for m in found if m in names and m != key}
    return graph


def cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """The strongly connected components of more than one module (Tarjan's algorithm)."""
    index, low, stack, on_stack, found = {}, {}, [], set(), []

    def visit(v):
        index[v] = low[v] = len(index)
        stack.append(v)
        on_stack.add(v)
        for w in graph[v]:
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = []
            while not component or component[-1] != v:
                component.append(stack.pop())
                on_stack.discard(component[-1])
            if len(component) > 1:
                found.append(sorted(component))
    for v in graph:
        if v not in index:
            visit(v)
    return found


def test_no_module_imports_itself_through_others_lazy_imports_included():
    assert cycles(import_graph()) == []


def test_the_cycle_check_finds_a_cycle():
    assert cycles({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}) == [["a", "b", "c"]]


@pytest.mark.parametrize("columns, meanings", [("harness.study.chain.rows:COLUMNS", "harness.study.chain.rows:COLUMN_MEANINGS"),
                                               ("harness.measure.rates:RATE_COLUMNS", "harness.measure.rates:COLUMN_MEANINGS"),
                                               ("harness.measure.efficiency:COLUMNS", "harness.measure.efficiency:COLUMN_MEANINGS")])
def test_every_csv_column_has_the_meaning_the_docs_print(columns, meanings):
    """The docs' tables of results.csv, rates.csv and efficiency.csv are generated from these
    meanings (docs/_ext/generate.py): a column added without one fails here."""
    import importlib

    def get(spec):
        module, _, name = spec.partition(":")
        return getattr(importlib.import_module(module), name)
    assert list(get(meanings)) == list(get(columns))
