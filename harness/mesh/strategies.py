"""The mesh axis of a study: a strategy names how a case's level sequence is made::

    uniform     red refinement of the case's netgen mesh (``levels.UniformRefinement``)
    graded      a priori grading toward the singular points (and lines, 3D), Remark 4.4 (``bisection.GradedRefinement``)
    adaptive    SOLVE -> ESTIMATE -> MARK -> REFINE (``bisection.AdaptiveRefinement``); a
                parameter, ``adaptive:theta=0.3`` (Dörfler's bulk fraction, default 0.5)
    hp          geometric layers toward the singular points, the degree growing away from them
                (``hp.HpRefinement``; parameters ``hp:sigma=0.15,mu=1``); for the methods of a
                contact law and the nodal cones of degree k >= 3, on scalar 2D cases with u and
                declared singular points

``all`` is the three h strategies (uniform, graded, adaptive); hp is asked for by name.

A strategy also says which methods can share a sequence: every method on uniform meshes, the
methods of one order on graded ones (the grading exponent depends on k), none on adaptive ones
(each method's solutions drive its own meshes).

A strategy from outside the package is any object with the ``Strategy`` protocol: a file
(``--mesh path/to/grading.py[:name]``, its ``strategy``, its ``strategies`` or every strategy it
defines), a dotted name (``--mesh mypkg.meshes:fine_grading``), an installed package's entry
point (group "signorini_harness.meshes", selected by its label) or an object
(``harness.run(..., meshes=[my_strategy, "uniform"])``), checked by ``check_strategy``.
"""
from __future__ import annotations

import functools
import math
import re
from dataclasses import dataclass
from typing import Protocol, runtime_checkable

import numpy as np

from ..core.names import assignments, split_spec, unknown
from ..core.plugins import PluginError, entry_point_objects, is_external, load_spec
from .bisection import AdaptiveRefinement, GradedRefinement
from .hp import DEFAULT_MU, DEFAULT_SIGMA, HpRefinement
from .levels import LevelSequence, UniformRefinement, coarse_mesh
from .newest_vertex import straight_polygon
from .points import coordinates, geometry_vertices

STRATEGIES = ("uniform", "graded", "adaptive", "hp")
# what ``all`` names: the h strategies (every method, every kind of case)
H_STRATEGIES = STRATEGIES[:3]
DEFAULT_THETA = 0.5
# each strategy's parameters and their defaults
PARAMETERS = {"adaptive": {"theta": DEFAULT_THETA}, "hp": {"sigma": DEFAULT_SIGMA, "mu": DEFAULT_MU}}
ENTRY_POINTS = "signorini_harness.meshes"
# a label: a CSV cell and a file name's part; a strategy's parameters are written name:key=value,...
LABEL = re.compile(r"^[A-Za-z0-9][A-Za-z0-9_.=+,:-]*$")


@runtime_checkable
class Strategy(Protocol):
    """What a study asks of a mesh strategy (``MeshStrategy`` is the package's own)."""

    label: str          # the ``mesh`` column of its rows; letters, digits and _.=+,:-

    def applies_to(self, case) -> str | None:
        """None if it can mesh ``case``, else why not (one clause): the study skips the case on
        it in one line, before any solve."""

    def group_key(self, method) -> object:
        """Methods with equal keys share one level sequence (None: all of them)."""

    def sequence(self, case, order: int) -> LevelSequence:
        """The meshes of a chain of methods of finite element ``order`` on ``case``."""


def check_strategy(obj, where: str) -> Strategy:
    """``obj`` if it has the ``Strategy`` protocol and a label that fits a CSV cell; a one-line
    PluginError naming ``where`` else."""
    if not isinstance(obj, Strategy):
        raise PluginError(f"{where}: {obj!r} is not a mesh strategy (label, applies_to, group_key, sequence)")
    if not isinstance(obj.label, str) or not LABEL.match(obj.label):
        raise PluginError(f"{where}: mesh strategy label {obj.label!r} is not letters, digits and _.=+,:-")
    return obj


