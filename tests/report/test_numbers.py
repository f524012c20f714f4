"""Tick labels never misstate a tick (gd_analyze.report.numbers).

Oracle: the ticks' own positions. Every label, read as a number and multiplied by the power of
ten its axis label states, gives back its tick; labels of one axis are distinct; negative
ticks carry the minus sign U+2212.
"""

import re

import numpy as np
import pytest
from figure_checks import tick_texts
from hypothesis import given, settings
from hypothesis import strategies as st

from gd_analyze.report.numbers import (
    decade_formatter,
    label_axes,
    nice_ticks,
    scaled_formatter,
    set_ticks,
)

MINUS = "\u2212"
_DIGITS = "\u2070\u00b9\u00b2\u00b3\u2074\u2075\u2076\u2077\u2078\u2079"

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


def _power(label):
    """k of a "10ᵏ" in an axis label, 0 if none."""
    m = re.search(f"10(\u207b?)([{_DIGITS}]+)", label)
    if not m:
        return 0
    k = int("".join(str(_DIGITS.index(c)) for c in m.group(2)))
    return -k if m.group(1) else k


def _axes(*tick_sets, label="[kg m\u00b2]"):
    """One figure, a panel per tick set, its y ticks fixed there and labelled by label_axes;
    the (value, text) pairs and the power each axis label states."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=(2.0 * len(tick_sets), 2.0))
    axes = fig.subplots(1, len(tick_sets), squeeze=False)[0]
    for ax, ticks in zip(axes, tick_sets):
        t = np.asarray(ticks, float)
        pad = 0.1 * (np.ptp(t) or max(abs(t).max(), 1.0))
        ax.set_ylim(t.min() - pad, t.max() + pad)
        ax.yaxis.set_ticks(t)
        ax.set_ylabel(label)
    label_axes([ax.yaxis for ax in axes])
    return [([(v, lab.get_text()) for v, lab in tick_texts(ax, "y")], _power(ax.get_ylabel()))
            for ax in axes]


def read(label, k=0):
    return float(label.replace(MINUS, "-")) * 10.0 ** k


def check(values, labels, k):
    """Each label gives back its tick to 1e-9 of the tick spacing (or of the largest tick;
    not below the float rounding of k * step), labels are distinct, negative ones start with
    U+2212, zero never reads as negative."""
    values = np.asarray(values, float)
    u = np.unique(values)
    step = float(np.min(np.diff(u))) if u.size > 1 else max(abs(values).max(), 1.0)
    big = float(np.abs(values).max())
    tol = max(1e-9 * min(step, big), 4 * np.spacing(big)) if big else 0.0
    assert len(labels) == len(values)
    for v, lab in zip(values, labels):
        assert abs(read(lab, k) - v) <= tol, (values.tolist(), labels, k)
        assert "-" not in lab and "e" not in lab
        assert lab.startswith(MINUS) == (v < 0), (v, lab)
    assert len(set(labels)) == len(set(values.tolist()))


def test_at_least_twenty_sets():
    assert len(TICK_SETS) >= 20


@pytest.mark.parametrize("values", TICK_SETS, ids=range(len(TICK_SETS)))
def test_labels_give_back_the_ticks(values):
    [(pairs, k)] = _axes(values)
    check([v for v, _ in pairs], [s for _, s in pairs], k)


def test_the_two_cases_of_the_issue():
    [(quarter, k1), (tiny, k2)] = _axes([0, -0.25, -0.5, -0.75], [0, 1.5e-5, 3e-5])
    assert sorted(read(s, k1) for _, s in quarter) == pytest.approx([-0.75, -0.5, -0.25, 0])
    assert [read(s, k2) for _, s in tiny] == pytest.approx([0, 1.5e-5, 3e-5])
    assert (k1, k2) == (-1, -5)               # the figure is scaled: every panel below 1 too


def test_power_of_ten_stated_once_in_the_axis_label():
    """An axis outside [0.01, 10⁴) is written in units of its 10ᵏ, the power in its units
    ("[10⁻⁵ kg m²]"), no offset text on the axis; an axis in [1, 10⁴) beside it keeps its
    ticks as they are; a figure with every axis in [0.01, 10⁴) is written plain."""
    from matplotlib.figure import Figure

    fig = Figure()
    a, b = fig.subplots(1, 2)
    a.set_ylim(0, 4e-5)
    b.set_ylim(0, 40)
    set_ticks(a.yaxis, 0, 4e-5, 4, labels=False)
    set_ticks(b.yaxis, 0, 40, 4, labels=False)
    a.set_ylabel("[kg m\u00b2]")
    b.set_ylabel("[N m]")
    label_axes([a.yaxis, b.yaxis])
    assert a.get_ylabel() == "[10\u207b\u2075 kg m\u00b2]" and b.get_ylabel() == "[N m]"
    assert not a.yaxis.get_offset_text().get_visible()
    assert [s.get_text() for _, s in tick_texts(a)] == ["0", "1", "2", "3", "4"]
    assert [s.get_text() for _, s in tick_texts(b)] == ["0", "10", "20", "30", "40"]
    [(plain, k1), (quarter, k2)] = _axes([0, 20, 40], [0, 0.25, 0.5])
    assert (k1, k2) == (0, 0) and [s for _, s in quarter] == ["0.00", "0.25", "0.50"]


def test_one_form_per_figure():
    """When one panel is scaled, every panel whose ticks are all below 1 is too: no "0.01"
    beside "5" in units of 10⁻³ (PUMA Fig. 4)."""
    for (pairs, k), ticks in zip(_axes([0, 0.004, 0.008], [0, 0.01, 0.02], [0, 2, 4]),
                                 ([0, 0.004, 0.008], [0, 0.01, 0.02], [0, 2, 4])):
        big = max(abs(t) for t in ticks)
        assert (k != 0) == (big < 1), (ticks, k)
        check([v for v, _ in pairs], [s for _, s in pairs], k)


def test_matplotlib_locator_sets():
    """Ticks matplotlib's own locator picks on ranges of every magnitude."""
    from matplotlib.ticker import MaxNLocator

    rng = np.random.default_rng(12)
    for _ in range(100):
        scale = 10.0 ** rng.uniform(-12, 9)
        lo, hi = sorted(rng.uniform(-1, 1, 2) * scale)
        ticks = MaxNLocator(nbins=4).tick_values(lo, hi)
        [(pairs, k)] = _axes(ticks)
        check([v for v, _ in pairs], [s for _, s in pairs], k)


