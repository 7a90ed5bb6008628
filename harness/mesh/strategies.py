"""The mesh axis of a study: a strategy names how a case's level sequence is made.

    uniform     red refinement of the case's netgen mesh (``levels.UniformRefinement``)
    graded      a priori grading toward the singular points, Remark 4.4 (``bisection.GradedRefinement``)
    adaptive    SOLVE -> ESTIMATE -> MARK -> REFINE (``bisection.AdaptiveRefinement``); a
                parameter, ``adaptive:theta=0.3`` (Dörfler's bulk fraction, default 0.5)

A strategy also says which methods can share a sequence: every method on uniform meshes, the
methods of one order on graded ones (the grading exponent depends on k), none on adaptive ones
(each method's solutions drive its own meshes).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .bisection import AdaptiveRefinement, GradedRefinement
from .levels import UniformRefinement, coarse_mesh
from .points import coordinates, geometry_vertices

STRATEGIES = ("uniform", "graded", "adaptive")
DEFAULT_THETA = 0.5


@dataclass(frozen=True)
class MeshStrategy:
    name: str
    theta: float = DEFAULT_THETA        # adaptive only

    @property
    def label(self) -> str:
        """The name in results files: ``adaptive`` with the default theta, else ``adaptive:theta=0.3``."""
        if self.name == "adaptive" and self.theta != DEFAULT_THETA:
            return f"adaptive:theta={self.theta:g}"
        return self.name

    def applies_to(self, case) -> str | None:
        """None if the strategy can mesh ``case``, else why not (one clause)."""
        if self.name == "uniform":
            return None
        if case.bodies != 1:
            return "graded and adaptive meshes refine one body (two bodies: uniform meshes only)"
        if not case.exact:
            return "graded and adaptive meshes need an exact case (errors against a reference need uniform refinement)"
        if case.dimension != 2:
            return "graded and adaptive meshes are 2D only"
        if case.physics.elastic:
            return "graded and adaptive meshes are scalar only (the estimator has no elastic terms yet)"
        if self.name == "graded" and not (case.nu > 1):
            return "a graded mesh needs the case's nu (its singular exponent nu - 1)"
        return None

    def group_key(self, method) -> object:
        """Methods with equal keys share one level sequence."""
        return {"uniform": None, "graded": method.order, "adaptive": method.name}[self.name]

    def sequence(self, case, order: int):
        """The level sequence for methods of ``order`` on ``case``."""
        if self.name == "uniform":
            return UniformRefinement(case)
        if self.name == "graded":
            return GradedRefinement(case, case.nu - 1.0, order, singular_points(case))
        return AdaptiveRefinement(case, self.theta)


def element_budget(case, levels: int, extra_levels: int = 0) -> int:
    """The triangles of the uniform level ``levels`` - 1 (+ ``extra_levels``, P1's): where a
    graded or adaptive chain stops, so that it gets the uniform chain's budget of dofs."""
    return coarse_mesh(case).ne * 4 ** (levels - 1 + extra_levels)


def singular_points(case) -> np.ndarray:
    """The case's declared singular points, else every point of its geometry (as the error
    quadrature takes them, ``fem.element_quadrature.singular_vertices``)."""
    if case.singular_points is not None:
        return np.asarray(case.singular_points, dtype=float).reshape(-1, 2)
    mesh = coarse_mesh(case)
    return coordinates(mesh)[geometry_vertices(mesh)]


def parse_mesh(spec: str) -> list[MeshStrategy]:
    """``uniform``, ``graded``, ``adaptive``, ``adaptive:theta=0.3`` or ``all``; a one-line
    ValueError otherwise."""
    name, _, parameters = str(spec).strip().partition(":")
    if name == "all" and not parameters:
        return [MeshStrategy(s) for s in STRATEGIES]
    if name not in STRATEGIES:
        raise ValueError(f"unknown mesh strategy {spec!r}: choose from {', '.join(STRATEGIES)} or all")
    if not parameters:
        return [MeshStrategy(name)]
    if name != "adaptive":
        raise ValueError(f"mesh strategy {name!r} has no parameters (got {spec!r})")
    key, _, value = parameters.partition("=")
    if key.strip() != "theta":
        raise ValueError(f"mesh strategy 'adaptive' has the parameter theta, not {key.strip()!r}")
    try:
        theta = float(value)
    except ValueError:
        raise ValueError(f"adaptive: theta must be a number in (0, 1], got {value!r}") from None
    if not (math.isfinite(theta) and 0 < theta <= 1):
        raise ValueError(f"adaptive: theta must be a number in (0, 1], got {value!r}")
    return [MeshStrategy("adaptive", theta)]


def parse_meshes(specs) -> list[MeshStrategy]:
    """Several specs (``--mesh`` repeated), duplicates dropped, in order."""
    out: list[MeshStrategy] = []
    for spec in specs or ["uniform"]:
        for strategy in parse_mesh(spec):
            if strategy not in out:
                out.append(strategy)
    return out