@dataclass(frozen=True)
class MeshStrategy:
    name: str
    theta: float = DEFAULT_THETA        # adaptive only
    sigma: float = DEFAULT_SIGMA        # hp only: the ratio of the geometric layers
    mu: float = DEFAULT_MU              # hp only: the degree's increase per layer

    @property
    def label(self) -> str:
        """The name in results files: the name, with the parameters that differ from their
        defaults (``adaptive:theta=0.3``, ``hp:mu=0.5``)."""
        changed = [f"{key}={getattr(self, key):g}" for key, default in PARAMETERS.get(self.name, {}).items()
                   if getattr(self, key) != default]
        return f"{self.name}:{','.join(changed)}" if changed else self.name

    def serves(self, method) -> bool:
        """Whether the strategy's meshes can carry ``method`` (``carries``)."""
        return self.carries(method) is None

    def carries(self, method) -> str | None:
        """Why the strategy's meshes cannot carry ``method`` (one clause), or None: hp meshes
        carry only a method whose space may vary in degree from element to element
        (``methods.method.Method.variable_degree``: the contact laws, the cones of functionals
        given per degree)."""
        if self.name == "hp" and not getattr(method, "variable_degree", False):
            return ("hp meshes vary the degree from element to element, and its space is of one degree (only a method "
                    "with variable_degree runs on them: the contact laws, the cones given per degree)")
        return None

    def level_refusal(self, case, levels: int) -> str | None:
        """Why the strategy cannot make ``levels`` levels of ``case`` (one line), or None: hp
        meshes stop where their layers would reach below round-off (``mesh.hp.HpRefinement.
        level_refusal``); the study asks before its first solve."""
        if self.name != "hp" or self.applies_to(case) is not None:
            return None
        return self.sequence(case, 2).level_refusal(levels)

    def applies_to(self, case) -> str | None:
        """None if the strategy can mesh ``case``, else why not (one clause)."""
        if self.name == "uniform":
            return None
        if self.name == "hp":
            return hp_refusal(case)
        if case.bodies != 1 and (case.dimension != 2 or not case.exact):
            # the mortar coupling is on a line (``fem.mortar``); without u each body is measured
            # against one reference k uniform levels finer (``study.chain.two_body.TwoBodyErrors``)
            return ("graded and adaptive meshes of two bodies need a 2D case with u (the mortar coupling on a line; "
                    "a reference is nested in uniform pairs only)")
        if self.name == "adaptive" and case.bodies != 1 and len(case.history) > 1:
            # ``measure.two_body_estimator.TwoBodyEstimator``: no terms for the slip of a load step
            return "adaptive meshes of two bodies follow an estimator without a load step's friction terms"
        if not case.exact and case.dimension != 2:
            # each level's own reference (``measure.level_reference``) embeds u_h exactly in 2D only
            return "errors against a reference on graded and adaptive meshes are 2D only (the exact P2 embedding)"
        if self.name == "graded" and case.dimension != 2 and case.singular_points is None and case.singular_lines is None:
            # a 3D solution's singular set is curves of Gamma_C that no mesh vertex marks (in 2D the
            # geometry's corners and breaks are found on the mesh); a smooth case declares []
            return "a graded 3D mesh refines toward the case's singular_lines or singular_points, which it does not declare ([] for none)"
        if self.name == "graded" and not (case.nu > 1):
            return "a graded mesh needs the case's nu (its singular exponent nu - 1)"
        return None

    def group_key(self, method) -> object:
        """Methods with equal keys share one level sequence."""
        return {"uniform": None, "graded": method.order, "adaptive": method.name, "hp": method.order}[self.name]

    def sequence(self, case, order: int):
        """The level sequence for methods of ``order`` on ``case``."""
        if self.name == "uniform":
            return UniformRefinement(case)
        if self.name == "graded":
            return GradedRefinement(case, case.nu - 1.0, order, singular_points(case), singular_lines(case))
        if self.name == "hp":
            return HpRefinement(case, order, singular_points(case), self.sigma, self.mu)
        if order > 2 and case.dimension == 3:
            # the 3D residual estimator's terms are written for P1 and P2 (``measure.estimator_3d``)
            raise ValueError(f"adaptive 3D meshes drive methods of order 1 or 2, not {order}")
        return AdaptiveRefinement(case, self.theta)


def hp_refusal(case) -> str | None:
    """Why hp meshes cannot mesh ``case`` (None if they can): per-element degrees are set for the
    scalar problem in 2D (``fem.assembly.set_degrees``), its errors are measured against u (a
    reference solution is P2 on one mesh), and its layers need the singular points."""
    if case.dimension != 2 or case.bodies != 1 or case.physics.rotated_frame:
        return "hp meshes serve one scalar body in 2D (per-element degrees of the scalar space)"
    if not case.exact:
        return "hp meshes measure errors against u, which the case does not give"
    if not case.singular_points:
        return "hp meshes refine toward the case's singular_points, which it does not declare"
    if not straight_polygon(case.geometry):
        return "hp meshes are made on the arrays of a polygon's mesh (their new boundary vertices on straight sides)"
    return None


def serves(strategy, method) -> bool:
    """Whether ``strategy``'s meshes can carry ``method`` (a strategy without ``serves``: all)."""
    return getattr(strategy, "serves", lambda _: True)(method)


