"""Names as a user gives them on the command line or to ``harness.run``: a registered name
looked up with a one-line refusal naming the known ones (``look_up``), and a spec
``name:key=value,...`` split into the name and its parameter assignments (``split_spec``,
``assignments``). Methods, mesh strategies and cases read their names this way."""
from __future__ import annotations

from collections.abc import Iterable, Mapping


def unknown(kind: str, name: str, known: Iterable[str], plural: str | None = None, also: str = "") -> str:
    """The one line that refuses ``name``: "unknown case 'x'; known cases: a, b" (``also``:
    what else would be taken, after the names)."""
    return f"unknown {kind} {name!r}; known {plural or kind + 's'}: {', '.join(known)}{also}"


def look_up(table: Mapping, name: str, kind: str, error: type[Exception] = ValueError, **message):
    """``table[name]``, or ``error`` with the line of ``unknown`` (``message``: its ``plural``,
    ``also``, ``known`` if not the table's keys)."""
    if name in table:
        return table[name]
    known = message.pop("known", table)
    raise error(unknown(kind, name, known, **message))


def split_spec(spec: str) -> tuple[str, str]:
    """(name, parameters) of ``name:key=value,...`` (parameters "" when there are none)."""
    name, _, parameters = spec.partition(":")
    return name, parameters


def assignments(text: str) -> list[tuple[str, str | None]]:
    """The items of ``key=value,...`` as (key, value), keys stripped, value None for an item
    without "="; empty items (a trailing comma) are skipped."""
    out = []
    for item in filter(None, text.split(",")):
        key, sep, value = item.partition("=")
        out.append((key.strip(), value if sep else None))
    return out
