"""What a study refuses or leaves out of its inputs, before anything runs, and why, one line
each: cases a mesh strategy cannot mesh, methods that discretise none of the cases (their own
reasons, ``methods.method.Method.refusal``), methods a strategy's meshes cannot carry, level
counts a strategy cannot make (``mesh.strategies.MeshStrategy.level_refusal``), a hook of the
wrong signature. ``engines.study_jobs`` raises the refusals; ``harness.run`` warns of and
summarises what is left out (``left_out``)."""
from __future__ import annotations

import inspect

from ...mesh.strategies import refusal, serves
from ...methods import left_out as left_out_of
from ...methods import methods_for


def check_methods(case, methods) -> None:
    """ValueError in one line if none of ``methods`` discretises ``case``, saying why
    (``methods.left_out``)."""
    if not methods_for(case, methods):
        reasons = "; ".join(f"{name}: {why}" for name, why in left_out_of(case, methods))
        raise ValueError(f"case {case.name} ({case.physics.name}): none of the methods discretises it ({reasons})")


def skipped_meshes(cases, meshes) -> list[str]:
    """One line per (case, mesh strategy) a study skips because the strategy cannot mesh the
    case, and why (``mesh.strategies.refusal``)."""
    return [f"{case.name}: {mesh.label} meshes skipped: {reason}" for case in cases for mesh in meshes
            if (reason := refusal(mesh, case)) is not None]


def skipped_methods(cases, methods, partial: bool = False) -> list[str]:
    """One line per method of ``methods`` that discretises none of ``cases`` (its reasons,
    ``methods.method.Method.refusal``), which a study would leave without a row; with
    ``partial``, then one per (method, case) of a method that discretises some of them only (the
    run's mix: named in the summary, not warned about)."""
    lines = []
    for method in methods:
        reasons = {case.name: why for case in cases for _, why in left_out_of(case, [method])}
        if cases and len(reasons) == len(cases):
            lines.append(f"{method.name} skipped: " + "; ".join(dict.fromkeys(reasons.values())))
    for method in methods if partial else ():
        reasons = {case.name: why for case in cases for _, why in left_out_of(case, [method])}
        if 0 < len(reasons) < len(cases):
            lines += [f"{method.name} not run on {name}: {why}" for name, why in reasons.items()]
    return lines


def unserved(mesh, method) -> str:
    """Why ``mesh``'s meshes cannot carry ``method`` (``mesh.strategies.serves`` said no), in one
    clause: the strategy's own (``mesh.strategies.MeshStrategy.carries``), else its ``serves``' verdict."""
    reason = getattr(mesh, "carries", lambda _: None)(method)
    return reason or f"the strategy {getattr(mesh, 'label', mesh)} does not carry it (its serves())"


def skipped_on_meshes(cases, methods, meshes) -> list[str]:
    """One line per (method, mesh strategy) a study skips because the strategy's meshes cannot
    carry the method, for a case both would otherwise run (``unserved``)."""
    return [f"{method.name} skipped on {mesh.label} meshes: {unserved(mesh, method)}" for mesh in meshes
            for method in methods if not serves(mesh, method)
            and any(method.supports(case) and refusal(mesh, case) is None for case in cases)]


def check_runs(cases, methods, meshes) -> None:
    """ValueError in one line if no case would get a row: no method that discretises it on a mesh
    strategy that meshes it and carries the method."""
    runs = (case for case in cases for mesh in meshes if refusal(mesh, case) is None
            for method in methods_for(case, methods) if serves(mesh, method))
    if cases and next(runs, None) is None:
        raise ValueError("nothing to run: " + "; ".join(skipped_on_meshes(cases, methods, meshes)))


def left_out(cases, methods, meshes, partial: bool = False) -> list[str]:
    """What a study leaves out and why, one line each: the cases a strategy cannot mesh, the
    methods that discretise none of the cases (with ``partial``, also those cases a method that
    discretises others leaves out), the methods a strategy's meshes cannot carry."""
    return skipped_meshes(cases, meshes) + skipped_methods(cases, methods, partial) + \
        skipped_on_meshes(cases, methods, meshes)


HOOK_ARGUMENTS = ("case", "method", "level", "problem", "solve")


def check_hook(on_level) -> None:
    """ValueError in one line if ``on_level`` cannot be called as ``on_level(case, method, level,
    problem, solve)`` (``walk``'s call), before anything runs."""
    if on_level is None:
        return
    try:
        signature = inspect.signature(on_level)
    except (TypeError, ValueError):         # a callable without a signature (a builtin): called as it is
        return
    try:
        signature.bind(*HOOK_ARGUMENTS)
    except TypeError:
        name = getattr(on_level, "__qualname__", type(on_level).__qualname__)
        raise ValueError(f"on_level must take ({', '.join(HOOK_ARGUMENTS)}); {name}{signature} does not") from None


def check_meshes(cases, meshes, levels: int | None = None) -> None:
    """ValueError in one line if a mesh strategy applies to none of ``cases``, or cannot make
    ``levels`` levels of one of them (``mesh.strategies.MeshStrategy.level_refusal``: hp layers below round-off)."""
    for mesh in meshes:
        reasons = [refusal(mesh, case) for case in cases]
        if cases and all(reasons):
            raise ValueError(f"--mesh {mesh.label}: {reasons[0]} ({', '.join(c.name for c in cases)})")
        for case in cases if levels else ():
            limit = getattr(mesh, "level_refusal", lambda *_: None)(case, levels)
            if limit:
                raise ValueError(f"--mesh {mesh.label}: {limit}")
