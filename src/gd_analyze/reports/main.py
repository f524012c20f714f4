"""Report: the stored analysis as one self-contained HTML file and a PDF.

The report reads a results file written by the main job
(:func:`gd_analyze.workflows.analyze.analyze_to_file`) and never
recomputes the dynamics: every number and curve comes from the dataset's variables and global
attributes. It has seven parts:

1. the robot (DH table, link inertial parameters) and the trajectory, with joint plots;
2. the acceleration-related elements of D, translational, rotational and combined, one panel per
   element with i <= j (the analogue of Fig. 3.10 of Fu, Gonzalez & Lee 1987, Sec. 3.4.1);
3. the Coriolis and centrifugal elements of h (the analogue of Fig. 3.11);
4. the dominance ranking;
5. the simplified model and its torque error;
6. a comparison with the dominance the chapter reports for its PUMA 560 trajectory;
7. the provenance.

``report.html`` is one file with no external resources: the figures are inline SVG and the style
sheet is inline. ``report.pdf`` is written with matplotlib's PdfPages; its text pages are
matplotlib figures too. Both are written atomically (:func:`gd_analyze.files.atomic_path`).

Long trajectories are drawn through one helper that reduces a series of more than
:data:`ENVELOPE_THRESHOLD` points to its min/max envelope (:func:`envelope`), one pair per pixel
column of the panel at 300 dpi and at most :data:`ENVELOPE_COLUMNS` columns, without markers, so
the figures, and the HTML, stay small whatever the number of set points (about 0.7 MB of HTML
for 100,000 set points of a 6-joint arm).
"""

from __future__ import annotations

import contextlib
import datetime
import os
import math
import textwrap
from pathlib import Path

import numpy as np

from .common import A4 as _A4, A4_LANDSCAPE as _A4_LANDSCAPE
from .common import CLASS_COLOURS as _CLASS_COLOURS, SUPTITLE_RC
from .common import attr as _attr, check as _check, fmt as _fmt, pct as _pct
from .common import gridspec as _gridspec, strings as _strings, style as _style
from .common import table as _table, thresholds as _thresholds
from .common import check_formats, grid_shape, inline_svgs, joint_colours, render_template
from .common import utc_now
from ..io.sweep_datasets import payload_part

__all__ = [
    "REPORT_FORMATS", "ENVELOPE_THRESHOLD", "ENVELOPE_COLUMNS", "envelope", "make_figures",
    "render_html", "render_pdf", "write_report",
]

#: The formats :func:`write_report` can write.
REPORT_FORMATS = ("html", "pdf")
#: Series longer than this are drawn as a min/max envelope, without markers.
ENVELOPE_THRESHOLD = 2000
#: Columns of the min/max envelope (at most two points each).
ENVELOPE_COLUMNS = 1000
#: Series of at most this many points are drawn with a marker at every point.
_ALL_MARKERS = 100
#: Series up to ENVELOPE_THRESHOLD points are drawn with about this many markers.
_FEW_MARKERS = 40
#: Pixel columns per inch of axes width for the envelope (print resolution).
_PRINT_DPI = 300

# Colour-blind-safe colours (Okabe & Ito), used the same way in every figure and table.
_PART = {
    "tran": {"color": "#0072B2", "marker": "o", "linestyle": "-",
             "label": "translational effect", "mfc": "none"},
    "rot": {"color": "#D55E00", "marker": "x", "linestyle": "--",
            "label": "rotational effect", "mfc": None},
    "total": {"color": "#000000", "marker": "^", "linestyle": ":",
              "label": "combined effect", "mfc": "none"},
}
_AGREE_COLOURS = {"yes": "#007A4D", "no": "#B00020"}
_FULL_COLOUR, _SIMPLIFIED_COLOUR = "#000000", "#009E73"

# matplotlib settings of every figure; a fixed title position: no per-draw placement.
_RC = {**SUPTITLE_RC, "lines.markersize": 3.5, "axes.titley": 1.0, "axes.titlepad": 2.5}

_REQUIRED = ("t", "q", "qd", "qdd", "D_tran", "D_rot", "D", "h_tran", "h_rot", "h", "tau",
             "tau_simplified", "share_tran", "dominance", "chapter_dominance", "choice",
             "peak_tran", "peak_rot", "peak_total", "tau_error_peak", "tau_error_rms",
             "tau_peak", "tau_error_relative_peak", "tau_error_relative_rms", "dh_d", "dh_a",
             "dh_alpha", "dh_offset", "link_mass", "link_com", "link_inertia")

_DERIVATIVES = {
    "file": "read from the file (columns qd1..qdn, qdd1..qddn)",
    "cubic-spline": "derived from q by a not-a-knot cubic spline",
    "quintic": "analytic derivatives of a planned quintic motion",
}
_CHOICE_TEXT = {"tran": "translational part only", "rot": "rotational part only",
                "both": "translational + rotational", "none": "dropped (negligible)"}


# --------------------------------------------------------------------------------------------
# Plotting helpers
# --------------------------------------------------------------------------------------------

def envelope(x, y, columns=ENVELOPE_COLUMNS):
    """Reduce a series to its min/max envelope over equal-width columns of x.

    Parameters
    ----------
    x : array_like, shape (N,)
        Abscissae, e.g. time [s] or set point index; sorted here if they are not.
    y : array_like, shape (N,)
        Ordinates, any units; NaN values are ignored.
    columns : int, optional
        Number of columns (think of pixel columns) the range of x is cut into.

    Returns
    -------
    xe, ye : ndarray, shape (M,)
        The points of the series that are the minimum or the maximum of their column, plus the
        first and the last point, in order of x; M <= 2 * columns + 2. The global minimum and
        maximum of y are kept exactly. If N <= 2 * columns the series is returned unchanged
        (as float copies).

    Raises
    ------
    ValueError
        If x and y are not 1-D of the same length, or columns < 1.

    Notes
    -----
    Plotting the envelope instead of every point keeps figures of long trajectories small and
    fast while drawing the same band a full plot would show at print resolution. Used for the
    panels of the analogues of Figs. 3.10 and 3.11 (Sec. 3.4.1).
    """
    x = np.asarray(x, dtype=float)
    y = np.asarray(y, dtype=float)
    if x.ndim != 1 or x.shape != y.shape:
        raise ValueError(f"x and y must be 1-D of the same length, got {x.shape} and {y.shape}")
    columns = int(columns)
    if columns < 1:
        raise ValueError(f"columns must be >= 1, got {columns}")
    N = x.size
    if N <= 2 * columns:
        return x.copy(), y.copy()
    if np.any(np.diff(x) < 0):
        order = np.argsort(x, kind="stable")
        x, y = x[order], y[order]
    x0, x1 = x[0], x[-1]
    if np.isfinite(x0) and np.isfinite(x1) and x1 > x0:
        col = np.minimum(((x - x0) * (columns / (x1 - x0))).astype(np.intp), columns - 1)
    else:                                   # degenerate or non-finite x: equal counts
        col = (np.arange(N) * columns) // N
    starts = np.flatnonzero(np.r_[True, col[1:] != col[:-1]])
    seg = np.repeat(np.arange(starts.size), np.diff(np.r_[starts, N]))
    with np.errstate(invalid="ignore"):
        ymin = np.fmin.reduceat(y, starts)
        ymax = np.fmax.reduceat(y, starts)

    def first_hit(target):
        hit = np.flatnonzero(y == target[seg])          # NaN never matches
        found, first = np.unique(seg[hit], return_index=True)
        idx = starts.copy()                             # an all-NaN column: its first point
        idx[found] = hit[first]
        return idx

    idx = np.unique(np.concatenate([first_hit(ymin), first_hit(ymax), [0, N - 1]]))
    return x[idx], y[idx]


