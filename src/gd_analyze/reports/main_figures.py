"""Figures of the main report, sized for print: a 7.2-in page width or a 3.5-in column.

Every figure is a plain :class:`matplotlib.figure.Figure` drawn at the size it is printed at, with
type of at least 7 pt, so that it goes into a paper unscaled. The figures read *plot data*
(:class:`PlotData`): the stored series, or for long trajectories their min/max envelope per
column, which :func:`plot_data` reads from the stored file in chunks. They never see the full
dataset and never recompute the dynamics.

- ``joints``: q, qd, qdd against time [deg, deg/s, deg/s^2];
- ``D``: the n x n upper triangle of D_ij, translational (o), rotational (x) and combined (^)
  against time: the analogue of Fig. 3.10 of Fu, Gonzalez & Lee (1987), Sec. 3.4.1;
- ``h``: the n elements h_i the same way, on panels of the same size (Fig. 3.11);
- ``torque``: tau and tau_s against time per joint.

An element whose parts are all zero to rounding (:func:`identically_zero`) is drawn as an empty
panel reading "≡ 0": its share_tran is rounding noise and is not shown.
"""

from __future__ import annotations

import math

import numpy as np

from ..core.selection.ranking import (
    ROUND_OFF,
    element_label,
    element_units,
    identically_zero,  # noqa: F401  (the ranking's rule)
    joint_motion_units,
    joint_torque_units,
)
from .common import joint_style, panel_markevery
from .markup import label as _math
from .plot_data import (  # noqa: F401
    DERIVED,
    ENVELOPE_COLUMNS,
    ENVELOPE_THRESHOLD,
    READ_CHUNK,
    PlotData,
    plot_data,
)
from .ticks import decade_label, label_axes, set_ticks

__all__ = ["PAGE_WIDTH", "COLUMN_WIDTH", "ZERO_TOL", "PART_STYLE", "SHORT_CLASS", "PlotData", "plot_data",
           "identically_zero", "fig_D", "fig_h", "fig_joints", "fig_torque",
           "RC"]

#: Width of a figure spanning the text of a page [in] (two-column journals: 7.0-7.3).
PAGE_WIDTH = 7.2
#: Width of a one-column figure [in].
COLUMN_WIDTH = 3.5
#: An element is identically zero if all its parts stay below this fraction of its scale
#: (:data:`gd_analyze.core.selection.ranking.ROUND_OFF`).
ZERO_TOL = ROUND_OFF

