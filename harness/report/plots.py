"""The report's main figures as functions of DataFrames, for a notebook (``harness.plot``) as
for the report:

    import harness
    df = harness.run(["transition-r32", "corner-r12"], methods="cones", levels=5)
    harness.plot(df, "transition-r32")          # H1 error against h, each theory's bound dashed
    harness.plot(df, kind="verdicts")           # cases x methods: fitted / expected rate, by verdict
    harness.plot(df, kind="rates")              # fitted against expected rates

Each returns a matplotlib Figure (or draws into ``ax``) and needs nothing but the results'
columns (``harness.run``'s rows, ``rate_table``'s rows): the theories' rates are in them.
Nothing here chooses a backend or writes a file (``figures`` saves the report's PNG and PDF).

Colours are assigned, not listed: each method takes the next colour and marker of ``PALETTE``
and ``MARKERS``, the methods that declare the roles PAPER and BASELINE (``Method.roles``) first,
so that the paper's models and the P1 baseline look the same in every figure (``method_styles``).
"""
from __future__ import annotations

import re

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd
from matplotlib.ticker import LogFormatterSciNotation, LogLocator

from ..methods import BASELINE, METHODS, PAPER, Method, MethodError, get_method, with_role
from ..problem.case import fraction

# the colours and markers methods take in turn (``method_styles``)
PALETTE = ("tab:blue", "tab:orange", "tab:green", "tab:cyan", "tab:red", "tab:purple", "tab:brown", "tab:pink",
           "tab:olive", "tab:gray", "black", "darkgoldenrod", "navy", "limegreen", "teal", "maroon",
           "darkviolet", "chocolate", "slategray", "crimson", "olivedrab", "deeppink")
MARKERS = ("o", "s", "^", "v", "D")           # the last for every later method (the colours tell them apart)
# every method's style so far in this process, by name (``style``, ``register_methods``)
METHOD_STYLE: dict[str, dict] = {}
# the sweep figure's colours, one per swept method (``figures.sweep``)
OTHER_COLORS = ["tab:red", "tab:purple", "tab:brown", "tab:pink", "tab:olive", "tab:cyan"]
# the verdicts' colours: the HTML table's and the figure's
VERDICT_COLORS = {"meets": "#cdeccf", "above": "#cfe0f5", "below": "#f6cdcd", "pre-asymptotic": "#f8e3c2",
                  "no theory": "#ececec"}


def _slot(k: int) -> dict:
    return dict(color=PALETTE[k % len(PALETTE)], marker=MARKERS[min(k, len(MARKERS) - 1)])


def _method(item):
    """A Method for a Method or a name (None for a name this process does not know)."""
    if isinstance(item, Method):
        return item
    try:
        return get_method(item)
    except (MethodError, ValueError):
        return None


def method_styles(methods=()) -> dict[str, dict]:
    """{name: dict(color, marker)} for ``methods`` (Method objects or names): the k-th of the
    palette for the k-th method, counted over the methods that declare the role PAPER (the
    registered ones and any of ``methods``), then those that declare BASELINE, then the rest of
    ``methods`` in their order. The registered PAPER and BASELINE methods always take the first
    places, present or not: `mean`'s colour is the same in every report."""
    given = [m for m in (_method(item) for item in methods) if m is not None]
    known = [*METHODS.values(), *given]
    first = [m.name for m in with_role(PAPER, known) + with_role(BASELINE, known)]
    names = dict.fromkeys([*first, *(m.name if isinstance(m, Method) else m for m in methods)])
    return {name: _slot(k) for k, name in enumerate(names)}


def register_methods(methods) -> None:
    """Give every method of a figure its style: ``methods`` (Method objects or names, the styles
    then ``method_styles``'), or a {name: style} of ``method_styles`` (what a figure worker is
    sent, so that every process that draws a figure of the same study draws each method in the
    same colour). Replaces the styles given before."""
    styles = methods if isinstance(methods, dict) else method_styles(methods)
    METHOD_STYLE.clear()
    METHOD_STYLE.update({name: dict(value) for name, value in styles.items()})


