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
from dataclasses import dataclass

import numpy as np

from ..core.ranking import element_label, element_units, joint_motion_units, joint_torque_units
from .ticks import set_ticks

__all__ = ["PAGE_WIDTH", "COLUMN_WIDTH", "ZERO_TOL", "PART_STYLE", "SHORT_CLASS", "PlotData", "plot_data",
           "identically_zero", "fig_D", "fig_h", "fig_joints", "fig_torque",
           "RC"]

#: Width of a figure spanning the text of a page [in] (two-column journals: 7.0-7.3).
PAGE_WIDTH = 7.2
#: Width of a one-column figure [in].
COLUMN_WIDTH = 3.5
#: An element is identically zero if all its parts stay below this fraction of its scale.
ZERO_TOL = 1e-12
#: Series longer than this are read and drawn as a min/max envelope per column.
ENVELOPE_THRESHOLD = 2000
#: Columns of the envelope of a long series (about 300 dpi on a panel).
ENVELOPE_COLUMNS = 400
#: Set points read per chunk when a long series is reduced.
READ_CHUNK = 32768

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
_LEFT, _RIGHT, _WGAP, _HGAP, _TOP, _BOTTOM = 0.5, 0.06, 0.46, 0.3, 0.2, 0.36
_MIN_PANEL_W = 0.55


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
        ``q``, ``qd``, ``qdd``, ``h_tran``, ``h_rot``, ``h``, ``tau``, ``tau_simplified``
        (M, n) and ``D_tran``, ``D_rot``, ``D`` (M, n, n).
    N : int
        Set points stored.
    """

    x: np.ndarray
    enveloped: bool
    series: dict
    N: int


def _read(var, a, b):
    return np.asarray(var[a:b].values, dtype=float)


#: Series computed from stored ones as they are read: name -> (a, b), meaning a - b.
DERIVED = {"tau_error": ("tau_simplified", "tau")}


def _chunk(ds, v, a, b):
    if v in DERIVED:
        first, second = DERIVED[v]
        return _read(ds[first], a, b) - _read(ds[second], a, b)
    return _read(ds[v], a, b)


def plot_data(ds, names=("q", "qd", "qdd", "D_tran", "D_rot", "D", "h_tran", "h_rot", "h",
                          "tau", "tau_simplified", "tau_error"), columns=ENVELOPE_COLUMNS,
              threshold=ENVELOPE_THRESHOLD, chunk=READ_CHUNK, progress=None):
    """Read the series to plot from a stored analysis, reduced if long.

    Parameters
    ----------
    ds : xarray.Dataset
        An opened results file (lazily loaded: only chunks are read) with ``t`` (N,) [s] and
        the variables ``names`` with first dimension ``setpoint``.
    names : sequence of str, optional
        The variables to read; ``tau_error`` is tau_simplified - tau (:data:`DERIVED`), taken
        per chunk before the envelope.
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
    t = np.asarray(ds["t"].values, dtype=float)
    N = t.size
    if N <= threshold:
        series = {v: _chunk(ds, v, 0, N) for v in names}
        if progress:
            progress(N)
        return PlotData(x=t, enveloped=False, series=series, N=N)
    t0, t1 = float(t[0]), float(t[-1])
    if t1 > t0:
        col = np.minimum(((t - t0) * (columns / (t1 - t0))).astype(np.intp), columns - 1)
    else:
        col = (np.arange(N) * columns) // N
    lo = {v: None for v in names}
    hi = {v: None for v in names}
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
    series = {}
    for v in names:
        pair = np.stack([lo[v][used], hi[v][used]], axis=1)      # (C, 2, ...)
        series[v] = pair.reshape((2 * used.size,) + pair.shape[2:])
    return PlotData(x=x, enveloped=True, series=series, N=N)