#: matplotlib settings: 7 pt ticks, 8 pt titles and labels at print size.
RC = {
    "font.size": 8.0, "axes.titlesize": 8.0, "axes.labelsize": 8.0, "xtick.labelsize": 7.0,
    "ytick.labelsize": 7.0, "legend.fontsize": 8.0, "figure.titlesize": 9.0,
    "axes.linewidth": 0.6, "axes.grid": True, "grid.color": "0.88", "grid.linewidth": 0.5,
    "lines.linewidth": 0.9, "lines.markersize": 3.2, "xtick.major.size": 2.5,
    "ytick.major.size": 2.5, "xtick.major.pad": 1.5, "ytick.major.pad": 1.5,
    "axes.titlepad": 2.5, "axes.titley": 1.0, "svg.fonttype": "none", "pdf.fonttype": 3,
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
_ALL_MARKERS, _FEW_MARKERS = 100, 40

# Panel geometry of D and h [in].
_LEFT, _RIGHT, _WGAP, _HGAP, _TOP, _BOTTOM = 0.53, 0.06, 0.49, 0.3, 0.2, 0.36
_MIN_PANEL_W = 0.55
#: Least panel width of the column-width D figure [in]: three a row even with each panel's
#: units on its axis (a mixed arm), so that the figure fits a page (two a row: 13 in tall).
_MIN_COLUMN_PANEL_W = 0.5




def _figure(w, h):
    from matplotlib.figure import Figure

    return Figure(figsize=(w, h))


def _axes(fig, x, y, w, h):
    """Axes at (x, y) from the top left, of size w x h [in]."""
    W, H = fig.get_size_inches()
    return fig.add_axes((x / W, 1 - (y + h) / H, w / W, h / H))


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


#: Line widths of the parts: the combined curve thin, under the two parts it sums.
_PART_WIDTH = {"tran": 0.8, "rot": 0.8, "total": 0.55, "arm": 0.8}
#: Drawing order: the combined curve first, so that o and x stay visible on top of it.
_PART_ORDER = ("total", "tran", "rot")


def _plot(ax, x, y, part, enveloped):
    """One part of an element: the tran, rot and total curves of a panel together carry at
    most about :data:`gd_analyze.reports.common.MAX_MARKERS` markers (every k-th set point,
    :func:`gd_analyze.reports.common.panel_markevery`; the line through all of them); the
    armature curve has none (told apart by its colour and dash-dot line)."""
    style = PART_STYLE[part]
    kw = {"color": style["color"], "linestyle": style["linestyle"], "label": style["label"],
          "linewidth": _PART_WIDTH[part],
          "zorder": {"total": 2, "tran": 3, "rot": 4, "arm": 3}[part]}
    if not enveloped and part != "arm":
        every = panel_markevery(x.size, len(_PART_ORDER))
        kw["marker"] = style["marker"]
        start = {"tran": 0, "rot": every // 3, "total": (2 * every) // 3,
                 "arm": every // 2}[part]
        kw["markevery"] = (start, every) if every > 1 else 1
        kw["markersize"] = 2.6 if part == "total" else 3.2
        kw["markeredgewidth"] = 0.6 if part == "total" else 0.8    # open, not a blot
        if style["mfc"] is not None:
            kw["markerfacecolor"] = style["mfc"]
    return ax.plot(x, y, **kw)


def _time_axis(ax, x, labels, nbins=3):
    t0, t1 = float(x[0]), float(x[-1])
    pad = 0.03 * (t1 - t0) if t1 > t0 else 0.5
    ax.set_xlim(t0 - pad, t1 + pad)
    # within the drawn range: an envelope's first point is half a column after t = 0
    set_ticks(ax.xaxis, t0 - pad, t1 + pad, nbins, labels)


def _zero_panel(ax, x, title):
    ax.set_title(f"{_math(title)}: \u2261 0", color=_CLASS_COLOURS["negligible"], loc="center")
    ax.text(0.5, 0.5, "\u2261 0", transform=ax.transAxes, ha="center", va="center",
            fontsize=10, color="0.35")
    ax.set_ylim(-1, 1)
    ax.yaxis.set_ticks([])
    ax.grid(False)


def _element_panel(ax, x, parts, title, cls, enveloped, nbins=3):
    """Parts (tran, rot, total and, on a diagonal panel of an arm with drives, arm) of one
    element; y ticks placed, labelled by the figure
    (:func:`gd_analyze.reports.ticks.label_axes`: one notation per figure)."""
    by_part = dict(zip(("tran", "rot", "total", "arm"), parts))
    for part in _PART_ORDER + (("arm",) if "arm" in by_part else ()):
        _plot(ax, x, by_part[part], part, enveloped)
    lo, hi = _limits(*parts)
    ax.set_ylim(lo, hi)
    pad = (hi - lo) / 1.2 * 0.1
    set_ticks(ax.yaxis, lo + pad, hi - pad, nbins, labels=False)
    ax.set_title(f"{_math(title)}: {SHORT_CLASS.get(cls, cls)}", color=_CLASS_COLOURS.get(cls, "black"))


def _gaps(per_panel_units):
    """Horizontal gap between panels [in]: room for 7-char tick labels (``−2.5e−3``) and, when
    the panels' units differ (a mixed arm), each panel's unit label."""
    return _WGAP + (0.15 if per_panel_units else 0.0)


def _panel_width(n, width=PAGE_WIDTH, wgap=_WGAP):
    free = width - _LEFT - _RIGHT - (n - 1) * wgap
    return max(_MIN_PANEL_W, free / max(n, 1))


def _panel_height(w):
    return float(np.clip(0.7 * w, 0.5, 0.9))


def _shown(units):
    return units.replace("m2", "m\u00b2")


def _unit_label(ax, units):
    """The panel's units on its y axis, e.g. ``[kg m]`` (a mixed arm's panels differ)."""
    ax.set_ylabel(f"[{_shown(units)}]", fontsize=7, labelpad=1.0)


def _legend_order(ax):
    handles, labels = ax.get_legend_handles_labels()
    order = [PART_STYLE[p]["label"] for p in ("tran", "rot", "total", "arm")]
    pairs = sorted(zip(handles, labels), key=lambda p: order.index(p[1]))
    return [p[0] for p in pairs], [p[1] for p in pairs]


def _grid(count, width, wgap, min_w=0.55):
    """Columns and panel size [in] of ``count`` panels in reading order within ``width``."""
    cols = max(1, min(count, int((width - _LEFT - _RIGHT + wgap) / (min_w + wgap))))
    w = (width - _LEFT - _RIGHT - (cols - 1) * wgap) / cols
    return cols, w, _panel_height(w)


def fig_D(data, dominance, zero, s, e, prismatic=None, width=PAGE_WIDTH, armature=None):
    """The analogue of Fig. 3.10: one panel per D_ij, i <= j, on an n x n grid.

    Parameters
    ----------
    data : PlotData
        With ``D_tran``, ``D_rot``, ``D`` (M, n, n) [kg m^2] and time x [s].
    dominance : dict of str to str
        Class of each element label (``"D12"`` -> ``"both"``).
    zero : dict of str to bool
        Elements drawn as "≡ 0" panels (round-off in every part, :func:`identically_zero`).
    s, e : float
        Thresholds of the ranking, for the key.
    prismatic : ndarray of bool, shape (n,), optional
        Prismatic joints: each panel's y axis gives its units
        (:func:`gd_analyze.core.selection.labels.element_units`: kg m², kg m or kg); with one unit for
        all panels it is said once, in the key.
    width : float, optional
        :data:`PAGE_WIDTH` (the upper triangle, panel D_ij in row i, column j) or
        :data:`COLUMN_WIDTH` [in] (the panels in reading order, three a row, the key below).
    armature : ndarray, shape (n,), optional
        The drives' armature [kg m^2]: drawn as a fourth part on the diagonal panels where
        nonzero (the combined curve includes it).

    Returns
    -------
    matplotlib.figure.Figure
        ``width`` wide (wider for n >= 8 at page width, with panels of at least 0.55 in);
        at most :data:`gd_analyze.reports.common.MAX_MARKERS` markers per line; the combined
        curve drawn first and thin; y tick labels in one notation for the whole figure.
    """
    Dt, Dr, D = (data.series[k] for k in ("D_tran", "D_rot", "D"))
    n = D.shape[1]
    units = {element_label("D", i, j): element_units("D", i, j, prismatic)
             for i in range(n) for j in range(i, n)}
    mixed = len(set(units.values())) > 1
    wgap = _gaps(True)                  # as fig_h's: panels of one size in both figures
    column = width < PAGE_WIDTH and n > 2
    if column:                          # three a row: said-once units leave room for it
        wgap = _gaps(mixed)
        cols, w, h = _grid(len(units), width, wgap, _MIN_COLUMN_PANEL_W)
        rows = math.ceil(len(units) / cols)
        place = {lab: divmod(k, cols) for k, lab in enumerate(units)}
        H_panels = _TOP + rows * h + (rows - 1) * _HGAP + _BOTTOM
        W = width
    else:
        w = _panel_width(n, width, wgap)
        h = _panel_height(w)
        place = {element_label("D", i, j): (i, j) for i in range(n) for j in range(i, n)}
        W = _LEFT + _RIGHT + n * w + (n - 1) * wgap
        H_panels = _TOP + _BOTTOM + n * h + (n - 1) * _HGAP
    key = (f"{_math('D_ij')}"
           + ("" if mixed else f" [{_shown(next(iter(units.values())))}]")
           + " against time t [s]" + ("; units on each panel's axis" if mixed else "")
           + ("" if column else f"; panel {_math('D_ij')} in row i, column j")
           + f". Title: element and its class: tran(slational), rot(ational), both, "
           f"negl(igible) (s = {s:g}, e = {e:g}); \u2261\u00a00: zero in every part "
           f"(below {decade_label(ROUND_OFF)} of its scale).")
    H = H_panels + (1.05 if column else 0.0)
    fig = _figure(W, H)
    x = data.x
    first = None
    ys = []
    nb = 2 if h < 0.6 else 3
    for i in range(n):
        for j in range(i, n):
            label = element_label("D", i, j)
            r, c = place[label]
            ax = _axes(fig, _LEFT + c * (w + wgap), _TOP + r * (h + _HGAP), w, h)
            if zero.get(label, False):
                _zero_panel(ax, x, label)
            else:
                parts = (Dt[:, i, j], Dr[:, i, j], D[:, i, j])
                if i == j and armature is not None and armature[i] > 0:
                    parts += (np.full(np.shape(Dt[:, i, j]), float(armature[i])),)
                _element_panel(ax, x, parts, label, dominance.get(label, ""), data.enveloped,
                               nb)
                first = first or ax
                ys.append(ax.yaxis)
            if mixed:
                _unit_label(ax, units[label])
            bottom = i == j
            if column:                  # the lowest panel of its column
                bottom = not any(cc == c and rr == r + 1 for rr, cc in place.values())
            _time_axis(ax, x, labels=bottom, nbins=2 if w < 0.7 else 3)
            if bottom:
                ax.set_xlabel("t [s]", labelpad=1.0)
    label_axes(ys)
    if column:
        _key_below(fig, first, W, H, H_panels, key)
    else:
        _key(fig, first, n, w, h, W, H, key, wgap)
    return fig


def _key_below(fig, source, W, H, top, text):
    """Legend and key under the panels of a column-width figure."""
    import textwrap

    if source is None:
        return
    fig.legend(*_legend_order(source), loc="upper center", ncol=3, frameon=False,
               handlelength=2.4, columnspacing=1.0, bbox_to_anchor=(0.5, 1 - (top - 0.05) / H),
               borderaxespad=0.0, fontsize=7)
    chars = max(24, int((W - 0.2) / (7.0 * 0.52 / 72)))
    fig.text(0.1 / W, 1 - (top + 0.22) / H, textwrap.fill(text, chars), fontsize=7, va="top",
             ha="left", linespacing=1.25)


def _key(fig, source, n, w, h, W, H, text, wgap=_WGAP):
    import textwrap

    if source is None:
        return
    handles, labels = _legend_order(source)
    if n >= 3:
        width = (n // 2) * (w + wgap)
        y = _TOP + (n - n // 2) * (h + _HGAP) + 0.1
        fig.legend(handles, labels, loc="upper left", frameon=False, handlelength=2.6,
                   bbox_to_anchor=(0.05 / W, 1 - y / H), borderaxespad=0.0)
        chars = max(24, int(width / (7.0 * 0.55 / 72)))
        below = 0.62 + 0.16 * max(0, len(handles) - 3)     # the legend's height [in]
        fig.text(0.08 / W, 1 - (y + below) / H, textwrap.fill(text, chars), fontsize=7,
                 va="top", ha="left", linespacing=1.3)
    else:
        fig.legend(handles, labels, loc="lower center", ncol=3, frameon=False,
                   handlelength=2.6, bbox_to_anchor=(0.5, 0.0))


def fig_h(data, dominance, zero, prismatic=None, width=PAGE_WIDTH):
    """The analogue of Fig. 3.11: one panel per h_i, as large as the panels of :func:`fig_D`.

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
        n panels in rows (up to 7 a row at page width, 3 at column width), legend below; one
        tick notation per figure; at most about 12 markers per line.
    """
    ht, hr, hh = (data.series[k] for k in ("h_tran", "h_rot", "h"))
    n = hh.shape[1]
    units = [element_units("h", i, None, prismatic) for i in range(n)]
    wgap = _gaps(True)
    if width < PAGE_WIDTH:
        cols, w, h = _grid(n, width, wgap)
    else:
        w = _panel_width(n, width, wgap)
        h = _panel_height(w)
        cols = min(n, max(1, int((width - _LEFT - _RIGHT + wgap) / (w + wgap) + 1e-6)))
    rows = math.ceil(n / cols)
    W = max(width, _LEFT + _RIGHT + cols * w + (cols - 1) * wgap)
    hgap = _HGAP + 0.28
    H = _TOP + 0.62 + rows * h + (rows - 1) * hgap
    fig = _figure(W, H)
    first = None
    ys = []
    for i in range(n):
        r, c = divmod(i, cols)
        ax = _axes(fig, _LEFT + c * (w + wgap), _TOP + r * (h + hgap), w, h)
        label = element_label("h", i)
        if zero.get(label, False):
            _zero_panel(ax, data.x, label)
        else:
            _element_panel(ax, data.x, (ht[:, i], hr[:, i], hh[:, i]), label,
                           dominance.get(label, ""), data.enveloped, 2 if h < 0.6 else 3)
            first = first or ax
            ys.append(ax.yaxis)
        _unit_label(ax, units[i])
        _time_axis(ax, data.x, labels=True, nbins=2 if w < 0.7 else 3)
        ax.set_xlabel("t [s]", labelpad=1.0)
    label_axes(ys)
    if first is not None:
        fig.legend(*_legend_order(first), loc="lower center", ncol=3,
                   frameon=False, handlelength=2.6, bbox_to_anchor=(0.5, 0.02 / H))
    return fig


def fig_joints(data, prismatic=None, width=PAGE_WIDTH):
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
        joints, :func:`gd_analyze.reports.common.joint_style`), legend on top; an arm with
        both joint types gets panels for its revolute joints [deg, deg/s, deg/s^2] and panels
        for its prismatic ones [mm, mm/s, mm/s^2]
        (:func:`gd_analyze.core.selection.labels.joint_motion_units`), never two units on one axis.
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
    fig = _figure(W, H)
    left, gap = 0.6, 0.55
    w = (W - left - 0.1 - (per_row - 1) * gap) / per_row
    symbols = ("q", "q\u0307", "q\u0308")
    first = {}
    for p, (kind, k) in enumerate(panels):
        r, c = divmod(p, per_row)
        joints = np.flatnonzero(prismatic == kind)
        scale = 1000.0 if kind else np.degrees(1.0)
        units = joint_motion_units(kind, shown=True)
        name = ("q", "qd", "qdd")[k]
        ax = _axes(fig, left + c * (w + gap), top + r * (row_h + gap_h), w, row_h)
        y = data.series[name][:, joints] * scale
        for col, jn in enumerate(joints):
            style = joint_style(int(jn), 1 if data.enveloped else y.shape[0], len(joints))
            if data.enveloped:
                style = {k2: v for k2, v in style.items() if not k2.startswith("marker")}
            ax.plot(data.x, y[:, col], linewidth=0.9, label=f"joint {jn + 1}", **style)
        first.setdefault(kind, ax)
        lo, hi = _limits(y)
        ax.set_ylim(lo, hi)
        pad = (hi - lo) / 1.2 * 0.1
        set_ticks(ax.yaxis, lo + pad, hi - pad, 4 if row_h > 1.2 else 3, labels=False)
        _time_axis(ax, data.x, True)
        ax.set_xlabel("t [s]", labelpad=1.0)
        ax.set_ylabel(f"{symbols[k]} [{units[k]}]", labelpad=1.0)
    label_axes([ax.yaxis for ax in fig.axes])
    handles, labels = [], []
    for ax in first.values():
        hs, ls = ax.get_legend_handles_labels()
        handles, labels = handles + hs, labels + ls
    order = np.argsort([int(lab.split()[1]) for lab in labels])
    fig.legend([handles[o] for o in order], [labels[o] for o in order], loc="upper center",
               ncol=min(n, 3 if column else 7), frameon=False, handlelength=3.0,
               columnspacing=1.2, bbox_to_anchor=(0.5, 1.0), fontsize=7 if column else 8)
    return fig


def fig_torque(data, peak_error, rel_error, prismatic=None):
    """tau of the full and of the simplified model per joint against time [N m].

    Parameters
    ----------
    data : PlotData
        With ``tau`` and ``tau_simplified`` (M, n) [N m].
    peak_error, rel_error : ndarray, shape (n,)
        Peak |tau_s - tau| [N m] and the same over peak |tau| [1]; the titles give the
        latter (the table of the report gives both).
    prismatic : ndarray of bool, shape (n,), optional
        Prismatic joints, whose axes read N (the others N m).

    Returns
    -------
    matplotlib.figure.Figure
        7.2 in wide, three panels a row.
    """
    tau, tau_s = data.series["tau"], data.series["tau_simplified"]
    n = tau.shape[1]
    cols = min(n, 3)
    rows = math.ceil(n / cols)
    left, gap, hgap, w_h = 0.55, 0.5, 0.55, 1.05
    w = (PAGE_WIDTH - left - 0.1 - (cols - 1) * gap) / cols
    H = 0.3 + rows * w_h + (rows - 1) * hgap + 0.65
    fig = _figure(PAGE_WIDTH, H)
    for i in range(n):
        r, c = divmod(i, cols)
        ax = _axes(fig, left + c * (w + gap), 0.3 + r * (w_h + hgap), w, w_h)
        ax.plot(data.x, tau[:, i], color=_FULL, linestyle="-", linewidth=1.0,
                label="full model \u03c4")
        ax.plot(data.x, tau_s[:, i], color=_SIMPLIFIED, linestyle="--", linewidth=1.2,
                label="simplified model \u03c4\u209b")
        lo, hi = _limits(tau[:, i], tau_s[:, i])
        ax.set_ylim(lo, hi)
        pad = (hi - lo) / 1.2 * 0.1
        set_ticks(ax.yaxis, lo + pad, hi - pad, 3, labels=False)
        _time_axis(ax, data.x, True)
        ax.set_xlabel("t [s]", labelpad=1.0)
        units = joint_torque_units(bool(prismatic[i])) if prismatic is not None else "N m"
        ax.set_ylabel(_math("\u03c4" + str(i + 1)) + f" [{units}]", labelpad=1.0)
        rel = f"{100 * rel_error[i]:.2g} %" if np.isfinite(rel_error[i]) else "n/a"
        ax.set_title(f"joint {i + 1}: peak error {rel}")
    label_axes([ax.yaxis for ax in fig.axes])
    fig.legend(*fig.axes[0].get_legend_handles_labels(), loc="lower center", ncol=2,
               frameon=False, handlelength=2.6, bbox_to_anchor=(0.5, 0.0))
    return fig