def refusal(strategy, case) -> str | None:
    """Why ``strategy`` cannot mesh ``case`` (its ``applies_to``), or None. A strategy of one's
    own makes one body's level sequence, which a two-body case cannot use: its pairs of meshes
    are the package's (``mesh.two_body_levels``)."""
    if case.bodies != 1 and not isinstance(strategy, MeshStrategy):
        return "two bodies are meshed by the package's strategies only (uniform, graded, adaptive)"
    return strategy.applies_to(case)


def element_budget(case, levels: int, extra_levels: int = 0) -> int:
    """The elements of the uniform level ``levels`` - 1 (+ ``extra_levels``, P1's): where a
    graded or adaptive chain stops, so that it gets the uniform chain's budget of dofs. Red
    refinement makes 2^d elements of each (``mesh.levels.mesh_hierarchy``): 4 triangles, 8
    tetrahedra."""
    return coarse_mesh(case).ne * (2 ** case.dimension) ** (levels - 1 + extra_levels)


def singular_points(case) -> np.ndarray:
    """The case's declared singular points (p, d), else in 2D every point of its geometry (as
    the error quadrature takes them, ``fem.element_quadrature.singular_vertices``); in 3D none
    (its singular sets are lines, ``singular_lines``)."""
    if case.singular_points is not None:
        return np.asarray(case.singular_points, dtype=float).reshape(-1, case.dimension)
    if case.dimension != 2:
        return np.zeros((0, case.dimension))
    mesh = coarse_mesh(case)
    return coordinates(mesh)[geometry_vertices(mesh)]


def singular_lines(case) -> np.ndarray:
    """The case's declared singular lines (3D), as segments (m, 2, 3); none if it declares none."""
    return np.asarray(case.singular_lines or (), dtype=float).reshape(-1, 2, case.dimension)


def parse_mesh(spec) -> list:
    """``uniform``, ``graded``, ``adaptive``, ``adaptive:theta=0.3``, ``all``, the label of an
    installed strategy, a file or a dotted name (``core.plugins``) or a strategy object; a one-line
    ValueError otherwise."""
    if not isinstance(spec, str):
        return [check_strategy(spec, "a mesh strategy object")]
    name, parameters = split_spec(spec.strip())
    if name == "all" and not parameters:
        return [MeshStrategy(s) for s in H_STRATEGIES]
    if name not in STRATEGIES and spec in installed_strategies():
        return [installed_strategies()[spec]]
    if is_external(spec):
        objects, _ = load_spec(spec, ("strategy", "strategies"), Strategy, "mesh strategy")
        return [check_strategy(obj, spec) for obj in objects]
    if name not in STRATEGIES:
        raise ValueError(unknown("mesh strategy", spec, [*STRATEGIES, *installed_strategies()], "mesh strategies",
                                 " or all, a file (path/to/strategy.py[:name]) or a module (package.module[:name])"))
    if not parameters:
        return [MeshStrategy(name)]
    return [MeshStrategy(name, **_parameters(name, spec, parameters))]


def _parameters(name: str, spec: str, text: str) -> dict:
    """The parameters ``key=value,...`` of strategy ``name`` (``PARAMETERS``), each checked."""
    known = PARAMETERS.get(name)
    if not known:
        raise ValueError(f"mesh strategy {name!r} has no parameters (got {spec!r})")
    values = {}
    for key, value in assignments(text):
        if key not in known:
            raise ValueError(f"mesh strategy {name!r} has the parameter{'s' if len(known) > 1 else ''} "
                             f"{', '.join(known)}, not {key!r}")
        values[key] = _parameter(name, key, value or "")
    return values


# the admissible range of each parameter: (low, high, whether high is allowed, what it is)
_RANGES = {"theta": (0.0, 1.0, True, "a number in (0, 1]"), "sigma": (0.0, 1.0, False, "a number in (0, 1)"),
           "mu": (0.0, 8.0, True, "a number in (0, 8]")}


def _parameter(name: str, key: str, value: str) -> float:
    low, high, closed, what = _RANGES[key]
    try:
        number = float(value)
    except ValueError:
        number = math.nan
    if not (math.isfinite(number) and low < number and (number <= high if closed else number < high)):
        raise ValueError(f"{name}: {key} must be {what}, got {value!r}")
    return number


@functools.lru_cache(maxsize=1)
def installed_strategies() -> dict:
    """The strategies installed packages declare in the entry-point group ``ENTRY_POINTS``, by label."""
    return {strategy.label: strategy
            for objects, _, where in entry_point_objects(ENTRY_POINTS, ("strategy", "strategies"), Strategy, "mesh strategy")
            for strategy in (check_strategy(obj, where) for obj in objects)}


def parse_meshes(specs) -> list:
    """Several specs or objects (``--mesh`` repeated), duplicates dropped, in order."""
    out: list = []
    for spec in specs or ["uniform"]:
        for strategy in parse_mesh(spec):
            if strategy not in out:
                out.append(strategy)
    return out


UNIFORM = MeshStrategy("uniform")
