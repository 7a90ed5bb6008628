"""The report's section "Meshes that fit the singularity (Remark 4.4)": the mesh study's rows
beside the uniform rows of the same cases and methods, their rates in N, the estimator's
effectivity, the finest adaptive mesh, and "Is P2 worth it?" on adaptive meshes; and its figures
(``queue_figures``: the error and the effectivity against N, ``error_against_ndof``, and the
finest adaptive mesh, ``adaptive_mesh``). What the mesh study runs (its cases, methods, mesh
strategies and levels) and how its rows and finest meshes are stored is planned by
``study.planning.mesh_study``, run by ``study.planning.cache``."""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd

from ...measure.efficiency import baseline_name, efficiency_table
from ...measure.rates import rate_table
from ...study.planning.mesh_study import PICTURE_METHOD
from ..document import Document
from ..plan import ReportPlan
from ..tables import _fmt, efficiency_view

GROUP = "meshes"        # the figures' group (``report.figure_jobs.FigurePool``)
# the line of each mesh strategy in the figures (here and ``report.sections.degrees``)
LINESTYLE = {"uniform": ":", "graded": "--", "adaptive": "-", "hp": "--"}

MESH_NOTE = (
    "On uniform meshes every method's rate is set by the case's singular point: N^{-(ν-1)/d} "
    "(h^{ν-1}). Remark 4.4 names the remedy, meshes refined toward the singular points. Graded: "
    "h_T ≈ H r^{1-μ} within 0.5 of each declared singular point, μ = 0.9 (ν-1)/k for P_k (Apel, "
    "Sändig & Whiteman, Math. Methods Appl. Sci. 19 (1996): optimal for μ < λ/k, λ = ν-1), by "
    "bisection, H halved per level. Adaptive: SOLVE → ESTIMATE → MARK (Dörfler, θ = 0.5) → REFINE "
    "(bisection), each method on its own meshes, driven by the residual estimator η (element "
    "residual, flux jumps, Neumann residual, and on Γ_C the flux against the discrete pressure, "
    "tension, penetration and complementarity), until the mesh has as many triangles as the "
    "uniform finest level. In 3D (transition-line-3d, in the fine profile) the same on tetrahedra, graded toward the "
    "declared singular line (Apel & Nicaise: μ < λ/k) and the estimator's terms on faces; the picture "
    "shows the finest adaptive mesh's triangles on Γ_C. Rates are fitted against N over the last "
    "three levels; on any mesh P_k can do at best N^{-k/d} in d dimensions. smooth-obstacle has no "
    "closed-form solution: each of its graded and adaptive levels is measured against its own reference "
    "(the level's mesh refined uniformly reference_levels times), and where its contact zone ends is "
    "not known beforehand, so only the adaptive meshes can refine there (its graded meshes grade toward "
    "the corners of Ω). Effectivity: η / ‖u − u_h‖ₐ (1 is ideal; the estimator's "
    "constant is not computed, only its ratio to the error, which the exact cases and the references let us measure)."
)


def mesh_rows(results: pd.DataFrame, meshes: pd.DataFrame) -> pd.DataFrame:
    """The mesh study's rows with the uniform rows of the same cases and methods."""
    if meshes.empty:
        return meshes
    pairs = set(zip(meshes.case, meshes.method))
    uniform = results[[pair in pairs for pair in zip(results.case, results.method)]]
    return pd.concat([uniform.assign(mesh=uniform.get("mesh", "uniform")), meshes], ignore_index=True)


def ndof_rates_view(rates: pd.DataFrame) -> pd.DataFrame:
    """Per case, method and mesh: the fitted rate in N, the uniform theory's, the optimal one,
    the estimator's rate and its effectivity on the finest level."""
    return pd.DataFrame({
        "case": rates.case, "method": rates.method, "mesh": rates.mesh,
        "fitted N-rate": [_fmt(v, ".3f") for v in rates.fitted_rate_ndof],
        "uniform theory": [_fmt(v, ".3g") for v in rates.uniform_rate_ndof],
        "optimal k/d": [_fmt(v, ".3g") for v in rates.optimal_rate_ndof],
        "verdict": rates.ndof_verdict, "pairwise N-rates": rates.pairwise_rates_ndof.str.split().str[-4:].str.join(" "),
        "estimator N-rate": [_fmt(v, ".3f") for v in rates.fitted_rate_estimator],
        "effectivity, finest": [_fmt(v, ".2f") for v in rates.effectivity_finest],
    })


