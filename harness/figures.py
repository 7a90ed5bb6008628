"""Figures of the report (matplotlib, Agg): PNG for the HTML page, PDF for papers."""
from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import matplotlib.tri as mtri  # noqa: E402
import numpy as np  # noqa: E402

from .case import fraction  # noqa: E402

MODEL_STYLE = {"mean": dict(color="tab:blue", marker="o"), "nodal": dict(color="tab:orange", marker="s")}
FORMATS = ("png", "pdf")


def save(fig, folder: Path, stem: str) -> dict[str, Path]:
    paths = {}
    for fmt in FORMATS:
        paths[fmt] = folder / f"{stem}.{fmt}"
        fig.savefig(paths[fmt], dpi=130, bbox_inches="tight")
    plt.close(fig)
    return paths


def _bound_tex(p: float, q: float) -> str:
    bound = rf"$C\,h^{{{fraction(p)}}}"
    if q:
        bound += rf"\,|\log h|^{{{fraction(q)}}}"
    return bound + "$"


def _slope_marker(ax, h, e, rate, label):
    """A slope triangle of the theorem's rate below the data, in the middle of the range."""
    h0, h1 = h[len(h) // 2], h[len(h) // 2 + 1] if len(h) > 2 else h[-1]
    e0 = e[len(e) // 2] * 0.45
    e1 = e0 * (h1 / h0) ** rate
    ax.plot([h0, h1, h0, h0], [e0, e1, e1, e0], color="0.3", lw=0.8)
    ax.annotate(label, (h0, np.sqrt(e0 * e1)), textcoords="offset points", xytext=(4, 0), fontsize=8, color="0.3")


def convergence(case, results, folder: Path) -> dict[str, Path]:
    """log-log H^1 error against h, both models, with the theorem's bound through the finest point."""
    fig, ax = plt.subplots(figsize=(5.2, 4.0))
    p, q = case.expected_rate, case.expected_log_exponent
    for model, g in results.groupby("model"):
        g = g.sort_values("h")
        ax.loglog(g.h, g.err_h1, label=f"{model}", lw=1.2, ms=5, **MODEL_STYLE.get(model, {}))
    g = results.sort_values("h")
    h = np.geomspace(g.h.min(), g.h.max(), 50)
    bound = h**p * np.abs(np.log(h)) ** q
    anchor = g.err_h1.iloc[0] / (g.h.iloc[0] ** p * abs(np.log(g.h.iloc[0])) ** q)
    ax.loglog(h, anchor * bound, "k--", lw=0.9, label=f"theorem: {_bound_tex(p, q)}")
    hs = np.sort(g.h.unique())[::-1]
    es = g.groupby("h").err_h1.max().reindex(hs).to_numpy()
    _slope_marker(ax, hs, es, p, fraction(p))
    ax.set_xlabel("h (largest element diameter)")
    ax.set_ylabel(r"$\|u-u_h\|_{H^1(\Omega)}$")
    ax.set_title(f"{case.name}: Theorem {case.theorem}", fontsize=10)
    ax.grid(True, which="both", alpha=0.25)
    ax.legend(fontsize=8)
    return save(fig, folder, f"{case.name}_convergence")


def contact(case, snapshots: dict, folder: Path) -> dict[str, Path]:
    """u_h and the discrete contact pressure along Gamma_C on the finest level."""
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(6.4, 5.2), sharex=True)
    first = next(iter(snapshots.values()))
    top.plot(first["s"], first["u"] - first["gap"], "k-", lw=1.0, label=r"exact $u-\alpha$")
    bottom.plot(first["s"], first["exact_pressure"], "k-", lw=1.0, label=r"exact $\partial_n u - g_C$")
    for model, snap in snapshots.items():
        style = MODEL_STYLE.get(model, {})
        top.plot(snap["s"], snap["u_h"] - snap["gap"], color=style.get("color"), lw=1.0, ls="--", label=f"{model}: $u_h-\\alpha$")
        bottom.step(snap["edge_s"], snap["pressure"], where="mid", color=style.get("color"), lw=1.0, label=f"{model}: discrete pressure")
    free = first["u"] - first["gap"] > 1e-12 * max(1.0, np.abs(first["u"]).max())
    for ax in (top, bottom):
        ax.axhline(0, color="0.6", lw=0.6)
        ax.fill_between(first["s"], 0, 1, where=~free, transform=ax.get_xaxis_transform(), color="0.85", alpha=0.6, lw=0)
        ax.grid(True, alpha=0.25)
        ax.legend(fontsize=7, loc="best")
    top.set_ylabel(r"$u_h - \alpha$ on $\Gamma_C$")
    bottom.set_ylabel("contact pressure")
    bottom.set_xlabel(r"coordinate along $\Gamma_C$ (x for a horizontal $\Gamma_C$); shaded: exact contact zone")
    top.set_title(f"{case.name}: finest level, both models", fontsize=10)
    return save(fig, folder, f"{case.name}_contact")


def domain(case, snapshot: dict, folder: Path) -> dict[str, Path]:
    tri = mtri.Triangulation(snapshot["points"][:, 0], snapshot["points"][:, 1], snapshot["triangles"])
    fig, ax = plt.subplots(figsize=(5.6, 3.6))
    shading = ax.tricontourf(tri, snapshot["values"], levels=30, cmap="viridis")
    ax.tricontour(tri, snapshot["values"], levels=12, colors="k", linewidths=0.3)
    fig.colorbar(shading, ax=ax, shrink=0.85)
    ax.set_aspect("equal")
    ax.set_title(f"{case.name}: $u_h$ (model nodal)", fontsize=10)
    return save(fig, folder, f"{case.name}_solution")


def summary(rates, folder: Path) -> dict[str, Path]:
    """Fitted against expected rates, every case x model, with the +-0.1 verdict band."""
    fig, ax = plt.subplots(figsize=(5.0, 4.4))
    lo, hi = 0.3, 2.3
    ax.plot([lo, hi], [lo, hi], "k-", lw=0.8)
    ax.fill_between([lo, hi], [lo - 0.1, hi - 0.1], [lo + 0.1, hi + 0.1], color="0.9")
    for model, g in rates.groupby("model"):
        offset = -0.02 if model == "mean" else 0.02
        ax.errorbar(g.expected_rate + offset, g.fitted_rate, yerr=g.fitted_rate_se.fillna(0), ls="none",
                    label=model, ms=6, **MODEL_STYLE.get(model, {}))
    for _, row in rates.drop_duplicates("case").iterrows():
        ax.annotate(row.case, (row.expected_rate, row.fitted_rate), textcoords="offset points",
                    xytext=(8, -10), fontsize=7)
    ax.set_xlim(lo, hi), ax.set_ylim(lo, hi)
    ax.set_xlabel("theorem rate p")
    ax.set_ylabel("fitted rate (last levels)")
    ax.set_title("Fitted H¹ rates against the theorems", fontsize=10)
    ax.grid(True, alpha=0.25)
    ax.legend(fontsize=8, loc="upper left")
    return save(fig, folder, "summary_rates")
