"""Tick labels that never misstate a value, and cheap axes for small multiples.

:func:`tick_labels` writes each tick with the fewest digits that still give back the tick's
value: ticks at 0, -0.25, -0.5, -0.75 read "0, −0.25, −0.5, −0.75" (not "−0.2, −0.8"), ticks at
0, 1.5e-5, 3e-5 read "0, 1.5e−5, 3e−5". :func:`nice_ticks` places at most a few ticks at round
values, once, so that matplotlib does not rebuild locators at every draw; :func:`set_ticks`
puts both on an axis.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Iterable
from typing import TYPE_CHECKING, Any

import numpy as np

from .numbers import decade_label, power_of_ten

if TYPE_CHECKING:
    import numpy.typing as npt
    from matplotlib.axes import Axes
    from matplotlib.axis import Axis
    from matplotlib.figure import Figure
    from matplotlib.text import Text
    from matplotlib.ticker import Formatter

__all__ = ["tick_labels", "ticks_once", "tick_texts", "nice_ticks", "set_ticks",
           "formatter", "MINUS", "notation", "label_axes", "with_power"]

#: The minus sign of the labels (U+2212, as wide as the plus sign).
MINUS = "\u2212"
#: A label is exact if it gives back its tick to this fraction of the largest |tick| (or of the
#: tick spacing, if smaller): far below what a plot can show, far above float noise.
_REL = 1e-9
#: Fixed notation between these magnitudes of the largest |tick|, scientific outside.
_FIXED = (1e-3, 1e5)
#: :func:`label_axes` writes ticks as they are between these magnitudes of the largest |tick|,
#: in units of a power of ten outside (no 0.0015, no 20000 on a small panel).
_PLAIN = (1e-2, 1e4)


def _exact(texts, values, tol):
    return all(abs(float(t) - v) <= tol for t, v in zip(texts, values))


def _fewest(values, tol, fmt):
    for digits in range(0, 16):
        texts = [fmt(x, digits) for x in values]
        if _exact(texts, values, tol):
            return texts
    return None


def _width(texts):
    return max(len(t) for t in texts)


def _sci(x, digits):
    mant, exp = f"{x:.{digits}e}".split("e")
    return f"{mant}e{int(exp)}"


def tick_labels(values: npt.ArrayLike, style: str | None = None) -> list[str]:
    """Labels of axis ticks, each giving back its tick's value.

    Parameters
    ----------
    values : array_like, shape (K,)
        Tick positions, any order; NaN or inf are written as "n/a".
    style : {None, "fixed", "sci"}, optional
        Force one notation (for one tick format across a figure, :func:`label_axes`); by
        default the rule below picks it.

    Returns
    -------
    list of str
        One label per tick: ``"0"`` for zero (never "−0"). All labels of a set get the same
        number of decimals (or mantissa digits): the fewest with which every label, read back,
        equals its tick within 1e-9 of the tick spacing. Fixed notation if the largest |tick|
        is in [1e-3, 1e5) and its widest label is at most one character wider than in
        ``1.5e−5`` style, else that style (narrow labels for narrow panels). A minus sign is
        U+2212.

    Examples
    --------
    >>> tick_labels([0, -0.25, -0.5, -0.75])
    ['0', '−0.25', '−0.50', '−0.75']
    >>> tick_labels([0, 1.5e-5, 3e-5])
    ['0', '1.5e−5', '3.0e−5']
    >>> tick_labels([0, 200, 400])
    ['0', '200', '400']
    >>> tick_labels([-0.001, -0.0005, 0])
    ['−1e−3', '−5e−4', '0']
    """
    v = np.asarray(values, dtype=float).ravel()
    if v.size == 0:
        return []
    finite = v[np.isfinite(v)]
    big = float(np.max(np.abs(finite))) if finite.size else 0.0
    if big == 0.0:
        return ["0" if np.isfinite(x) else "n/a" for x in v]
    u = np.unique(finite)
    step = float(np.min(np.diff(u))) if u.size > 1 else big
    tol = _REL * min(big, step)
    fixed = _fewest(finite, tol, lambda x, d: f"{x:.{d}f}")
    sci = _fewest(finite, tol, _sci)
    if fixed is None and sci is None:       # not representable in 15 digits: full precision
        texts = [repr(float(x)) for x in finite]
    elif style == "sci" and sci is not None:
        texts = sci
    elif style == "fixed" and fixed is not None:
        texts = fixed
    elif sci is None or (fixed is not None and _FIXED[0] <= big < _FIXED[1]
                         and _width(fixed) <= _width(sci) + 1):
        texts = fixed
    else:
        texts = sci
    it = iter(texts)
    out = []
    for x in v:
        if not np.isfinite(x):
            out.append("n/a")
            continue
        t = next(it)
        out.append("0" if x == 0 or float(t) == 0 else t.replace("-", MINUS))
    return out


def notation(values: npt.ArrayLike) -> str:
    """The notation :func:`tick_labels` picks for a set of ticks: ``"fixed"`` or ``"sci"``.

    Parameters
    ----------
    values : array_like, shape (K,)
        Tick positions.

    Returns
    -------
    str
        ``"sci"`` if any label is written like ``1.5e−5``, else ``"fixed"``.

    Examples
    --------
    >>> notation([0, 0.5, 1.0]), notation([0, 2e-5, 4e-5])
    ('fixed', 'sci')
    """
    return "sci" if any("e" in t for t in tick_labels(values)) else "fixed"


def label_axes(axes: Iterable[Axis]) -> str:
    """Write the tick labels of several axes of one figure in one notation and one form.

    Parameters
    ----------
    axes : iterable of matplotlib.axis.Axis
        Axes whose ticks are placed (:func:`set_ticks` with ``labels=False`` or ``True``) and
        whose axis label, if any, is written.

    Returns
    -------
    str
        ``"fixed"``: no label of the figure is written like ``1.5e−5`` (a figure never mixes
        2e−5 and 0.0015).

    Notes
    -----
    The rule, one form for the whole figure ("one tick format per figure"):

    - *plain*, if every axis can be written as its ticks are: largest |tick| in [0.01, 10⁴)
      and :func:`tick_labels` writes them in fixed notation. Every axis then reads, e.g.,
      0, 0.25, 0.5 or 0, 20, 40.
    - *in units of a power of ten* otherwise: every axis whose largest |tick| is below 1 or at
      least 10⁴ (or whose ticks :func:`tick_labels` writes like ``1.5e−5``) is labelled in
      units of its own 10^k, 1 <= max|tick| / 10^k < 10: its ticks read 0, 1.5, 3 and its axis
      label says the power (:func:`with_power`). An axis whose largest |tick| is in [1, 10⁴)
      keeps its ticks as they are (0, 2.5, 5 or 0, 20, 40: no leading "0.", as the scaled
      ones). So no figure shows "0.01" on one panel beside "5 [×10⁻³]" on the next.

    Every label, times its axis' 10^k, gives back its tick (:func:`tick_labels`).
    """
    placed = []
    for a in axes:
        ticks = np.asarray(a.get_ticklocs(), float)
        if not len(ticks):
            continue
        finite = np.abs(ticks[np.isfinite(ticks)])
        big = float(finite.max()) if finite.size else 0.0
        odd = big > 0 and (not _PLAIN[0] <= big < _PLAIN[1] or notation(ticks) == "sci")
        placed.append((a, ticks, big, odd))
    scaled = any(odd for *_, odd in placed)
    for a, ticks, big, odd in placed:
        k = 0
        if odd or (scaled and 0 < big < 1.0):
            k = int(math.floor(math.log10(big)))
        _place(a, ticks, tick_labels(ticks / 10.0 ** k, "fixed"))
        if k:
            a.set_label_text(with_power(a.label.get_text(), k))
    return "fixed"


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


def nice_ticks(lo: float, hi: float, nbins: int = 3) -> npt.NDArray[np.float64]:
    """At most ``nbins + 1`` ticks at round values (1, 2, 2.5, 5 times a power of 10) in [lo, hi].

    Parameters
    ----------
    lo, hi : float
        The axis limits (any order).
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
    # the ticks MaxNLocator places within [lo, hi]: more bins until they would be too many
    for k in range(nbins, 4 * nbins + 4):
        ticks = np.asarray(MaxNLocator(nbins=k, steps=[1, 2, 2.5, 5, 10]).tick_values(lo, hi))
        ticks = ticks[(ticks >= lo - tol) & (ticks <= hi + tol)]
        if len(ticks) > nbins + 1:
            break
        if len(ticks) >= len(best):
            best = ticks
    best[np.abs(best) < 1e-12 * (float(np.ptp(best)) / max(len(best) - 1, 1) or span)] = 0.0
    return best


