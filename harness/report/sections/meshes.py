"""The report's section "Meshes that fit the singularity (Remark 4.4)": the mesh study's rows
(``study.planning.mesh_study``) beside the uniform rows of the same cases and methods, their rates in N,
the estimator's effectivity, the finest adaptive mesh, and "Is P2 worth it?" on adaptive meshes."""
from __future__ import annotations

import numpy as np
import pandas as pd

from ..measure.efficiency import baseline_name, efficiency_table
from ..measure.rates import rate_table
from .tables import _fmt, efficiency_view

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


def add_mesh_section(doc, results: pd.DataFrame, meshes: pd.DataFrame, figs: dict) -> None:
    frame = mesh_rows(results, meshes)
    if frame.empty:
        return
    doc.heading("Meshes that fit the singularity (Remark 4.4)")
    doc.paragraph(MESH_NOTE)
    rates = rate_table(frame)
    doc.table(ndof_rates_view(rates))
    for case in dict.fromkeys(meshes.case):
        pictures = figs.get("meshes", {}).get(case, {})
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
