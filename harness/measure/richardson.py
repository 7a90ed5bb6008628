"""Observed order, Richardson extrapolation and the grid convergence index of each quantity of
interest (``quantities``) along a chain of levels.

The procedure is Celik, Ghia, Roache, Freitas, Coleman & Raad, *Procedure for estimation and
reporting of uncertainty due to discretization in CFD applications*, J. Fluids Eng. 130 (2008)
078001, steps 1-5, on the three finest levels phi_1 (finest), phi_2, phi_3 with mesh sizes
h_1 < h_2 < h_3: eps_21 = phi_2 - phi_1, eps_32 = phi_3 - phi_2, s = sign(eps_32 / eps_21),

    p = |ln|eps_32 / eps_21| + q(p)| / ln r_21,   q(p) = ln((r_21^p - s) / (r_32^p - s)),

solved by fixed-point iteration (q = 0 when the ratios r = h_coarse / h_fine are equal), the
extrapolated value phi_ext = (r_21^p phi_1 - phi_2) / (r_21^p - 1) and the fine-grid index
GCI = 1.25 |phi_1 - phi_2| / (r_21^p - 1) (Roache's safety factor for three or more grids),
kept here in the quantity's own units (the paper's is relative to |phi_1|; a penetration's
exact value is 0): the band phi_1 +- GCI is meant to hold the exact value. h is the rows' h
on uniform meshes and N^{-1/d} on graded and adaptive ones (the paper's step 1).

The band is honest only in the asymptotic range, which three levels cannot test (p is chosen
to fit them exactly); with four or more, the order of the second to fourth finest levels
(``order_previous``) must agree with ``order`` (``ORDER_AGREEMENT``) and the convergence be
monotone (0 < eps_21 / eps_32 < 1). On the cases with u, ``covered`` says whether the band
holds the exact value: the measurement of how far the index can be trusted.
"""
from __future__ import annotations

import numpy as np
import pandas as pd

from .quantities import QUANTITY_COLUMNS, exact_column
from .rates import fit_rate, space_dimension

SAFETY_FACTOR = 1.25
# the orders of the finest three levels and of the three before them agree within this fraction:
# the quantity converges like a power of h over four levels, the asymptotic range
ORDER_AGREEMENT = 0.1
# differences below this fraction of the value's size are round-off: a settled quantity
SETTLED = 1e-12

QUANTITY_TABLE_COLUMNS = ["case", "mesh", "method", "order", "quantity", "levels", "value", "exact", "error", "fitted_rate",
                          "observed_order", "order_previous", "convergence", "extrapolated", "gci", "gci_relative",
                          "asymptotic", "covered"]
QUANTITY_TABLE_MEANINGS = {
    "case": "the case", "mesh": "the mesh strategy", "method": "the method", "order": "its order k",
    "quantity": "the quantity of interest (force, contact_measure, peak_pressure, energy, penetration)",
    "levels": "levels of the chain", "value": "its value on the finest level, φ₁",
    "exact": "its exact value (cases with u)", "error": "|φ₁ − exact|",
    "fitted_rate": "the error's fitted rate in h (N^{-1/d} on graded and adaptive meshes)",
    "observed_order": "Celik et al.'s observed order p from the three finest levels",
    "order_previous": "p from the second to fourth finest levels (four or more levels)",
    "convergence": "`monotone`, `oscillatory`, `divergent` or `settled` (the values agree to round-off)",
    "extrapolated": "Richardson's extrapolated value φ_ext", "gci": "the fine-grid convergence index, in the quantity's units: φ₁ ± gci",
    "gci_relative": "gci / |φ₁|", "asymptotic": "monotone, and the two orders agree within 10%",
    "covered": "the band φ₁ ± gci holds the exact value (cases with u)",
}


def observed_order(phi: np.ndarray, h: np.ndarray, iterations: int = 200) -> tuple[float, float]:
    """(p, s) of Celik et al.'s step 3 from values ``phi`` and sizes ``h`` of three levels,
    finest first; p is NaN where a difference vanishes."""
    e21, e32 = phi[1] - phi[0], phi[2] - phi[1]
    if e21 == 0 or e32 == 0:
        return float("nan"), 0.0
    r21, r32 = h[1] / h[0], h[2] / h[1]
    s = float(np.sign(e32 / e21))
    ratio = np.log(abs(e32 / e21))
    p = abs(ratio) / np.log(r21)
    for _ in range(iterations):
        with np.errstate(invalid="ignore", divide="ignore"):
            q = np.log((r21**p - s) / (r32**p - s))
        new = abs(ratio + q) / np.log(r21)
        if not np.isfinite(new):
            return float("nan"), s
        if abs(new - p) <= 1e-12 * max(1.0, new):
            return float(new), s
        p = new
    return float(p), s