def _plot_series(ax, x, y, *, marker=None, threshold=ENVELOPE_THRESHOLD, columns=None,
                 **kwargs):
    """Plot one series on ``ax``: every point if short, its min/max envelope if long.

    Above ``threshold`` points the series is reduced by :func:`envelope` to one min/max pair
    per pixel column of the axes at print resolution (``_PRINT_DPI``), at most
    :data:`ENVELOPE_COLUMNS` columns, and drawn without markers. Markers are drawn at every
    point up to ``_ALL_MARKERS`` points and at about ``_FEW_MARKERS`` of them up to
    ``threshold`` points.
    """
    x = np.asarray(x, dtype=float)
    y = np.asarray(y, dtype=float)
    N = x.size
    if N > threshold:
        if columns is None:
            width = ax.get_position().width * ax.get_figure().get_size_inches()[0]
            columns = int(min(ENVELOPE_COLUMNS, max(100, width * _PRINT_DPI)))
        x, y = envelope(x, y, columns)
        marker = None
    elif marker is not None and N > _ALL_MARKERS:
        kwargs.setdefault("markevery", max(1, math.ceil(N / _FEW_MARKERS)))
    if marker is None:
        kwargs.pop("markerfacecolor", None)
        kwargs.pop("mfc", None)
    return ax.plot(x, y, marker=marker, **kwargs)


def _part_kwargs(part):
    spec = _PART[part]
    kw = {"color": spec["color"], "marker": spec["marker"], "linestyle": spec["linestyle"],
          "label": spec["label"], "linewidth": 0.8}
    if spec["mfc"] is not None:
        kw["markerfacecolor"] = spec["mfc"]
    return kw


# --------------------------------------------------------------------------------------------
# Figures
# --------------------------------------------------------------------------------------------

def make_figures(ds):
    """Make the report's figures from a stored analysis.

    Parameters
    ----------
    ds : xarray.Dataset
        A dataset as :func:`gd_analyze.io.datasets.build_dataset` makes it (N set points, n joints):
        t (N,) [s]; q, qd, qdd (N, n) [rad, rad/s, rad/s^2]; D_tran, D_rot, D (N, n, n)
        [kg m^2]; h_tran, h_rot, h, tau, tau_simplified (N, n) [N m]; dominance (M,).

    Returns
    -------
    dict of str to matplotlib.figure.Figure
        ``"joints"``: q, qd, qdd vs t in [deg], [deg/s], [deg/s^2], one panel each;
        ``"D"``: one panel per element D_ij, i <= j, on an n x n grid with the lower triangle
        empty, translational ('o'), rotational ('x') and combined ('^') effect over the set
        points (analogue of Fig. 3.10); ``"h"``: the same for h_i (analogue of Fig. 3.11);
        ``"torque"``: tau and tau_simplified vs t [N m], one panel per joint;
        ``"payload"`` (if the dataset holds a payload sweep): share_tran and class per element
        against the load mass, and peak |tau| per joint;
        ``"formulations"`` (if the dataset holds the operation counts): multiplications and
        additions per set point against n, log-log, for L-E, N-E and G-D as implemented, with
        the formulas of Table 3.5 beside them.
        The figures are plain :class:`matplotlib.figure.Figure` objects (no pyplot state).

    Raises
    ------
    KeyError
        If a variable the figures need is missing from ``ds``.

    Notes
    -----
    Source: Sec. 3.4.1 and Figs. 3.10-3.11 of Fu, Gonzalez & Lee (1987). Series of more than
    :data:`ENVELOPE_THRESHOLD` points are drawn as their min/max envelope (:func:`envelope`).
    """
    with _style(_RC):
        from .simplified_section import error_figure, has_simplified

        figures = {"joints": _fig_joints(ds), "D": _fig_D(ds), "h": _fig_h(ds),
                   "torque": error_figure(ds) if has_simplified(ds) else _fig_torque(ds)}
        if "op_multiplications" in ds.variables:
            figures["formulations"] = _fig_formulations(ds)
        if "payload_share_tran" in ds.variables:
            from .figures import payload_figure

            figures["payload"] = payload_figure(payload_part(ds))
        return figures


def _dominance_of(ds):
    return dict(zip(_strings(ds["element"].values), _strings(ds["dominance"].values)))


def _element_title(ax, label, cls):
    ax.set_title(f"{label}: {cls}", color=_CLASS_COLOURS.get(cls, "black"), pad=2.5)


def _formatter():
    from matplotlib.ticker import Formatter

    class _TickFormatter(Formatter):
        """Tick labels with just enough digits to tell the ticks apart, and no offset text
        (an offset text would collide with the panel titles)."""

        def __call__(self, x, pos=None):
            return self.format_ticks([x])[0]

        def format_ticks(self, values):
            v = np.asarray(values, dtype=float)
            if v.size == 0:
                return []
            big = float(np.max(np.abs(v)))
            if big == 0 or not np.isfinite(big):
                return ["0" if x == 0 else f"{x:g}" for x in v]
            u = np.unique(v)
            step = float(np.min(np.diff(u))) if u.size > 1 else big
            step = max(step, big * 1e-12)
            if np.all(v == np.round(v)) and big < 1e7:
                out = [f"{x:.0f}" for x in v]
            elif 1e-3 <= big < 1e5:
                dec = max(0, int(-np.floor(np.log10(step) + 1e-9)))
                out = [f"{x:.{dec}f}" for x in v]
            else:
                dig = max(0, int(np.floor(np.log10(big) + 1e-9) - np.floor(np.log10(step)
                                                                          + 1e-9)))
                out = [f"{x:.{dig}e}".replace("e-0", "e-").replace("e+0", "e").replace("e+", "e")
                       for x in v]
            return ["0" if float(s) == 0 else s.replace("-", "\u2212") for s in out]

    return _TickFormatter()


