"""Polynomial bases on the cells of Gamma_C for the traces of P_k, k >= 3: on an edge, the
Lagrange basis of the k + 1 Gauss-Lobatto points of [0, 1] (``lobatto_points``, ``lagrange``);
on a triangle (3D), the Lagrange basis of degree n of the barycentric lattice
(``barycentric_lattice``, ``lattice_lagrange``); and the least value of an edge's polynomial
given at its Gauss-Lobatto points (``polynomial_minimum``). ``fem.assembly.ContactTraceFunction``
keeps a trace in these bases.
"""
from __future__ import annotations

import numpy as np


def lobatto_points(k: int) -> np.ndarray:
    """The k + 1 Gauss-Lobatto points of [0, 1]: the ends and the roots of P_k' (Legendre)."""
    interior = np.polynomial.legendre.Legendre.basis(k).deriv().roots() if k > 1 else np.zeros(0)
    return np.concatenate([[0.0], 0.5 * (np.sort(interior.real) + 1.0), [1.0]])


def lagrange(nodes: np.ndarray, t) -> np.ndarray:
    """The Lagrange basis of ``nodes`` at ``t``: shape t.shape + (len(nodes),)."""
    t = np.asarray(t, float)[..., None]
    out = np.ones(t.shape[:-1] + (len(nodes),))
    for j, xj in enumerate(nodes):
        others = np.delete(nodes, j)
        out[..., j] = np.prod((t - others) / (xj - others), axis=-1)
    return out


def barycentric_lattice(n: int) -> np.ndarray:
    """The (n + 1)(n + 2)/2 points (i, j, n - i - j) / n of a triangle, in barycentric coordinates."""
    return np.array([(i, j, n - i - j) for i in range(n + 1) for j in range(n + 1 - i)], dtype=float) / n


def lattice_degree(points: int) -> int:
    """n of a lattice of ``points`` = (n + 1)(n + 2)/2 points."""
    return int(round((np.sqrt(8 * points + 1) - 3) / 2))


def lattice_lagrange(n: int, barycentric: np.ndarray) -> np.ndarray:
    """(len(barycentric), lattice points) the Lagrange basis of degree n on ``barycentric_lattice(n)``
    at the given points: monomials in the first two coordinates, the lattice's Vandermonde
    inverted (n <= 4: well conditioned)."""
    exponents = [(i, j) for i in range(n + 1) for j in range(n + 1 - i)]

    def monomials(lam):
        return np.stack([lam[:, 0] ** i * lam[:, 1] ** j for i, j in exponents], axis=1)
    return monomials(np.asarray(barycentric, float)) @ np.linalg.inv(monomials(barycentric_lattice(n)))


def polynomial_minimum(values: np.ndarray, samples: int = 33, steps: int = 8) -> np.ndarray:
    """The parameter in [0, 1] of the least value of each row's polynomial (given at the
    Gauss-Lobatto points): the best of ``samples`` equispaced values, then Newton's method on
    the derivative (monomial coefficients, degree <= 4), kept where it lowers the value."""
    k = values.shape[1] - 1
    coefficients = np.linalg.solve(np.vander(lobatto_points(k), increasing=True), values.T).T     # (m, k + 1)
    powers = np.arange(k + 1)

    def derivative(t, order):
        falling = np.ones(k + 1)
        for i in range(order):
            falling = falling * np.maximum(powers - i, 0)
        exponents = np.maximum(powers - order, 0)
        return (coefficients * falling * t[:, None] ** exponents).sum(axis=1)

    grid = np.linspace(0.0, 1.0, samples)
    t = grid[np.argmin(values @ lagrange(lobatto_points(k), grid).T, axis=1)]
    best = derivative(t, 0)
    for _ in range(steps):
        curvature = derivative(t, 2)
        step = np.where(curvature > 0, derivative(t, 1) / np.where(curvature > 0, curvature, 1.0), 0.0)
        trial = np.clip(t - step, 0.0, 1.0)
        value = derivative(trial, 0)
        better = value < best
        t, best = np.where(better, trial, t), np.where(better, value, best)
    return t
