"""Figure style of the reports: matplotlib settings, joint line styles and markers, fixed
grids, and the text raised to the printed minimum.

Private to the reports (:mod:`gd_analyze.report.common` re-exports these names).
"""

from __future__ import annotations

import contextlib
import math
import textwrap
from collections.abc import Iterator, Sequence
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    import numpy.typing as npt
    from matplotlib.artist import Artist
    from matplotlib.axes import Axes
    from matplotlib.backend_bases import RendererBase
    from matplotlib.figure import Figure
    from matplotlib.gridspec import GridSpec
    from matplotlib.text import Text
    from matplotlib.transforms import Bbox

__all__ = ["BASE_RC", "SUPTITLE_RC", "grid_shape", "joint_style",
           "JOINT_STYLES", "MAX_MARKERS", "MIN_MARKERS", "markevery", "panel_markevery",
           "MARK_EVERY_POINT", "element_markevery",
           "gridspec", "joint_axes", "joint_key", "joint_lines", "new_figure", "grid_boxes", "raise_small_text", "text_extent",
           "COLUMN_PAD", "columns_apart"]

#: matplotlib settings every report uses; each adds its own to them.
BASE_RC = {
    "font.family": "DejaVu Sans",  # the reports' text font too: one family on the page
    "font.size": 8.0,
    "axes.titlesize": 8.5,
    "axes.labelsize": 8.0,
    "xtick.labelsize": 7.0,
    "ytick.labelsize": 7.0,
    "axes.grid": True,
    "grid.color": "0.88",
    "grid.linewidth": 0.5,
    "lines.linewidth": 1.0,
    "svg.fonttype": "none",      # text stays text in the SVG: searchable and small
    "pdf.fonttype": 42,          # embed TrueType fonts in the PDF
    "path.simplify": True,
}
#: :data:`BASE_RC` with bold 11 pt figure titles, 8 pt legends and thin axes lines (the
#: analysis and the sweep report).
SUPTITLE_RC = {**BASE_RC, "legend.fontsize": 8.0, "figure.titlesize": 11.0,
               "figure.titleweight": "bold", "axes.linewidth": 0.6}


def raise_small_text(fig: Figure, least: float) -> int:
    """Set every text of a figure smaller than ``least`` at ``least``: tick labels, labels,
    titles, legends, annotations.

    Parameters
    ----------
    fig : matplotlib.figure.Figure
        The figure, changed in place (its tick parameters too, so that ticks made when it is
        drawn again keep the size).
    least : float
        The least font size [pt] at the figure's drawn size.

    Returns
    -------
    int
        How many texts, and axes' tick labels, were raised.

    Notes
    -----
    A mathtext script is drawn at 0.7 of its text's size; the reports' figures write indices
    as plain characters, so ``least`` is the size of every glyph drawn. Nothing is drawn: the
    tick labels are raised through the axes' tick parameters, and only a raised text is
    measured (a legend's once its legend is laid out on a measuring renderer), to wrap it
    again where it now runs past the figure's right edge.
    """
    from matplotlib.backends.backend_agg import RendererAgg

    raised = 0
    for ax in fig.axes:             # the tick labels made when the figure is drawn too
        for axis in (ax.xaxis, ax.yaxis):
            made = [float(t.label1.get_fontsize()) for t in (axis.majorTicks[0],
                                                             axis.minorTicks[0])]
            if min(made) < least:
                axis.set_tick_params(which="both", labelsize=least)
                raised += 1
    right = fig.bbox.width
    small = [t for t in _texts(fig) if t.get_text() and float(t.get_fontsize()) < least]
    for t in small:
        t.set_fontsize(least)
    raised += len(small)
    renderer = RendererAgg(int(right), int(fig.bbox.height), fig.dpi)      # measures only
    legends = [*fig.legends, *(leg for ax in fig.axes if (leg := ax.get_legend()) is not None)]
    owner = {id(t): leg for leg in legends for t in (*leg.get_texts(), leg.get_title())}
    for leg in legends:             # a legend within the figure holds its texts; another is
        box = leg.get_window_extent(renderer)      # laid out (drawn) to measure them
        if box.x1 <= right + 0.5:
            small = [t for t in small if owner.get(id(t)) is not leg]
        else:
            _laid_out(leg, renderer)
    for _ in range(4):              # again after a text is wrapped anew: its legend moves
        wrapped = False
        for t in small:
            box = t.get_window_extent(renderer)
            if box.x1 <= right + 0.5 or box.x0 >= right:
                continue
            # a note wrapped for the smaller size: wrapped again, as many characters a
            # line as the room from its left end to the figure's edge holds
            lines = t.get_text().split("\n")
            chars = max(12, int(max(map(len, lines)) * (right - box.x0) / box.width) - 1)
            t.set_text(textwrap.fill(" ".join(lines), chars))
            wrapped = True
            if id(t) in owner:
                _laid_out(owner[id(t)], renderer)
        if not wrapped:
            break
    return raised


