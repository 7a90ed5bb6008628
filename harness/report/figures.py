"""Figures of the report (matplotlib, Agg): PNG for the HTML page, PDF for papers."""
from __future__ import annotations

import io
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import matplotlib.tri as mtri  # noqa: E402
import numpy as np  # noqa: E402

from ..study.storage.files import write_atomic
from . import plots
from .document import save_compact
from .plots import OTHER_COLORS, register_methods, style  # noqa: F401  (register_methods: figure_jobs's)

FORMATS = ("png", "pdf")
# The figure files' resolution, and the page's: the HTML page shows a figure at most 1060 px wide
# (520 px two to a row), and the page, every figure embedded, is to stay under 3 MB, which
# 130 dpi figures exceed; 100 dpi draws them 8.9 to 6.4 inches wide in 890 to 640 pixels.
FILE_DPI, PAGE_DPI = 130, 100


def save(fig, folder: Path, stem: str) -> dict[str, Path]:
    """``fig`` as ``stem``.png and .pdf, cropped to its drawn content. The crop (matplotlib's
    "tight" box, padded 0.1 in) is computed once for both formats: "tight" per format lays the
    figure out once more each time, a large share of drawing it.
    Log-axis labels are written in Unicode (``plots.unicode_log_labels``)."""
    plots.unicode_log_labels(fig)
    fig.draw_without_rendering()
    box = fig.get_tightbbox(fig.canvas.get_renderer()).padded(0.1)
    paths = {}
    for fmt in FORMATS:
        paths[fmt] = folder / f"{stem}.{fmt}"
        buffer = io.BytesIO()
        fig.savefig(buffer, format=fmt, dpi=FILE_DPI, bbox_inches=box)
        write_atomic(paths[fmt], buffer.getvalue())      # a report killed while drawing leaves no half figure
    page = io.BytesIO()
    fig.savefig(page, format="png", dpi=PAGE_DPI, bbox_inches=box)
    plt.close(fig)
    save_compact(paths["png"], page.getvalue())
    return paths


def convergence(case, results, folder: Path) -> dict[str, Path]:
    """``plots.convergence`` of one case, titled with its theorem."""
    fig = plots.convergence(results, case.name, title=f"{case.name}: P2 {plots.theorem_label(case.theorem)}")
    return save(fig, folder, f"{case.name}_convergence")


# What the contact figure draws, by physics (``problem.physics``): the contact variable minus its
# obstacle (the gap left open), of the exact and the discrete solution, and the exact pressure.
CONTACT_LABELS = {
    "scalar": (r"$u-\alpha$", r"$u_h-\alpha$", r"$\partial_n u - g_C$"),
    "elasticity": (r"$\alpha - u\cdot n$", r"$\alpha - u_h\cdot n$", r"$-(\sigma_n(u) - g_n)$"),
}
# two bodies: the opening of the interface (the sum of both contact variables) against twice the gap
TWO_BODY_LABELS = (r"$[u]-2\alpha$", r"$[u_h]-2\alpha$", "pressure")