def identically_zero(peak_tran, peak_rot, peak_total, scale, tol=ZERO_TOL):
    """Which elements are zero to rounding in every part along the trajectory.

    Parameters
    ----------
    peak_tran, peak_rot, peak_total : ndarray, shape (M,)
        Peak |part| of each element over the set points.
    scale : ndarray, shape (M,)
        Each element's own scale (peak sqrt(D_ii D_jj) [kg m^2] or peak |tau_i| [N m]).
    tol : float, optional
        The fraction of the scale below which a part counts as zero.

    Returns
    -------
    ndarray of bool, shape (M,)
        True where all three peaks are <= tol * scale (e.g. D45 and D56 of the PUMA 560, whose
        parts are about 1e-19; h when q̇ = 0).

    Examples
    --------
    >>> identically_zero(np.array([1e-19, 0.2]), np.array([2e-19, 0.1]),
    ...                  np.array([1e-19, 0.3]), np.array([1.0, 1.0])).tolist()
    [True, False]
    """
    peak = np.fmax(np.fmax(np.abs(peak_tran), np.abs(peak_rot)), np.abs(peak_total))
    return np.asarray(peak <= tol * np.abs(scale)) & np.isfinite(peak)


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


def _plot(ax, x, y, part, enveloped):
    style = PART_STYLE[part]
    kw = {"color": style["color"], "linestyle": style["linestyle"], "label": style["label"],
          "linewidth": 0.8}
    if not enveloped:
        kw["marker"] = style["marker"]
        if style["mfc"] is not None:
            kw["markerfacecolor"] = style["mfc"]
        if x.size > _ALL_MARKERS:
            kw["markevery"] = max(1, math.ceil(x.size / _FEW_MARKERS))
    return ax.plot(x, y, **kw)


def _time_axis(ax, x, labels, nbins=3):
    t0, t1 = float(x[0]), float(x[-1])
    pad = 0.03 * (t1 - t0) if t1 > t0 else 0.5
    ax.set_xlim(t0 - pad, t1 + pad)
    set_ticks(ax.xaxis, t0, t1, nbins, labels)


def _zero_panel(ax, x, title):
    ax.set_title(f"{title}: \u2261 0", color=_CLASS_COLOURS["negligible"], loc="center")
    ax.text(0.5, 0.5, "\u2261 0", transform=ax.transAxes, ha="center", va="center",
            fontsize=10, color="0.35")
    ax.set_ylim(-1, 1)
    ax.yaxis.set_ticks([])
    ax.grid(False)


def _element_panel(ax, x, parts, title, cls, enveloped, nbins=3):
    for part, y in zip(("tran", "rot", "total", "arm"), parts):
        _plot(ax, x, y, part, enveloped)
    lo, hi = _limits(*parts)
    ax.set_ylim(lo, hi)
    pad = (hi - lo) / 1.2 * 0.1
    set_ticks(ax.yaxis, lo + pad, hi - pad, nbins)
    ax.set_title(f"{title}: {SHORT_CLASS.get(cls, cls)}", color=_CLASS_COLOURS.get(cls, "black"))


def _panel_width(n):
    free = PAGE_WIDTH - _LEFT - _RIGHT - (n - 1) * _WGAP
    return max(_MIN_PANEL_W, free / max(n, 1))


def _panel_height(w):
    return float(np.clip(0.7 * w, 0.5, 0.9))


def _unit_label(ax, units):
    """The panel's units on its y axis, e.g. ``[kg m]`` (every panel: a mixed arm's differ)."""
    shown = units.replace("m2", "m\u00b2")
    ax.set_ylabel(f"[{shown}]", fontsize=7, labelpad=0.5)