def _laid_out(artist: Artist, renderer: RendererBase) -> None:
    """Lay an artist out (place its texts) on a measuring renderer, painting nothing.

    Parameters
    ----------
    artist : matplotlib.artist.Artist
        E.g. a legend: drawn, the renderer's drawing calls made no-ops by matplotlib's
        private ``_draw_disabled`` (as :meth:`matplotlib.figure.Figure.draw_without_rendering`
        does); painted as before on a renderer without it.
    renderer : matplotlib.backend_bases.RendererBase
        The renderer, of the figure's size and resolution.
    """
    with getattr(renderer, "_draw_disabled", contextlib.nullcontext)():
        artist.draw(renderer)


def _texts(fig: Figure) -> Iterator[Text]:
    """Every text of a figure but its tick labels, none made that is not made yet (an axis's
    ticks are made when the figure is drawn)."""
    from matplotlib.axis import Axis
    from matplotlib.text import Text

    stack: list[Artist] = [fig]
    while stack:
        a = stack.pop()
        if isinstance(a, Axis):
            yield from (a.label, a.offsetText)
            continue
        if isinstance(a, Text):
            yield a
        stack.extend(a.get_children())


def text_extent(fig: Figure, renderer: RendererBase | None = None) -> Bbox:
    """The figure's box grown up or down to hold every text drawn above or below it (never
    wider: the width is the one the figure is printed at).

    Parameters
    ----------
    fig : matplotlib.figure.Figure
        The figure.
    renderer : matplotlib.backend_bases.RendererBase, optional
        The renderer that has just drawn the figure (its text measured then, not again); the
        figure's own if not given.

    Returns
    -------
    matplotlib.transforms.Bbox
        In inches: ``bbox_inches`` of :meth:`~matplotlib.figure.Figure.savefig`, which then
        keeps the figure's own box where no text sticks out of it.
    """
    from matplotlib.transforms import Bbox

    page, drawn = fig.bbox_inches, fig.get_tightbbox(renderer)           # in inches
    return Bbox.from_extents(page.x0, min(page.y0, drawn.y0), page.x1, max(page.y1, drawn.y1))


def grid_shape(n: int, max_cols: int) -> tuple[int, int]:
    """Rows and columns of a grid of n panels, at most ``max_cols`` a row.

    Parameters
    ----------
    n : int
        Number of panels.
    max_cols : int
        Most columns.

    Returns
    -------
    rows, cols : int
    """
    cols = max(1, min(max_cols, n))
    return math.ceil(n / cols), cols


#: Line style and marker of joints 1..7: no two joints share either, so that seven lines are
#: told apart in greyscale (dash patterns as (offset, (on, off, ...)) in points).
JOINT_STYLES = (("-", "o"), ((0, (4.0, 1.6)), "s"), ((0, (1.0, 1.3)), "^"),
                ((0, (5.0, 1.5, 1.0, 1.5)), "D"), ((0, (2.2, 1.4)), "v"),
                ((0, (6.0, 1.5, 1.0, 1.5, 1.0, 1.5)), "x"), ((0, (8.0, 2.0)), "+"))