def formatter() -> Formatter:
    """A :class:`matplotlib.ticker.Formatter` that writes :func:`tick_labels`.

    Returns
    -------
    matplotlib.ticker.Formatter
        No offset text: each label carries its full value.
    """
    from matplotlib.ticker import Formatter

    class _Formatter(Formatter):
        def __call__(self, x, pos=None):
            return tick_labels([x])[0]

        def format_ticks(self, values):
            return tick_labels(values)

    return _Formatter()


def decade_formatter() -> Formatter:
    """A :class:`matplotlib.ticker.Formatter` writing :func:`decade_label` (no mathtext)."""
    from matplotlib.ticker import FuncFormatter

    return FuncFormatter(lambda x, pos=None: decade_label(x))


def set_ticks(axis: Axis, lo: float, hi: float, nbins: int = 3,
              labels: bool = True) -> npt.NDArray[np.float64]:
    """Fixed ticks and labels on one axis of a plot.

    Parameters
    ----------
    axis : matplotlib.axis.Axis
        ``ax.xaxis`` or ``ax.yaxis``.
    lo, hi : float
        The axis limits the ticks must lie within.
    nbins : int, optional
        The most intervals between ticks (:func:`nice_ticks`).
    labels : bool, optional
        Write the labels (else ticks without labels).

    Returns
    -------
    ndarray
        The tick positions.
    """
    ticks = nice_ticks(lo, hi, nbins)
    _place(axis, ticks, tick_labels(ticks) if labels else [""] * len(ticks))
    return ticks


