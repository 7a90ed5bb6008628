"""Comments and docstrings say what the code is today: no date of a measurement sits in the
package's or the cases' comments and docstrings (CHANGELOG.md and the commit messages keep the
history), and every dotted name a docstring of the package cites in double backticks names
something that exists."""
import ast
import dataclasses
import importlib
import importlib.util
import inspect
import io
import re
import textwrap
import tokenize
import warnings
from pathlib import Path

import pytest

REPOSITORY = Path(__file__).resolve().parent.parent
PACKAGE = REPOSITORY / "harness"


def package_modules() -> list[Path]:
    return sorted(PACKAGE.rglob("*.py"))


def sources() -> list[Path]:
    return [*package_modules(), *sorted((REPOSITORY / "cases").glob("*.py"))]


def relative(path: Path) -> str:
    return path.relative_to(REPOSITORY).as_posix()


# --- docstrings and comments, read from the source (not from the imported module) -------------

def docstrings(tree: ast.Module) -> list[tuple[int, str, list[ast.AST]]]:
    """Every module, class and function docstring of ``tree``: its first line, its text and the
    nodes it sits in, outermost first (itself last). A string literal anywhere else is code, not
    a docstring."""
    found = []

    def visit(node, scope):
        if isinstance(node, (ast.Module, ast.ClassDef, ast.FunctionDef, ast.AsyncFunctionDef)):
            scope = [*scope, node]
            first = node.body[0] if node.body else None
            if (isinstance(first, ast.Expr) and isinstance(first.value, ast.Constant)
                    and isinstance(first.value.value, str)):
                found.append((first.lineno, first.value.value, scope))
        for child in ast.iter_child_nodes(node):
            visit(child, scope)
    visit(tree, [])
    return found


def comments(source: str) -> list[tuple[int, str]]:
    return [(token.start[0], token.string) for token in tokenize.generate_tokens(io.StringIO(source).readline)
            if token.type == tokenize.COMMENT]


def prose(source: str) -> list[tuple[int, str]]:
    """The comments and docstrings of ``source``, each with the line it starts on."""
    return comments(source) + [(line, text) for line, text, _ in docstrings(ast.parse(source))]


def line_of(start: int, text: str, offset: int) -> int:
    return start + text.count("\n", 0, offset)


def check(path: Path, found: list[tuple[int, str]], what: str) -> None:
    """Nothing ``found`` (line, text) in ``path``, or each named."""
    assert not found, f"{what}:\n" + "\n".join(f"{relative(path)}:{line} {text}" for line, text in found)


# --- no dates ----------------------------------------------------------------------------------

MONTH = (r"(?:January|February|March|April|May|June|July|August|September|October|November|December"
         r"|(?:Jan|Feb|Mar|Apr|Jun|Jul|Aug|Sept?|Oct|Nov|Dec)\.?)")
DATE = re.compile(r"\b20\d\d-\d\d(?:-\d\d)?\b"                                    # 2026-11-26, 2026-11
                  rf"|\b\d{{1,2}}(?:st|nd|rd|th)? (?:of )?{MONTH}(?![\w-])"           # 26 November
                  rf"|(?<![\w-]){MONTH} \d{{1,2}}(?:st|nd|rd|th)?\b"                 # November 26
                  rf"|(?<![\w-]){MONTH},? 20\d\d\b")                                 # November 2026

def dates(path: Path) -> list[tuple[int, str]]:
    source = path.read_text()
    return [(line_of(start, text, match.start()), match.group()) for start, text in prose(source)
            for match in DATE.finditer(text)]


@pytest.mark.parametrize("path", sources(), ids=relative)
def test_no_docstring_or_comment_of_the_package_or_the_cases_carries_a_date(path):
    check(path, dates(path), "a date in a comment or docstring")


def test_the_date_check_reads_comments_and_docstrings_and_not_code(tmp_path):
    source = textwrap.dedent('''\
        """Module: CG took 26 steps (measured 2026-11-26)."""
        STAMP = "%Y-%m-%d"                      # a format is code
        RELEASED = "2026-11-26"
        PAGES = "pp. 2001-2015, Numer. Math. 84 (1999)"

        def f():
            """Measured on 3 December, with maxh 0.5 (2-3 levels)."""
            return 1                            # at 1e6 dofs, November 2026

        class A:
            """A class: nothing dated (Hertz 1882, Section 2.1)."""
            def g(self):
                # timed in a run of 2026-11 on two cores
                return "2025-01-01"
        ''')
    (tmp_path / "m.py").write_text(source)
    assert dates(tmp_path / "m.py") == [(8, "November 2026"), (13, "2026-11"), (1, "2026-11-26"), (7, "3 December")]


# --- every cited dotted name resolves ----------------------------------------------------------

CITED = re.compile(r"``(.+?)``", re.S)
# a dotted name, then at most a call (its arguments are not read) and punctuation
DOTTED = re.compile(r"([A-Za-z_]\w*(?:\.[A-Za-z_]\w*)+)(?:\(.*\))?[.,;:!?]*", re.S)
# a file's name is not a dotted name: ``all.tex``, ``report_profile.csv``
FILE_SUFFIXES = {"py", "md", "tex", "csv", "pdf", "json", "txt", "png", "webp", "svg", "vtu", "pvd", "toml", "cfg",
                 "ini", "yaml", "yml", "html", "log", "npz", "ipynb", "cff"}


