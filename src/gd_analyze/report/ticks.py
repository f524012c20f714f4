"""Ticks of the report figures: matplotlib's locators and formatters, set once per figure.

:func:`set_ticks` places a few round ticks (:class:`matplotlib.ticker.MaxNLocator`) within
given limits; :func:`label_axes` writes the ticks of a figure's axes in one form with
:class:`matplotlib.ticker.ScalarFormatter`, each axis in units of a power of ten stated once,
in its axis label (no offset text: "[10⁻³ kg m²]"); :func:`decade_formatter` writes the
decades of a logarithmic axis as 10⁶; :func:`joint_ticks` labels a panel's joints across
"joint i", or "i" under an axis label "joint" where those would touch.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from typing import TYPE_CHECKING

import numpy as np

from .numbers import decade_label, power_of_ten

if TYPE_CHECKING:
    import numpy.typing as npt
    from matplotlib.axis import Axis
    from matplotlib.ticker import Formatter, ScalarFormatter

__all__ = ["nice_ticks", "set_ticks", "label_axes", "tick_label_width", "with_power",
           "scaled_formatter", "decade_formatter", "joint_ticks", "time_origin"]

#: :func:`label_axes` writes ticks as they are while the largest |tick| is in this range,
#: in units of a power of ten outside (no 0.0015, no 20000 on a small panel).
_PLAIN = (1e-2, 1e4)


def nice_ticks(lo: float, hi: float, nbins: int = 3) -> npt.NDArray[np.float64]:
    """At most ``nbins + 1`` ticks at round values (1, 2, 2.5, 5 times a power of 10) in [lo, hi].

    Parameters
    ----------
    lo, hi : float
        The limits the ticks must lie within (any order).
    nbins : int, optional
        The most intervals between ticks.

    Returns
    -------
    ndarray, shape (K,)
        Tick positions within the limits, at least one (the midpoint of a degenerate range):
        the most that :class:`matplotlib.ticker.MaxNLocator` places within them.

    Examples
    --------
    >>> nice_ticks(0.0, 1.0, 4).tolist()
    [0.0, 0.25, 0.5, 0.75, 1.0]
    """
    from matplotlib.ticker import MaxNLocator

    lo, hi = float(min(lo, hi)), float(max(lo, hi))
    span = hi - lo
    if not (np.isfinite(span) and span > 0):
        return np.array([lo])
    nbins, tol = max(1, int(nbins)), 1e-9 * span
    best = np.array([0.5 * (lo + hi)])
    # the locator covers [lo, hi]: more bins until the ticks within would be too many
    for k in range(nbins, 4 * nbins + 4):
        ticks = np.asarray(MaxNLocator(nbins=k, steps=[1, 2, 2.5, 5, 10]).tick_values(lo, hi))
        ticks = ticks[(ticks >= lo - tol) & (ticks <= hi + tol)]
        if len(ticks) > nbins + 1:
            break
        if len(ticks) >= len(best):
            best = ticks
    best[np.abs(best) < 1e-12 * (float(np.ptp(best)) / max(len(best) - 1, 1) or span)] = 0.0
    return best


def scaled_formatter(k: int | None = 0) -> ScalarFormatter:
    """Tick labels in units of 10^k: 0.0025 reads ``2.5`` for k = -3.

    Parameters
    ----------
    k : int or None, optional
        The power of ten, stated elsewhere (the axis label, :func:`with_power`): no offset
        text; 0 writes the ticks as they are. None: matplotlib's, for ticks outside
        [0.01, 10⁴) in magnitude, stated at the axis' end ("1e−5", offset text).

    Returns
    -------
    matplotlib.ticker.ScalarFormatter
        No offset; fixed notation with the fewest common decimals that give back round
        ticks, a minus sign U+2212 (``axes.unicode_minus``).
    """
    from matplotlib.ticker import ScalarFormatter

    fmt = ScalarFormatter(useOffset=False, useMathText=False)      # no mathtext to parse
    if k is None:
        fmt.set_powerlimits((-3, 4))        # scaled outside [0.01, 10⁴), as _PLAIN
    elif k:
        fmt.set_powerlimits((k, k))         # equal limits: this power whatever the ticks
    else:
        fmt.set_scientific(False)
    return fmt


def set_ticks(axis: Axis, lo: float, hi: float, nbins: int = 3,
              labels: bool = True) -> npt.NDArray[np.float64]:
    """Fixed round ticks on one axis of a plot.

    Parameters
    ----------
    axis : matplotlib.axis.Axis
        ``ax.xaxis`` or ``ax.yaxis``.
    lo, hi : float
        The limits the ticks must lie within.
    nbins : int, optional
        The most intervals between ticks (:func:`nice_ticks`).
    labels : bool, optional
        Write the ticks (:func:`scaled_formatter` with matplotlib's power of ten); else no
        labels, until :func:`label_axes` writes them.

    Returns
    -------
    ndarray
        The tick positions.
    """
    from matplotlib.ticker import FixedLocator, NullFormatter

    ticks = nice_ticks(lo, hi, nbins)
    axis.set_major_locator(FixedLocator(ticks.tolist()))
    axis.set_major_formatter(scaled_formatter(None) if labels else NullFormatter())
    return ticks


def label_axes(axes: Iterable[Axis]) -> None:
    """Write the tick labels of several axes of one figure in one form.

    Parameters
    ----------
    axes : iterable of matplotlib.axis.Axis
        Axes whose ticks are placed (:func:`set_ticks`) and whose axis label, if any, is
        written; each gets a :func:`scaled_formatter` and, if scaled, its power in its label.

    Notes
    -----
    The rule, one form for the whole figure:

    - *plain*, if every axis' largest |tick| is in [0.01, 10⁴): every axis reads, e.g.,
      0.00, 0.25, 0.50 or 0, 20, 40.
    - *in units of a power of ten* otherwise: every axis whose largest |tick| is below 1 or at
      least 10⁴ is written in units of its own 10^k, 1 <= max|tick| / 10^k < 10 (its ticks
      read 0.0, 1.5, 3.0 and its axis label says the power); an axis whose largest |tick| is
      in [1, 10⁴) keeps its ticks as they are. So no figure shows "0.01" on one panel beside
      "5 [×10⁻³]" on the next.
    """
    placed = []
    for a in axes:
        ticks = np.abs(np.asarray(a.get_ticklocs(), float))
        ticks = ticks[np.isfinite(ticks)]
        placed.append((a, float(ticks.max()) if ticks.size else 0.0))
    odd = [big > 0 and not _PLAIN[0] <= big < _PLAIN[1] for _, big in placed]
    for (a, big), scale in zip(placed, odd):
        k = math.floor(math.log10(big)) if scale or (any(odd) and 0 < big < 1) else 0
        a.set_major_formatter(scaled_formatter(k))
        a.get_offset_text().set_visible(False)          # the label states the power
        if k:
            a.set_label_text(with_power(a.label.get_text(), k))


def with_power(label: str, k: int) -> str:
    """An axis label in units of 10^k: ``"[kg m²]"`` reads ``"[10⁻⁵ kg m²]"``.

    Parameters
    ----------
    label : str
        The axis label: with its units in brackets, or without units, or empty.
    k : int
        The power of ten the ticks are written in.

    Returns
    -------
    str
        The power written into the last brackets, or appended as ``"[×10ᵏ]"`` (``"×10ᵏ"``
        alone for an empty label).

    Examples
    --------
    >>> with_power("[kg m\u00b2]", -5), with_power("", 3), with_power("t [s]", 0)
    ('[10⁻⁵ kg m²]', '×10³', 't [s]')
    """
    if not k:
        return label
    power = power_of_ten(k)
    at = label.rfind("[")
    if at >= 0 and label.endswith("]"):
        return f"{label[:at + 1]}{power} {label[at + 1:]}"
    return f"{label} [\u00d7{power}]" if label else f"\u00d7{power}"


def time_origin(t: npt.ArrayLike, name: str = "t") -> tuple[float, str]:
    """The time a figure's time axis counts from, and that axis' label.

    A time axis whose first stamp lies farther from 0 than 10⁴ times its span (Unix time
    stamps, as a ROS log writes them: 1.7e9 s for a few seconds of motion) would need ticks
    of ten digits, which run into each other: it counts from its first stamp instead, and
    its label says from which.

    Parameters
    ----------
    t : array_like, shape (N,)
        The time stamps [s], in order (the first and the last are read).
    name : str, optional
        The axis label's name of time.

    Returns
    -------
    origin : float
        0, or the first stamp [s], or the whole second before it where that is as near:
        subtract it from the times drawn.
    label : str
        ``"t [s]"``, or ``"t − 1700000000 [s]"`` (the origin written exactly).

    Examples
    --------
    >>> time_origin([0.0, 4.2])
    (0.0, 't [s]')
    >>> time_origin([1.7e9 + 0.77, 1.7e9 + 4.2])
    (1700000000.0, 't − 1700000000 [s]')
    """
    t = np.asarray(t, dtype=float).reshape(-1)
    if t.size == 0 or not np.isfinite(t[[0, -1]]).all():
        return 0.0, f"{name} [s]"
    t0, span = float(t[0]), abs(float(t[-1]) - float(t[0]))
    if span == 0.0 or abs(t0) <= 1e4 * span:
        return 0.0, f"{name} [s]"
    if t0 - math.floor(t0) <= 1e4 * span:      # from a whole second where that is near
        t0 = float(math.floor(t0))
    text = np.format_float_positional(abs(t0), trim="-")
    sign = "\u2212" if t0 > 0 else "+"
    return t0, f"{name} {sign} {text} [s]"


def decade_formatter() -> Formatter:
    """Decades of a logarithmic axis as 10⁶ in the tick labels' own type
    (:func:`gd_analyze.report.numbers.decade_label`; mathtext's exponents print at 70 %)."""
    from matplotlib.ticker import FuncFormatter

    return FuncFormatter(lambda x, pos=None: decade_label(x))


def joint_ticks(axis: Axis, n: int, slot: float, least: float, short: bool = False) -> bool:
    """Label positions 1 to n of an axis as the arm's joints: "joint i" where the widest such
    label, at the size it prints at, fits its slot with a gap, else "i" with the axis label
    "joint" (a panel of 12 or 15 joints across a page: "joint 9joint 10oint 11").

    Parameters
    ----------
    axis : matplotlib.axis.Axis
        The axis across which the joints sit, at 1, ..., n.
    n : int
    slot : float
        The room of one joint along the axis [in].
    least : float
        The least size [pt] a text of the figure is drawn at, so that it prints at the
        reports' minimum (tick labels smaller than it are raised to it when drawn).
    short : bool, optional
        "i" whatever the room (a column-wide figure).

    Returns
    -------
    bool
        The short labels were set (the callers set their other per-joint texts the same way).
    """
    from matplotlib.textpath import TextPath

    labels = [f"joint {i}" for i in range(1, n + 1)]
    axis.set_ticks(range(1, n + 1), labels)
    if not short and n:
        size = max(float(axis.get_major_ticks()[0].label1.get_fontsize()), least)    # [pt]
        widest = max(TextPath((0, 0), t, size=size).get_extents().width for t in labels) / 72
        short = widest > 0.85 * slot
    if short:
        axis.set_ticks(range(1, n + 1), [str(i) for i in range(1, n + 1)])
        axis.set_label_text("joint")
        axis.labelpad = 1.0
    return short


def tick_label_width(axis: Axis) -> float:
    """The width of the widest tick label an axis will print.

    Parameters
    ----------
    axis : matplotlib.axis.Axis
        An axis whose ticks and formatter are set (:func:`set_ticks`, :func:`label_axes`).

    Returns
    -------
    float
        [in], each label measured on its glyphs' outlines
        (:class:`matplotlib.textpath.TextPath`) at the axis' own tick-label size, so that a
        fixed layout can leave room for the labels without drawing the figure.
    """
    from matplotlib.textpath import TextPath

    lo, hi = sorted(axis.get_view_interval())
    locs = [x for x in axis.get_ticklocs() if lo <= x <= hi]
    if not locs:
        return 0.0
    size = float(axis.get_major_ticks()[0].label1.get_fontsize())         # [pt]
    texts = axis.get_major_formatter().format_ticks(locs)
    return max((TextPath((0, 0), t, size=size).get_extents().width / 72.0
                for t in texts if t), default=0.0)