def style(method: str) -> dict:
    """A fixed colour and marker per method: the registered one's (``register_methods``), or the
    next free place of the palette after the roles' methods (``method_styles``)."""
    if not METHOD_STYLE:
        register_methods(())
    if method not in METHOD_STYLE:
        METHOD_STYLE[method] = _slot(len(METHOD_STYLE))
    return METHOD_STYLE[method]


_SUPERSCRIPT = str.maketrans("-0123456789", "⁻⁰¹²³⁴⁵⁶⁷⁸⁹")
_SCIENTIFIC = re.compile(r"^\$\\mathdefault\{(?:([0-9.]+)\\times)?10\^\{(-?[0-9]+)\}\}\$$")


class UnicodeLogFormatter(LogFormatterSciNotation):
    """matplotlib's log-axis labels (10^-3, 2 x 10^-3) as Unicode text, 10⁻³ and 2×10⁻³, not
    mathtext: parsing mathtext (pyparsing, per label and again per resolution) is a large share
    of the report's figure time. A label of another form stays mathtext."""

    def __call__(self, x, pos=None):
        label = super().__call__(x, pos)
        match = _SCIENTIFIC.match(label)
        if match is None:
            return label
        mantissa, exponent = match.groups()
        return (f"{mantissa}×" if mantissa else "") + "10" + exponent.translate(_SUPERSCRIPT)

    def set_locs(self, locs=None):
        """Below a decade matplotlib labels the minor ticks 2, 3, 4, 6 (or all): written out,
        2×10³ 3×10³ 4×10³ run into each other on a panel a few inches wide. Keep 2 and 5 of
        them (and 3 and 7 on an axis under 0.4 decades)."""
        super().set_locs(locs)
        if self._sublabels is not None and len(self._sublabels) > 1:
            self._sublabels = {1.0, 2.0, 5.0} if len(self._sublabels) < 9 else {1.0, 2.0, 3.0, 5.0, 7.0}


def unicode_log_labels(fig) -> None:
    """Every log-scaled axis of ``fig`` labelled by ``UnicodeLogFormatter``, with the settings of
    the formatters it replaces (which minor ticks get a label)."""
    for ax in fig.axes:
        for axis in (ax.xaxis, ax.yaxis):
            if axis.get_scale() != "log":
                continue
            for formatter, setter in ((axis.get_major_formatter(), axis.set_major_formatter),
                                      (axis.get_minor_formatter(), axis.set_minor_formatter)):
                if type(formatter) is LogFormatterSciNotation:
                    setter(UnicodeLogFormatter(formatter._base, labelOnlyBase=formatter.labelOnlyBase,
                                               minor_thresholds=formatter.minor_thresholds,
                                               linthresh=formatter._linthresh))


def theorem_label(theorem: str) -> str:
    """"Theorem 4.1 ii, 5.1 ii" for a theorem number, the text itself for a remark or a section
    ("Remark 4.9", not "Theorem Remark 4.9")."""
    return f"Theorem {theorem}" if theorem[:1].isdigit() else theorem


def bound_tex(p: float, q: float) -> str:
    bound = rf"$C\,h^{{{fraction(p)}}}"
    if q:
        bound += rf"\,|\log h|^{{{fraction(q)}}}"
    return bound + "$"


def _axes(ax, figsize):
    if ax is not None:
        return ax.figure, ax
    return plt.subplots(figsize=figsize)