def dotted_names(text: str) -> list[tuple[int, str]]:
    """The dotted names ``text`` cites in double backticks, each with its offset in ``text``."""
    found = []
    for cited in CITED.finditer(text):
        match = DOTTED.fullmatch(cited.group(1).strip())
        if match and match.group(1).rsplit(".", 1)[1] not in FILE_SUFFIXES:
            found.append((cited.start(), match.group(1)))
    return found


def module_name(path: Path, package: Path) -> str:
    parts = list(path.relative_to(package.parent).with_suffix("").parts)
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


class Unknown:
    """What an attribute is when only its declaration is known (a field without a default)."""


class Missing:
    """What an attribute is when there is none."""


def declared(cls: type) -> set[str]:
    """The attributes of ``cls`` an instance has without its class having them: dataclass
    fields, annotations through the MRO, and ``self.x`` assigned in a method."""
    names = {f.name for f in dataclasses.fields(cls)} if dataclasses.is_dataclass(cls) else set()
    for klass in inspect.getmro(cls):
        names |= set(vars(klass).get("__annotations__", {}))
        try:
            tree = ast.parse(textwrap.dedent(inspect.getsource(klass)))
        except (OSError, TypeError, SyntaxError):
            continue
        names |= {node.attr for node in ast.walk(tree) if isinstance(node, ast.Attribute)
                  and isinstance(node.ctx, ast.Store) and isinstance(node.value, ast.Name) and node.value.id == "self"}
    return names


def attribute(obj, name: str):
    """``obj.name``, or submodule ``name`` of module ``obj``, or ``Unknown`` for a declared
    attribute of class ``obj``; ``Missing`` if there is none."""
    if obj is Unknown:
        return Unknown                          # past a declaration: the rest is not checked
    if inspect.ismodule(obj) and hasattr(obj, "__path__") and importable(f"{obj.__name__}.{name}"):
        # a submodule first, as the import system takes a dotted path: ``harness.report`` is a
        # function, ``harness.report.figures`` the report package's module
        return importlib.import_module(f"{obj.__name__}.{name}")
    if hasattr(obj, name):
        return getattr(obj, name)
    if inspect.ismodule(obj) and name != "__main__" and hasattr(obj, "__path__"):
        try:
            return importlib.import_module(f"{obj.__name__}.{name}")
        except ImportError:
            return Missing
    if inspect.isclass(obj) and name in declared(obj):
        return Unknown
    return Missing


def follows(obj, parts: list[str]) -> bool:
    for part in parts:
        obj = attribute(obj, part)
        if obj is Missing:
            return False
    return True


def importable(name: str) -> bool:
    """Whether ``name`` is a top-level module (found without importing anything)."""
    try:
        return importlib.util.find_spec(name) is not None
    except (ImportError, ValueError):
        return False


def resolves(name: str, module) -> bool:
    """Whether ``name``, cited in ``module``, names something today: as ``resolves_somehow``, and
    not through a deprecated path of the harness (a pointer to a module that moved)."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        found = resolves_somehow(name, module)
    return found and not any(issubclass(w.category, DeprecationWarning) and "harness" in str(w.message) for w in caught)


def resolves_somehow(name: str, module) -> bool:
    """Whether ``name``, cited in ``module``, names something: (i) as an absolute import path and
    attributes, (ii) below ``harness``, (iii) below the citing module's package or a parent of it,
    (iv) from the citing module's globals."""
    parts = name.split(".")
    packages = module.__name__.split(".")[:-1] if not hasattr(module, "__path__") else module.__name__.split(".")
    prefixes = [[]] + [packages[:k] for k in range(len(packages), 0, -1)]
    for prefix in prefixes:                     # (i), then (iii), whose last package is harness: (ii)
        full = [*prefix, *parts]
        if full[0] != "__main__" and importable(full[0]) and follows(importlib.import_module(full[0]), full[1:]):
            return True
    return parts[0] in vars(module) and follows(vars(module)[parts[0]], parts[1:])     # (iv)


