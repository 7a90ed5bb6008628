"""The architecture page's map of the package, read from the code: each stage in the order the
layout test enforces (``tests/test_layout.py``'s ``STAGES``), then each of its modules and
subpackages with the first sentence of its docstring. Nothing here is typed by hand: a module
moved, added or reworded shows on the next build."""
import ast
import re
from pathlib import Path

import pandas as pd

REPOSITORY = Path(__file__).resolve().parents[2]
PACKAGE = REPOSITORY / "harness"


def stages() -> list[str]:
    """The stages in pipeline order, as ``tests/test_layout.py`` checks them."""
    tree = ast.parse((REPOSITORY / "tests" / "test_layout.py").read_text())
    for node in tree.body:
        if isinstance(node, ast.Assign) and any(getattr(t, "id", None) == "STAGES" for t in node.targets):
            return ast.literal_eval(node.value)
    raise LookupError("tests/test_layout.py defines no STAGES")


def first_sentence(path: Path) -> str:
    """The first sentence of ``path``'s module docstring ("" without one), on one line."""
    text = ast.get_docstring(ast.parse(path.read_text())) or ""
    text = " ".join(text.split())
    # a sentence ends at a period after a word (not "J." of a journal, not "u . n") before a capital
    match = re.match(r"(.+?[a-z0-9)`]{2}\.)(?:\s+(?=[A-Z(`])|$)", text)
    return match.group(1) if match else text


def entries(folder: Path, prefix: str) -> list[dict]:
    """One row per module and subpackage of ``folder`` (subpackages' modules after them)."""
    rows = []
    for path in sorted(folder.iterdir()):
        if path.is_dir() and (path / "__init__.py").is_file():
            rows.append({"module": f"`{prefix}{path.name}/`", "holds": first_sentence(path / "__init__.py")})
            rows += entries(path, f"{prefix}{path.name}/")
        elif path.suffix == ".py" and path.name != "__init__.py":
            rows.append({"module": f"`{prefix}{path.name}`", "holds": first_sentence(path)})
    return rows


def stages_table() -> pd.DataFrame:
    """Each stage, in order: what its package says it is."""
    return pd.DataFrame([{"stage": f"`{stage}/`", "holds": first_sentence(PACKAGE / stage / "__init__.py")}
                         for stage in stages()])


def modules_table() -> pd.DataFrame:
    """Each module of each stage, in order, and the entry points on top."""
    rows = []
    for stage in stages():
        rows += [{"stage": stage, **row} for row in entries(PACKAGE / stage, f"{stage}/")]
    rows += [{"stage": "top", "module": f"`{path.name}`", "holds": first_sentence(path)}
             for path in sorted(PACKAGE.glob("*.py")) if path.name != "__init__.py"]
    return pd.DataFrame(rows, columns=["stage", "module", "holds"])