def contact(case, snapshots: dict, folder: Path) -> dict[str, Path]:
    """u_h (in elasticity its normal displacement) and the discrete contact pressure along
    Gamma_C on the finest level (3D: over Gamma_C, ``contact_faces``)."""
    if "faces" in next(iter(snapshots.values())):
        return contact_faces(case, snapshots, folder)
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(6.4, 5.2), sharex=True)
    first = next(iter(snapshots.values()))
    exact = bool(np.isfinite(first["u"]).any())        # a reference case has no exact u to draw
    gap_u, gap_uh, pressure_label = TWO_BODY_LABELS if "two_bodies" in first else CONTACT_LABELS[case.physics.name]
    if exact:
        top.plot(first["s"], first["u"] - first["gap"], "k-", lw=1.0, label=f"exact {gap_u}")
        bottom.plot(first["s"], first["exact_pressure"], "k-", lw=1.0, label=f"exact {pressure_label}")
    if case.predicted_pressure is not None:
        # the theory at the finest level's force of the first method: the integral of its edge means
        force = float(first["pressure"] @ first["edge_lengths"])
        theory = case.prediction.split(" (")[0]
        predicted = case.predicted_pressure(first["s"], force)
        bottom.plot(first["s"], predicted, "k-", lw=1.0, label=f"{theory} at F = {force:.4g}")
        zone = first["s"][predicted > 0]
        if len(zone):               # the contact zone and as much again: where the theory has something to say
            middle, width = (zone.max() + zone.min()) / 2, zone.max() - zone.min()
            bottom.set_xlim(middle - width, middle + width)
            gaps = np.concatenate([(snap["u_h"] - snap["gap"])[np.abs(snap["s"] - middle) <= width]
                                   for snap in snapshots.values()])
            top.set_ylim(min(gaps.min(), 0.0) - 0.05 * np.ptp(gaps), gaps.max() + 0.05 * np.ptp(gaps))
    for method, snap in snapshots.items():
        color = style(method)["color"]
        top.plot(snap["s"], snap["u_h"] - snap["gap"], color=color, lw=1.0, ls="--", label=f"{method}: {gap_uh}")
        bottom.step(snap["edge_s"], snap["pressure"], where="mid", color=color, lw=1.0, label=f"{method}: discrete pressure")
    free = first["u"] - first["gap"] > 1e-12 * max(1.0, np.abs(first["u"]).max())
    for ax in (top, bottom):
        ax.axhline(0, color="0.6", lw=0.6)
        if exact:
            ax.fill_between(first["s"], 0, 1, where=~free, transform=ax.get_xaxis_transform(), color="0.85", alpha=0.6, lw=0)
        ax.grid(True, alpha=0.25)
        ax.legend(fontsize=7, loc="best")
    top.set_ylabel(f"{gap_uh} on $\\Gamma_C$")
    bottom.set_ylabel("contact pressure")
    bottom.set_xlabel(r"coordinate along $\Gamma_C$ (x for a horizontal $\Gamma_C$)"
                      + ("; shaded: exact contact zone" if exact else "; no closed-form solution"))
    top.set_title(f"{case.name}: finest level of each method", fontsize=10)
    return save(fig, folder, f"{case.name}_contact")


def contact_faces(case, snapshots: dict, folder: Path) -> dict[str, Path]:
    """3D: Gamma_C seen from below (x runs to the left), one column per method: u_h - alpha
    (in elasticity alpha - u_h . n; red: below the obstacle, i.e. penetration) and the discrete
    pressure per triangle, with the exact transition curve in black."""
    methods = list(snapshots)
    gap_uh = CONTACT_LABELS[case.physics.name][1]
    fig, axes = plt.subplots(2, len(methods), figsize=(3.3 * len(methods) + 0.6, 6.4), squeeze=False)
    gaps = [snap["u_h"] - snap["gap"] for snap in snapshots.values()]
    scale = max(np.abs(g).max() for g in gaps) or 1.0
    windows = [_pressure_window(snap) for snap in snapshots.values()]
    # one window for every column: the largest of the methods' (none if one has none)
    window = None if any(w is None for w in windows) else tuple(
        (min(w[axis][0] for w in windows), max(w[axis][1] for w in windows)) for axis in (0, 1))
    for k, (method, snap) in enumerate(snapshots.items()):
        tri = mtri.Triangulation(snap["points"][:, 0], snap["points"][:, 1], snap["triangles"])
        top, bottom = axes[0, k], axes[1, k]
        # rasterized: as vector graphics a PDF of Gamma_C's gouraud triangles is slow to write
        shown = top.tripcolor(tri, gaps[k], shading="gouraud", cmap="RdBu", norm=matplotlib.colors.TwoSlopeNorm(0.0, -scale, scale),
                              rasterized=True)
        fig.colorbar(shown, ax=top, shrink=0.8)
        pressure = np.tile(snap["pressure"], 4)          # the four sub-triangles of each triangle
        shown = bottom.tripcolor(tri, facecolors=pressure, cmap="viridis", rasterized=True)
        fig.colorbar(shown, ax=bottom, shrink=0.8)
        top.set_title(f"{method}: {gap_uh} (min {gaps[k].min():.2g})", fontsize=9)
        bottom.set_title(f"{method}: discrete pressure", fontsize=9)
        for ax in (top, bottom):
            for line in case.transition_curve:
                ax.plot(*np.array(line).T, color="k", lw=1.0)
            ax.set_aspect("equal")
            if window is not None:
                ax.set_xlim(*window[0])
                ax.set_ylim(*window[1])
            ax.invert_xaxis()                 # seen from below
            ax.set_xlabel("x (seen from below)", fontsize=8)
            ax.tick_params(labelsize=7)
    curve = "; black: the exact transition curve" if case.transition_curve else ""
    fig.suptitle(f"{case.name}: Γ_C on the finest level{curve}", fontsize=10)
    return save(fig, folder, f"{case.name}_contact")


