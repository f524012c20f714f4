"""Figures of the main report, sized for print: a 7.2-in page width or a 3.5-in column.

Every figure is a plain :class:`matplotlib.figure.Figure` drawn at the size it is printed at, with
type of at least 7 pt, so that it goes into a paper unscaled. The figures read *plot data*
(:class:`PlotData`): the stored series, or for long trajectories their min/max envelope per
column, which :func:`plot_data` reads from the stored file in chunks. They never see the full
dataset and never recompute the dynamics.

- ``joints``: q, qd, qdd against time [deg, deg/s, deg/s^2];
- ``D``: the elements D_ij, i <= j, translational (o), rotational (x) and combined (^)
  against time, in reading order on panels at least 1.1 in wide: the analogue of Fig. 3.10
  of Fu, Gonzalez & Lee (1987), Sec. 3.4.1;
- ``h``: the n elements h_i the same way, on panels of the same size (Fig. 3.11);
- ``torque``: tau and tau_s against time per joint;
- ``payload`` (:func:`payload_figure`): a payload sweep, which the main report
  (``--payload-sweep``) and the sweep report both show.

An element whose parts are all zero to rounding (:func:`identically_zero`) is not drawn: a note
below the panels names it ("≡ 0"); its share_tran is rounding noise.
"""

from __future__ import annotations

import math
import operator
import textwrap
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from ..ranking.ranking import (
    ROUND_OFF,
    element_label,
    element_units,
    identically_zero,
    joint_motion_units,
    joint_torque_units,
)
from ..store.names import Var
from ..store.sweep_view import PAYLOAD_REQUIRED, PayloadSweep
from .common import CLASS_COLOURS, say, units_text
from .figure_style import (
    SUPTITLE_RC,
    columns_apart,
    element_markevery,
    grid_boxes,
    joint_key,
    joint_lines,
    joint_style,
    new_figure,
)
from .markup import label as _math
from .numbers import label_axes, set_ticks, time_origin

if TYPE_CHECKING:
    import numpy.typing as npt
    import xarray as xr
    from matplotlib.figure import Figure

__all__ = ["PAGE_WIDTH", "COLUMN_WIDTH", "ZERO_TOL", "PART_STYLE", "PART_ZORDER", "SHORT_CLASS",
           "PlotData", "plot_data", "identically_zero", "fig_D", "fig_h", "fig_joints",
           "fig_torque", "d_panels", "panel_grid", "element_parts", "element_row",
           "part_rows", "d_size", "LEAST_FIRST_ROWS", "MIN_PANEL_W", "MAX_ROWS",
           "RC", "payload_figure", "PAYLOAD_REQUIRED", "CLASS_LETTER", "DERIVED", "OPTIONAL",
           "ENVELOPE_THRESHOLD", "ENVELOPE_COLUMNS", "READ_CHUNK"]

#: Width of a figure spanning the text of a page [in] (two-column journals: 7.0-7.3).
PAGE_WIDTH = 7.2
#: Width of a one-column figure [in].
COLUMN_WIDTH = 3.5
#: An element is identically zero if all its parts stay below this fraction of its scale
#: (:data:`gd_analyze.ranking.ranking.ROUND_OFF`).
ZERO_TOL = ROUND_OFF

#: matplotlib settings: 7 pt ticks, 8 pt titles and labels at print size.
RC = {
    "font.size": 8.0, "axes.titlesize": 8.0, "axes.labelsize": 8.0, "xtick.labelsize": 7.0,
    "ytick.labelsize": 7.0, "legend.fontsize": 8.0, "figure.titlesize": 9.0,
    "axes.linewidth": 0.6, "axes.grid": True, "grid.color": "0.88", "grid.linewidth": 0.5,
    "lines.linewidth": 0.9, "lines.markersize": 3.2, "xtick.major.size": 2.5,
    "ytick.major.size": 2.5, "xtick.major.pad": 1.5, "ytick.major.pad": 1.5,
    "axes.titlepad": 2.5, "axes.titley": 1.0, "svg.fonttype": "none",
    "path.simplify": True, "svg.hashsalt": "gd-analyze", "axes.xmargin": 0.0,
    # every line is given its colour: a one-colour cycle makes each new axes cheaper
    "axes.prop_cycle": __import__("cycler").cycler(color=["#000000"]),
}

#: Colour (Okabe & Ito), marker and line of each part: told apart in greyscale by marker and
#: line style alone.
PART_STYLE = {
    "tran": {"color": "#0072B2", "marker": "o", "linestyle": "-", "mfc": "none",
             "label": "translational"},
    "rot": {"color": "#D55E00", "marker": "x", "linestyle": "--", "mfc": None,
            "label": "rotational"},
    "total": {"color": "#000000", "marker": "^", "linestyle": ":", "mfc": "none",
              "label": "combined"},
    "arm": {"color": "#CC79A7", "marker": "s", "linestyle": "-.", "mfc": "none",
            "label": "armature"},
}
_CLASS_COLOURS = {"translational": "#0072B2", "rotational": "#D55E00", "both": "#6A3D9A",
                  "negligible": "#555555"}
#: Short class names of the panel titles (the key spells them out).
SHORT_CLASS = {"translational": "tran", "rotational": "rot", "both": "both",
               "negligible": "negl"}
_FULL, _SIMPLIFIED = "#000000", "#009E73"
# Panel geometry of D and h [in]: margins, the gap between columns (tick labels and each
# panel's unit label) and between rows (x tick labels and the next row's titles).
_LEFT, _RIGHT, _WGAP, _HGAP, _TOP = 0.5, 0.06, 0.6, 0.44, 0.22
#: Least panel width of the D and h figures at page width [in]: four panels a row.
MIN_PANEL_W = 1.1
#: Least panel width of the column-width D and h figures [in]: three a row.
_MIN_COLUMN_PANEL_W = 0.5
#: Most rows of panels in one figure; more panels go to further parts (:func:`element_parts`).
#: Five at page width: a part (7.4 in) with its caption, its section's heading and lead
#: paragraph fits an A4 or letter page (a part of six rows, 8.7 in, went to the next page and
#: left the heading and the lead alone on theirs).
MAX_ROWS = {"page": 5, "column": 8}