def fig_D(data, dominance, zero, s, e, prismatic=None, armature=None):
    """The analogue of Fig. 3.10: one panel per D_ij, i <= j, on an n x n grid.

    Parameters
    ----------
    data : PlotData
        With ``D_tran``, ``D_rot``, ``D`` (M, n, n) [kg m^2] and time x [s].
    dominance : dict of str to str
        Class of each element label (``"D12"`` -> ``"both"``).
    zero : dict of str to bool
        Elements drawn as "≡ 0" panels.
    s, e : float
        Thresholds of the ranking, for the key.
    prismatic : ndarray of bool, shape (n,), optional
        Prismatic joints: each panel's y axis gives its units
        (:func:`gd_analyze.core.labels.element_units`: kg m², kg m or kg).
    armature : ndarray, shape (n,), optional
        The drives' armature [kg m^2]: drawn as a fourth part on the diagonal panels where
        nonzero (the combined curve includes it).

    Returns
    -------
    matplotlib.figure.Figure
        7.2 in wide for n <= 7 (wider for n >= 8, with panels of at least 0.55 in); panels of
        the same size as those of :func:`fig_h`; the legend and key in the empty lower left.
    """
    Dt, Dr, D = (data.series[k] for k in ("D_tran", "D_rot", "D"))
    n = D.shape[1]
    w = _panel_width(n)
    h = _panel_height(w)
    W = _LEFT + _RIGHT + n * w + (n - 1) * _WGAP
    H = _TOP + _BOTTOM + n * h + (n - 1) * _HGAP
    fig = _figure(W, H)
    x = data.x
    first = None
    for i in range(n):
        for j in range(i, n):
            ax = _axes(fig, _LEFT + j * (w + _WGAP), _TOP + i * (h + _HGAP), w, h)
            label = element_label("D", i, j)
            if zero.get(label, False):
                _zero_panel(ax, x, label)
            else:
                parts = (Dt[:, i, j], Dr[:, i, j], D[:, i, j])
                if i == j and armature is not None and armature[i] > 0:
                    parts += (np.full(np.shape(Dt[:, i, j]), float(armature[i])),)
                _element_panel(ax, x, parts, label,
                               dominance.get(label, ""), data.enveloped, 2 if h < 0.6 else 3)
                first = first or ax
            _unit_label(ax, element_units("D", i, j, prismatic))
            _time_axis(ax, x, labels=i == j, nbins=2 if w < 0.7 else 3)
            if i == j:
                ax.set_xlabel("t [s]", labelpad=1.0)
    _key(fig, first, n, w, h, W, H,
         f"D_ij against time t [s], units on each panel's axis; panel D_ij in row i, "
         f"column j. Title: "
         f"element and its class: tran(slational), rot(ational), both, negl(igible) "
         f"(s = {s:g}, e = {e:g}); \u2261\u00a00: zero in every part.")
    return fig