def _pressure_window(snap: dict) -> tuple | None:
    """((x0, x1), (y0, y1)): where the discrete pressure is positive (above a thousandth of its
    largest value) and as much again on each side, when that covers less than a quarter of
    Gamma_C's width (a Hertz disc); else None."""
    points, triangles = snap["points"], snap["triangles"]
    pressure = np.tile(snap["pressure"], 4)
    # above round-off and the discrete pressure's small ripples far from the zone
    pressed = triangles[np.flatnonzero(pressure > 1e-3 * pressure.max(initial=0.0))]
    if not len(pressed):
        return None
    low, high = points[pressed.ravel(), :2].min(axis=0), points[pressed.ravel(), :2].max(axis=0)
    extent = points[:, :2].max(axis=0) - points[:, :2].min(axis=0)
    if np.any(high - low > extent / 4):
        return None
    middle, half = (low + high) / 2, (high - low).max()
    return (middle[0] - half, middle[0] + half), (middle[1] - half, middle[1] + half)


def domain(case, snapshot: dict, folder: Path) -> dict[str, Path] | None:
    """u_h on Omega (2D; the deformed shape in elasticity); None without a snapshot (3D)."""
    if not snapshot:
        return None
    if snapshot["values"].ndim == 2:
        return deformed(case, snapshot, folder)
    tri = mtri.Triangulation(snapshot["points"][:, 0], snapshot["points"][:, 1], snapshot["triangles"])
    fig, ax = plt.subplots(figsize=(5.6, 3.6))
    shading = ax.tricontourf(tri, snapshot["values"], levels=30, cmap="viridis")
    ax.tricontour(tri, snapshot["values"], levels=12, colors="k", linewidths=0.3)
    fig.colorbar(shading, ax=ax, shrink=0.85)
    ax.set_aspect("equal")
    ax.set_title(f"{case.name}: $u_h${_whose(snapshot)}", fontsize=10)
    return save(fig, folder, f"{case.name}_solution")


def _whose(snapshot: dict) -> str:
    """" (nodal)": the method whose solution a domain picture shows (``study.chain.snapshots.SnapshotHook``)."""
    method = snapshot.get("method")
    return "" if method is None else f" ({method})"


def interface(case, snapshot: dict | None, folder: Path) -> dict[str, Path] | None:
    """Two bodies: both meshes near the interface on a coarse level (``study.chain.snapshots.INTERFACE_LEVEL``),
    upper and lower in their own colours, and the vertices of each on Gamma_C: they do not match."""
    if not snapshot:
        return None
    points, triangles, body = snapshot["points"], snapshot["triangles"], snapshot["body"]
    fig, ax = plt.subplots(figsize=(7.2, 3.0))
    for k, (color, label) in enumerate((("tab:blue", "upper body (slave)"), ("tab:orange", "lower body (master)"))):
        mine = triangles[body == k]
        ax.triplot(mtri.Triangulation(points[:, 0], points[:, 1], mine), color=color, lw=0.5)
        on = np.unique(mine.ravel())
        on = on[np.abs(points[on, 1]) < 1e-12]
        ax.plot(points[on, 0], np.full(len(on), 0.02 if k == 0 else -0.02), "|", color=color, ms=8, label=f"{label}: Γ_C vertices")
    ax.axhline(0.0, color="k", lw=1.0)
    ax.set_ylim(-0.35, 0.35)
    ax.set_aspect("equal")
    ax.legend(fontsize=7, loc="upper right", ncol=2)
    ax.set_title(f"{case.name}: the two meshes at the interface (level 1)", fontsize=10)
    return save(fig, folder, f"{case.name}_interface")


def deformed(case, snapshot: dict, folder: Path) -> dict[str, Path]:
    """The deformed body of an elastic case: the mesh moved by u_h, magnified so that the largest
    displacement is a tenth of the body's size, coloured by |u_h|; the body at rest in grey."""
    points, displacement = snapshot["points"], snapshot["values"]
    size = np.ptp(points, axis=0).max()
    largest = np.abs(displacement).max()
    scale = 0.1 * size / largest if largest > 0 else 1.0
    moved = points + scale * displacement
    fig, ax = plt.subplots(figsize=(5.6, 3.8))
    rest = mtri.Triangulation(points[:, 0], points[:, 1], snapshot["triangles"])
    ax.triplot(rest, color="0.8", lw=0.3)
    tri = mtri.Triangulation(moved[:, 0], moved[:, 1], snapshot["triangles"])
    shading = ax.tripcolor(tri, np.hypot(*displacement.T), shading="gouraud", cmap="viridis", rasterized=True)
    ax.triplot(tri, color="k", lw=0.2, alpha=0.5)
    ax.axhline(points[:, 1].min(), color="0.3", lw=1.2, ls="-")         # the foundation's surface
    fig.colorbar(shading, ax=ax, shrink=0.85, label=r"$|u_h|$")
    ax.set_aspect("equal")
    ax.set_title(f"{case.name}: deformed shape, displacement x{scale:.3g}{_whose(snapshot)}", fontsize=10)
    return save(fig, folder, f"{case.name}_solution")


