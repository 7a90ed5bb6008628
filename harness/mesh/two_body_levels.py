"""The meshes of a two-body chain: each body's mesh refined on its own, so that the two stay
non-matching on Gamma_C, a level being the pair of them (``study.chain.two_body``; the mortar coupling
of each level is assembled anew on the level's two meshes by the method's solve,
``fem.mortar.mortar_coupling``).

    UniformPair     each body refined uniformly (``levels.UniformRefinement``)
    GradedPair      each body graded toward its own singular points (``bisection.GradedRefinement``,
                    Remark 4.4), the same H sequence relative to each body's maxh
    AdaptivePair    SOLVE -> ESTIMATE -> MARK -> REFINE with one Dörfler marking over the union of
                    both bodies' elements (``measure.two_body_estimator``), each body bisecting
                    its own marked elements

A level's h is the coarser body's (the larger of the two meshes' h).
"""
from __future__ import annotations

from collections.abc import Iterator

import numpy as np

from .bisection import GRADED_START, GradedRefinement, bisection, dorfler
from .levels import Level, UniformRefinement


class UniformPair:
    """Both bodies refined uniformly, level by level."""

    name = "uniform"
    nested = True
    adaptive = False
    budgeted = False

    def __init__(self, bodies: tuple):
        self.bodies = bodies

    def observe(self, indicators) -> None:
        pass

    def levels(self, count: int) -> Iterator[Level]:
        walks = [UniformRefinement(body).levels(count) for body in self.bodies]
        for index, steps in enumerate(zip(*walks)):
            yield Level(index, tuple(step.mesh for step in steps), max(step.h for step in steps))


class GradedPair:
    """Each body graded as a one-body graded chain grades it (``GradedRefinement``: h_T <=
    H_k min(1, r_T / R)^(1 - mu), mu = 0.9 lam / k, r_T the distance to the body's own singular
    points), with H_k = GRADED_START maxh_k 2^-l: both bodies' H halve together, keeping the
    ratio of their coarse meshes (2 : 3 on Gamma_C in the non-matching cases). A halving that
    neither mesh needs (the coarse meshes already meet it) is no new level. ``limit``: a level is
    abandoned half made once the two meshes have more elements than that (the chain's budget)."""

    name = "graded"
    nested = True
    adaptive = False
    budgeted = True

    def __init__(self, bodies: tuple, lam: float, order: int, points: list, lines: list, limit: float = np.inf):
        self.bodies, self.limit = bodies, limit
        self.gradings = [GradedRefinement(body, lam, order, p, line) for body, p, line in zip(bodies, points, lines)]

    def observe(self, indicators) -> None:
        pass

    def levels(self, count: int) -> Iterator[Level]:
        refiners = [bisection(body) for body in self.bodies]
        H = [GRADED_START * body.maxh for body in self.bodies]
        index = 0
        while index < count:
            sweeps = []
            for grading, refiner, size in zip(self.gradings, refiners, H):
                # the other body's elements count against the same budget
                others = sum(r.ne for r in refiners if r is not refiner)
                sweeps.append(grading.grade(refiner, size, self.limit - others if index else np.inf))
            if any(s is None for s in sweeps):
                return
            if any(sweeps) or index == 0:
                yield pair_level(index, refiners)
                index += 1
            H = [size / 2 for size in H]


class AdaptivePair:
    """Level 0: both bodies' coarse meshes. After each level's solve the study hands the
    indicators of both bodies' elements (upper then lower, one array) to ``observe``; the next
    level bisects, in each body, its elements of Dörfler's set for ``theta`` taken over the
    union (one ranking: the body whose elements carry the larger part of the estimate is refined
    more). A body none of whose elements is marked keeps its mesh."""

    name = "adaptive"
    nested = True
    adaptive = True
    budgeted = True

    def __init__(self, bodies: tuple, theta: float = 0.5):
        if not (0 < theta <= 1):
            raise ValueError(f"adaptive: theta must be in (0, 1], got {theta}")
        self.bodies, self.theta = bodies, theta
        self._indicators = None

    def observe(self, indicators: np.ndarray) -> None:
        self._indicators = np.asarray(indicators, dtype=float)

    def levels(self, count: int) -> Iterator[Level]:
        refiners = [bisection(body) for body in self.bodies]
        for index in range(count):
            if index:
                self.refine(refiners)
            yield pair_level(index, refiners)

    def refine(self, refiners: list) -> None:
        """Dörfler's set over both bodies, each body's part bisected in its mesh."""
        sizes = [refiner.ne for refiner in refiners]
        if self._indicators is None or len(self._indicators) != sum(sizes):
            raise RuntimeError("adaptive refinement: observe() the level's indicators (both bodies) before the next level")
        marked = dorfler(self._indicators, self.theta)
        for refiner, flags in zip(refiners, np.split(marked, np.cumsum(sizes)[:-1])):
            if flags.any():
                refiner.refine(flags)
        self._indicators = None


def pair_level(index: int, refiners: list) -> Level:
    """The level of both bodies' meshes as their bisections stand (``mesh.bisection``); no
    prolongation: the two-body solves factorise."""
    levels = [refiner.level(index) for refiner in refiners]
    return Level(index, tuple(level.mesh for level in levels), max(level.h for level in levels))