@pytest.fixture(scope="module")
def one_axes():
    from matplotlib.figure import Figure

    return Figure().subplots()


@settings(max_examples=200, deadline=None)
@given(st.floats(-1e8, 1e8, allow_nan=False), st.floats(1e-10, 1e8), st.integers(1, 6))
def test_nice_ticks_are_labelled_exactly(one_axes, lo, span, nbins):
    """Within the limits, at most nbins + 1; written by set_ticks' labels with the power of
    ten matplotlib states at the axis' end, each gives back its tick."""
    ticks = nice_ticks(lo, lo + span, nbins)
    assert 1 <= len(ticks) <= nbins + 1
    slack = 1e-9 * span + 1e-14 * (abs(lo) + span)         # rounding of k * step
    assert ticks.min() >= lo - slack and ticks.max() <= lo + span + slack
    if not lo + span > lo:                  # the span lost in lo's rounding: no axis
        return
    ax = one_axes
    ax.set_ylim(lo, lo + span)
    set_ticks(ax.yaxis, lo, lo + span, nbins)
    pairs = tick_texts(ax, "y")
    shown = np.array([v for v, _ in pairs])
    assert len(shown) and set(shown.tolist()) <= set(ticks.tolist())
    offset = ax.yaxis.get_major_formatter().get_offset()        # "1e−10": the power, once
    k = int(offset.replace(MINUS, "-").split("e")[1]) if offset else 0
    if len(shown) > 1:
        check(shown, [s.get_text() for _, s in pairs], k)


def test_scaled_formatter_without_axis_limits():
    fmt = scaled_formatter(3)
    fmt.set_locs([0.0, 2500.0, 5000.0])
    assert fmt.format_ticks([0.0, 2500.0, 5000.0]) == ["0.0", "2.5", "5.0"]


def test_decades_in_superscripts():
    fmt = decade_formatter()
    assert [fmt(v) for v in (1e-6, 1.0, 1e3, 300.0)] == ["10\u207b\u2076", "10\u2070",
                                                        "10\u00b3", ""]


@settings(max_examples=200, deadline=None)
@given(st.floats(-2e9, 2e9), st.floats(1e-3, 1e5))
def test_a_time_axis_counts_from_its_first_stamp_only_where_ticks_would_be_long(t0, span):
    """The origin a time axis counts from (time_origin): 0 unless the first stamp lies beyond
    10^4 spans from 0; else a time at most 10^4 spans before the first stamp, which the axis
    label gives back exactly."""
    from gd_analyze.report.numbers import time_origin

    t = np.array([t0, t0 + span])
    origin, label = time_origin(t)
    if abs(t[0]) <= 1e4 * (t[1] - t[0]):
        assert (origin, label) == (0.0, "t [s]")
        return
    assert 0.0 <= t[0] - origin <= 1e4 * (t[1] - t[0])
    m = re.fullmatch(r"t ([\u2212+]) ([0-9.]+) \[s\]", label)
    assert m and float(m[2]) * (1 if m[1] == MINUS else -1) == origin, label


def test_the_trajectory_figure_on_unix_time_stamps_has_short_time_ticks():
    """Fig. 1 of the main report on a trajectory stamped in Unix time: ticks of ten digits
    ran into each other; the axis now counts from a whole second and says so."""
    from gd_analyze.report.main_figures import PlotData, fig_joints

    M = 31
    x = 1.7e9 + 0.25 + np.linspace(0.0, 4.2, M)
    q = np.sin(np.outer(x - x[0], [1.0, 2.0]))
    fig = fig_joints(PlotData(x=x, enveloped=False, N=M,
                              series={"q": q, "qd": q, "qdd": q}))
    for ax in fig.axes:
        assert ax.get_xlabel() == "t \u2212 1700000000 [s]"
        texts = [label.get_text() for _, label in tick_texts(ax, "x")]
        assert texts and all(len(t) <= 4 for t in texts), texts
        lo, hi = ax.get_xlim()
        assert -0.2 < lo < 0.25 < 4.45 < hi < 4.7