def _place(axis, ticks, labels):
    """Fixed ticks and labels by the axis' locator and formatter (its Tick objects are made
    only when it is drawn)."""
    from matplotlib.ticker import FixedFormatter, FixedLocator

    axis.set_major_locator(FixedLocator(ticks))
    axis.set_major_formatter(FixedFormatter(labels))



def _shown_ticks(axis, which):
    """(positions, labels, first Tick) of the ticks an axis draws now: located within its
    view, as :meth:`matplotlib.axis.Axis.draw` picks them."""
    if which == "major":
        locs = np.asarray(axis.get_majorticklocs(), float)
        fmt, ticks = axis.get_major_formatter(), axis.get_major_ticks(1)
    else:
        locs = np.asarray(axis.get_minorticklocs(), float)
        fmt, ticks = axis.get_minor_formatter(), axis.get_minor_ticks(1)
    if not len(locs):
        return locs, [], None
    fmt.set_locs(locs)
    labels = fmt.format_ticks(locs)
    lo, hi = sorted(axis.get_view_interval())
    tol = 1e-10 * max(abs(hi - lo), abs(lo), abs(hi), 1e-300)
    keep = (locs >= lo - tol) & (locs <= hi + tol)
    return locs[keep], [t for t, k in zip(labels, keep) if k], ticks[0]


def _edge_box(ax, texts, side):
    """A callable (renderer -> Bbox): the drawn tick marks and labels of one side of an axis
    together with that side's spine, which matplotlib puts an axis label next to."""
    from matplotlib.transforms import Bbox

    def box(renderer):
        spine = ax.spines.get(side)
        edge = (spine if spine is not None else ax).get_window_extent(renderer)
        return Bbox.union([edge] + [t.get_window_extent(renderer) for t in texts
                                    if t.get_visible()])
    return box


