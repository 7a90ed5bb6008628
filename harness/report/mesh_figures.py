"""The figures of the report's section on meshes (``study.planning.mesh_study``): error and effectivity
against the number of dofs per mesh strategy, and the finest adaptive mesh with a zoom on the
singular point."""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd

from .figures import plt, save, style

LINESTYLE = {"uniform": ":", "graded": "--", "adaptive": "-", "hp": "--"}


def error_against_ndof(case, frame: pd.DataFrame, folder: Path) -> dict[str, Path]:
    """H^1 error (left) and the estimator's effectivity (right) against N, every method on every
    mesh strategy; the slopes N^-1/2 and N^-1 (P1's and P2's best) for comparison."""
    chains = frame.groupby(["mesh", "method"], sort=False)
    rows = -(-chains.ngroups // 4)          # the legend's rows below the panels, four chains a row
    fig, (left, right) = plt.subplots(1, 2, figsize=(11, 4.2 + 0.16 * rows))
    for (mesh, method), g in chains:
        g = g.sort_values("ndof")
        kind = str(mesh).split(":")[0]
        s = style(method)
        line = dict(color=s["color"], linestyle=LINESTYLE.get(kind, "-."), lw=1.2)
        marker = dict(marker=s["marker"], ms=3 if kind == "adaptive" else 4)
        left.loglog(g.ndof, g.err_h1, **line, **marker, label=f"{method}, {mesh}")
        if g.effectivity.notna().any():
            right.semilogx(g.ndof, g.effectivity, **line, **marker)
    n = np.array([frame.ndof.min(), frame.ndof.max()], float)
    e0 = frame.err_h1.min()
    for rate, label in ((0.5, "$N^{-1/2}$"), (1.0, "$N^{-1}$")):
        left.loglog(n, e0 * (n / n[1]) ** -rate * 3, color="0.6", lw=0.8)
        left.annotate(label, (n[0], e0 * (n[0] / n[1]) ** -rate * 3), fontsize=8, color="0.4")
    left.set_xlabel("ndof N")
    left.set_ylabel("H¹ error")
    left.set_title(f"{case.name}: error against N")
    left.legend(fontsize=6.5, ncol=2, loc="lower left")
    right.axhspan(0.5, 10, color="0.93", zorder=0)
    right.set_xlabel("ndof N")
    right.set_ylabel("η / ‖u − u_h‖ₐ")
    right.set_title("effectivity of the estimator")
    return save(fig, folder, f"{case.name}-meshes")


def adaptive_mesh(case, points: np.ndarray, triangles: np.ndarray, folder: Path, method: str) -> dict[str, Path]:
    """The finest adaptive mesh, whole and zoomed on its smallest triangle (by area): windows of
    60 and of 6 times that triangle's size. In 3D its triangles on Gamma_C (the bottom face,
    seen from above in (x, y)), with the exact transition curve."""
    on_gamma_c = case.dimension == 3
    points = points[:, :2]
    fig, axes = plt.subplots(1, 3, figsize=(13, 3.6))
    corners = points[triangles]
    sides = corners - np.roll(corners, 1, axis=1)
    areas = 0.5 * np.abs(sides[:, 0, 0] * sides[:, 1, 1] - sides[:, 0, 1] * sides[:, 1, 0])
    smallest = int(np.argmin(areas))
    centre = corners[smallest].mean(axis=0)
    size = np.sqrt((sides[smallest] ** 2).sum(axis=1)).max()
    extent = np.ptp(points, axis=0).max()
    # windows of 60 and 6 times the smallest triangle, each at most a third of the one before
    wide = min(30 * size, extent / 6)
    for ax, half in zip(axes, (None, wide, min(3 * size, wide / 3))):
        ax.triplot(points[:, 0], points[:, 1], triangles, lw=0.25, color="0.2")
        for line in (case.transition_curve or ()) if on_gamma_c else ():
            ax.plot(*np.array(line).T, color="tab:red", lw=0.8)
        if half is not None:
            ax.set_xlim(centre[0] - half, centre[0] + half)
            # in 2D Gamma_C is the bottom: nothing below
            low = centre[1] - half if on_gamma_c else max(centre[1] - half, points[:, 1].min())
            ax.set_ylim(low - 0.02 * half, low + 2 * half)
            ax.set_title(f"zoom ×{extent / (2 * half):.3g} at ({centre[0]:.3g}, {centre[1]:.3g})", fontsize=9)
            ax.locator_params(nbins=3)
        else:
            what = "triangles on Γ_C (red: the exact transition curve)" if on_gamma_c else "triangles"
            ax.set_title(f"{case.name}, {method}: {len(triangles):,} {what}", fontsize=9)
        ax.set_aspect("equal")
        ax.tick_params(labelsize=6)
    return save(fig, folder, f"{case.name}-adaptive-mesh")


def degree_errors(case, frame: pd.DataFrame, folder: Path) -> dict[str, Path]:
    """The degree study's figure of one case: the H^1 error against N and against the seconds
    spent up to each level (the rows' total_seconds, summed along each chain), every method on
    every mesh strategy."""
    chains = frame.groupby(["mesh", "method"], sort=False)
    rows = -(-chains.ngroups // 4)          # the legend's rows below the panels, four chains a row
    fig, (left, right) = plt.subplots(1, 2, figsize=(11, 4.2 + 0.16 * rows))
    for (mesh, method), g in chains:
        g = g.sort_values("level")
        kind = str(mesh).split(":")[0]
        s = style(method)
        line = dict(color=s["color"], linestyle=LINESTYLE.get(kind, "-."), lw=1.2, marker=s["marker"], ms=3)
        label = f"{method} (k = {int(g.order.iloc[0])}), {mesh}"
        left.loglog(g.ndof, g.err_h1, **line, label=label)
        # a level of an hp chain is made anew from the coarse mesh: its own seconds, not a sum
        seconds = g.total_seconds if kind == "hp" else g.total_seconds.cumsum()
        right.loglog(seconds, g.err_h1, **line)
    left.set_xlabel("ndof N")
    left.set_ylabel("H¹ error")
    left.set_title(f"{case.name}: error against N")
    right.set_xlabel("seconds up to the level")
    right.set_title("error against time")
    # below the panels, not over the curves (hp's fall where a corner legend sits)
    fig.legend(*left.get_legend_handles_labels(), fontsize=6.5, ncol=4, loc="lower center", frameon=False)
    fig.subplots_adjust(bottom=0.12 + 0.16 * rows / (4.2 + 0.16 * rows), wspace=0.22)
    return save(fig, folder, f"{case.name}-degrees")