def _y_axis(ax, nbins, *arrays):
    """y limits around the arrays (:func:`_limits`), round ticks within the data's range,
    labelled by the figure (:func:`gd_analyze.report.numbers.label_axes`)."""
    lo, hi = _limits(*arrays)
    ax.set_ylim(lo, hi)
    pad = (hi - lo) / 1.2 * 0.1
    set_ticks(ax.yaxis, lo + pad, hi - pad, nbins, labels=False)


def _limits(*arrays):
    vals = np.concatenate([np.ravel(a) for a in arrays])
    vals = vals[np.isfinite(vals)]
    if vals.size == 0:
        return -1.0, 1.0
    lo, hi = float(vals.min()), float(vals.max())
    if hi - lo <= 1e-9 * max(abs(lo), abs(hi)):          # constant: a range around it
        half = 0.5 * abs(hi) if hi != 0 else 1.0
        lo, hi = lo - half, hi + half
    pad = 0.1 * (hi - lo)                                # markers at the extremes stay inside
    return lo - pad, hi + pad


#: Line widths of the parts: the combined curve thin, under the parts it sums.
_PART_WIDTH = {"tran": 0.8, "rot": 0.8, "total": 0.55, "arm": 0.8}
#: Drawing order (z-order) of the parts: the combined curve first, so that o and x stay
#: visible on top of it; the drives' armature last, above the combined curve that includes it.
PART_ZORDER = {"total": 2, "tran": 3, "rot": 4, "arm": 5}
#: Marker size of each part [pt]: small enough for a marker at every one of 50 set points
#: on a 1.1-in panel.
_PART_MARKER = {"tran": 2.6, "rot": 2.8, "total": 2.4, "arm": 2.4}