def ticks_once(fig: Figure) -> Figure:
    """Draw each Axes' ticks as one marker line per side and plain texts: no Tick objects.

    Matplotlib builds a :class:`~matplotlib.axis.Tick` (two marks, two labels and a gridline)
    for every tick of every Axes and lays each out again at every draw; for figures of many
    small panels that is most of their drawing. This replaces the ticks placed now by the
    same picture from fewer, simpler artists.

    Parameters
    ----------
    fig : matplotlib.figure.Figure
        A figure whose ticks, labels and grid are placed (:func:`set_ticks`,
        :func:`label_axes`, ``ax.grid``).

    Returns
    -------
    matplotlib.figure.Figure
        ``fig``: per Axes and axis, the gridlines of the visible grid as one
        :class:`~matplotlib.collections.LineCollection` (colour, width, style, z-order,
        clipped to the Axes); per side, the tick marks as one
        :class:`~matplotlib.lines.Line2D` of the ticks' own markers (size, width, colour,
        direction); the labels as texts at
        the ticks' positions and padding (read back by
        :func:`tick_texts`), each axis label as an annotation kept outside those labels by
        its label pad, as matplotlib places it; the axes' locators then place no ticks.
    """
    from matplotlib.lines import Line2D
    from matplotlib.ticker import NullLocator
    from matplotlib.transforms import TransformedPatchPath

    for ax in fig.axes:
        # the Axes' clip path, made once: Axes.add_artist gives every artist without one a
        # transform of its own (these artists are not clipped: clip_on=False)
        clip = TransformedPatchPath(ax.patch)
        for name, axis in (("x", ax.xaxis), ("y", ax.yaxis)):
            texts: dict[int, list[Any]] = {1: [], 2: []}    # labels and marks of each side
            for which in ("major", "minor"):
                locs, labels, tick = _shown_ticks(axis, which)
                if tick is None or not len(locs):
                    continue
                if tick.gridline.get_visible():
                    _grid(ax, name, locs, tick.gridline, axis.get_zorder())
                pad = tick.get_pad() + tick.get_tick_padding()
                for side, mark, label in ((1, tick.tick1line, tick.label1),
                                          (2, tick.tick2line, tick.label2)):
                    at = np.full(len(locs), 0.0 if side == 1 else 1.0)
                    if mark.get_visible():
                        xy = (locs, at) if name == "x" else (at, locs)
                        texts[side].append(_marks(Line2D(
                            *xy, linestyle="none", marker=mark.get_marker(),
                            markersize=mark.get_markersize(),
                            markeredgewidth=mark.get_markeredgewidth(),
                            markeredgecolor=mark.get_markeredgecolor(), clip_on=False,
                            clip_path=clip, zorder=mark.get_zorder(),
                            transform=(ax.get_xaxis_transform() if name == "x"
                                       else ax.get_yaxis_transform()))))
                        ax.add_artist(texts[side][-1])
                    if not label.get_visible():
                        continue
                    get = {("x", 1): ax.get_xaxis_text1_transform,
                           ("x", 2): ax.get_xaxis_text2_transform,
                           ("y", 1): ax.get_yaxis_text1_transform,
                           ("y", 2): ax.get_yaxis_text2_transform}[(name, side)]
                    transform, va, ha = get(pad)
                    for v, s in zip(locs, labels):
                        if not s:
                            continue
                        xy = (v, 0.0 if side == 1 else 1.0) if name == "x" else (
                            0.0 if side == 1 else 1.0, v)
                        texts[side].append(ax.add_artist(_tick_label()(
                            *xy, s, transform=transform, va=va, ha=ha,
                            fontproperties=label.get_fontproperties(),
                            color=label.get_color(), rotation=label.get_rotation(),
                            clip_on=False, clip_path=clip, axis_name=name,
                            value=float(v))))
            axis.set_major_locator(NullLocator())
            axis.set_minor_locator(NullLocator())
            _move_label(ax, axis, name, texts)
        _frame(ax)
    return fig


def _frame(ax):
    """Four alike visible spines as one line collection: one artist where matplotlib draws
    four (the same segments, colour, width, caps and z-order)."""
    from matplotlib.collections import LineCollection
    from matplotlib.colors import same_color

    sides = ("left", "right", "bottom", "top")
    spines = [ax.spines.get(side) for side in sides]
    if any(s is None or not s.get_visible() for s in spines):
        return
    first = spines[0]
    if any(s.get_linewidth() != first.get_linewidth()
           or not same_color(s.get_edgecolor(), first.get_edgecolor())
           or s.get_linestyle() != first.get_linestyle()
           or s.get_zorder() != first.get_zorder() for s in spines):
        return
    segments = [((0.0, 0.0), (0.0, 1.0)), ((1.0, 0.0), (1.0, 1.0)),
                ((0.0, 0.0), (1.0, 0.0)), ((0.0, 1.0), (1.0, 1.0))]
    ax.add_collection(LineCollection(
        segments, colors=[first.get_edgecolor()], linewidths=first.get_linewidth(),
        linestyles=first.get_linestyle(), capstyle=first.get_capstyle(),
        joinstyle=first.get_joinstyle(), zorder=first.get_zorder(), transform=ax.transAxes,
        clip_on=False), autolim=False)
    for s in spines:
        s.set_visible(False)