def _slope_marker(ax, h, e, rate, label):
    """A slope triangle of the theorem's rate below the data, in the middle of the range."""
    h0, h1 = h[len(h) // 2], h[len(h) // 2 + 1] if len(h) > 2 else h[-1]
    e0 = e[len(e) // 2] * 0.45
    e1 = e0 * (h1 / h0) ** rate
    ax.plot([h0, h1, h0, h0], [e0, e1, e1, e0], color="0.3", lw=0.8)
    ax.annotate(label, (h0, np.sqrt(e0 * e1)), textcoords="offset points", xytext=(4, 0), fontsize=8, color="0.3")


def convergence(results: pd.DataFrame, case: str | None = None, ax=None, title: str | None = None):
    """log-log H^1 error against h of every method of one case (``case``: needed when the rows
    hold several), each theory's bound dashed in the colour of its first method, through the
    coarsest point, and a slope triangle of the P2 theory's rate."""
    if case is None:
        names = results.case.unique()
        if len(names) != 1:
            raise ValueError(f"the results hold {len(names)} cases: name one of {', '.join(names)}")
        case = names[0]
    results = results[results.case == case]
    if "mesh" in results:
        results = results[results["mesh"].fillna("uniform") == "uniform"]
    fig, ax = _axes(ax, (5.2, 4.0))
    for method, g in results.groupby("method", sort=False):
        g = g.sort_values("h")
        ax.loglog(g.h, g.err_h1, label=method, lw=1.2, ms=5, **style(method))
    theories = results.dropna(subset=["expected_rate"]).groupby(["expected_rate", "expected_log_exponent"],
                                                                 sort=False).method.unique()
    for (p, q), methods in theories.items():
        g = results[results.method == methods[0]].sort_values("h")
        h = np.geomspace(g.h.min(), g.h.max(), 50)
        anchor = g.err_h1.iloc[0] / (g.h.iloc[0] ** p * abs(np.log(g.h.iloc[0])) ** q)
        ax.loglog(h, anchor * h**p * np.abs(np.log(h)) ** q, "--", color=style(methods[0])["color"], lw=0.8,
                  label=f"theory ({', '.join(methods)}): {bound_tex(p, q)}")
    g = results[results.order == results.order.max()]
    p2_rate = g.expected_rate.dropna()
    if len(p2_rate):
        hs = np.sort(g.h.unique())[::-1]
        es = g.groupby("h").err_h1.max().reindex(hs).to_numpy()
        _slope_marker(ax, hs, es, p2_rate.iloc[0], fraction(p2_rate.iloc[0]))
    ax.set_xlabel("h (largest element diameter)")
    ax.set_ylabel(r"$\|u-u_h\|_{H^1(\Omega)}$")
    ax.set_title(title or case, fontsize=10)
    # h spans a decade or two: label the minor ticks at 2 and 5 only, not every one (they overlap)
    ax.xaxis.set_minor_locator(LogLocator(subs=(2.0, 5.0)))
    ax.xaxis.set_minor_formatter(LogFormatterSciNotation(labelOnlyBase=False, minor_thresholds=(np.inf, np.inf)))
    ax.grid(True, which="both", alpha=0.25)
    ax.legend(fontsize=8)
    return fig


def _uniform(rates: pd.DataFrame) -> pd.DataFrame:
    return rates[rates["mesh"].fillna("uniform") == "uniform"] if "mesh" in rates else rates


def verdict_cells(rates: pd.DataFrame) -> pd.DataFrame:
    """Cases (rows, in the order given) x methods (columns): "fitted / expected" H^1 rate, the
    verdict of each cell in ``attrs["verdicts"]`` (a frame of the same shape; "" where the
    method did not run on the case)."""
    rates = _uniform(rates)
    cases, methods = list(dict.fromkeys(rates.case)), list(dict.fromkeys(rates.method))
    text = pd.DataFrame("", index=pd.Index(cases, name="case"), columns=methods)
    verdict = text.copy()
    for row in rates.itertuples():
        expected = "–" if pd.isna(row.expected_rate) else f"{row.expected_rate:.2f}"
        text.loc[row.case, row.method] = f"{row.fitted_rate:.2f} / {expected}"
        verdict.loc[row.case, row.method] = row.verdict
    text.attrs["verdicts"] = verdict
    return text


def verdict_matrix(rates: pd.DataFrame, ax=None):
    """One glance at the study: every case x method cell the fitted / expected H^1 rate,
    coloured by the verdict (green meets its theory within ±0.1, blue above, red below, amber
    pre-asymptotic, grey no theory; ``measure.rates``)."""
    cells = verdict_cells(rates)
    verdicts = cells.attrs["verdicts"]
    rows, columns = cells.shape
    fig, ax = _axes(ax, (1.2 + 1.05 * columns, 0.8 + 0.3 * rows))
    for i, case in enumerate(cells.index):
        for j, method in enumerate(cells.columns):
            colour = VERDICT_COLORS.get(verdicts.loc[case, method], "white")
            ax.add_patch(plt.Rectangle((j, i), 1, 1, facecolor=colour, edgecolor="white", lw=1.5))
            ax.text(j + 0.5, i + 0.5, cells.loc[case, method], ha="center", va="center", fontsize=7.5)
    ax.set_xlim(0, columns), ax.set_ylim(rows, 0)
    ax.set_xticks(np.arange(columns) + 0.5, cells.columns, fontsize=8)
    ax.xaxis.tick_top()
    ax.set_yticks(np.arange(rows) + 0.5, cells.index, fontsize=8)
    ax.tick_params(length=0)
    for spine in ax.spines.values():
        spine.set_visible(False)
    handles = [plt.Rectangle((0, 0), 1, 1, facecolor=c) for c in VERDICT_COLORS.values()]
    ax.legend(handles, list(VERDICT_COLORS), ncol=len(VERDICT_COLORS), fontsize=7.5, frameon=False,
              loc="upper center", bbox_to_anchor=(0.5, 0.0))
    ax.set_title("fitted / expected H¹ rate (the last three levels)", fontsize=9, pad=22)
    return fig


def _spread(y: np.ndarray, gap: float, lo: float, hi: float) -> np.ndarray:
    """Positions as close to ``y`` (sorted) as they can be with at least ``gap`` between
    neighbours, inside [lo, hi]: the label column of ``rate_summary``."""
    out = np.clip(np.array(y, float), lo, hi)
    for k in range(1, len(out)):
        out[k] = max(out[k], out[k - 1] + gap)
    if len(out) and out[-1] > hi:               # pushed past the top: pack down from there
        out[-1] = hi
        for k in range(len(out) - 2, -1, -1):
            out[k] = min(out[k], out[k + 1] - gap)
    return out


def rate_summary(rates: pd.DataFrame, ax=None, band: float = 0.1):
    """Fitted against expected H^1 rates, every case x method, the ±``band`` verdict band grey.
    The points outside the band are named in a column to the right, joined to their points
    (inside the band every point meets its theory; ``verdict_matrix`` names every cell)."""
    rates = _uniform(rates).dropna(subset=["expected_rate"])
    fig, ax = _axes(ax, (7.4, 4.6))
    lo, hi = 0.3, 2.3
    ax.plot([lo, hi], [lo, hi], "k-", lw=0.8)
    ax.fill_between([lo, hi], [lo - band, hi - band], [lo + band, hi + band], color="0.9")
    methods = list(dict.fromkeys(rates.method))
    x = {}
    for k, (method, g) in enumerate(rates.groupby("method", sort=False)):
        offset = 0.03 * (k - (len(methods) - 1) / 2)
        x.update({(c, method): e + offset for c, e in zip(g.case, g.expected_rate)})
        ax.errorbar(g.expected_rate + offset, g.fitted_rate, yerr=g.fitted_rate_se.fillna(0), ls="none",
                    label=method, ms=6, **style(method))
    outside = rates[(rates.fitted_rate - rates.expected_rate).abs() > band].sort_values("fitted_rate")
    if len(outside):
        ys = _spread(outside.fitted_rate.to_numpy(), 0.075, lo + 0.03, hi - 0.03)
        for (_, row), y in zip(outside.iterrows(), ys):
            ax.annotate(f"{row.case} ({row.method})", xy=(x[row.case, row.method], row.fitted_rate),
                        xytext=(hi + 0.05, y), textcoords="data", fontsize=7, va="center", annotation_clip=False,
                        arrowprops=dict(arrowstyle="-", color="0.6", lw=0.5, shrinkA=0, shrinkB=3))
    ax.set_xlim(lo, hi), ax.set_ylim(lo, hi)
    ax.set_xlabel("rate p of the method's theory")
    ax.set_ylabel("fitted rate (last levels)")
    ax.set_title(f"Fitted H¹ rates against the theorems (grey: ±{band}; named: outside it)", fontsize=9)
    ax.grid(True, alpha=0.25)
    if methods:         # a study of cases without a theorem rate (Coulomb's) has no point to name
        ax.legend(fontsize=8, loc="upper left")
    return fig