def _plot(ax, x, y, part, enveloped, lines):
    """One part of an element: a marker at every set point for up to
    :data:`gd_analyze.report.figure_style.MARK_EVERY_POINT` of them, else at every k-th
    (:func:`gd_analyze.report.figure_style.element_markevery`, staggered between the parts);
    none on a min/max envelope."""
    style = PART_STYLE[part]
    kw = {"color": style["color"], "linestyle": style["linestyle"], "label": style["label"],
          "linewidth": _PART_WIDTH[part], "zorder": PART_ZORDER[part]}
    if not enveloped:
        every = element_markevery(x.size, lines)
        start = {"tran": 0, "rot": every // 3, "total": (2 * every) // 3,
                 "arm": every // 2}[part]
        kw.update(marker=style["marker"], markevery=(start, every) if every > 1 else 1,
                  markersize=_PART_MARKER[part],
                  markeredgewidth=0.5 if part in ("total", "arm") else 0.6)   # open, not a blot
        if style["mfc"] is not None:
            kw["markerfacecolor"] = style["mfc"]
    return ax.plot(x, y, **kw)


def _time_axis(ax, x, labels, nbins=3):
    t0, t1 = float(x[0]), float(x[-1])
    pad = 0.03 * (t1 - t0) if t1 > t0 else 0.5
    ax.set_xlim(t0 - pad, t1 + pad)
    # within the drawn range: an envelope's first point is half a column after t = 0
    set_ticks(ax.xaxis, t0 - pad, t1 + pad, nbins, labels)


def _legend_order(ax):
    order = [style["label"] for style in PART_STYLE.values()]     # tran, rot, total, arm
    pairs = sorted(zip(*ax.get_legend_handles_labels()), key=lambda p: order.index(p[1]))
    return [p[0] for p in pairs], [p[1] for p in pairs]


def panel_grid(count: int, width: float = PAGE_WIDTH) -> tuple[int, float, float]:
    """Columns and panel size of the D and h figures.

    Parameters
    ----------
    count : int
        Panels to lay out (at least one column).
    width : float, optional
        Figure width [in]: :data:`PAGE_WIDTH` gives panels of at least :data:`MIN_PANEL_W`.

    Returns
    -------
    cols : int
    w, h : float
        Panel width and height [in].

    Examples
    --------
    >>> cols, w, h = panel_grid(19)
    >>> cols, w >= MIN_PANEL_W
    (4, True)
    """
    min_w = MIN_PANEL_W if width >= PAGE_WIDTH else _MIN_COLUMN_PANEL_W
    fit = int((width - _LEFT - _RIGHT + _WGAP) / (min_w + _WGAP) + 1e-9)
    # at page width one panel size for D and h: as many as D has
    cols = max(1, fit if width >= PAGE_WIDTH else min(max(count, 1), fit))
    w = (width - _LEFT - _RIGHT - (cols - 1) * _WGAP) / cols
    return cols, w, float(np.clip(0.68 * w, 0.5, 0.85))


def element_parts(labels: Sequence[str], width: float = PAGE_WIDTH,
                  first_rows: int | None = None,
                  rows: Sequence[int] | None = None) -> list[list[str]]:
    """The panels of a D or h figure split into parts of at most :data:`MAX_ROWS` rows.

    Parameters
    ----------
    labels : sequence of str
        The elements drawn, in reading order.
    width : float, optional
        Figure width [in].
    first_rows : int, optional
        Rows of the first part: those that fit under the text citing the figure
        (:func:`gd_analyze.report.typeset.figure_rooms`, :func:`part_rows`).
    rows : sequence of int, optional
        Rows of each part after a first part of ``first_rows``, the last part holding the
        rest (:data:`MAX_ROWS` each if not given).

    Returns
    -------
    list of list of str
        One list per figure part (one part if all fit; ``[[]]`` for none), in whole rows;
        without ``first_rows`` the parts as few as :data:`MAX_ROWS` allows and of about one
        size.

    Examples
    --------
    >>> [len(p) for p in element_parts([f"D{k}" for k in range(30)])]
    [16, 14]
    >>> [len(p) for p in element_parts([f"D{k}" for k in range(30)], first_rows=1, rows=[6])]
    [4, 26]
    """
    cols = panel_grid(len(labels), width)[0]
    most = cols * MAX_ROWS["page" if width >= PAGE_WIDTH else "column"]
    labels = list(labels)
    if first_rows is not None and 0 < first_rows * cols < len(labels):
        out, at = [labels[:first_rows * cols]], first_rows * cols
        for k in range(len(labels)):
            if at >= len(labels):
                break
            size = len(labels) if rows is not None and k == len(rows) - 1 else cols * (
                rows[k] if rows is not None and k < len(rows) else most // cols)
            out.append(labels[at:at + size])
            at += size
        return out
    parts = max(1, -(-len(labels) // most))
    per = cols * max(1, -(-len(labels) // (parts * cols)))     # balanced, in whole rows
    return [labels[k:k + per] for k in range(0, len(labels), per)] or [[]]


def element_row(count: int, width: float = PAGE_WIDTH) -> float:
    """The height a row of panels adds to a D or h figure [in]: a panel and the gap under it.

    Parameters
    ----------
    count : int
        Panels of the figure (all its parts).
    width : float, optional
        Figure width [in].

    Returns
    -------
    float
        As :func:`_element_figure` lays the panels out (:func:`panel_grid`).
    """
    return panel_grid(count, width)[2] + _HGAP


#: Fewest rows of panels a first part is drawn with to stand under the text citing it
#: (:func:`part_rows`): one row, its legend, key and caption (3 in on A4) fill the foot of a
#: page that a whole part left 4.1 in empty (Unitree G1's right arm).
LEAST_FIRST_ROWS = 1
#: Room kept spare when a part is fitted to a page or under the text citing it [in].
_SPARE = 0.1


def part_rows(count: int, room: float, need: float, scale: float, body: float,
              after: float = 0.0) -> tuple[int, tuple[int, ...]] | None:
    """How a D figure in parts fills its pages, when its first part (:func:`element_parts`)
    does not fit under the text citing it: the rows of a first part that fits that room, then
    of each later part.

    Parameters
    ----------
    count : int
        Panels of the figure, all parts, at page width.
    room : float
        Room left on the page under the text citing the figure [in]
        (:func:`gd_analyze.report.typeset.figure_rooms`).
    need : float
        Height the first part needs there, printed with its caption [in].
    scale : float
        Printed size / drawn size of the parts (:func:`gd_analyze.report.typeset.printed_width`).
    body : float
        Height of a page's text area [in] (:func:`gd_analyze.report.typeset.body_height`).
    after : float, optional
        Height of what follows the last part (the next section's heading and figure) [in]:
        on the last part's page if it fits there.

    Returns
    -------
    (int, tuple of int) or None
        Rows of the first part (at least :data:`LEAST_FIRST_ROWS`) and of each later part,
        one page each; None if fewer than :data:`LEAST_FIRST_ROWS` rows fit the room. The
        later parts are as few as a page's rows allow (at least :data:`MAX_ROWS` a page):
        each page filled and the rest last, or the rows spread evenly, whichever leaves the
        least room empty on the emptiest page (what follows counted on the last part's page).

    Examples
    --------
    >>> part_rows(55, 4.11, 7.82, 0.94, 10.14, 5.7)    # a 10-joint arm (Unitree G1), A4
    (1, (6, 6, 1))
    >>> part_rows(55, 4.11, 7.82, 0.94, 10.14, 8.0)    # what follows does not fit beside it
    (1, (5, 4, 4))
    >>> part_rows(55, 2.5, 7.82, 0.94, 10.14)          # no row fits: the part moves on whole
    """
    cols, _, _ = panel_grid(count)
    row = element_row(count) * scale                       # printed [in]
    shown = -(-len(element_parts([str(k) for k in range(count)])[0]) // cols)
    first = shown - math.ceil((need - room + _SPARE) / row)
    if first < LEAST_FIRST_ROWS:
        return None
    rest = need - shown * row                   # a part's caption, legend, key and note
    page = max(MAX_ROWS["page"], int((body - rest - _SPARE) / row))
    left = -(-count // cols) - first
    parts = -(-left // page)
    filled = (page,) * (left // page) + ((left % page,) if left % page else ())
    base, extra = divmod(left, parts)
    even = (base + 1,) * extra + (base,) * (parts - extra)

    def emptiest(rows: tuple[int, ...]) -> float:
        empty = [body - rest - r * row for r in rows]
        if empty[-1] >= after + _SPARE:     # what follows stands under the last part
            empty[-1] -= after
        return max(empty)

    return first, min((filled, even), key=emptiest)


def _title_key(fig, y, W, H):
    """A legend of the panel titles' colours: one coloured square per class."""
    from matplotlib.patches import Patch

    handles = [Patch(facecolor=_CLASS_COLOURS[c], edgecolor="none") for c in _CLASS_COLOURS]
    names = [f"{SHORT_CLASS[c]}" + ("" if SHORT_CLASS[c] == c else f" ({c})")
             for c in _CLASS_COLOURS]
    fig.legend(handles, names, loc="upper center", ncol=4 if W >= PAGE_WIDTH else 2,
               frameon=False, fontsize=7,
               handlelength=1.0, handleheight=0.7, columnspacing=1.2, borderaxespad=0.0,
               title="panel title: element and its class, in the class's colour"
               if W >= PAGE_WIDTH else "panel title: element and class, in its colour",
               title_fontsize=7, bbox_to_anchor=(0.5, 1 - y / H))


def _element_layout(panels, width, key):
    """The wrapped note, the heights of the legend, the key and the panels, and the height
    of :func:`_element_figure` [in]: its size planned without making it."""
    cols, _, h = panel_grid(len(panels), width)
    rows = max(1, math.ceil(len(panels) / cols))
    note = textwrap.fill(key, max(30, int((width - 0.2) / (7.0 * 0.5 / 72))))
    legend_h = 0.22 + 0.16 * (width < PAGE_WIDTH and any("arm" in p[1] for p in panels))
    title_h = 0.4 + 0.14 * (width < PAGE_WIDTH)     # the title colours' key: two rows
    panels_h = _TOP + rows * h + (rows - 1) * _HGAP + 0.3 if panels else 0.0
    H = panels_h + (legend_h + title_h if panels else 0.0) + 0.14 * (note.count("\n") + 1) + 0.12
    return note, legend_h, title_h, panels_h, H


def _element_figure(x, panels, enveloped, width, key):
    """Panels in reading order, the parts' legend, the title colours' key and a note below.

    ``panels``: (label, parts dict, class, units) per panel drawn; ``key``: the note."""
    cols, w, h = panel_grid(len(panels), width)
    origin, t_label = time_origin(x)
    x = np.asarray(x, dtype=float) - origin
    note, legend_h, title_h, panels_h, H = _element_layout(panels, width, key)
    fig = new_figure(width, H)
    first, ys = None, []
    boxes = grid_boxes(fig, len(panels), cols, (_LEFT, _TOP), (w, h), (_WGAP, _HGAP))
    for k, ((label, parts, cls, units), box) in enumerate(zip(panels, boxes)):
        ax = fig.add_axes(box)
        # the element's parts (tran, rot, total and, on a diagonal panel of an arm with
        # drives, arm); y ticks placed, labelled by the figure (label_axes: one notation)
        for part, y in parts.items():
            _plot(ax, x, y, part, enveloped, len(parts))
        _y_axis(ax, 2 if h < 0.6 else 3, *parts.values())
        ax.set_title(f"{_math(label)}: {SHORT_CLASS.get(cls, cls)}",
                     color=_CLASS_COLOURS.get(cls, "black"))
        if first is None or len(parts) > len(first[1]):
            first = (ax, parts)
        ys.append(ax.yaxis)
        ax.set_ylabel(f"[{units_text(units)}]", fontsize=7, labelpad=1.0)
        _time_axis(ax, x, labels=True, nbins=2 if w < 0.7 else 3)
        if k + cols >= len(panels):         # the lowest panel of its column
            ax.set_xlabel(t_label, labelpad=1.0)
    label_axes(ys)
    y = panels_h
    if first is not None:
        fig.legend(*_legend_order(first[0]), loc="upper center", frameon=False, fontsize=7,
                   ncol=4 if width >= PAGE_WIDTH else 2, handlelength=2.6,
                   columnspacing=1.2, borderaxespad=0.0, bbox_to_anchor=(0.5, 1 - y / H))
        _title_key(fig, y + legend_h, width, H)
        y += legend_h + title_h
    fig.text(0.1 / width, 1 - (y + 0.04) / H, note, fontsize=7, va="top", ha="left",
             linespacing=1.25)
    return fig


def d_panels(data: PlotData, dominance: Mapping[str, str], zero: Mapping[str, bool],
             prismatic: npt.NDArray[np.bool_] | None = None,
             armature: npt.NDArray[np.float64] | None = None) -> tuple[list[tuple[str, dict[str, Any], str, str]], list[str]]:
    """The panels of :func:`fig_D`: every D_ij, i <= j, that is not ≡ 0.

    Parameters
    ----------
    data, dominance, zero, prismatic, armature
        As for :func:`fig_D`.

    Returns
    -------
    panels : list of (str, dict, str, str)
        Label, parts (``tran``, ``rot``, ``total`` and, on a diagonal with armature,
        ``arm``: arrays (M,)), class and stored units, in reading order (row by row).
    zero_labels : list of str
        The elements left out.
    """
    Dt, Dr, D = (data.series[k] for k in ("D_tran", "D_rot", "D"))
    n = D.shape[1]
    panels, zeros = [], []
    for i in range(n):
        for j in range(i, n):
            label = element_label("D", i, j)
            if zero.get(label, False):
                zeros.append(label)
                continue
            parts = {"tran": Dt[:, i, j], "rot": Dr[:, i, j], "total": D[:, i, j]}
            if i == j and armature is not None and armature[i] > 0:
                parts["arm"] = np.full(np.shape(Dt[:, i, j]), float(armature[i]))
            panels.append((label, parts, dominance.get(label, ""),
                           element_units("D", i, j, prismatic)))
    return panels, zeros


def fig_D(data: PlotData, dominance: Mapping[str, str], zero: Mapping[str, bool], s: float,
          e: float, prismatic: npt.NDArray[np.bool_] | None = None, width: float = PAGE_WIDTH,
          armature: npt.NDArray[np.float64] | None = None, part: int = 0,
          first_rows: int | None = None, rows: Sequence[int] | None = None) -> Figure:
    """The analogue of Fig. 3.10: one panel per D_ij, i <= j, that is not ≡ 0.

    Parameters
    ----------
    data : PlotData
        With ``D_tran``, ``D_rot``, ``D`` (M, n, n) [kg m^2] and time x [s].
    dominance : dict of str to str
        Class of each element label (``"D12"`` -> ``"both"``).
    zero : dict of str to bool
        Elements zero in every part (round-off, :func:`identically_zero`): not drawn, named
        in the note below the panels.
    s, e : float
        Thresholds of the ranking, for the key.
    prismatic : ndarray of bool, shape (n,), optional
        Prismatic joints: each panel's y axis gives its units
        (:func:`gd_analyze.ranking.labels.element_units`: kg m², kg m or kg).
    width : float, optional
        :data:`PAGE_WIDTH` (panels of at least :data:`MIN_PANEL_W`, four a row) or
        :data:`COLUMN_WIDTH` [in] (three a row).
    armature : ndarray, shape (n,), optional
        The drives' armature [kg m^2]: drawn as a fourth part on the diagonal panels where
        nonzero, above the combined curve (which includes it).
    part : int, optional
        Which part of :func:`element_parts` to draw (0: the first).
    first_rows, rows : int, optional
        Rows of the first part and of each later part (:func:`element_parts`).

    Returns
    -------
    matplotlib.figure.Figure
        ``width`` wide, the panels in reading order (D11, D12, ..., D22, ...), each y axis
        labelled with its units and power of ten (``[10⁻³ kg m²]``); a marker at every set
        point for up to :data:`gd_analyze.report.figure_style.MARK_EVERY_POINT` of them;
        below, the parts' legend, the key of the title colours and a note naming the ≡ 0
        elements.
    """
    return _element_figure(data.x, *_d_part(data, dominance, zero, s, e, prismatic, width,
                                            armature, part, first_rows, rows))


def d_size(*args: Any, **kwargs: Any) -> tuple[float, float]:
    """The size of a part of the D figure as :func:`fig_D` plans it, without making it.

    Parameters
    ----------
    *args
        As for :func:`fig_D` (``data``, ``dominance``, ``zero``, ``s``, ``e``, ...).
    **kwargs
        As for :func:`fig_D` (``width``, ``armature``, ``part``, ``first_rows``, ``rows``).

    Returns
    -------
    (float, float)
        Width and height [in]: those of the figure :func:`fig_D` makes
        (``Figure.get_size_inches``).
    """
    panels, _, width, key = _d_part(*args, **kwargs)
    return width, _element_layout(panels, width, key)[-1]


def _d_part(data, dominance, zero, s, e, prismatic=None, width=PAGE_WIDTH, armature=None,
            part=0, first_rows=None, rows=None):
    """The panels of a part of :func:`fig_D`, the enveloped flag, the width and the key."""
    panels, zeros = d_panels(data, dominance, zero, prismatic, armature)
    chunks = element_parts([p[0] for p in panels], width, first_rows, rows)
    drawn = [p for p in panels if p[0] in set(chunks[part])]
    arm = any("arm" in p[1] for p in panels)
    key = say("element_key", symbol="D", s=f"{s:g}", e=f"{e:g}", arm=arm,
              zeros=", ".join(map(_math, zeros)), part=part + 1, parts=len(chunks))
    return drawn, data.enveloped, width, key


def fig_h(data: PlotData, dominance: Mapping[str, str], zero: Mapping[str, bool],
          prismatic: npt.NDArray[np.bool_] | None = None, width: float = PAGE_WIDTH) -> Figure:
    """The analogue of Fig. 3.11: one panel per h_i that is not ≡ 0, as large as those of
    :func:`fig_D`.

    Parameters
    ----------
    data : PlotData
        With ``h_tran``, ``h_rot``, ``h`` (M, n) [N m] and time x [s].
    dominance, zero : dict
        As for :func:`fig_D`.
    prismatic : ndarray of bool, shape (n,), optional
        Prismatic joints: their panels' axes read N, the others N m.
    width : float, optional
        :data:`PAGE_WIDTH` or :data:`COLUMN_WIDTH` [in].

    Returns
    -------
    matplotlib.figure.Figure
        As :func:`fig_D`: panels in rows, legend, title colours' key and the note below.
    """
    ht, hr, hh = (data.series[k] for k in ("h_tran", "h_rot", "h"))
    panels, zeros = [], []
    for i in range(hh.shape[1]):
        label = element_label("h", i)
        if zero.get(label, False):
            zeros.append(label)
            continue
        panels.append((label, {"tran": ht[:, i], "rot": hr[:, i], "total": hh[:, i]},
                       dominance.get(label, ""), element_units("h", i, None, prismatic)))
    key = say("element_key", symbol="h", zeros=", ".join(map(_math, zeros)))
    return _element_figure(data.x, panels, data.enveloped, width, key)


def fig_joints(data: PlotData, prismatic: npt.NDArray[np.bool_] | None = None,
               width: float = PAGE_WIDTH) -> Figure:
    """q, qd and qdd of every joint against time, side by side [deg, deg/s, deg/s^2].

    Parameters
    ----------
    data : PlotData
        With ``q``, ``qd``, ``qdd`` (M, n) [rad, rad/s, rad/s^2; m, m/s, m/s^2 for a prismatic
        joint] and time x [s].
    prismatic : ndarray of bool, shape (n,), optional
        Prismatic joints, drawn in mm (mm/s, mm/s^2) on panels of their own.
    width : float, optional
        :data:`PAGE_WIDTH` (three panels a row) or :data:`COLUMN_WIDTH` [in] (one panel a
        row).

    Returns
    -------
    matplotlib.figure.Figure
        One line per joint, told apart by colour, line style and marker (distinct for up to 7
        joints, :func:`gd_analyze.report.figure_style.joint_style`), legend on top; an arm with
        both joint types gets panels for its revolute joints [deg, deg/s, deg/s^2] and panels
        for its prismatic ones [mm, mm/s, mm/s^2]
        (:func:`gd_analyze.ranking.labels.joint_motion_units`), never two units on one axis.
    """
    n = data.series["q"].shape[1]
    prismatic = np.zeros(n, bool) if prismatic is None else np.asarray(prismatic, bool)
    kinds = [k for k in (False, True) if np.any(prismatic == k)]
    column = width < PAGE_WIDTH
    per_row = 1 if column else 3
    panels = [(kind, k) for kind in kinds for k in range(3)]
    rows = math.ceil(len(panels) / per_row)
    row_h, gap_h, bottom = (0.95, 0.42, 0.4) if column else (1.5, 0.55, 0.45)
    top = 0.25 + 0.16 * math.ceil(n / (3 if column else 7))
    W, H = width, top + rows * row_h + (rows - 1) * gap_h + bottom
    fig = new_figure(W, H)
    left, gap = 0.6, 0.55
    w = (W - left - 0.1 - (per_row - 1) * gap) / per_row
    symbols = ("q", "q\u0307", "q\u0308")
    origin, t_label = time_origin(data.x)
    x = np.asarray(data.x, dtype=float) - origin
    first: dict[Any, Any] = {}
    boxes = grid_boxes(fig, len(panels), per_row, (left, top), (w, row_h), (gap, gap_h))
    for (kind, k), box in zip(panels, boxes):
        joints = np.flatnonzero(prismatic == kind)
        scale = 1000.0 if kind else np.degrees(1.0)
        units = joint_motion_units(kind, shown=True)
        name = ("q", "qd", "qdd")[k]
        ax = fig.add_axes(box)
        y = data.series[name][:, joints] * scale
        for col, jn in enumerate(joints):
            style = joint_style(int(jn), 1 if data.enveloped else y.shape[0], len(joints))
            if data.enveloped:
                style = {k2: v for k2, v in style.items() if not k2.startswith("marker")}
            ax.plot(x, y[:, col], linewidth=0.9, label=f"joint {jn + 1}", **style)
        first.setdefault(kind, ax)
        _y_axis(ax, 4 if row_h > 1.2 else 3, y)
        _time_axis(ax, x, True)
        ax.set_xlabel(t_label, labelpad=1.0)
        ax.set_ylabel(f"{symbols[k]} [{units[k]}]", labelpad=1.0)
    label_axes([ax.yaxis for ax in fig.axes])
    # each column's y labels clear of the panel to their left, measured where the figure is
    # drawn (its text raised to the printed size: a q̈ axis's "−2000" needs more room)
    columns_apart(fig, [fig.axes[c::per_row] for c in range(per_row)], left, 0.1)
    fig.legend(*joint_key(list(first.values())), loc="upper center",
               ncol=min(n, 3 if column else 7), frameon=False, handlelength=3.0,
               columnspacing=1.2, bbox_to_anchor=(0.5, 1.0), fontsize=7 if column else 8)
    return fig


def fig_torque(data: PlotData, rel_error: npt.NDArray[np.float64],
               prismatic: npt.NDArray[np.bool_] | None = None) -> Figure:
    """tau of the full and of the simplified model per joint against time [N m].

    Parameters
    ----------
    data : PlotData
        With ``tau`` and ``tau_simplified`` (M, n) [N m].
    rel_error : ndarray, shape (n,)
        Peak |tau_s - tau| over peak |tau| [1], given in the titles (the table of the report
        gives the peak error too).
    prismatic : ndarray of bool, shape (n,), optional
        Prismatic joints, whose axes read N (the others N m).

    Returns
    -------
    matplotlib.figure.Figure
        7.2 in wide, three panels a row (:func:`gd_analyze.report.figure_style.joint_lines`).
    """
    tau, tau_s = data.series["tau"], data.series["tau_simplified"]
    n = tau.shape[1]
    units = [joint_torque_units(bool(prismatic[i])) if prismatic is not None else "N m"
             for i in range(n)]
    rel = [f"{100 * r:.2g} %" if np.isfinite(r) else "n/a" for r in rel_error]
    return joint_lines(data.x, [((_FULL, "-", 1.0, "full model \u03c4"), tau),
                                ((_SIMPLIFIED, "--", 1.2, "simplified model"), tau_s)],
                       [f"joint {i + 1}: peak error {rel[i]}" for i in range(n)],
                       [_math("\u03c4" + str(i + 1)) + f" [{units[i]}]" for i in range(n)],
                       PAGE_WIDTH, 3)


# --------------------------------------------------------------------------------------------
# The payload sweep, shown by the main report (``--payload-sweep``) and the sweep report
# --------------------------------------------------------------------------------------------
#: One letter per dominance class, drawn in the heat map's cells.
CLASS_LETTER = {"translational": "T", "rotational": "R", "both": "B", "negligible": "N"}


def payload_figure(ds: PayloadSweep | xr.Dataset, width: float = PAGE_WIDTH) -> Figure:
    """Translational share and dominance class of every element vs payload, and peak |tau| vs
    payload.

    Parameters
    ----------
    ds : xarray.Dataset
        A payload sweep from :func:`gd_analyze.jobs.payload.payload_sweep`: coordinate ``payload``
        (P,) [kg]; ``share_tran`` and ``dominance`` (payload, element); ``tau_peak``
        (payload, joint) [N m].
    width : float, optional
        :data:`PAGE_WIDTH` (payload down, elements across) or :data:`COLUMN_WIDTH` [in]
        (elements down, payload across: a row of 7-pt element labels per element).

    Returns
    -------
    matplotlib.figure.Figure
        ``width`` wide, type of at least 7 pt. Top: a heat map of the translational share
        over (payload, element) from rotational (0, orange) through 0.5 (white) to
        translational (1, blue), each cell marked with its class (T, R, B or N) and with a
        bold frame where the class differs from that at the first payload; grey where the
        element is round-off in every part (``round_off``: its share is noise); elements
        written D(1,2) (:func:`gd_analyze.report.markup.label`: no subscript under 8 pt).
        Bottom: peak |tau| per joint vs payload [N m, N for a prismatic joint]. A plain
        Figure (no pyplot state).

    Raises
    ------
    InputError
        If a variable the figure needs is missing.

    Notes
    -----
    The dominance of Sec. 3.4.1 of Fu, Gonzalez & Lee (1987) depends on the load the arm
    carries through link n's inertial parameters.
    """
    from matplotlib.colors import LinearSegmentedColormap
    from matplotlib.patches import Rectangle

    part = PayloadSweep.of(ds)
    column = width < PAGE_WIDTH
    import matplotlib

    with matplotlib.rc_context(SUPTITLE_RC):  # type: ignore[arg-type]  # keys typed as literals
        masses = part.masses
        labels = [_math(lab) for lab in part.elements]
        share = part.share_tran
        if part.round_off is not None:         # a share of round-off is noise: not drawn
            share = np.where(part.round_off, np.nan, share)
        dom = part.dominance.reshape(share.shape)
        P, M = share.shape
        n = len(part.prismatic)
        W = width
        s, e = (float(np.nan if v is None else v)
                for v in (part.dominance_threshold, part.negligible_threshold))
        title = say("payload_title", s=f"{s:g}", e=f"{e:g}")
        if column:          # bold 8 pt: about 44 characters a line; elements down, 7 pt a row
            title = textwrap.fill(title.replace("\n", "; "), 44)
            heat_h, top, left = 0.15 * M, 0.22 + 0.15 * (title.count("\n") + 1), 0.5
            tau_h, legend_h = 1.5, 0.2 + 0.16 * -(-n // 3)
            H = top + heat_h + 0.5 + tau_h + 0.42 + legend_h
            heat_w = W - left - 1.0
        else:
            heat_h, top, left = max(1.4, 0.3 * P), 0.75, 0.9
            tau_h = 2.6
            H = heat_h + 4.6
            heat_w = W - 2.0
        fig = new_figure(W, H)
        ax = fig.add_axes((left / W, (H - top - heat_h) / H, heat_w / W, heat_h / H))
        cmap = LinearSegmentedColormap.from_list(
            "rot_tran", [CLASS_COLOURS["rotational"], "#FFFFFF",
                         CLASS_COLOURS["translational"]]).with_extremes(bad="0.8")
        grid = share.T if column else share
        im = ax.imshow(np.ma.masked_invalid(grid), aspect="auto", cmap=cmap, vmin=0, vmax=1,
                       interpolation="nearest")
        for p in range(P):
            for k in range(M):
                v = share[p, k]
                dark = np.isfinite(v) and abs(v - 0.5) > 0.33
                x, y = (p, k) if column else (k, p)
                ax.text(x, y, CLASS_LETTER.get(dom[p, k], "?"), ha="center", va="center",
                        fontsize=7, color="white" if dark else "black")
                if dom[p, k] != dom[0, k]:
                    ax.add_patch(Rectangle((x - 0.5, y - 0.5), 1, 1, fill=False, lw=1.4,
                                           ec="black"))
        mass_ticks = [f"{m:g}" for m in masses]
        if column:
            ax.set_yticks(np.arange(M), labels, fontsize=7)
            ax.set_xticks(np.arange(P), mass_ticks, fontsize=7)
            ax.set_xlabel("payload [kg]", labelpad=1.0)
        else:
            ax.set_xticks(np.arange(M), labels, rotation=90, fontsize=7)
            ax.set_yticks(np.arange(P), mass_ticks, fontsize=7)
            ax.set_ylabel("payload [kg]")
        ax.tick_params(length=2.0, pad=1.5)
        ax.grid(False)
        cax = fig.add_axes(((left + heat_w + 0.12 if column else W - 0.95) / W,
                            (H - top - heat_h) / H, 0.12 / W, heat_h / H))
        cb = fig.colorbar(im, cax=cax)
        cb.set_label("translational share [1]")
        cb.ax.tick_params(labelsize=7)
        cb.ax.grid(False)                   # no grid lines across the colour scale
        bottom = 0.42 + legend_h if column else 0.6
        tau = part.tau_peak
        units = [joint_torque_units(p) for p in part.prismatic]
        kinds = list(dict.fromkeys(units))  # one panel per unit: never N m and N on one axis
        gap = 0.3
        each = (tau_h - gap * (len(kinds) - 1)) / len(kinds)
        for k, unit in enumerate(kinds):
            y0 = bottom + (len(kinds) - 1 - k) * (each + gap)
            bx = fig.add_axes((left / W, y0 / H, (heat_w if column else W - 2.0) / W, each / H))
            for j in (j for j in range(n) if units[j] == unit):    # style and marker differ
                bx.plot(masses, tau[:, j], label=f"joint {j + 1}", linewidth=0.9,
                        **joint_style(j, len(masses), sum(u == unit for u in units)))
            if k == len(kinds) - 1:
                bx.set_xlabel("payload [kg]", labelpad=1.0)
            else:
                bx.tick_params(labelbottom=False)
            bx.set_ylabel(f"peak |\u03c4| [{unit}]")
            bx.tick_params(labelsize=7)
        handles, names = joint_key(fig.axes[2:])      # the heat map and its colour bar first
        if column:
            fig.legend(handles, names, loc="upper center", ncol=3, frameon=False, fontsize=7,
                       handlelength=2.6, bbox_to_anchor=(0.5, legend_h / H))
        else:
            fig.legend(handles, names, loc="center left", frameon=False, fontsize=7,
                       bbox_to_anchor=((W - 1.05) / W, (bottom + tau_h / 2) / H))
        fig.suptitle(title, y=1 - 0.08 / H, va="top", fontsize=8 if column else 8.5)
        return fig


# --------------------------------------------------------------------------------------------
# The series the figures draw, read from the stored results file
# --------------------------------------------------------------------------------------------
#: Series longer than this are read and drawn as a min/max envelope per column.
ENVELOPE_THRESHOLD = 2000
#: Columns of the envelope of a long series (about 300 dpi on a panel).
ENVELOPE_COLUMNS = 400
#: Set points read per chunk when a long series is reduced.
READ_CHUNK = 32768


@dataclass(frozen=True)
class PlotData:
    """The series the figures draw, as stored or reduced to their envelope.

    Attributes
    ----------
    x : ndarray, shape (M,)
        Time [s] of each plotted point (M = N, or two points per envelope column).
    enveloped : bool
        True if the series are min/max envelopes (no markers are drawn).
    series : dict of str to ndarray
        ``q``, ``qd``, ``qdd``, ``h_tran``, ``h_rot``, ``h``, ``c``, ``tau``,
        ``tau_simplified``, ``tau_error``, ``D_tran_qdd``, ``D_rot_qdd`` (M, n) and
        ``D_tran``, ``D_rot``, ``D`` (M, n, n).
    N : int
        Set points stored.
    """

    x: np.ndarray
    enveloped: bool
    series: dict
    N: int


def _read(var, a, b):
    return np.asarray(var[a:b].values, dtype=float)


def _times_qdd(D, qdd):
    return np.einsum("tij,tj->ti", D, qdd)


#: Series computed from stored ones as they are read, per chunk: name -> (stored variables,
#: function of their chunks). ``tau_error`` = tau_s - tau; ``D_tran_qdd`` and ``D_rot_qdd``
#: = D^tran qdd and D^rot qdd (N, n), the inertial contributions to tau (Eq. (3.4-25)).
DERIVED = {"tau_error": (("tau_simplified", "tau"), operator.sub),
           "D_tran_qdd": (("D_tran", "qdd"), _times_qdd),
           "D_rot_qdd": (("D_rot", "qdd"), _times_qdd)}
#: Series read only if the dataset holds what they need (the torque contributions' figure).
OPTIONAL = ("c", "D_tran_qdd", "D_rot_qdd")


def _chunk(ds, v, a, b):
    if v in DERIVED:
        inputs, f = DERIVED[v]
        return f(*(_read(ds[k], a, b) for k in inputs))
    return _read(ds[v], a, b)


def _held(ds, v):
    return all(k in ds.variables for k in (DERIVED[v][0] if v in DERIVED else (v,)))


def plot_data(ds: xr.Dataset,
              names: Sequence[str] = ("q", "qd", "qdd", "D_tran", "D_rot", "D", "h_tran", "h_rot", "h", "tau", "tau_simplified", "tau_error", *OPTIONAL),
              columns: int = ENVELOPE_COLUMNS, threshold: int = ENVELOPE_THRESHOLD,
              chunk: int = READ_CHUNK, progress: Callable[[int], object] | None = None) -> PlotData:
    """Read the series to plot from a stored analysis, reduced if long.

    Parameters
    ----------
    ds : xarray.Dataset
        An opened results file (lazily loaded: only chunks are read) with ``t`` (N,) [s] and
        the variables ``names`` with first dimension ``setpoint``.
    names : sequence of str, optional
        The variables to read; ``tau_error``, ``D_tran_qdd`` and ``D_rot_qdd`` are derived
        from stored ones (:data:`DERIVED`), per chunk before the envelope; those of
        :data:`OPTIONAL` are left out if the dataset lacks what they need.
    columns : int, optional
        Columns of the envelope of a long series.
    threshold : int, optional
        Up to this many set points the series are read whole.
    chunk : int, optional
        Set points read at a time.
    progress : callable, optional
        Called with the number of set points read, per chunk (for a progress bar).

    Returns
    -------
    PlotData
        For N > threshold: per column of equal time, the minimum and the maximum of each series
        at the column's mid-time, in time order (2 * columns points); memory stays a few chunks
        whatever N is.
    """
    names = [v for v in names if v not in OPTIONAL or _held(ds, v)]
    t = np.asarray(ds[Var.T].values, dtype=float)
    N = t.size
    if threshold >= N:
        series = {v: _chunk(ds, v, 0, N) for v in names}
        if progress:
            progress(N)
        return PlotData(x=t, enveloped=False, series=series, N=N)
    t0, t1 = float(t[0]), float(t[-1])
    col = (np.minimum(((t - t0) * (columns / (t1 - t0))).astype(np.intp), columns - 1)
           if t1 > t0 else (np.arange(N) * columns) // N)
    lo: dict[str, Any] = dict.fromkeys(names)
    hi: dict[str, Any] = dict.fromkeys(names)
    for a in range(0, N, chunk):
        b = min(N, a + chunk)
        c = col[a:b]
        starts = np.flatnonzero(np.r_[True, c[1:] != c[:-1]])
        cols = c[starts]
        for v in names:
            y = _chunk(ds, v, a, b)
            if lo[v] is None:
                lo[v] = np.full((columns,) + y.shape[1:], np.nan)
                hi[v] = np.full((columns,) + y.shape[1:], np.nan)
            with np.errstate(invalid="ignore"):
                lo[v][cols] = np.fmin(lo[v][cols], np.fmin.reduceat(y, starts, axis=0))
                hi[v][cols] = np.fmax(hi[v][cols], np.fmax.reduceat(y, starts, axis=0))
        if progress:
            progress(b - a)
    used = np.unique(col)
    edges = np.linspace(t0, t1, columns + 1) if t1 > t0 else np.arange(columns + 1.0)
    mid = 0.5 * (edges[used] + edges[used + 1])
    x = np.repeat(mid, 2)
    series = {v: np.stack([lo[v][used], hi[v][used]], axis=1)      # (C, 2, ...): lo, hi
              .reshape((2 * used.size,) + lo[v].shape[1:]) for v in names}
    return PlotData(x=x, enveloped=True, series=series, N=N)
