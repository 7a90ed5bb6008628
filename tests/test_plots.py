"""The report's figures as functions of DataFrames (``harness.report.plots``), as a notebook
calls them: from `harness.run`'s rows and their rate table, nothing else."""
import matplotlib

matplotlib.use("Agg")
import itertools  # noqa: E402

import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402
import pytest  # noqa: E402

from harness.measure.rates import rate_table  # noqa: E402
from harness.report import plots  # noqa: E402

DATA = __import__("pathlib").Path(__file__).parent / "data"


@pytest.fixture(scope="module")
def rows():
    import harness
    return harness.run(["transition-r32", "corner-r12"], methods=["mean", "nodal", "p1", "nitsche"], levels=3,
                       show_progress=False)


def test_convergence_draws_every_method_and_each_theory(rows):
    fig = plots.convergence(rows, "transition-r32")
    labels = [line.get_label() for line in fig.axes[0].get_lines()]
    assert {"mean", "nodal", "p1", "nitsche"} <= set(labels)
    assert sum(label.startswith("theory") for label in labels) == 2          # h^{3/2} (P2) and h (P1)
    with pytest.raises(ValueError, match="2 cases"):
        plots.convergence(rows)


def test_verdict_matrix_has_one_coloured_cell_per_case_and_method(rows):
    rates = rate_table(rows)
    cells = plots.verdict_cells(rates)
    assert cells.shape == (2, 4)
    verdicts = cells.attrs["verdicts"]
    assert verdicts.loc["corner-r12", "nitsche"] == "no theory" and cells.loc["corner-r12", "nitsche"].endswith("/ –")
    fig = plots.verdict_matrix(rates)
    assert len(fig.axes[0].patches) == 8
    colours = {tuple(np.round(p.get_facecolor()[:3], 3)) for p in fig.axes[0].patches}
    assert len(colours) >= 2


def test_rate_summary_names_the_points_outside_the_band_without_overlap():
    """Made-up rates: many points outside the band at nearly the same fitted rate, whose names
    must not overlap."""
    rates = pd.DataFrame({"case": [f"case-{k}" for k in range(12)], "method": "nodal",
                          "expected_rate": 1.5, "fitted_rate": 0.9 + 0.001 * np.arange(12), "fitted_rate_se": 0.01,
                          "verdict": "below"})
    fig = plots.rate_summary(rates)
    fig.canvas.draw()
    names = [t for t in fig.axes[0].texts if t.get_text().startswith("case-")]
    assert len(names) == 12
    # the text's own box (an annotation's box includes its connector line)
    boxes = [matplotlib.text.Text.get_window_extent(t) for t in names]
    assert not any(a.overlaps(b) for a, b in itertools.combinations(boxes, 2))


def test_theorem_label_does_not_call_a_remark_a_theorem():
    assert plots.theorem_label("4.1 ii, 5.1 ii") == "Theorem 4.1 ii, 5.1 ii"
    assert plots.theorem_label("Remark 4.9") == "Remark 4.9"


class _RecordingExecutor:
    """Stands in for the figure processes: records what is handed to them, draws nothing."""

    def __init__(self):
        self.drawn = []

    def submit(self, timed, draw, methods, *args):
        from concurrent.futures import Future
        self.drawn.append(draw.__name__)
        done = Future()
        done.set_result(({"png": f"{draw.__name__}.png"}, 0.0))
        return done

    def shutdown(self, **_):
        pass


def test_figures_wait_for_the_cores_the_study_leaves_free_and_all_are_drawn_at_collect(tmp_path):
    import time

    from harness.problem.case import load_case
    from harness.report.sections import figure_pool
    from harness.report.sections.summary import summary_figures
    with figure_pool(["nodal"], tmp_path, workers=2, store=tmp_path) as pool:
        pool.pool = executor = _RecordingExecutor()
        pool.case_stored(load_case("corner-r12"))         # the study still uses every core
        pool.case_stored(load_case("transition-r32"))
        time.sleep(0.2)
        assert executor.drawn == []
        pool.cores_free(1)                                # its tail: one core idle
        deadline = time.monotonic() + 5
        while len(executor.drawn) < 2 and time.monotonic() < deadline:
            time.sleep(0.01)
        assert executor.drawn == ["case_figures", "case_figures"]
        pool.cores_free(0)
        pool.job("summary", summary_figures, pd.DataFrame())
        time.sleep(0.2)
        assert len(executor.drawn) == 2
        figs, seconds = pool.collect()                    # the study is done: every worker draws
    assert executor.drawn[-1] == "summary_figures"
    assert set(figs) == {"corner-r12", "transition-r32", "summary", "sweeps", "meshes", "degree_study"} and set(seconds) == set(figs)


@pytest.mark.parametrize("low, high, kept", [(1e3, 4e3, {"2×10³"}), (1.5e3, 6e3, {"2×10³", "5×10³"})])
def test_log_labels_below_a_decade_keep_two_and_five_only(low, high, kept):
    """Below a decade matplotlib labels the minor ticks 2, 3, 4 and 6, whose written-out labels
    run into each other on a narrow panel: 2 and 5 keep a label."""
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(4, 3))
    ax.loglog([low, high], [1.0, 2.0])
    plots.unicode_log_labels(fig)
    fig.canvas.draw()
    labels = {t.get_text() for t in ax.xaxis.get_minorticklabels() if t.get_text() and low <= t.get_position()[0] <= high}
    plt.close(fig)
    assert labels == kept