def _ticks(ax, xbins=5, ybins=4, integer_x=False):
    from matplotlib.ticker import MaxNLocator

    ax.xaxis.set_major_locator(MaxNLocator(nbins=xbins, integer=integer_x))
    ax.yaxis.set_major_locator(MaxNLocator(nbins=ybins))
    ax.xaxis.set_major_formatter(_formatter())
    ax.yaxis.set_major_formatter(_formatter())
    ax.tick_params(length=2.5, pad=1.5)


def _labels(ax, xlabel=None, ylabel=None, xoff=0.27, yoff=0.5):
    """Axis labels at fixed offsets [in] from the axes (no per-draw label placement)."""
    from matplotlib.transforms import offset_copy

    fig = ax.get_figure()
    ax.xaxis.set_label_coords(0.5, 0.0, transform=offset_copy(ax.transAxes, fig=fig, x=0.0,
                                                                y=-xoff, units="inches"))
    ax.yaxis.set_label_coords(0.0, 0.5, transform=offset_copy(ax.transAxes, fig=fig, x=-yoff,
                                                                y=0.0, units="inches"))
    if xlabel:
        ax.set_xlabel(xlabel)
    if ylabel:
        ax.set_ylabel(ylabel)


def _fig_joints(ds):
    from matplotlib.figure import Figure

    t = ds["t"].values
    n = ds.sizes["joint"]
    colours = joint_colours(n)
    fig = Figure(figsize=(_A4[0], 8.0))
    gs = _gridspec(fig, 3, 1, left=0.9, right=0.25, top=0.95, bottom=0.55, wgap=0, hgap=0.22)
    spec = (("q", "joint position q [deg]"), ("qd", "joint velocity q\u0307 [deg/s]"),
            ("qdd", "joint acceleration q\u0308 [deg/s\u00b2]"))
    axes = []
    for r, (name, ylabel) in enumerate(spec):
        ax = fig.add_subplot(gs[r, 0], sharex=axes[0] if axes else None)
        values = np.degrees(ds[name].values)
        for k in range(n):
            _plot_series(ax, t, values[:, k], color=colours[k], label=f"joint {k + 1}")
        _ticks(ax, xbins=8, ybins=6)
        _labels(ax, "time t [s]" if r == 2 else None, ylabel, xoff=0.2, yoff=0.55)
        ax.tick_params(labelbottom=r == 2)
        axes.append(ax)
    if t[-1] > t[0]:
        axes[0].set_xlim(t[0], t[-1])
    fig.legend(*axes[0].get_legend_handles_labels(), loc="upper center",
               bbox_to_anchor=(0.5, 1 - 0.45 / 8.0), ncol=min(n, 6), frameon=False)
    fig.suptitle("Joint trajectory", y=1 - 0.15 / 8.0, va="top")
    return fig


def _fig_D(ds):
    from matplotlib.figure import Figure

    n = ds.sizes["joint"]
    x = ds["setpoint"].values
    dom = _dominance_of(ds)
    D_tran, D_rot, D = ds["D_tran"].values, ds["D_rot"].values, ds["D"].values
    W, H = _A4_LANDSCAPE
    fig = Figure(figsize=_A4_LANDSCAPE)
    gs = _gridspec(fig, n, n, left=0.85, right=0.2, top=0.6, bottom=0.5, wgap=0.5, hgap=0.3)
    first = None
    for i in range(n):
        for j in range(i, n):
            ax = fig.add_subplot(gs[i, j], sharex=first)
            first = first or ax
            for part, y in (("tran", D_tran[:, i, j]), ("rot", D_rot[:, i, j]),
                            ("total", D[:, i, j])):
                _plot_series(ax, x, y, **_part_kwargs(part))
            label = f"D{i + 1}{j + 1}"
            _element_title(ax, label, dom.get(label, ""))
            _ticks(ax, xbins=4, ybins=4, integer_x=True)
            _labels(ax, "set point" if i == j else None, None, xoff=0.16)
            ax.tick_params(labelbottom=(i == j))
    if n > 1:   # legend and key in the empty lower triangle
        k = n // 2
        lax = fig.add_subplot(gs[k:, :k])
        lax.axis("off")
        handles, labels = first.get_legend_handles_labels()
        lax.legend(handles, labels, loc="upper left", bbox_to_anchor=(0.0, 0.85),
                   frameon=False, fontsize=9, markerscale=1.5, handlelength=3)
        lax.text(0.0, 0.4, _D_key(ds), transform=lax.transAxes, va="top", ha="left",
                 fontsize=8, linespacing=1.4)
    else:
        first.legend(frameon=False)
    if x[-1] > x[0]:
        first.set_xlim(x[0], x[-1])
    fig.supylabel("element of D [kg m\u00b2]", x=0.15 / W, ha="left")
    fig.suptitle("Acceleration-related elements of D along the trajectory "
                 "(analogue of Fig. 3.10)", y=1 - 0.15 / H, va="top")
    return fig


def _D_key(ds):
    s, e = _thresholds(ds)
    return textwrap.fill(
        "D_ij = D_ij(tran) + D_ij(rot). Panel D_ij: row i, column j (i \u2264 j). Title: "
        f"element and its dominance class (s = {s:g}, e = {e:g}). x: set point index; "
        "y: kg m\u00b2, own scale per panel.", 55)