def joint_style(j: int, n_lines: int = 1, in_panel: int = 1) -> dict[str, Any]:
    """Colour, line style and marker of joint ``j`` (0-based): distinct for up to 7 joints.

    Parameters
    ----------
    j : int
        The joint, 0-based.
    n_lines : int, optional
        Set points on the line.
    in_panel : int, optional
        Lines on the panel: together they carry at most about :data:`MAX_MARKERS` markers
        (:func:`panel_markevery`).

    Returns
    -------
    dict
        Keyword arguments of :meth:`matplotlib.axes.Axes.plot`: ``color`` (Okabe & Ito
        colour-blind-safe set, then tab10), ``linestyle``, ``marker`` (open), ``markevery``,
        ``markersize``; the markers of joint j start at an offset so that two joints' markers
        do not fall on the same set points.
    """
    from matplotlib import colormaps

    colours = ("#000000", "#0072B2", "#D55E00", "#009E73", "#CC79A7", "#E69F00", "#56B4E9")
    ls, marker = JOINT_STYLES[j % len(JOINT_STYLES)]
    colour = colours[j] if j < len(colours) else colormaps["tab10"](j % 10)     # then tab10
    every = panel_markevery(n_lines, in_panel)
    offset = (j * max(1, every // 7)) % every if every > 1 else 0
    return {"color": colour, "linestyle": ls, "marker": marker, "markevery": (offset, every),
            "markersize": 3.0, "markerfacecolor": "none", "markeredgewidth": 0.7}


#: The most markers drawn on one panel, all its lines together: more merge into a band at
#: print size (each line keeps at least :data:`MIN_MARKERS`).
MAX_MARKERS = 12
#: The fewest markers of a line that has any: enough to tell its marker.
MIN_MARKERS = 2


def panel_markevery(m: int, lines: int) -> int:
    """The stride of the markers of each of ``lines`` lines of ``m`` points on one panel.

    Parameters
    ----------
    m : int
        Points on each line.
    lines : int
        Lines with markers on the panel.

    Returns
    -------
    int
        :func:`markevery` for at most ``max(MIN_MARKERS, MAX_MARKERS // lines)`` markers a
        line: at most about :data:`MAX_MARKERS` on the panel.

    Examples
    --------
    >>> panel_markevery(31, 3), panel_markevery(31, 6), panel_markevery(8, 1)
    (8, 16, 1)
    """
    return markevery(m, max(MIN_MARKERS, MAX_MARKERS // max(1, int(lines))))


#: Runs of up to this many set points get a marker at every set point on every line, as the
#: chapter's Figs. 3.10 and 3.11 do; longer runs a thinned set (:func:`panel_markevery`).
MARK_EVERY_POINT = 50


def element_markevery(m: int, lines: int = 3) -> int:
    """The stride of the markers on the element panels (Figs. 3.10 and 3.11 analogues).

    Parameters
    ----------
    m : int
        Set points on each line.
    lines : int, optional
        Lines with markers on a panel.

    Returns
    -------
    int
        1 (a marker at every set point) for ``m <= MARK_EVERY_POINT``; else
        :func:`panel_markevery`.

    Examples
    --------
    >>> element_markevery(31), element_markevery(50), element_markevery(51)
    (1, 1, 13)
    """
    return 1 if int(m) <= MARK_EVERY_POINT else panel_markevery(m, lines)


def markevery(m: int, most: int = MAX_MARKERS) -> int:
    """The stride that leaves at most ``most`` markers on a line of ``m`` points.

    Parameters
    ----------
    m : int
        Points on the line.
    most : int, optional
        The most markers (:data:`MAX_MARKERS`).

    Returns
    -------
    int
        k >= 1 with ceil(m / k) <= most (markers at points 0, k, 2k, ...).

    Examples
    --------
    >>> markevery(31), markevery(12), markevery(0)
    (3, 1, 1)
    """
    return max(1, -(-int(m) // max(1, int(most))))


def joint_key(axes: Sequence[Axes]) -> tuple[list[Artist], list[str]]:
    """The key entries of the joints' lines drawn on ``axes``, in the order of the joints.

    Parameters
    ----------
    axes : sequence of matplotlib.axes.Axes
        Axes whose lines are labelled "joint <number>" (1-based), each joint on one of them.

    Returns
    -------
    handles : list of matplotlib.artist.Artist
        The lines, joint 1 first.
    labels : list of str
        Their labels, in the same order.
    """
    pairs = sorted(((h, lab) for ax in axes for h, lab in zip(*ax.get_legend_handles_labels())),
                   key=lambda pair: int(pair[1].split()[1]))
    return [h for h, _ in pairs], [lab for _, lab in pairs]


def new_figure(width: float, height: float) -> Figure:
    """A matplotlib figure of this size, made without pyplot (no global state).

    Parameters
    ----------
    width, height : float
        [in].

    Returns
    -------
    matplotlib.figure.Figure
    """
    from matplotlib.figure import Figure

    return Figure(figsize=(width, height))


def grid_boxes(fig: Figure, n: int, cols: int, at: tuple[float, float],
               size: tuple[float, float], gaps: tuple[float, float]
               ) -> list[tuple[float, float, float, float]]:
    """Where n panels go, ``cols`` a row in reading order, in a fixed layout in inches.

    Parameters
    ----------
    fig : matplotlib.figure.Figure
        The figure (its size [in]).
    n, cols : int
        Panels, and panels a row.
    at : (float, float)
        The first panel's top left corner (x, y) from the figure's top left [in].
    size : (float, float)
        Each panel's width and height [in].
    gaps : (float, float)
        Room between columns and between rows [in].

    Returns
    -------
    list of (float, float, float, float)
        Each panel's left, bottom, width and height as shares of the figure's, for
        :meth:`~matplotlib.figure.Figure.add_axes` or
        :meth:`~matplotlib.axes.Axes.set_position`.
    """
    W, H = fig.get_size_inches()
    (x0, y0), (w, h), (gx, gy) = at, size, gaps
    cells = [divmod(k, cols) for k in range(n)]          # (row, column) of each panel
    return [((x0 + c * (w + gx)) / W, 1 - (y0 + r * (h + gy) + h) / H, w / W, h / H)
            for r, c in cells]


#: Least room between a panel's frame and the y-axis labels of the panel to its right [in]
#: (:func:`columns_apart`): 4 pt.
COLUMN_PAD = 4 / 72


def columns_apart(fig: Figure, columns: Sequence[Sequence[Axes]], left: float,
                  right: float, pad: float = COLUMN_PAD) -> None:
    """Lay out columns of panels when the figure is drawn, so that each column's y-axis
    labels (tick labels and axis label, measured at the size they are drawn at) stand at
    least ``pad`` from the frame of the panel to their left and within the figure.

    Parameters
    ----------
    fig : matplotlib.figure.Figure
        The figure, given a layout engine that runs before each drawing (after
        :func:`raise_small_text` has set the text at its printed size).
    columns : sequence of sequences of matplotlib.axes.Axes
        The panels of each column, left to right; the columns share one width.
    left, right : float
        The least margin left of the first column's frames, and the margin right of the last
        column's frames [in].
    pad : float, optional
        Least room between a frame and the labels to its right [in], and between the first
        column's labels and the figure's left edge.

    Notes
    -----
    Only the panels' x positions and widths change: the rows stay where they were put.
    """
    from matplotlib.layout_engine import LayoutEngine

    class _Apart(LayoutEngine):
        _adjust_compatible = False
        _colorbar_gridspec = False

        def execute(self, fig: Figure) -> None:
            renderer = fig._get_renderer()              # type: ignore[attr-defined]
            dpi, W = fig.dpi, float(fig.get_size_inches()[0])
            need = []                   # room each column's y labels take left of its frames
            for column in columns:
                room = 0.0
                for ax in column:
                    frame = ax.get_window_extent(renderer)
                    labels = ax.yaxis.get_tightbbox(renderer)
                    if labels is not None:
                        room = max(room, (frame.x0 - labels.x0) / dpi)
                need.append(room)
            x0 = max(left, need[0] + pad)
            gaps = [n + pad for n in need[1:]]
            w = (W - x0 - right - sum(gaps)) / len(columns)
            for c, column in enumerate(columns):
                x = x0 + c * w + sum(gaps[:c])
                for ax in column:
                    box = ax.get_position()
                    ax.set_position((x / W, box.y0, w / W, box.height))

    fig.set_layout_engine(_Apart())


def joint_axes(n: int, cols: int, size: tuple[float, float], top: float, bottom: float,
               wspace: float, hspace: float, xlabel: str) -> tuple[Figure, list[Axes]]:
    """A figure of one panel per joint, ``cols`` a row, sharing x, in fixed margins (no
    layout engine: drawing stays fast).

    Parameters
    ----------
    n : int
        Panels (joints).
    cols : int
        Panels a row.
    size : (float, float)
        Figure width and height [in].
    top, bottom : float
        Margins above and below the panels [in]; 0.75 in on the left, 0.15 in on the right.
    wspace, hspace : float
        Room between panels [share of a panel's width, height].
    xlabel : str
        The x axis' label, with its tick labels, under the lowest panel of each column.

    Returns
    -------
    fig : matplotlib.figure.Figure
    axes : list of matplotlib.axes.Axes
        The n panels in reading order; the grid's spare panels are hidden.
    """
    W, H = size
    fig = new_figure(W, H)
    fig.subplots_adjust(left=0.75 / W, right=1 - 0.15 / W, top=1 - top / H,
                        bottom=bottom / H, wspace=wspace, hspace=hspace)
    axes = fig.subplots(math.ceil(n / cols), cols, squeeze=False, sharex=True).ravel()
    for ax in axes[n:]:
        ax.set_visible(False)
    for ax in axes[max(0, n - cols):n]:           # the lowest panel of its column
        ax.set_xlabel(xlabel)
        ax.xaxis.set_tick_params(labelbottom=True)      # sharex hid them over a gap
    return fig, list(axes[:n])


def gridspec(fig: Figure, rows: int, cols: int, left: float, right: float, top: float,
             bottom: float, wgap: float, hgap: float) -> GridSpec:
    """A gridspec with margins and gaps in inches (a fixed layout: no layout engine).

    Parameters
    ----------
    fig : matplotlib.figure.Figure
        The figure.
    rows, cols : int
        Grid shape.
    left, right, top, bottom : float
        Margins [in].
    wgap, hgap : float
        Gaps between columns and between rows [in].

    Returns
    -------
    matplotlib.gridspec.GridSpec
    """
    W, H = fig.get_size_inches()
    aw = (W - left - right - (cols - 1) * wgap) / cols
    ah = (H - top - bottom - (rows - 1) * hgap) / max(rows, 1)
    return fig.add_gridspec(rows, cols, left=left / W, right=1 - right / W, bottom=bottom / H,
                            top=1 - top / H, wspace=wgap / aw, hspace=hgap / ah)


def joint_lines(t: npt.ArrayLike, curves: Sequence[tuple[tuple[str, Any, float, str], Any]],
                titles: Sequence[str], ylabels: Sequence[str], width: float, cols: int = 2,
                step: int = 1) -> Figure:
    """A figure of one panel per joint (:func:`joint_axes`), each drawing the same curves
    against time, their key below.

    Parameters
    ----------
    t : array_like, shape (N,)
        Time [s].
    curves : sequence of ((str, object, float, str), array_like)
        Per curve its style, (colour, line style, line width [pt], key label), and its values,
        shape (N, n) [each joint's units].
    titles : sequence of str, length n
        Each panel's title, set on its left and taken as plain text (no mathtext).
    ylabels : sequence of str, length n
        Each panel's y label, said on every panel, the power of ten its ticks are written in
        put into its unit (:func:`gd_analyze.report.numbers.label_axes`): each panel states
        its own scale in one place, with no offset text.
    width : float
        Figure width [in].
    cols : int, optional
        Most panels a row.
    step : int, optional
        Every ``step``-th sample is drawn.

    Returns
    -------
    matplotlib.figure.Figure
        1.6 in a row of panels, round y ticks labelled in one notation for the figure
        (:func:`gd_analyze.report.numbers.label_axes`), time on the lowest panel of each column.
    """
    import numpy as np
    from matplotlib.lines import Line2D

    from .numbers import label_axes, set_ticks, time_origin

    n = len(titles)
    rows, cols = grid_shape(n, cols)
    origin, t_label = time_origin(t)
    fig, axes = joint_axes(n, cols, (width, 1.6 * rows + 0.3 + 0.85), 0.3, 0.85, 0.4, 0.45,
                           t_label)
    t = np.asarray(t, float) - origin
    handles: dict[str, Line2D] = {}
    for j, ax in enumerate(axes):
        for (colour, ls, lw, label), y in curves:
            ax.plot(t[::step], np.asarray(y, float)[::step, j], color=colour, linestyle=ls,
                    linewidth=lw)
            handles.setdefault(label, Line2D([], [], color=colour, linestyle=ls, linewidth=lw))
        ax.set_title(titles[j], loc="left", parse_math=False)
        lo, hi = ax.get_ylim()
        set_ticks(ax.yaxis, lo, hi, 4, labels=False)
        ax.set_ylabel(ylabels[j])
    label_axes([ax.yaxis for ax in axes])
    fig.legend(list(handles.values()), list(handles), loc="lower center", ncol=len(handles),
               frameon=False, bbox_to_anchor=(0.5, 0.02))
    return fig