def local_names(scope: list[ast.AST], module) -> set[str]:
    """What the first part of a name cited in a docstring of ``scope`` may be besides a module or
    a global: (v) a parameter or a local of its function or an enclosing one; ``self``, ``cls`` and
    the fields of its class (for a class, also its ``__init__``'s parameters)."""
    names = set()

    def function_names(function):
        arguments = function.args
        found = {a.arg for a in [*arguments.posonlyargs, *arguments.args, *arguments.kwonlyargs,
                                 arguments.vararg, arguments.kwarg] if a}
        for node in ast.walk(function):
            if isinstance(node, ast.Name) and isinstance(node.ctx, ast.Store):
                found.add(node.id)
            elif isinstance(node, (ast.Import, ast.ImportFrom)):
                found |= {(a.asname or a.name).split(".")[0] for a in node.names}
        return found

    for node in scope:
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
            names |= function_names(node)
        elif isinstance(node, ast.ClassDef):
            names |= {"self", "cls"}
            for item in node.body:
                if isinstance(item, ast.AnnAssign) and isinstance(item.target, ast.Name):
                    names.add(item.target.id)
                elif isinstance(item, ast.Assign):
                    names |= {t.id for t in item.targets if isinstance(t, ast.Name)}
                elif isinstance(item, ast.FunctionDef) and item.name == "__init__" and node is scope[-1]:
                    names |= function_names(item) - {"self"}
            names |= {n.attr for n in ast.walk(node) if isinstance(n, ast.Attribute) and isinstance(n.ctx, ast.Store)
                      and isinstance(n.value, ast.Name) and n.value.id == "self"}
            cls = vars(module).get(node.name)
            if inspect.isclass(cls):
                names |= declared(cls)
    return names


def enclosing(tree: ast.Module, line: int) -> list[ast.AST]:
    """The module, classes and functions of ``tree`` whose lines hold ``line``, outermost first."""
    scope, node = [tree], tree
    while True:
        inner = [child for child in ast.iter_child_nodes(node)
                 if isinstance(child, (ast.ClassDef, ast.FunctionDef, ast.AsyncFunctionDef))
                 and child.lineno <= line <= child.end_lineno]
        if not inner:
            return scope
        node = inner[0]
        scope.append(node)


def unresolved(path: Path, package: Path) -> list[tuple[int, str]]:
    """The dotted names cited in ``path``'s docstrings and comments that name nothing, by rules
    (i)-(v) (a comment read in the scope of the code around it)."""
    module = importlib.import_module(module_name(path, package))
    source = path.read_text()
    tree = ast.parse(source)
    cited = [(start, text, scope) for start, text, scope in docstrings(tree)]
    cited += [(line, text, enclosing(tree, line)) for line, text in comments(source)]
    found = []
    for start, text, scope in cited:
        for offset, name in dotted_names(text):
            if not resolves(name, module) and name.split(".")[0] not in local_names(scope, module):
                found.append((line_of(start, text, offset), name))
    return sorted(found)


@pytest.mark.parametrize("path", [p for p in package_modules() if p.name != "__main__.py"], ids=relative)
def test_every_dotted_name_a_docstring_or_comment_cites_resolves(path):
    check(path, unresolved(path, PACKAGE), "a cited name that names nothing (or only through a deprecated path)")


@pytest.mark.parametrize("path", sorted((REPOSITORY / "cases").glob("*.py")), ids=relative)
def test_every_dotted_name_a_case_file_cites_resolves(path):
    check(path, unresolved(path, REPOSITORY / "cases"), "a cited name that names nothing (or only through a deprecated path)")


@pytest.mark.parametrize("text, names", [
    ("``fem.laws.Nitsche``, ``harness.run(out=...)``, ``ngmesh.Copy()``.", ["fem.laws.Nitsche", "harness.run", "ngmesh.Copy"]),
    ("``z[C] >= alpha``, ``nitsche:gamma0=0.1``, ``tests/test_x.py``, ``all.tex``, ``Case``", []),
    ("a call over two lines, ``writer.written(case,\n    level)``, and ``a.b,``", ["writer.written", "a.b"]),
])
def test_a_dotted_name_is_identifiers_joined_by_dots_and_nothing_else(text, names):
    assert [name for _, name in dotted_names(text)] == names


def test_the_name_check_resolves_by_each_rule_and_reports_the_rest(tmp_path, monkeypatch):
    package = tmp_path / "pkg_docstrings_selftest"
    (package / "sub").mkdir(parents=True)
    (package / "__init__.py").write_text("")
    (package / "sub" / "__init__.py").write_text("")
    (package / "sub" / "other.py").write_text(textwrap.dedent('''\
        import dataclasses

        @dataclasses.dataclass
        class Record:
            tolerance: float
            level: object = None
        '''))
    (package / "sub" / "m.py").write_text(textwrap.dedent('''\
        """``numpy.linalg.norm`` (i), ``pkg_docstrings_selftest.sub.other.Record`` (i),
        ``sub.other.Record.tolerance`` (iii: a field), ``other.Record`` (iii), ``np.add.reduceat`` (iv),
        ``Record.level`` (iv: None), ``Record.nothing`` (fails), ``other.Gone`` (fails),
        ``options.tolerance`` (fails: no function here)."""
        import numpy as np

        from .other import Record


        def f(options, *rest):
            """``options.tolerance``, ``rest.x``, ``found.y`` (v), ``other.Nothing`` (fails)."""
            found = options
            return found


        class C:
            """``self.level``, ``solver.x`` (v: parameters of __init__), ``C.level`` (iv: set in a method)."""
            def __init__(self, solver):
                self.level = solver
        '''))
    monkeypatch.syspath_prepend(str(tmp_path))
    assert unresolved(package / "sub" / "m.py", package) == [(3, "Record.nothing"), (3, "other.Gone"),
                                                             (4, "options.tolerance"), (11, "other.Nothing")]
