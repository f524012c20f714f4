"""Tick labels never misstate a tick (gd_analyze.reports.ticks)."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from gd_analyze.reports.ticks import MINUS, nice_ticks, tick_labels

# The two sets of the issue (D12 and D66 of the shipped PUMA 560 report), then sets a panel of
# the report meets: negative, tiny, huge, integer, mixed sign, float noise from arange.
TICK_SETS = [
    [0, -0.25, -0.5, -0.75],
    [0, 1.5e-5, 3e-5],
    [0, 0.5, 1.0, 1.5],
    [-1, 0, 1],
    [0.1, 0.2, 0.3],
    list(np.arange(0, 1.0, 0.1)),                   # 0.30000000000000004 and friends
    [0, 2.5, 5, 7.5, 10],
    [0, 0.125, 0.25, 0.375],
    [-2e-5, -1e-5, 0, 1e-5],
    [1e-9, 2e-9, 3e-9],
    [1.25e-7, 2.5e-7, 3.75e-7],
    [0, 20000, 40000, 60000],
    [0, 250000, 500000, 750000],
    [1.2e6, 1.4e6, 1.6e6],
    [0.001, 0.0015, 0.002],
    [99.5, 99.75, 100.0],
    [-0.004, -0.002, 0, 0.002],
    [3.14, 3.15, 3.16],
    [0, 45, 90, 135, 180],
    [-180, -90, 0, 90],
    [0.6, 0.65, 0.7, 0.75],
    [12.5, 25, 37.5],
    [1e-3 * k for k in range(5)],
    [0.0],
    [7.0],
]


def read(label):
    return float(label.replace(MINUS, "-"))


def check(values, labels):
    values = np.asarray(values, float)
    u = np.unique(values)
    step = float(np.min(np.diff(u))) if u.size > 1 else max(abs(values).max(), 1.0)
    big = float(np.abs(values).max())
    tol = 1e-9 * min(step, big) if big else 0.0
    assert len(labels) == len(values)
    for v, lab in zip(values, labels):
        assert abs(read(lab) - v) <= tol, (values.tolist(), labels)
        assert not lab.startswith("-") and lab != MINUS + "0"
        if v == 0:
            assert lab == "0"
    assert len(set(labels)) == len(set(values.tolist()))


def test_at_least_twenty_sets():
    assert len(TICK_SETS) >= 20


@pytest.mark.parametrize("values", TICK_SETS, ids=range(len(TICK_SETS)))
def test_labels_give_back_the_ticks(values):
    check(values, tick_labels(values))


def test_the_two_cases_of_the_issue():
    assert [read(s) for s in tick_labels([0, -0.25, -0.5, -0.75])] == [0, -0.25, -0.5, -0.75]
    assert [read(s) for s in tick_labels([0, 1.5e-5, 3e-5])] == [0, 1.5e-5, 3e-5]


@pytest.mark.parametrize("values", [v for v in TICK_SETS if len(v) > 1], ids=str)
def test_fewest_digits(values):
    """One digit fewer (same notation) would misstate a tick, unless none is needed."""
    labels = tick_labels(values)
    body = [s.split("e")[0] for s in labels if s != "0"]
    decimals = max((len(b.split(".")[1]) if "." in b else 0) for b in body)
    if decimals == 0:
        return
    sci = any("e" in s for s in labels)
    fewer = []
    for v in values:
        if sci:
            fewer.append(float(f"{v:.{decimals - 1}e}"))
        else:
            fewer.append(float(f"{v:.{decimals - 1}f}"))
    assert any(abs(a - b) > 0 for a, b in zip(fewer, np.asarray(values, float))
               if abs(a - b) > 1e-12 * max(1.0, abs(b)))


def test_matplotlib_locator_sets():
    """Ticks matplotlib's own locator picks on ranges of every magnitude."""
    from matplotlib.ticker import MaxNLocator

    rng = np.random.default_rng(12)
    for _ in range(200):
        scale = 10.0 ** rng.uniform(-12, 9)
        lo, hi = sorted(rng.uniform(-1, 1, 2) * scale)
        ticks = MaxNLocator(nbins=4).tick_values(lo, hi)
        check(ticks, tick_labels(ticks))


@settings(max_examples=200, deadline=None)
@given(st.floats(-1e8, 1e8, allow_nan=False), st.floats(1e-10, 1e8), st.integers(1, 6))
def test_nice_ticks_are_labelled_exactly(lo, span, nbins):
    ticks = nice_ticks(lo, lo + span, nbins)
    assert 1 <= len(ticks) <= nbins + 1
    slack = 1e-9 * span + 1e-14 * (abs(lo) + span)         # rounding of k * step
    assert ticks.min() >= lo - slack and ticks.max() <= lo + span + slack
    check(ticks, tick_labels(ticks))


def test_non_finite_and_empty():
    assert tick_labels([]) == []
    assert tick_labels([np.nan, 1.0]) == ["n/a", "1"]


def _ticked(scale):
    """Two Axes with matplotlib's own ticks, tick labels, axis labels and per-tick grid (one
    of them log-scaled, with minor ticks), as the report's figures have them."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=(3.0, 2.4), dpi=100)
    for k, box in enumerate(((0.22, 0.6, 0.7, 0.33), (0.22, 0.14, 0.7, 0.33))):
        ax = fig.add_axes(box)
        x = np.linspace(0.0, 2.0, 50)
        ax.plot(x, 1.0 + x ** 2, linewidth=0.8)
        if k == 1:
            ax.set_yscale(scale)
            ax.set_xlabel("t [s]", labelpad=1.0)
        ax.set_ylabel("D$_{11}$ [kg m²]" if k else "q [deg]")
        ax.grid(True, color="0.7", linewidth=0.5)
    return fig


@pytest.mark.parametrize("scale", ["linear", "log"])
def test_ticks_once_draws_the_same_picture_as_matplotlibs_ticks(scale):
    """Oracle: matplotlib's own ticks, labels, axis labels and grid, one Tick per tick,
    rendered by Agg; the flattened figure must give the same pixels."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.collections import LineCollection

    from gd_analyze.reports.ticks import tick_texts, ticks_once

    def pixels(fig):
        canvas = FigureCanvasAgg(fig)
        canvas.draw()
        return np.asarray(canvas.buffer_rgba()).copy()

    reference = pixels(_ticked(scale))
    fig = _ticked(scale)
    FigureCanvasAgg(fig).draw()                 # ticks placed as when drawn
    ticks_once(fig)
    assert all(not len(ax.xaxis.get_majorticklocs()) and not len(ax.yaxis.get_majorticklocs())
               for ax in fig.axes)
    # per Axes: the x and y grids, and the frame drawn in place of the four spines
    assert sum(isinstance(c, LineCollection) for ax in fig.axes for c in ax.collections) == 6
    assert not any(s.get_visible() for ax in fig.axes for s in ax.spines.values())
    assert all(tick_texts(ax, "x") and tick_texts(ax, "y") for ax in fig.axes)
    assert np.array_equal(pixels(fig), reference)