def _fig_h(ds):
    from matplotlib.figure import Figure

    n = ds.sizes["joint"]
    x = ds["setpoint"].values
    dom = _dominance_of(ds)
    h_tran, h_rot, h = ds["h_tran"].values, ds["h_rot"].values, ds["h"].values
    rows, cols = grid_shape(n, 3)
    W, H = _A4_LANDSCAPE[0], min(_A4_LANDSCAPE[1], 1.6 + 3.0 * rows)
    fig = Figure(figsize=(W, H))
    gs = _gridspec(fig, rows, cols, left=0.85, right=0.2, top=0.6, bottom=0.95, wgap=0.85,
                   hgap=0.7)
    axes = []
    for i in range(n):
        ax = fig.add_subplot(gs[i // cols, i % cols], sharex=axes[0] if axes else None)
        for part, y in (("tran", h_tran[:, i]), ("rot", h_rot[:, i]), ("total", h[:, i])):
            _plot_series(ax, x, y, **_part_kwargs(part))
        label = f"h{i + 1}"
        _element_title(ax, label, dom.get(label, ""))
        _ticks(ax, xbins=6, ybins=5, integer_x=True)
        _labels(ax, "set point", f"{label} [N m]", xoff=0.2, yoff=0.55)
        axes.append(ax)
    if x[-1] > x[0]:
        axes[0].set_xlim(x[0], x[-1])
    fig.legend(*axes[0].get_legend_handles_labels(), loc="lower center",
               bbox_to_anchor=(0.5, 0.08 / H), ncol=3, frameon=False, markerscale=1.5,
               handlelength=3)
    fig.suptitle("Coriolis and centrifugal elements of h along the trajectory "
                 "(analogue of Fig. 3.11)", y=1 - 0.15 / H, va="top")
    return fig


def _fig_torque(ds):
    from matplotlib.figure import Figure

    n = ds.sizes["joint"]
    t = ds["t"].values
    tau, tau_s = ds["tau"].values, ds["tau_simplified"].values
    rel = ds["tau_error_relative_peak"].values
    peak = ds["tau_error_peak"].values
    rows, cols = grid_shape(n, 2)
    W, H = _A4[0], min(_A4[1] - 0.5, 1.6 + 2.6 * rows)
    fig = Figure(figsize=(W, H))
    gs = _gridspec(fig, rows, cols, left=0.85, right=0.2, top=0.6, bottom=0.9, wgap=0.85,
                   hgap=0.7)
    axes = []
    for i in range(n):
        ax = fig.add_subplot(gs[i // cols, i % cols], sharex=axes[0] if axes else None)
        _plot_series(ax, t, tau[:, i], color=_FULL_COLOUR, linestyle="-", linewidth=1.2,
                     label="full model \u03c4")
        _plot_series(ax, t, tau_s[:, i], color=_SIMPLIFIED_COLOUR, linestyle="--",
                     linewidth=1.2, label="simplified model \u03c4\u209b")
        ax.set_title(f"joint {i + 1}: peak |\u03c4\u209b \u2212 \u03c4| = {peak[i]:.3g} N m "
                     f"({_pct(rel[i])})")
        _ticks(ax, xbins=6, ybins=5)
        _labels(ax, "time t [s]", f"\u03c4{_sub(i + 1)} [N m]", xoff=0.2, yoff=0.55)
        axes.append(ax)
    if t[-1] > t[0]:
        axes[0].set_xlim(t[0], t[-1])
    fig.legend(*axes[0].get_legend_handles_labels(), loc="lower center",
               bbox_to_anchor=(0.5, 0.08 / H), ncol=2, frameon=False, handlelength=3)
    fig.suptitle("Joint torque of the full and the simplified model "
                 "(error in % of peak |\u03c4|)", y=1 - 0.15 / H, va="top")
    return fig


_FORMULATION_STYLE = {"lagrange-euler": ("L-E", "#0072B2", "o"),
                      "newton-euler": ("N-E", "#D55E00", "s"),
                      "gd": ("G-D", "#6A3D9A", "^")}


def _fig_formulations(ds):
    from matplotlib.figure import Figure

    n = ds["dof"].values
    names = _strings(ds["formulation"].values)
    fig = Figure(figsize=(_A4[0], 3.6))
    gs = _gridspec(fig, 1, 2, left=0.8, right=0.2, top=0.55, bottom=0.95, wgap=0.9, hgap=0.5)
    for k, (op, title) in enumerate((("multiplications", "multiplications"),
                                     ("additions", "additions"))):
        ax = fig.add_subplot(gs[0, k])
        for name, (short, colour, marker) in _FORMULATION_STYLE.items():
            if name not in names:
                continue
            j = names.index(name)
            ax.loglog(n, ds[f"op_{op}"].values[:, j], color=colour, marker=marker,
                      markersize=4, linestyle="-", linewidth=1.2,
                      label=f"{short} as implemented")
            ax.loglog(n, ds[f"op_{op}_table_3_5"].values[:, j], color=colour,
                      linestyle="--", linewidth=1.0, label=f"{short} Table 3.5")
        ax.set_title(f"{title} per set point")
        ax.set_xlabel("number of joints n")
        ax.set_ylabel(f"{title}")
        ax.grid(True, which="both", linewidth=0.3, alpha=0.5)
    fig.legend(*fig.axes[0].get_legend_handles_labels(), loc="lower center", ncol=3,
               frameon=False, bbox_to_anchor=(0.5, 0.0))
    fig.suptitle("Cost of the three formulations (Fu, Gonzalez & Lee 1987, Table 3.5)",
                 y=1 - 0.12 / 3.6, va="top")
    return fig


def _sub(k):
    return str(k).translate(str.maketrans("0123456789", "\u2080\u2081\u2082\u2083\u2084"
                                                       "\u2085\u2086\u2087\u2088\u2089"))


# --------------------------------------------------------------------------------------------
# Content shared by the HTML and the PDF
# --------------------------------------------------------------------------------------------

def _units(text):
    return str(text).replace("m2", "m\u00b2").replace("s-2", "s\u207b\u00b2") \
        .replace("s-1", "s\u207b\u00b9")


def _kv(rows):
    return _table(["item", "value"], rows, widths=[1.2, 3.4])


def _report_context(ds):
    from .simplified_section import has_simplified, simplified_context

    ctx = _report_context_base(ds)
    ctx["simplified_model"] = simplified_context(ds) if has_simplified(ds) else None
    return ctx


def _report_context_base(ds):
    """Everything both reports print, as strings and tables (no figures)."""
    from .._version import __version__

    _check(ds, _REQUIRED, "results")
    n = ds.sizes["joint"]
    t = ds["t"].values
    N = t.size
    labels = _strings(ds["element"].values)
    dominance = _strings(ds["dominance"].values)
    chapter = _strings(ds["chapter_dominance"].values)
    choice = _strings(ds["choice"].values)
    el_units = (_strings(ds["element_units"].values) if "element_units" in ds.variables
                else ["kg m2" if lab.startswith("D") else "N m" for lab in labels])
    s, e = _thresholds(ds)
    robot_name = _attr(ds, "robot", "robot")
    now = utc_now()

    # 1. robot and trajectory
    robot_kv = _kv([
        ("name", robot_name), ("description", _attr(ds, "robot_description")),
        ("reference", _attr(ds, "robot_reference")), ("robot file", _attr(ds, "robot_source")),
        ("robot file SHA-256", _attr(ds, "robot_sha256")), ("joints n", str(n)),
        ("gravity g [m/s\u00b2]", _attr(ds, "gravity")),
    ])
    com = ds["link_com"].values
    inertia = ds["link_inertia"].values
    dh = _table(
        ["joint", "d [m]", "a [m]", "\u03b1 [deg]", "offset [deg]"],
        [[str(k + 1), _fmt(ds["dh_d"].values[k]), _fmt(ds["dh_a"].values[k]),
          _fmt(np.degrees(ds["dh_alpha"].values[k])),
          _fmt(np.degrees(ds["dh_offset"].values[k]))] for k in range(n)],
        align=["left"] + ["right"] * 4, widths=[0.8, 1, 1, 1, 1])
    link = _table(
        ["joint", "mass [kg]", "com x [m]", "com y [m]", "com z [m]", "Ixx [kg m\u00b2]",
         "Iyy [kg m\u00b2]", "Izz [kg m\u00b2]"],
        [[str(k + 1), _fmt(ds["link_mass"].values[k]), _fmt(com[k, 0]), _fmt(com[k, 1]),
          _fmt(com[k, 2]), _fmt(inertia[k, 0, 0]), _fmt(inertia[k, 1, 1]),
          _fmt(inertia[k, 2, 2])] for k in range(n)],
        align=["left"] + ["right"] * 7, widths=[0.7] + [1] * 7)
    derivatives = str(ds.attrs.get("derivatives", ""))
    sha_in = _attr(ds, "input_sha256", "")
    traj_kv = _kv([
        ("source file", _attr(ds, "input_file")), ("path", _attr(ds, "input_path")),
        ("SHA-256", sha_in or "\u2014 (not read from a file)"),
        ("set points N", str(N)),
        ("duration [s]",
         f"{_fmt(t[-1] - t[0], 6)}  (t = {_fmt(t[0], 6)} \u2026 {_fmt(t[-1], 6)})"),
        ("derivatives", f"{derivatives}: {_DERIVATIVES.get(derivatives, 'as recorded')}"
         if derivatives else "\u2014"),
    ])
    q, qd, qdd = (np.degrees(ds[v].values) for v in ("q", "qd", "qdd"))
    joints = _table(
        ["joint", "q min [deg]", "q max [deg]", "peak |q\u0307| [deg/s]",
         "peak |q\u0308| [deg/s\u00b2]"],
        [[str(k + 1), _fmt(q[:, k].min()), _fmt(q[:, k].max()), _fmt(np.abs(qd[:, k]).max()),
          _fmt(np.abs(qdd[:, k]).max())] for k in range(n)],
        align=["left"] + ["right"] * 4, widths=[0.6, 1, 1, 1.2, 1.2])

    # 4. ranking
    share = ds["share_tran"].values
    pt, pr, ptot = ds["peak_tran"].values, ds["peak_rot"].values, ds["peak_total"].values
    ranking = _table(
        ["element", "share_tran", "class", "peak_tran", "peak_rot", "peak_total", "units"],
        [[lab, _fmt(share[k], 3) if np.isfinite(share[k]) else "n/a", dominance[k],
          _fmt(pt[k]), _fmt(pr[k]), _fmt(ptot[k]), _units(el_units[k])]
         for k, lab in enumerate(labels)],
        align=["left", "right", "left", "right", "right", "right", "left"],
        widths=[0.8, 0.9, 1.2, 1, 1, 1, 0.8], colour_cols=[2])
    counts = {c: dominance.count(c) for c in _CLASS_COLOURS}

    # 5. simplified model and torque error
    choices = _table(
        ["element", "class", "kept part", "meaning"],
        [[lab, dominance[k], choice[k], _CHOICE_TEXT.get(choice[k], "")]
         for k, lab in enumerate(labels)],
        widths=[0.8, 1.2, 0.8, 2.2], colour_cols=[1])
    err = _table(
        ["joint", "peak |\u03c4\u209b\u2212\u03c4| [N m]", "RMS |\u03c4\u209b\u2212\u03c4| [N m]",
         "peak |\u03c4| [N m]", "peak error / peak |\u03c4|", "RMS error / peak |\u03c4|"],
        [[str(k + 1), _fmt(ds["tau_error_peak"].values[k]), _fmt(ds["tau_error_rms"].values[k]),
          _fmt(ds["tau_peak"].values[k]), _pct(ds["tau_error_relative_peak"].values[k]),
          _pct(ds["tau_error_relative_rms"].values[k])] for k in range(n)],
        align=["left"] + ["right"] * 5, widths=[0.6, 1.2, 1.2, 1, 1.2, 1.2])
    rel_peak = ds["tau_error_relative_peak"].values
    worst = int(np.nanargmax(rel_peak)) if np.any(np.isfinite(rel_peak)) else None

    # 6. comparison with the chapter
    applicable = n == 6
    compare_rows, n_agree, n_compared = [], 0, 0
    for lab, ours, theirs in zip(labels, dominance, chapter):
        if theirs:
            n_compared += 1
            agree = ours == theirs
            n_agree += agree
            compare_rows.append([lab, ours, theirs, "yes" if agree else "no"])
        else:
            compare_rows.append([lab, ours, "\u2014", "\u2014"])
    if applicable:
        note = ("The chapter reads these classes by eye off Figs. 3.10 and 3.11 for its own "
                "PUMA 560 trajectory of 31 set points; it notes that the simplification depends "
                "on the trajectory, so disagreements are expected for another trajectory. The "
                "chapter has no 'negligible' class: an element classed negligible here counts "
                "as a disagreement.")
        if robot_name.lower() not in ("puma560", "puma 560", "puma-560"):
            note += (f" This robot ({robot_name}) is not the chapter's PUMA 560: the comparison "
                     "is indicative only.")
    else:
        note = (f"The chapter reports dominance only for the 6-joint PUMA 560 (Sec. 3.4.1); "
                f"this robot has {n} joint{'s' if n != 1 else ''}, so a comparison is not "
                "meaningful and none is made.")
    compare = _table(["element", "our class", "chapter's class", "agree"], compare_rows,
                     widths=[1, 1.4, 1.4, 0.7], colour_cols=[1, 2, 3])

    # 7. provenance
    prov = [
        ("report made by", f"gd-analyze {__version__}"),
        ("analysis made by", f"gd-analyze {_attr(ds, 'gd_analyze_version')}"),
        ("dataset history", _attr(ds, "history")),
        ("report created", now.isoformat()),
        ("input file", _attr(ds, "input_path")),
        ("input SHA-256", sha_in or "\u2014 (not read from a file)"),
        ("robot file", _attr(ds, "robot_source")),
        ("robot file SHA-256", _attr(ds, "robot_sha256")),
        ("dominance threshold s", _fmt(s, 6)),
        ("negligibility threshold e", _fmt(e, 6)),
    ]
    ver_keys = sorted(k for k in ds.attrs if k.startswith("verification_max_rel_error_"))
    if "verification_passed" in ds.attrs:
        passed = bool(int(ds.attrs["verification_passed"]))
        prov.append(("verification against " + _attr(ds, "verification_engine", "Pinocchio"),
                     ("passed" if passed else "FAILED")
                     + f" (tolerance {_attr(ds, 'verification_tolerance')}, "
                     f"{_attr(ds, 'verification_setpoints')} set points checked)"))
        verified = "passed" if passed else "FAILED"
    else:
        prov.append(("verification against Pinocchio", "not run (analysis without check)"))
        verified = "not run"
    for key in ver_keys:
        prov.append((f"max relative error {key[len('verification_max_rel_error_'):]}",
                     _fmt(ds.attrs[key], 3)))
    shown = {"robot", "robot_description", "robot_reference", "robot_source", "robot_sha256",
             "gravity", "gravity_units", "input_file", "input_path", "input_sha256",
             "derivatives", "dominance_threshold", "negligible_threshold", "history",
             "gd_analyze_version", "verification_passed", "verification_engine",
             "verification_tolerance", "verification_setpoints", *ver_keys}
    for key in sorted(k for k in ds.attrs if k not in shown):
        prov.append((key, _attr(ds, key)))

    formulations = _formulations_context(ds)
    payload = _payload_context(ds)
    title = f"G-D dominance analysis: {robot_name} along {_attr(ds, 'input_file')}"
    summary = (f"{n} joints, {N} set points over {_fmt(t[-1] - t[0], 4)} s. "
               f"{len(labels)} elements ranked (s = {s:g}, e = {e:g}): "
               + ", ".join(f"{counts[c]} {c}" for c in _CLASS_COLOURS) + ". "
               + (f"Largest torque error of the simplified model: joint {worst + 1}, "
                  f"{_pct(rel_peak[worst])} of peak |\u03c4|. " if worst is not None else "")
               + f"Verification against Pinocchio: {verified}.")
    return {
        "version": __version__, "title": title, "summary": summary, "robot_name": robot_name,
        "n": n, "N": N, "s": f"{s:g}", "e": f"{e:g}", "created": now.isoformat(),
        "robot_kv": robot_kv, "dh": dh, "link": link, "traj_kv": traj_kv, "joints": joints,
        "ranking": ranking, "counts": counts, "choices": choices, "error": err,
        "compare": {"applicable": applicable, "note": note, "table": compare,
                    "n_agree": n_agree, "n_compared": n_compared},
        "provenance": _kv(prov), "enveloped": N > ENVELOPE_THRESHOLD,
        "formulations": formulations, "payload": payload,
        "envelope_note": (f"The trajectory has {N} set points: curves are drawn as their "
                          f"min/max envelope per column of {1 / _PRINT_DPI:.4g} in "
                          f"({_PRINT_DPI} dpi, at most {ENVELOPE_COLUMNS} columns per panel), "
                          "without markers."
                          if N > ENVELOPE_THRESHOLD else ""),
        "keywords": (f"generalized d'Alembert; G-D dynamics; dominance; {robot_name}; "
                     f"input {_attr(ds, 'input_file')} sha256 {sha_in or '-'}; "
                     f"robot sha256 {_attr(ds, 'robot_sha256')}; s={s:g}; e={e:g}; "
                     f"verification {verified}"),
    }


def _payload_context(ds):
    if "payload_share_tran" not in ds.variables:
        return {"applicable": False, "table": None, "note": ""}
    part = payload_part(ds)
    masses = [float(m) for m in part["payload"].values]
    labels = _strings(part["element"].values)
    dom = np.array(_strings(part["dominance"].values.ravel())).reshape(part["dominance"].shape)
    rows = [[lab] + [dom[k, j] for k in range(len(masses))]
            for j, lab in enumerate(labels) if len(set(dom[:, j])) > 1]
    table = _table(["element"] + [f"{m:g} kg" for m in masses], rows,
                   colour_cols=list(range(1, len(masses) + 1)))
    note = (f"The ranking was repeated with a rigid load of {masses[0]:g} to {masses[-1]:g} kg "
            f"fixed to the last link (centre of mass {_attr(ds, 'payload_com')} m in link "
            f"frame n). {len(rows)} of {len(labels)} elements change class with the load; "
            "they are listed below. The load is merged into link n, so its parallel-axis "
            "terms about the combined centre of mass count as rotational.")
    return {"applicable": True, "table": table, "note": note}


def _formulations_context(ds):
    """Agreement and cost tables of L-E, N-E, G-D and Pinocchio, if the dataset has them."""
    if "formulation_disagreement" not in ds.variables:
        return {"applicable": False, "note": "The dataset holds no comparison of the "
                "formulations (made by `gd-analyze ROBOT TRAJECTORY.csv`).",
                "agreement": None, "costs": None}
    quantities = _strings(ds["quantity"].values)
    pairs = _strings(ds["formulation_pair"].values)
    dis = ds["formulation_disagreement"].values
    agreement = _table(["pair"] + [f"{q}" for q in quantities],
                       [[p] + [f"{v:.2e}" for v in dis[i]] for i, p in enumerate(pairs)],
                       align=["left"] + ["right"] * len(quantities))
    n = int(ds.attrs.get("formulations_n", ds.sizes["joint"]))
    names = _strings(ds["formulation"].values)
    dof = list(ds["dof"].values)
    rows = []
    if n in dof:
        k = dof.index(n)
        for j, name in enumerate(names):
            mul, add = ds["op_multiplications"].values[k, j], ds["op_additions"].values[k, j]
            bm = ds["op_multiplications_table_3_5"].values[k, j]
            ba = ds["op_additions_table_3_5"].values[k, j]
            rows.append([name, f"{mul:.0f}", f"{add:.0f}", f"{bm:.0f}", f"{ba:.0f}"])
    costs = _table(["formulation", "multiplications", "additions", "mult. Table 3.5",
                    "add. Table 3.5"], rows, align=["left"] + ["right"] * 4)
    worst = float(np.max(dis)) if dis.size else float("nan")
    note = (f"Lagrange-Euler (Sec. 3.2), recursive Newton-Euler (Sec. 3.3; D, h and c by "
            f"probing), the G-D equations (Sec. 3.4) and Pinocchio (crba, rnea) were run on "
            f"{ds.attrs.get('formulations_setpoints', '?')} set points of the trajectory; the "
            f"largest relative disagreement of any pair is {worst:.1e}. Operation counts are "
            f"per set point, counted on the code as implemented (gd: compiled G-D engine, "
            f"gd-numpy: array engine), beside the formulas of Table 3.5, for n = {n}.")
    return {"applicable": True, "note": note, "agreement": agreement, "costs": costs}


# --------------------------------------------------------------------------------------------
# HTML
# --------------------------------------------------------------------------------------------

def render_html(ds, figures=None):
    """Render the report as one self-contained HTML document.

    Parameters
    ----------
    ds : xarray.Dataset
        A stored analysis (see :func:`make_figures` for the variables used).
    figures : dict of str to matplotlib.figure.Figure, optional
        The figures of :func:`make_figures`; made here if not given.

    Returns
    -------
    str
        The HTML document: inline CSS, figures as inline SVG, no external resources. Built
        with the Jinja2 template ``templates/report.html.j2`` (autoescape on).

    Raises
    ------
    InputError
        If ``ds`` lacks a variable of a gd-analyze results dataset.

    Notes
    -----
    Source: Sec. 3.4.1 and Figs. 3.10-3.11 of Fu, Gonzalez & Lee (1987).
    """
    ctx = _report_context(ds)
    if figures is None:
        figures = make_figures(ds)
    return _html(ctx, figures)


def _html(ctx, figures):
    svgs = inline_svgs(figures, _RC)
    return render_template("report.html.j2", {**ctx, "figures": svgs},
                           {"class_colours": _CLASS_COLOURS})


# --------------------------------------------------------------------------------------------
# PDF
# --------------------------------------------------------------------------------------------

class _TextPages:
    """Flow headings, paragraphs and tables onto A4 pages drawn as matplotlib figures."""

    W, H = _A4
    LEFT = RIGHT = 0.75
    TOP, BOTTOM = 0.65, 0.8

    def __init__(self, pdf, footer):
        self.pdf = pdf
        self.footer = footer
        self.page = 0
        self.fig = None
        self.y = self.TOP

    @property
    def width(self):
        return self.W - self.LEFT - self.RIGHT

    @property
    def limit(self):
        return self.H - self.BOTTOM

    def _new_page(self):
        from matplotlib.figure import Figure

        self.flush()
        self.fig = Figure(figsize=(self.W, self.H))
        self.y = self.TOP

    def _ensure(self, height):
        if self.fig is None or self.y + height > self.limit:
            self._new_page()

    def _text(self, x, y, s, **kwargs):
        self.fig.text(x / self.W, 1.0 - y / self.H, s, va="top", **kwargs)

    def flush(self):
        """Write the current text page, if any."""
        if self.fig is not None:
            self.page += 1
            self._text(self.LEFT, self.limit + 0.35, f"{self.footer}   \u2014   page {self.page}",
                       fontsize=7, color="0.45")
            self.pdf.savefig(self.fig)
            self.fig = None

    def figure(self, fig):
        """Write a figure on a page of its own."""
        self.flush()
        self.page += 1
        self.pdf.savefig(fig)

    def heading(self, text, size=13):
        h = size * 1.7 / 72
        self._ensure(h + 0.6)            # keep a heading with what follows
        if self.y > self.TOP + 1e-9:
            self.y += 0.12
        self._text(self.LEFT, self.y, text, fontsize=size, fontweight="bold")
        self.y += h

    def paragraph(self, text, size=9, **kwargs):
        chars = max(20, int(self.width / (size * 0.53 / 72)))
        lh = size * 1.4 / 72
        for line in textwrap.wrap(text, chars) or [""]:
            self._ensure(lh)
            self._text(self.LEFT, self.y, line, fontsize=size, **kwargs)
            self.y += lh
        self.y += 0.08

    def table(self, table, size=7.5):
        from matplotlib.lines import Line2D
        from matplotlib.patches import Rectangle

        widths = np.asarray(table["widths"], float)
        widths = widths / widths.sum() * self.width
        xs = self.LEFT + np.r_[0.0, np.cumsum(widths)[:-1]]
        lh = size * 1.3 / 72
        pad = 0.04
        charw = size * 0.56 / 72
        colour_cols = set(table["colour_cols"])

        def wrap(row):
            cells = [textwrap.wrap(c, max(3, int((w - 2 * pad) / charw))) or [""]
                     for c, w in zip(row, widths)]
            return cells, max(len(c) for c in cells) * lh + 2 * pad

        def draw(cells, height, bold=False, shade=False):
            if shade:
                self.fig.add_artist(Rectangle(
                    (self.LEFT / self.W, 1 - (self.y + height) / self.H), self.width / self.W,
                    height / self.H, transform=self.fig.transFigure, facecolor="0.94",
                    edgecolor="none", zorder=0))
            for k, (lines, x, w) in enumerate(zip(cells, xs, widths)):
                right = table["align"][k] == "right"
                colour = "black"
                if k in colour_cols and not bold:
                    colour = _CLASS_COLOURS.get(lines[0], _AGREE_COLOURS.get(lines[0], "black"))
                for m, line in enumerate(lines):
                    self._text(x + (w - pad if right else pad), self.y + pad + m * lh, line,
                               fontsize=size, ha="right" if right else "left", color=colour,
                               fontweight="bold" if bold else "normal")
            self.y += height

        def rule(width=0.6):
            yy = 1 - self.y / self.H
            self.fig.add_artist(Line2D([self.LEFT / self.W, (self.LEFT + self.width) / self.W],
                                       [yy, yy], transform=self.fig.transFigure,
                                       color="black", linewidth=width))

        header, hh = wrap(table["header"])
        rows = [wrap(r) for r in table["rows"]]
        first = rows[0][1] if rows else 0.0
        total = hh + sum(h for _, h in rows)
        if total <= 0.4 * (self.limit - self.TOP):
            self._ensure(total + 0.05)      # keep a short table on one page
        else:
            self._ensure(hh + first + 0.05)
        rule(0.8)
        draw(header, hh, bold=True)
        rule()
        for k, (cells, height) in enumerate(rows):
            if self.y + height > self.limit:
                rule(0.8)
                self._new_page()
                rule(0.8)
                draw(header, hh, bold=True)
                rule()
            draw(cells, height, shade=k % 2 == 1)
        rule(0.8)
        self.y += 0.15


def render_pdf(ds, path, figures=None):
    """Write the report as a PDF with matplotlib's PdfPages.

    Parameters
    ----------
    ds : xarray.Dataset
        A stored analysis (see :func:`make_figures` for the variables used).
    path : str or os.PathLike
        The PDF file to write (not atomically: :func:`write_report` passes a temporary name).
    figures : dict of str to matplotlib.figure.Figure, optional
        The figures of :func:`make_figures`; made here if not given.

    Returns
    -------
    int
        The number of pages written.

    Raises
    ------
    InputError
        If ``ds`` lacks a variable of a gd-analyze results dataset.
    OSError
        If the file cannot be written.

    Notes
    -----
    Text pages are A4 portrait; figure pages have the figure's size. The PDF metadata carry the
    title, the author ``gd-analyze <version>``, a subject, and the provenance as keywords.
    Source: Sec. 3.4.1 and Figs. 3.10-3.11 of Fu, Gonzalez & Lee (1987).
    """
    ctx = _report_context(ds)
    if figures is None:
        figures = make_figures(ds)
    return _pdf(ctx, figures, path)


def _pdf(ctx, figures, path):
    from matplotlib.backends.backend_pdf import PdfPages

    metadata = {
        "Title": ctx["title"],
        "Author": f"gd-analyze {ctx['version']}",
        "Subject": "Translational and rotational dominance of the generalized d'Alembert "
                   "dynamics (Fu, Gonzalez & Lee 1987, Sec. 3.4.1, Figs. 3.10-3.11)",
        "Keywords": ctx["keywords"],
        "Creator": f"gd-analyze {ctx['version']}",
        "CreationDate": datetime.datetime.fromisoformat(ctx["created"]),
    }
    with _style(_RC), PdfPages(path, metadata=metadata) as pdf:
        doc = _TextPages(pdf, f"gd-analyze {ctx['version']}: {ctx['title']}")
        doc.heading(ctx["title"], size=14)
        doc.paragraph(ctx["summary"])
        doc.paragraph(f"Report created {ctx['created']}. Source of the method: Fu, Gonzalez & "
                      "Lee (1987), Robotics, Sec. 3.4.1, Figs. 3.10-3.11.", size=8, color="0.3")
        doc.heading("1. Robot and trajectory")
        doc.heading("1.1 Robot", size=10.5)
        doc.table(ctx["robot_kv"], size=8)
        doc.paragraph("Denavit-Hartenberg parameters (standard form, theta = q + offset):",
                      size=8.5)
        doc.table(ctx["dh"], size=8)
        doc.paragraph("Link inertial parameters: centre of mass (com) in link frame i, diagonal "
                      "of the inertia tensor about the centre of mass:", size=8.5)
        doc.table(ctx["link"], size=8)
        doc.heading("1.2 Trajectory", size=10.5)
        doc.table(ctx["traj_kv"], size=8)
        doc.table(ctx["joints"], size=8)
        if ctx["envelope_note"]:
            doc.paragraph(ctx["envelope_note"], size=8.5)
        doc.figure(figures["joints"])
        doc.figure(figures["D"])
        doc.figure(figures["h"])
        doc.heading("4. Dominance ranking")
        doc.paragraph(_RANKING_TEXT.format(s=ctx["s"], e=ctx["e"]), size=8.5)
        doc.table(ctx["ranking"])
        doc.heading("5. Simplified model")
        doc.paragraph(_SIMPLIFIED_TEXT, size=8.5)
        doc.table(ctx["error"], size=7.5)
        doc.table(ctx["choices"])
        sm = ctx.get("simplified_model")
        if sm:
            doc.paragraph(sm["text"], size=8.5)
            doc.table(sm["bound"], size=7.5)
            if sm["costs"]:
                doc.table(sm["costs"], size=7.5)
            if sm["ladder"]:
                doc.table(sm["ladder"], size=7.5)
            doc.paragraph("Emitted source files: " + ", ".join(sm["files"]), size=8.5)
        doc.figure(figures["torque"])
        doc.heading("6. Comparison with the chapter's PUMA 560")
        doc.paragraph(ctx["compare"]["note"], size=8.5)
        if ctx["compare"]["applicable"]:
            doc.paragraph(f"Agreement: {ctx['compare']['n_agree']} of "
                          f"{ctx['compare']['n_compared']} elements.", size=9,
                          fontweight="bold")
            doc.table(ctx["compare"]["table"])
        if ctx["payload"]["applicable"]:
            doc.heading("6.1 Dominance against the payload")
            doc.paragraph(ctx["payload"]["note"], size=8.5)
            if ctx["payload"]["table"]["rows"]:
                doc.table(ctx["payload"]["table"])
            doc.figure(figures["payload"])
        doc.heading("7. Formulations: Lagrange-Euler, Newton-Euler, G-D")
        doc.paragraph(ctx["formulations"]["note"], size=8.5)
        if ctx["formulations"]["applicable"]:
            doc.table(ctx["formulations"]["agreement"])
            doc.table(ctx["formulations"]["costs"])
            doc.figure(figures["formulations"])
        doc.heading("8. Provenance")
        doc.table(ctx["provenance"], size=7.5)
        doc.flush()
        return doc.page


_RANKING_TEXT = ("For each element, share_tran = sum|tran| / (sum|tran| + sum|rot|) over the "
                 "set points. Class: negligible if the peak |tran + rot| is below e = {e} times "
                 "the element's scale (peak sqrt(D_ii D_jj) for D_ij, peak |tau_i| for h_i); "
                 "else translational if share_tran >= s = {s}, rotational if share_tran <= "
                 "1 - s, both otherwise. Peaks are of the absolute values along the trajectory.")
_SIMPLIFIED_TEXT = ("The simplified model keeps, for each element of D (mirrored to the lower "
                    "triangle) and h, only the dominant part (both if neither dominates, none if "
                    "negligible); gravity c is kept whole: tau_s = D_s qdd + h_s + c. Its error "
                    "along the trajectory, per joint, relative to the peak |tau| of the joint:")


# --------------------------------------------------------------------------------------------
# Entry point
# --------------------------------------------------------------------------------------------

def write_report(results_path, outdir, formats=REPORT_FORMATS):
    """Write report.html and/or report.pdf for a stored analysis.

    Parameters
    ----------
    results_path : str or os.PathLike
        A results file written by :func:`gd_analyze.workflows.analyze.analyze_to_file`. Only read: the
        dynamics are never recomputed.
    outdir : str or os.PathLike
        Output folder; made if missing.
    formats : sequence of str, optional
        Any of ``"html"`` and ``"pdf"``.

    Returns
    -------
    list of pathlib.Path
        The files written (``outdir/report.html``, ``outdir/report.pdf``), in the order of
        ``formats``.

    Raises
    ------
    InputError
        If the results file is missing, unreadable or not a gd-analyze dataset.
    ValueError
        If a format is not one of :data:`REPORT_FORMATS`, or none is given.
    OSError
        If a file cannot be written.

    Notes
    -----
    Each file is written to a temporary name beside its destination and renamed
    (:func:`gd_analyze.files.atomic_path`). The report holds the analogues of Figs. 3.10 and
    3.11 of Fu, Gonzalez & Lee (1987), Sec. 3.4.1, and the ranking, simplified model, comparison
    with the chapter and provenance read from the dataset.
    """
    from ..files import atomic_path
    from ..io.datasets import open_results

    formats = check_formats(formats, REPORT_FORMATS)
    ds = open_results(results_path)
    ctx = _report_context(ds)            # fails early on a dataset that is not ours
    outdir = Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    figures = make_figures(ds)
    paths = {fmt: outdir / f"report.{fmt}" for fmt in formats}
    with contextlib.ExitStack() as stack:
        tmp = {fmt: stack.enter_context(atomic_path(paths[fmt])) for fmt in formats}
        child = _start_pdf_process(ctx, figures, tmp["pdf"]) if len(formats) == 2 else None
        for fmt in formats:
            if fmt == "html":
                text = _html(ctx, figures)
                with open(tmp["html"], "w", encoding="utf-8") as fh:
                    fh.write(text)
            elif child is None:
                _pdf(ctx, figures, tmp["pdf"])
        if child is not None:
            child.join()
            if child.exitcode != 0:
                raise OSError(f"rendering {paths['pdf']} failed (exit code {child.exitcode})")
    return [paths[fmt] for fmt in formats]


def _start_pdf_process(ctx, figures, path):
    """Render the PDF in a forked process while the caller writes the HTML; None if the
    platform cannot fork or there is a single core (then the caller renders it itself)."""
    import multiprocessing as mp

    if (os.cpu_count() or 1) < 2 or "fork" not in mp.get_all_start_methods():
        return None
    # With fork, the arguments are inherited, not pickled: the figures cost nothing to pass.
    child = mp.get_context("fork").Process(target=_pdf, args=(ctx, figures, path), daemon=True)
    child.start()
    return child
