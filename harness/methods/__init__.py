"""Discretisations as plug-ins: one module per method family in this folder
(``registry.FAMILIES``: ``cones``, ``nitsche``, ``penalty``, ``mortar``), each declaring its variants of every
degree in a ``methods`` list, and methods from outside the package: a file, a dotted name, an
installed package's entry point or an object (``plugins``). Every one passes the same checks
(``plugins.check_method``). What a method is: ``method``; the protocol's three levels:
``protocol``.

    >>> from harness.methods import METHODS, methods_named
    >>> methods_named(["paper", "p1"])     # mean, nodal, p1
    >>> methods_named("nitsche:gamma0=0.5,theta=-1")   # a method with other parameter values
"""
from __future__ import annotations

from ..fem.contact_laws.builtin import Nitsche, Penalty
from ..fem.contact_laws.protocol import ContactLaw, FrictionLaw, FrictionPoints, GammaPoints, LawError
from ..solvers.options import SolverOptions
from .cones import BoundConstrained, CellMean
from .external import External, ExternalError
from .method import (
    BASELINE,
    DEGREES,
    EXTRA_LEVELS,
    MESH_STUDY,
    PAPER,
    REFERENCE,
    ROLES,
    SWEPT,
    Carry,
    ConeCarry,
    Expectation,
    LawCarry,
    LevelSolve,
    Method,
    MortarCarry,
    SolveFields,
    no_theory,
    timer,
)
from .mortar import Mortar
from .plugins import MethodError, check_method, installed_methods, load_external
from .protocol import (
    ContactLawMethod,
    ContactNodes,
    ContactPoints,
    FunctionalCone,
    LevelProblem,
    OwnSolution,
    OwnSolve,
    TwoBodyLaw,
)
from .registry import (
    FAMILIES,
    GROUPS,
    METHODS,
    external,
    get_method,
    known,
    left_out,
    method_choices,
    methods_for,
    methods_named,
    names_with_role,
    parse_method,
    role_names,
    with_role,
)

__all__ = ["METHODS", "GROUPS", "FAMILIES", "BASELINE", "DEGREES", "MESH_STUDY", "PAPER", "REFERENCE", "ROLES", "SWEPT",
           "EXTRA_LEVELS", "known", "names_with_role", "role_names", "with_role", "BoundConstrained", "CellMean", "Mortar",
           "ContactLaw", "FrictionLaw", "FrictionPoints", "ContactLawMethod", "TwoBodyLaw", "ContactNodes", "ContactPoints", "GammaPoints", "LawError", "LevelProblem", "SolverOptions",
           "Nitsche", "OwnSolution", "OwnSolve", "Penalty", "Carry", "ConeCarry", "LawCarry", "MortarCarry", "Expectation",
           "SolveFields", "timer", "no_theory", "FunctionalCone", "LevelSolve", "Method", "MethodError", "check_method",
           "get_method", "installed_methods", "left_out", "load_external", "method_choices", "methods_for", "methods_named",
           "parse_method", "External", "ExternalError", "external"]
