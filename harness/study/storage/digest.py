"""The one digest that says which code and versions a stored result is valid for: a case of the
report's cache (``study.planning.cache.cache_key``), a checkpointed chain
(``study.storage.checkpoint.chain_key``) and a drawn figure (``report.figure_cache.job_key``)
each start from ``code_hash`` and add their own inputs.

The code is hashed by its syntax tree without docstrings (``ast.dump``: no comments, no line
numbers), so that a comment or a docstring edited anywhere reuses everything; the computing
code (``COMPUTING``) is the stages a study's rows are computed by and the study's chain,
execution and storage, not the report or its planning (``study.planning``): rewording the
report, or a plan's prose, reuses every cached case.
"""
from __future__ import annotations

import ast
import functools
import hashlib
import sys
from pathlib import Path

PACKAGE = Path(__file__).resolve().parents[2]

# the code a study's rows and snapshots are computed by, as folders of the package
COMPUTING = ("mesh", "problem", "fem", "solvers", "methods", "measure", "study/chain", "study/execution",
             "study/storage")


def _without_docstrings(source: str) -> str:
    """``source``'s syntax tree, dumped without docstrings (comments and layout are not in it)."""
    tree = ast.parse(source)
    for node in ast.walk(tree):
        if isinstance(node, (ast.Module, ast.ClassDef, ast.FunctionDef, ast.AsyncFunctionDef)) and node.body:
            first = node.body[0]
            if isinstance(first, ast.Expr) and isinstance(first.value, ast.Constant) and isinstance(first.value.value, str):
                node.body = node.body[1:] or [ast.Pass()]
    return ast.dump(tree)


@functools.lru_cache(maxsize=8)
def code_digest(package: Path = PACKAGE, parts: tuple[str, ...] = COMPUTING) -> str:
    """Hash of the source of ``parts`` (folders of ``package``, default this harness's computing
    code), each module by its path and its syntax tree without docstrings, with Python's version
    (whose ``ast.dump`` it is)."""
    digest = hashlib.sha256(f"python {sys.version_info[0]}.{sys.version_info[1]}".encode())
    for part in parts:
        for path in sorted((Path(package) / part).rglob("*.py")):
            digest.update(str(path.relative_to(package)).encode())
            digest.update(_without_docstrings(path.read_text()).encode())
    return digest.hexdigest()


@functools.lru_cache(maxsize=1)
def ngsolve_version() -> str:
    import ngsolve
    return ngsolve.__version__


def code_hash(parts: tuple[str, ...] = COMPUTING, *, harness_version: bool = False, versions: tuple[str, ...] = ()):
    """A SHA-256 hash (``hashlib``) begun with the digest of ``parts``' code (``code_digest``),
    NGSolve's version, the harness's if ``harness_version`` and ``versions`` (e.g. Matplotlib's):
    a key's caller adds its own inputs and takes ``hexdigest()``."""
    from ... import __version__
    digest = hashlib.sha256(code_digest(PACKAGE, tuple(parts)).encode())
    digest.update(f"ngsolve {ngsolve_version()}".encode())
    if harness_version:
        digest.update(f"harness {__version__}".encode())
    for version in versions:
        digest.update(str(version).encode())
    return digest