def effectivity_view(frame: pd.DataFrame, last: int = 4) -> pd.DataFrame:
    """The effectivity index over the levels of every (case, mesh, method): its range over all
    levels and over the last ``last``, and the max/min ratio there (a constant effectivity is
    what makes an estimator a measure of the error)."""
    rows = []
    for (case, mesh, method), g in frame.groupby(["case", "mesh", "method"], sort=False):
        eff = g.sort_values("ndof").effectivity.to_numpy()
        if not np.isfinite(eff).any():
            continue
        tail = eff[-last:]
        rows.append({"case": case, "mesh": mesh, "method": method, "levels": len(eff),
                     "min": _fmt(np.nanmin(eff), ".2f"), "max": _fmt(np.nanmax(eff), ".2f"),
                     f"last {last}: min": _fmt(tail.min(), ".2f"), f"last {last}: max": _fmt(tail.max(), ".2f"),
                     f"last {last}: max/min": _fmt(tail.max() / tail.min(), ".2f")})
    return pd.DataFrame(rows)


def write(doc: Document, plan: ReportPlan) -> None:
    """The section, where the report ran a mesh study."""
    if plan.meshes is not None and not plan.meshes.empty:
        add_mesh_section(doc, plan.results, plan.meshes, plan.figs)


def add_mesh_section(doc, results: pd.DataFrame, meshes: pd.DataFrame, figs: dict) -> None:
    """The section from the study's rows, the mesh study's and the figures."""
    frame = mesh_rows(results, meshes)
    if frame.empty:
        return
    doc.heading("Meshes that fit the singularity (Remark 4.4)")
    doc.paragraph(MESH_NOTE)
    rates = rate_table(frame)
    doc.table(ndof_rates_view(rates))
    for case in dict.fromkeys(meshes.case):
        pictures = figs.get(GROUP, {}).get(case, {})
        if "errors" in pictures:
            doc.figures([(pictures["errors"]["png"], f"{case}: H¹ error and effectivity against N; dotted uniform, "
                          "dashed graded, solid adaptive; grey band: effectivity between 0.5 and 10.")], wide=True)
        if pictures.get("mesh") is not None:
            where = " on Γ_C" if "dimension" in meshes and (meshes.dimension[meshes.case == case] == 3).any() else ""
            doc.figures([(pictures["mesh"]["png"], f"{case}: the finest adaptive mesh{where}, whole and zoomed on its "
                          "smallest triangle.")], wide=True)
    doc.heading("Effectivity of the estimator, level by level", level=3)
    doc.table(effectivity_view(frame))
    adaptive = frame[frame.mesh.astype(str).str.startswith("adaptive")]
    if not adaptive.empty and baseline_name(adaptive.method) is not None:      # the P1 baseline ran adaptively
        doc.heading("Is P2 worth it? On adaptive meshes", level=3)
        doc.paragraph("The cost at equal accuracy as above (target: the largest of the finest errors), each method "
                      "on its own adaptive meshes, where no method is held back by the singular point.")
        doc.table(efficiency_view(efficiency_table(adaptive)))


def queue_figures(pool, plan: ReportPlan, known: dict, results_dir: Path) -> None:
    """Per case of the mesh study: its errors and effectivities against N, and its finest
    adaptive mesh where one is stored (``study.planning.mesh_study.save_finest_mesh``)."""
    meshes = plan.meshes
    if meshes is None or meshes.empty:
        return
    both = mesh_rows(plan.results, meshes)
    for name in dict.fromkeys(meshes.case):
        adaptive = next((p for p in sorted((results_dir / "meshes").glob(f"{name}-adaptive*.npz"))), None)
        case = known[name]
        pool.job(f"meshes-{case.name}", mesh_figures, str(case.source), both[both.case == name],
                 str(adaptive or Path("-")), PICTURE_METHOD, group=GROUP, key=case.name)


def mesh_figures(source: str, frame: pd.DataFrame, mesh_file: str, method: str, folder: str) -> dict:
    """The job: the mesh study's figures of the case in file ``source``, in a worker."""
    from ...problem.case import load_case
    from ...study.planning.mesh_study import load_finest_mesh
    case, folder = load_case(source), Path(folder)
    finest = load_finest_mesh(Path(mesh_file))
    return {"errors": error_against_ndof(case, frame, folder),
            "mesh": adaptive_mesh(case, *finest, folder, method) if finest is not None else None}


def error_against_ndof(case, frame: pd.DataFrame, folder: Path) -> dict[str, Path]:
    """H^1 error (left) and the estimator's effectivity (right) against N, every method on every
    mesh strategy; the slopes N^-1/2 and N^-1 (P1's and P2's best) for comparison."""
    from ..figures import plt, save, style
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
    from ..figures import plt, save
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