def _grid(ax, name, locs, line, zorder):
    """The gridlines at ``locs`` as one line collection, as each tick's gridline draws."""
    from matplotlib.collections import LineCollection

    if name == "x":
        segments, transform = [((v, 0.0), (v, 1.0)) for v in locs], ax.get_xaxis_transform()
    else:
        segments, transform = [((0.0, v), (1.0, v)) for v in locs], ax.get_yaxis_transform()
    ax.add_collection(LineCollection(
        segments, colors=[line.get_color()], linewidths=line.get_linewidth(),
        linestyles=line.get_linestyle(), alpha=line.get_alpha(), zorder=zorder,
        transform=transform), autolim=False)


def _move_label(ax, axis, name, texts):
    """The axis label as an annotation placed as matplotlib places it: outside the tick
    labels of its side (and the spine) by its label pad."""
    label = axis.label
    if not (label.get_visible() and label.get_text()):
        return
    pos = axis.get_label_position()
    side = 1 if pos in ("bottom", "left") else 2
    box = _edge_box(ax, texts[side], pos)
    pad = axis.labelpad
    x, y = label.get_position()
    if name == "x":
        coords, xy = ("axes fraction", box), (x, 0.0 if side == 1 else 1.0)
        offset = (0.0, -pad if side == 1 else pad)
    else:
        coords, xy = (box, "axes fraction"), (0.0 if side == 1 else 1.0, y)
        offset = (-pad if side == 1 else pad, 0.0)
    ax.annotate(label.get_text(), xy=xy, xycoords=coords, xytext=offset,
                textcoords="offset points", va=label.get_va(), ha=label.get_ha(),
                rotation=label.get_rotation(), rotation_mode=label.get_rotation_mode(),
                fontproperties=label.get_fontproperties(), color=label.get_color(),
                annotation_clip=False)
    label.set_visible(False)


def tick_texts(ax: Axes, axis: str = "y") -> list[tuple[float, Text]]:
    """The tick labels :func:`ticks_once` wrote on one axis of an Axes.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        The Axes.
    axis : {"x", "y"}, optional
        Which axis.

    Returns
    -------
    list of (float, matplotlib.text.Text)
        Each label with its tick's position [data units of that axis].
    """
    kind = _tick_label()
    return [(t.value, t) for t in ax.texts if isinstance(t, kind) and t.axis_name == axis]


def _tick_label():
    """The class of the tick labels :func:`ticks_once` writes: a text that knows its tick."""
    return _artists()[0]


def _marks(line):
    """The tick marks of one side of an axis (a marker line) as an artist of their own, not
    one of the Axes' data lines (``ax.lines``)."""
    return _artists()[1](line)


@functools.cache
def _artists():
    """(TickLabel, Marks): the two artist classes of :func:`ticks_once`, made once (matplotlib
    is imported only when a figure is drawn)."""
    from matplotlib.artist import Artist
    from matplotlib.text import Text

    class TickLabel(Text):
        """A tick's label: ``axis_name`` ("x" or "y") and ``value`` (its position)."""

        def __init__(self, *args, axis_name, value, **kwargs):
            super().__init__(*args, **kwargs)
            self.axis_name, self.value = axis_name, value

    class Marks(Artist):
        """Draws one marker line (the tick marks of one side of an axis)."""

        def __init__(self, line):
            super().__init__()
            self.line = line
            self.set_zorder(line.get_zorder())
            if line.get_clip_path() is not None:        # the line's (one per Axes)
                self.set_clip_path(line.get_clip_path())

        def set_figure(self, fig):
            super().set_figure(fig)
            self.line.set_figure(fig)

        def draw(self, renderer):
            if self.get_visible():
                self.line.draw(renderer)

        def get_window_extent(self, renderer=None):
            return self.line.get_window_extent(renderer)

    return TickLabel, Marks
