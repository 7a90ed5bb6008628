"""What a user is shown imports only the public surface: `harness` and the protocol modules of
what a user brings (`harness.methods`, `harness.mesh`, `harness.problem`). Every example,
tutorial, docs page, README line and registered case file (the templates of a case of your own)
that imports anything else fails here, so the internals stay free to move."""
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
PUBLIC = {"harness", "harness.methods", "harness.mesh", "harness.problem"}
# the docs site's own build machinery (Sphinx extensions, conf.py) is not shown to users
NOT_SHOWN = {ROOT / "docs" / "conf.py", ROOT / "docs" / "_ext"}
IMPORT = re.compile(r"(?:^|[\s`>(])(?:from\s+(harness(?:\.\w+)*)\s+import\b|import\s+(harness(?:\.\w+)*))")


def shown_files() -> list[Path]:
    files = [ROOT / "README.md", *sorted((ROOT / "examples").rglob("*.py")), *sorted((ROOT / "cases").glob("*.py"))]
    for path in sorted((ROOT / "docs").rglob("*")):
        if path.suffix in (".py", ".md", ".rst") and "_build" not in path.parts and "tutorials_generated" not in path.parts \
                and not any(path == skip or skip in path.parents for skip in NOT_SHOWN):
            files.append(path)
    return files


def private_imports(text: str) -> list[str]:
    """``line: module`` of every import of a harness module that is not public."""
    return [f"{n}: {module}" for n, line in enumerate(text.splitlines(), 1) for match in IMPORT.finditer(line)
            if (module := match[1] or match[2]) not in PUBLIC]


@pytest.mark.parametrize("path", shown_files(), ids=lambda p: str(p.relative_to(ROOT)))
def test_what_users_are_shown_imports_only_the_public_surface(path):
    assert private_imports(path.read_text()) == []


def test_the_import_check_finds_every_form_of_a_private_import():
    text = ("import harness\nfrom harness import run\nfrom harness.methods import Method\n"
            "from harness.measure.rates import rate_table\n    import harness.report.plots as plots\n"
            "`from harness.study import DaskEngine`\nimport harnessing\n")
    assert private_imports(text) == ["4: harness.measure.rates", "5: harness.report.plots", "6: harness.study"]


def test_every_public_name_the_protocol_modules_list_imports():
    import importlib
    for module in sorted(PUBLIC):
        package = importlib.import_module(module)
        for name in getattr(package, "__all__", []):
            assert getattr(package, name) is not None, f"{module}.{name}"