def convergence_kind(phi: np.ndarray, scale: float) -> str:
    """Celik et al.'s classes by R = eps_21 / eps_32 (``settled``: both differences round-off)."""
    e21, e32 = phi[1] - phi[0], phi[2] - phi[1]
    if max(abs(e21), abs(e32)) <= SETTLED * scale:
        return "settled"
    if e32 == 0:
        return "divergent"
    ratio = e21 / e32
    return "monotone" if 0 < ratio < 1 else "oscillatory" if -1 < ratio < 0 else "divergent"


def richardson(phi, h) -> dict:
    """The columns of one quantity's chain (values ``phi``, sizes ``h``, coarsest first)."""
    phi, h = np.asarray(phi, float)[::-1], np.asarray(h, float)[::-1]        # finest first
    scale = max(np.abs(phi).max(), 1e-300)
    kind = convergence_kind(phi, scale)
    if kind == "settled":
        return {"observed_order": float("nan"), "order_previous": float("nan"), "convergence": kind,
                "extrapolated": float(phi[0]), "gci": SETTLED * scale, "asymptotic": True}
    p, _ = observed_order(phi[:3], h[:3])
    previous = observed_order(phi[1:4], h[1:4])[0] if len(phi) >= 4 else float("nan")
    if kind == "divergent" or not (np.isfinite(p) and p > 0):
        # the differences grow: no limit to extrapolate to (an unbounded peak pressure)
        return {"observed_order": p, "order_previous": previous, "convergence": kind, "extrapolated": float("nan"),
                "gci": float("nan"), "asymptotic": False}
    growth = (h[1] / h[0]) ** p
    return {"observed_order": p, "order_previous": previous, "convergence": kind,
            "extrapolated": float((growth * phi[0] - phi[1]) / (growth - 1.0)),
            "gci": float(SAFETY_FACTOR * abs(phi[0] - phi[1]) / (growth - 1.0)),
            "asymptotic": bool(kind == "monotone" and np.isfinite(previous)
                               and abs(previous - p) <= ORDER_AGREEMENT * p)}


def mesh_sizes(group: pd.DataFrame) -> np.ndarray:
    """The h of Celik et al.'s step 1: the rows' h on uniform meshes, N^{-1/d} on others."""
    if group.mesh.iloc[0] == "uniform":
        return group.h.to_numpy(float)
    return group.ndof.to_numpy(float) ** (-1.0 / space_dimension(group))


def quantity_table(results: pd.DataFrame) -> pd.DataFrame:
    """One row per (case, mesh, method, quantity) of ``results`` with at least three levels
    of that quantity."""
    rows = []
    if "mesh" not in results.columns:
        results = results.assign(mesh="uniform")
    for (case, mesh, method), group in results.groupby(["case", "mesh", "method"], sort=False):
        group = group.sort_values("level")
        h = mesh_sizes(group)
        for quantity, column in QUANTITY_COLUMNS.items():
            if column not in group or not group[column].notna().all() or len(group) < 3:
                continue
            phi = group[column].to_numpy(float)
            rows.append({"case": case, "mesh": mesh, "method": method, "order": int(group.order.iloc[0]),
                         "quantity": quantity, "levels": len(group), "value": phi[-1],
                         **exact_columns(group, column, h, phi), **richardson(phi, h)})
    table = pd.DataFrame(rows, columns=QUANTITY_TABLE_COLUMNS)
    table["gci_relative"] = table.gci / table.value.abs()
    table["covered"] = [bool(abs(e) <= g) if np.isfinite(e) and np.isfinite(g) else pd.NA
                        for e, g in zip(table.exact - table.value, table.gci)]
    return table


def exact_columns(group: pd.DataFrame, column: str, h: np.ndarray, phi: np.ndarray) -> dict:
    """The exact value (the finest row's: its rule is the finest), the error and its rate."""
    exact_name = exact_column(column)
    if column == QUANTITY_COLUMNS["penetration"]:
        exact = 0.0                             # u is feasible, on every case
    elif exact_name in group and not np.isnan(group[exact_name].iloc[-1]):
        exact = float(group[exact_name].iloc[-1])         # inf: an unbounded peak pressure
    else:
        return {"exact": float("nan"), "error": float("nan"), "fitted_rate": float("nan")}
    errors = np.abs(phi - exact)
    rate = fit_rate(h, errors)[0] if np.isfinite(exact) and (errors > 0).all() else float("nan")
    return {"exact": exact, "error": float(errors[-1]), "fitted_rate": rate}


def coverage(table: pd.DataFrame) -> dict:
    """Of the (case, mesh, method, quantity) with an exact value in the asymptotic range: how
    many, and the fraction whose band holds it."""
    judged = table[table.covered.notna() & table.asymptotic.astype(bool)]
    return {"judged": len(judged), "covered": int(judged.covered.astype(bool).sum()),
            "fraction": float(judged.covered.astype(bool).mean()) if len(judged) else float("nan")}