def _key(fig, source, n, w, h, W, H, text):
    import textwrap

    if source is None:
        return
    handles, labels = source.get_legend_handles_labels()
    if n >= 3:
        width = (n // 2) * (w + _WGAP)
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


def fig_h(data, dominance, zero, prismatic=None):
    """The analogue of Fig. 3.11: one panel per h_i, as large as the panels of :func:`fig_D`.

    Parameters
    ----------
    data : PlotData
        With ``h_tran``, ``h_rot``, ``h`` (M, n) [N m] and time x [s].
    dominance, zero : dict
        As for :func:`fig_D`.
    prismatic : ndarray of bool, shape (n,), optional
        Prismatic joints: their panels' axes read N, the others N m.

    Returns
    -------
    matplotlib.figure.Figure
        n panels in one row (up to 7, more rows beyond), legend below.
    """
    ht, hr, hh = (data.series[k] for k in ("h_tran", "h_rot", "h"))
    n = hh.shape[1]
    w = _panel_width(n)
    h = _panel_height(w)
    cols = min(n, max(1, int((PAGE_WIDTH - _LEFT - _RIGHT + _WGAP) / (w + _WGAP) + 1e-6)))
    rows = math.ceil(n / cols)
    W = max(PAGE_WIDTH, _LEFT + _RIGHT + cols * w + (cols - 1) * _WGAP)
    hgap = _HGAP + 0.28
    H = _TOP + 0.62 + rows * h + (rows - 1) * hgap
    fig = _figure(W, H)
    first = None
    for i in range(n):
        r, c = divmod(i, cols)
        ax = _axes(fig, _LEFT + c * (w + _WGAP), _TOP + r * (h + hgap), w, h)
        label = element_label("h", i)
        if zero.get(label, False):
            _zero_panel(ax, data.x, label)
        else:
            _element_panel(ax, data.x, (ht[:, i], hr[:, i], hh[:, i]), label,
                           dominance.get(label, ""), data.enveloped, 2 if h < 0.6 else 3)
            first = first or ax
        _unit_label(ax, element_units("h", i, None, prismatic))
        _time_axis(ax, data.x, labels=True, nbins=2 if w < 0.7 else 3)
        ax.set_xlabel("t [s]", labelpad=1.0)
    if first is not None:
        fig.legend(*first.get_legend_handles_labels(), loc="lower center", ncol=3,
                   frameon=False, handlelength=2.6, bbox_to_anchor=(0.5, 0.02 / H))
    fig.text(0.08 / W, 1 - (_TOP + h / 2) / H, "h_i", rotation=90, va="center",
             ha="left", fontsize=8)
    return fig


def fig_joints(data, prismatic=None):
    """q, qd and qdd of every joint against time, side by side [deg, deg/s, deg/s^2].

    Parameters
    ----------
    data : PlotData
        With ``q``, ``qd``, ``qdd`` (M, n) [rad, rad/s, rad/s^2; m, m/s, m/s^2 for a prismatic
        joint] and time x [s].
    prismatic : ndarray of bool, shape (n,), optional
        Prismatic joints, drawn in mm (mm/s, mm/s^2) on panels of their own.

    Returns
    -------
    matplotlib.figure.Figure
        7.2 in wide, three panels a row, one line per joint (colour and line style), legend
        on top; an arm with both joint types gets a row for its revolute joints [deg, deg/s,
        deg/s^2] and a row for its prismatic ones [mm, mm/s, mm/s^2]
        (:func:`gd_analyze.core.labels.joint_motion_units`), never two units on one axis.
    """
    n = data.series["q"].shape[1]
    prismatic = np.zeros(n, bool) if prismatic is None else np.asarray(prismatic, bool)
    kinds = [k for k in (False, True) if np.any(prismatic == k)]
    row_h, top, gap_h, bottom = 1.5, 0.55, 0.55, 0.45
    W, H = PAGE_WIDTH, top + len(kinds) * row_h + (len(kinds) - 1) * gap_h + bottom
    fig = _figure(W, H)
    left, gap = 0.55, 0.55
    w = (W - left - 0.1 - 2 * gap) / 3
    styles = ["-", "--", ":", "-."]
    from matplotlib import colormaps

    cmap = colormaps["tab10"]
    symbols = ("q", "q\u0307", "q\u0308")
    for r, kind in enumerate(kinds):
        joints = np.flatnonzero(prismatic == kind)
        scale = 1000.0 if kind else np.degrees(1.0)
        units = joint_motion_units(kind, shown=True)
        for k, name in enumerate(("q", "qd", "qdd")):
            ax = _axes(fig, left + k * (w + gap), top + r * (row_h + gap_h), w, row_h)
            y = data.series[name][:, joints] * scale
            for col, jn in enumerate(joints):
                ax.plot(data.x, y[:, col], color=cmap(jn % 10), linestyle=styles[jn % 4],
                        linewidth=0.9, label=f"joint {jn + 1}")
            lo, hi = _limits(y)
            ax.set_ylim(lo, hi)
            pad = (hi - lo) / 1.2 * 0.1
            set_ticks(ax.yaxis, lo + pad, hi - pad, 4)
            _time_axis(ax, data.x, True)
            ax.set_xlabel("t [s]", labelpad=1.0)
            ax.set_ylabel(f"{symbols[k]} [{units[k]}]", labelpad=1.0)
    handles, labels = [], []
    for r in range(len(kinds)):
        hs, ls = fig.axes[3 * r].get_legend_handles_labels()
        handles, labels = handles + hs, labels + ls
    order = np.argsort([int(lab.split()[1]) for lab in labels])
    fig.legend([handles[o] for o in order], [labels[o] for o in order], loc="upper center",
               ncol=min(n, 7), frameon=False, handlelength=2.4, bbox_to_anchor=(0.5, 1.0))
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
        set_ticks(ax.yaxis, lo + pad, hi - pad, 3)
        _time_axis(ax, data.x, True)
        ax.set_xlabel("t [s]", labelpad=1.0)
        units = joint_torque_units(bool(prismatic[i])) if prismatic is not None else "N m"
        ax.set_ylabel(f"\u03c4{i + 1} [{units}]", labelpad=1.0)
        rel = f"{100 * rel_error[i]:.2g} %" if np.isfinite(rel_error[i]) else "n/a"
        ax.set_title(f"joint {i + 1}: peak error {rel}")
    fig.legend(*fig.axes[0].get_legend_handles_labels(), loc="lower center", ncol=2,
               frameon=False, handlelength=2.6, bbox_to_anchor=(0.5, 0.0))
    return fig
