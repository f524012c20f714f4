"""Tick labels that never misstate a value, and cheap axes for small multiples.

:func:`tick_labels` writes each tick with the fewest digits that still give back the tick's
value: ticks at 0, -0.25, -0.5, -0.75 read "0, −0.25, −0.5, −0.75" (not "−0.2, −0.8"), ticks at
0, 1.5e-5, 3e-5 read "0, 1.5e−5, 3e−5". :func:`nice_ticks` places at most a few ticks at round
values, once, so that matplotlib does not rebuild locators at every draw; :func:`set_ticks`
puts both on an axis.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["tick_labels", "grid_once", "nice_ticks", "set_ticks", "formatter", "MINUS", "notation",
           "label_axes"]

#: The minus sign of the labels (U+2212, as wide as the plus sign).
MINUS = "\u2212"
#: A label is exact if it gives back its tick to this fraction of the largest |tick| (or of the
#: tick spacing, if smaller): far below what a plot can show, far above float noise.
_REL = 1e-9
#: Fixed notation between these magnitudes of the largest |tick|, scientific outside.
_FIXED = (1e-3, 1e5)


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


def tick_labels(values, style=None):
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


def notation(values):
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


def label_axes(axes):
    """Write the tick labels of several axes of one figure in one notation.

    Parameters
    ----------
    axes : iterable of matplotlib.axis.Axis
        Axes whose ticks are placed (:func:`set_ticks` with ``labels=False`` or ``True``).

    Returns
    -------
    str
        The notation used: ``"sci"`` for every axis if any one needs it (a figure never mixes
        2e−5 and 0.0015), else ``"fixed"``.
    """
    axes = [a for a in axes if len(a.get_ticklocs())]
    style = "sci" if any(notation(a.get_ticklocs()) == "sci" for a in axes) else "fixed"
    for a in axes:
        ticks = a.get_ticklocs()
        a.set_ticks(ticks, labels=tick_labels(ticks, style))
    return style


def nice_ticks(lo, hi, nbins=3):
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
        Tick positions within the limits, at least one (the midpoint of a degenerate range).

    Examples
    --------
    >>> nice_ticks(0.0, 1.0, 4).tolist()
    [0.0, 0.25, 0.5, 0.75, 1.0]
    """
    lo, hi = float(min(lo, hi)), float(max(lo, hi))
    span = hi - lo
    if not (np.isfinite(span) and span > 0):
        return np.array([lo])
    raw = span / max(1, int(nbins))
    mag = 10.0 ** math.floor(math.log10(raw))
    for m in (1.0, 2.0, 2.5, 5.0, 10.0):
        step = m * mag
        first = math.ceil(lo / step - 1e-9)
        last = math.floor(hi / step + 1e-9)
        if last - first <= nbins:
            break
    ticks = np.arange(first, last + 1) * step
    ticks[np.abs(ticks) < 1e-12 * step] = 0.0
    return ticks


def formatter():
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


def set_ticks(axis, lo, hi, nbins=3, labels=True):
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
    axis.set_ticks(ticks, labels=tick_labels(ticks) if labels else [""] * len(ticks))
    return ticks



def grid_once(fig):
    """Draw each Axes' major grid as one line collection instead of one line per tick.

    Parameters
    ----------
    fig : matplotlib.figure.Figure
        A figure whose ticks are placed (the grid is drawn where they are now).

    Returns
    -------
    matplotlib.figure.Figure
        ``fig``, each visible major grid replaced by a
        :class:`~matplotlib.collections.LineCollection` of the same lines (colour, width,
        style, z-order, clipped to the Axes): the same picture from fewer Artists.
    """
    from matplotlib.collections import LineCollection

    for ax in fig.axes:
        for name, axis in (("x", ax.xaxis), ("y", ax.yaxis)):
            lines = [g for g in axis.get_gridlines() if g.get_visible()]
            if not lines:
                continue
            lo, hi = sorted(axis.get_view_interval())
            locs = [v for v in axis.get_majorticklocs() if lo <= v <= hi]
            g = lines[0]
            if name == "x":
                segments = [((v, 0.0), (v, 1.0)) for v in locs]
                transform = ax.get_xaxis_transform()
            else:
                segments = [((0.0, v), (1.0, v)) for v in locs]
                transform = ax.get_yaxis_transform()
            ax.grid(False, which="major", axis=name)
            if segments:
                ax.add_collection(LineCollection(
                    segments, colors=[g.get_color()], linewidths=g.get_linewidth(),
                    linestyles=g.get_linestyle(), alpha=g.get_alpha(), zorder=axis.get_zorder(),
                    transform=transform), autolim=False)
    return fig