def summary(rates, folder: Path) -> dict[str, Path]:
    """``plots.rate_summary`` and ``plots.verdict_matrix`` of every case x method."""
    return {"rates": save(plots.rate_summary(rates), folder, "summary_rates"),
            "matrix": save(plots.verdict_matrix(rates), folder, "verdict_matrix")}


def efficiency(case, results, target: float, folder: Path) -> dict[str, Path]:
    """H^1 error against ndof and against time (cumulated over the levels, as nested iteration
    needs them: solid everything from mesh to solve, dashed the contact solves alone), every method."""
    fig, (by_ndof, by_time) = plt.subplots(1, 2, figsize=(9.6, 3.9), sharey=True)
    for method, g in results.groupby("method", sort=False):
        g = g.sort_values("level")
        st = style(method)
        by_ndof.loglog(g.ndof, g.err_h1, label=method, lw=1.2, ms=5, **st)
        by_time.loglog(g.total_seconds.cumsum(), g.err_h1, label=f"{method}: mesh to solve", lw=1.2, ms=5, **st)
        by_time.loglog(g.solve_seconds.cumsum(), g.err_h1, ls="--", lw=0.9, color=st["color"],
                       label=f"{method}: contact solves")
    for ax in (by_ndof, by_time):
        ax.axhline(target, color="0.4", lw=0.7, ls=":")
        ax.grid(True, which="both", alpha=0.25)
    by_ndof.annotate("target", (by_ndof.get_xlim()[0], target), textcoords="offset points", xytext=(4, 3), fontsize=7)
    by_ndof.set_xlabel("ndof")
    by_ndof.set_ylabel(r"$\|u-u_h\|_{H^1(\Omega)}$")
    by_time.set_xlabel("seconds, summed over the levels so far")
    by_ndof.legend(fontsize=7)
    by_time.legend(fontsize=6)
    fig.suptitle(f"{case.name}: error against cost", fontsize=10)
    return save(fig, folder, f"{case.name}_efficiency")


def sweep(case, frame, folder: Path) -> dict[str, Path]:
    """H^1 error and largest penetration against the swept parameter (eps0 / gamma0), one line
    per swept method, the reference methods as horizontal lines; hollow markers: not converged."""
    fig, (left, right) = plt.subplots(1, 2, figsize=(10.4, 4.0))
    swept = frame[frame.sweep_parameter.fillna("") != ""]
    for k, (label, g) in enumerate(swept.groupby("sweep_method", sort=False)):
        g = g.sort_values("sweep_value")
        color = OTHER_COLORS[k % len(OTHER_COLORS)]
        ok = g.status == "converged"
        for ax, column in ((left, "err_h1"), (right, "max_penetration")):
            ax.loglog(g.sweep_value, g[column].clip(lower=1e-16), color=color, lw=1.2, label=label)
            ax.plot(g.sweep_value[ok], g[column][ok].clip(lower=1e-16), "o", color=color, ms=4)
            ax.plot(g.sweep_value[~ok], g[column][~ok].clip(lower=1e-16), "o", mfc="none", color=color, ms=7)
    for _, row in frame[frame.sweep_parameter.fillna("") == ""].iterrows():
        for ax, column in ((left, "err_h1"), (right, "max_penetration")):
            if row[column] > 0:
                ax.axhline(row[column], color="0.3", ls="--", lw=1.0, label=f"{row.method} (no parameter)")
    names = sorted(set(swept.sweep_parameter))
    for ax, ylabel in ((left, r"$H^1$ error"), (right, r"max penetration $\max(\alpha - u_h)$ on $\Gamma_C$")):
        scale = r"$\cdot\, h$" if case.physics.modulus == 1 else rf"$\cdot\, h / M$, $M = \lambda + 2\mu = {case.physics.modulus:.3g}$"
        ax.set_xlabel(" / ".join(names) + r"  ($\varepsilon = $ value " + scale + ")")
        ax.set_ylabel(ylabel)
        ax.grid(True, which="both", alpha=0.3)
    ndof = ", ".join(f"{n:.3g}" for n in sorted(set(frame.ndof)))
    left.set_title(f"{case.name}: level {int(frame.level.max())}, {ndof} dofs", fontsize=9)
    left.legend(fontsize=7)
    right.set_title("hollow: Newton not converged", fontsize=9)
    return save(fig, folder, f"sweep_{case.name}")
