"""The control report's figures: tracking error, closed-loop torque difference and applied
torques per joint, drawn from a stored control dataset at a page's width (7.2 in) or a
column's (3.5 in). Integrator noise is never drawn as data
(:func:`gd_analyze.ranking.ranking.is_round_off` against :func:`noise_floors`): a tracking
error at or below the integrator's rtol times the joint's scale, a torque difference at or
below its measured noise floor (``tau_difference_floor``,
:attr:`gd_analyze.jobs.control.ControlResult.tau_noise_floor`).
"""

from __future__ import annotations

import math
import textwrap
from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np

from ..ranking.ranking import ROUND_OFF, is_round_off, joint_motion_units, joint_torque_units
from ..store.stored_control import StoredControl
from .common import BASE_RC, grid_shape, panel_markevery
from .markup import sub
from .ticks import decade_formatter, label_axes, set_ticks

if TYPE_CHECKING:                       # for the type hints only
    import xarray as xr
    from matplotlib.figure import Figure

__all__ = ["control_figures", "noise_scales", "noise_floors", "PAGE_WIDTH", "COLUMN_WIDTH", "page_columns",
           "CONTROLLER_LABELS", "CONTROLLER_STYLES", "marker_starts", "marker_stride", "markers_words", "noise_words"]

#: Figure widths [in]: the text of a page, one column.
PAGE_WIDTH, COLUMN_WIDTH = 7.2, 3.5

# Okabe & Ito colours, the same in every figure; line style, width and marker differ too, so
# that the three controllers are told apart in black and white, where their curves coincide
# too (the full-model controller's wide solid line under the others).
_COLOURS = {"full": "#000000", "simplified": "#009E73", "pd_gravity": "#D55E00"}
#: Line style (dash pattern in points), width [pt] and marker of each controller.
CONTROLLER_STYLES = {"full": ("-", 1.6, "o"), "simplified": ((0, (4.0, 2.0)), 1.0, "s"),
                     "pd_gravity": ((0, (1.0, 1.6)), 1.1, "^")}
#: A band within +-floor is in the key only where it shows: at least this share of a panel's
#: y range (a thinner one is invisible at print size).
_VISIBLE_BAND = 0.01
CONTROLLER_LABELS = CONTROL_LABELS = {"full": "computed torque, full model", "simplified": "computed torque, simplified "
           "model", "pd_gravity": "PD + gravity"}
_MAX_LINE_POINTS = 600
#: Axis labels ({u}: the joint's units) without subscripts: q_d (desired), tau_s and tau_f
#: (the simplified- and the full-model controller) have subscripts that Unicode has no
#: character for, and mathtext's print at 70 % of the label (5.6 pt), under the reports'
#: 8 pt; the labels name the tracking error e = q_d - q and the difference
#: delta tau = tau_s - tau_f, which the captions and the text define.
_TRACKING_ERROR = "|e| [{u}]"
_TAU_DIFFERENCE = "\u0394\u03c4 [{u}]"
#: The key's entry of the shaded band within +-floor of a torque difference.
_BAND = "integrator noise floor (\u00b1): not drawn"
FIGURE_RC = {**BASE_RC, "legend.fontsize": 7.5, "lines.markersize": 3.0}


#: Height [in] of a row of panels at page width, by the number of columns (three narrower
#: panels a row are drawn lower: a six-joint figure in two rows is under half a page, so that
#: a figure prints on the page of the text citing it or the next, and the PUMA 560's report,
#: its three figures of six joints, ends on a full page rather than one holding its
#: provenance alone).
_ROW_HEIGHT = {1: 1.9, 2: 1.9, 3: 1.3}
#: Horizontal room between panels at page width [share of a panel's width], by the number of
#: columns: a narrower panel needs a larger share for its neighbour's tick labels and label.
_WSPACE = {1: 0.3, 2: 0.3, 3: 0.5}
#: A page-width note's characters a line, and the height [in] of each line after the first.
_NOTE_CHARS, _NOTE_LINE = 110, 0.15


def page_columns(n: int) -> int:
    """Panels a row at page width: two for up to four joints, else three.

    Parameters
    ----------
    n : int
        Number of joints (panels).

    Returns
    -------
    int
        2 or 3: a six-joint arm's figure has two rows, not three.
    """
    return 2 if n <= 4 else 3


def _stride(m):
    return max(1, int(math.ceil(m / _MAX_LINE_POINTS)))


def _joint_panels(s, values, ylabel, title, log=False, floor=None, which="q",
                  width=PAGE_WIDTH):
    """A figure with one panel per joint; values: name -> (M, n) array along the stored
    control run's time.

    ``ylabel`` is formatted with each joint's units (``{u}``). With ``floor`` (n,)
    (:func:`noise_floors`), no point at or below a joint's floor is drawn, and a controller
    whose curve on a joint is all integrator noise is not drawn there: the panel says so; a
    log axis starts at the floor, a linear one shades the band within +-floor.
    """
    from matplotlib.figure import Figure
    from matplotlib.lines import Line2D
    from matplotlib.ticker import LogLocator, NullFormatter


    t = np.asarray(s.time, dtype=float)
    is_set = s.is_setpoint
    n = s.n
    units = joint_units_of(s, which)
    column = width < PAGE_WIDTH
    rows, cols = grid_shape(n, 1 if column else page_columns(n))
    top = (0.5 if floor is None else 0.72) + ((0.25 if floor is None else 0.54) if column
                                              else 0.0)     # column: a note of 3 lines
    bottom = 0.62 + 0.14 * len(values) if column else 0.85     # the key, one entry a line
    height = (1.35 if column else _ROW_HEIGHT[cols]) * rows + bottom - 0.35 + top
    W = width
    fig = Figure(figsize=(W, height))
    # fixed margins [in] instead of a layout engine: drawing stays fast
    fig.subplots_adjust(left=0.75 / W, right=1 - 0.15 / W, top=1 - top / height,
                        bottom=bottom / height, wspace=0.3 if column else _WSPACE[cols],
                        hspace=0.35)
    axes = fig.subplots(rows, cols, squeeze=False, sharex=True)
    k = _stride(t.size)
    keep = np.zeros(t.size, dtype=bool)
    keep[::k] = True
    keep |= is_set
    every = marker_stride(s, len(values))
    handles = {}
    quiet = {}                          # controller -> [(joint, peak)] of noise-only curves
    linear = []
    for j in range(rows * cols):
        ax = axes[j // cols, j % cols]
        if j >= n:
            ax.set_visible(False)
            continue
        drawn = 0
        for order, (name, y) in enumerate(values.items()):
            yj = np.asarray(y[:, j], dtype=float)
            if log:
                yj = np.abs(yj)
            peak = float(np.nanmax(np.abs(yj))) if yj.size else 0.0
            if floor is not None and is_round_off(peak, floor[j], 1.0):
                quiet.setdefault(name, []).append((j, peak))
                continue
            drawn += 1
            if floor is not None:       # a point at or below the floor is noise: a gap
                yj = np.where(is_round_off(yj, floor[j], 1.0), np.nan, yj)
            elif log:
                yj = np.where(yj > 0.0, yj, np.nan)
            ls, lw, marker = CONTROLLER_STYLES.get(name, ("-", 1.0, "o"))
            kw = {"color": _COLOURS.get(name, "#0072B2"), "linestyle": ls, "linewidth": lw,
                  "label": CONTROL_LABELS.get(name, name), "zorder": 2 + order}
            ax.plot(t[keep], yj[keep], **kw)
            handles.setdefault(kw["label"], Line2D(
                [], [], marker=marker, markersize=3.5, mfc="none", markeredgewidth=0.8, **kw))
            start = marker_starts(every, len(values))[order]   # staggered: none coincide
            ax.plot(t[is_set], yj[is_set], linestyle="none", marker=marker, markersize=3.0,
                    color=kw["color"], mfc="none", markeredgewidth=0.8, zorder=5 + order,
                    markevery=(start, every) if every > 1 else 1)
        if log:
            ax.set_yscale("log")
            if floor is not None and floor[j] > 0:
                ax.set_ylim(bottom=floor[j])
            # decades written 10⁻⁶ in the tick labels' own 7 pt (mathtext's exponents: 4.9 pt)
            ax.yaxis.set_major_locator(LogLocator(numticks=6))
            ax.yaxis.set_major_formatter(decade_formatter())
            ax.yaxis.set_minor_formatter(NullFormatter())
        elif drawn:                     # round ticks, labelled below in one notation
            lo, hi = ax.get_ylim()
            if floor is not None and floor[j] > 0:
                band = ax.axhspan(-floor[j], floor[j], color="0.85", linewidth=0, zorder=0)
                if 2 * floor[j] >= _VISIBLE_BAND * (hi - lo):     # in the key if it shows
                    handles.setdefault(_BAND, band)
            set_ticks(ax.yaxis, lo, hi, 4, labels=False)
            linear.append(ax.yaxis)
        if not drawn and floor is not None:
            ax.text(0.5, 0.5, "integrator noise only: not drawn", transform=ax.transAxes,
                    ha="center", va="center", fontsize=7, color="0.35")
            ax.set_yticks([])
        ax.set_title(f"joint {j + 1}")
        if j // cols == rows - 1 or j + cols >= n:     # the lowest panel of its column
            ax.set_xlabel("time t [s]")
            ax.xaxis.set_tick_params(labelbottom=True)      # sharex hid them over a gap
        ax.set_ylabel(ylabel.format(u=units[j]))
    label_axes(linear)                  # one tick notation for the figure
    if handles:
        fig.legend(list(handles.values()), list(handles), loc="lower center",
                   ncols=1 if column else min(3, len(handles)), frameon=False,
                   bbox_to_anchor=(0.5, 0.0))
    note = ""
    if floor is not None:
        notes = [f"Integrator noise ({noise_words(s, which, figure=True)}) is not drawn"]
        for name, where in quiet.items():            # said as noise: its digits are not data
            joints = ("every joint" if len(where) == n else
                      "joint" + ("s " if len(where) > 1 else " ")
                      + ", ".join(str(j + 1) for j, _ in where))
            notes.append(f"{CONTROL_LABELS.get(name, name)}: \u2261 0 on {joints} (integrator noise)")
        # wrapped by the width drawn (at the size it prints at, 8 pt)
        note = textwrap.fill("; ".join(notes) + ".", 70 if column else _NOTE_CHARS)
    extra = 0.0 if column else _NOTE_LINE * note.count("\n")
    if extra:                           # a page-width note of more lines: room above the panels
        height += extra
        fig.set_size_inches(W, height)
        fig.subplots_adjust(top=1 - (top + extra) / height, bottom=bottom / height)
    fig.suptitle(textwrap.fill(title, 48) if column else title, fontsize=9 if column else 10,
                 fontweight="bold", y=1 - 0.12 / height, va="top")
    if note:
        fig.text(0.5, 1 - (0.62 if column else 0.36) / height, note, ha="center", va="top",
                 fontsize=7, color="0.3")
    return fig


def noise_words(ds: StoredControl | xr.Dataset, which: str, figure: bool = False) -> str:
    """The rule by which a closed-loop quantity is integrator noise (:func:`noise_floors`), in
    the words of every caption, table, figure note and the verdict.

    Parameters
    ----------
    ds : StoredControl or xarray.Dataset
        A stored control run (:class:`gd_analyze.store.stored_control.StoredControl`), or its
        dataset (its ``rtol``, and the attributes of the measured noise floor).
    which : {"q", "tau"}
        A tracking error (at most rtol times the larger of the range and the peak |q_d| of
        the joint) or the closed-loop torque difference (at most its stored noise floor,
        ``tau_difference_floor``; in a file without one, rtol times the full-model
        controller's peak |tau|).
    figure : bool, optional
        The short form of a figure's note, without subscripts (the caption gives the
        joint's scale).

    Returns
    -------
    str
        E.g. "at most 1e-08 of the joint's scale, max(range, peak |q_d|)" or "at most twice
        the largest change the difference shows when both runs are integrated again with rtol
        and atol / 100, or 1e-08 of the full-model controller's peak |tau| where that is
        larger".
    """
    s = StoredControl.of(ds)
    tol = noise_scales(s)[0]
    if which == "tau":
        if s.tau_difference_floor is None:
            return f"at most {tol:g} of the full-model controller's peak |\u03c4|"
        settings = s.settings
        factor = float(_or(settings.noise_factor, np.nan))
        tighten = float(settings.rtol) / float(_or(settings.noise_rtol, np.nan))
        times = {1.0: "", 2.0: "twice "}.get(factor, f"{factor:g} times ")
        if figure:                      # short: the note is one line at page width
            return (f"at most {times}its change with rtol and atol / {tighten:g}, or {tol:g} "
                    "of peak |\u03c4|")
        return (f"at most {times}the largest change the difference shows when both runs are "
                f"integrated again with rtol and atol / {tighten:g}, or {tol:g} of the "
                "full-model controller's peak |\u03c4| where that is larger")
    if figure:                          # short: the note is one line at page width
        return f"at most {tol:g} of the joint's scale"
    return f"at most {tol:g} of the joint's scale, max(range, peak |q{sub('d')}|)"


def _or(value, default):
    """A stored attribute's value, or ``default`` where it is missing (None)."""
    return default if value is None else value


def marker_stride(ds: StoredControl | xr.Dataset, lines: int) -> int:
    """The set points between two markers on a line of a figure with ``lines`` lines a panel
    (:func:`gd_analyze.report.figure_style.panel_markevery`), for the figures and their
    captions alike.

    Parameters
    ----------
    ds : StoredControl or xarray.Dataset
        A stored control run, or its dataset (``is_setpoint`` along ``time``).
    lines : int
        Lines with markers on each panel.

    Returns
    -------
    int
        k >= 1: a marker at every k-th set point.
    """

    return panel_markevery(int(StoredControl.of(ds).is_setpoint.sum()), lines)


def marker_starts(every: int, lines: int) -> list[int]:
    """The set point of each line's first marker on a panel of ``lines`` lines with a marker
    at every ``every``-th set point: staggered, so that no two lines mark the same set point
    (as :func:`gd_analyze.report.main_figures._plot` staggers the parts of an element).

    Parameters
    ----------
    every : int
        The stride (:func:`marker_stride`).
    lines : int
        Lines with markers on each panel.

    Returns
    -------
    list of int, length ``lines``
        0-based indices of the first marked set point: ``i * every // lines``; all 0 when
        ``every`` is 1 (every line marks every set point).

    Examples
    --------
    >>> marker_starts(8, 3), marker_starts(16, 1), marker_starts(1, 3)
    ([0, 2, 5], [0], [0, 0, 0])
    """
    return [i * every // max(1, lines) for i in range(max(1, lines))]


def markers_words(ds: StoredControl | xr.Dataset, lines: int | Sequence[str]) -> str:
    """What a figure's markers are, in words.

    Parameters
    ----------
    ds : StoredControl or xarray.Dataset
        A stored control run, or its dataset.
    lines : int or sequence of str
        Lines with markers on each panel (:func:`marker_stride`), or the controllers drawn, in
        the order they are drawn (:data:`CONTROLLER_LABELS` names them).

    Returns
    -------
    str
        "markers: every set point", "markers: every 8th set point, the first included", or
        for several lines "markers: every 8th set point, staggered so that no two controllers
        mark the same one; the first at set point 1 (computed torque, full model), 3 (...) and
        6 (...)" (:func:`marker_starts`).
    """
    names = None if isinstance(lines, int) else [str(c) for c in lines]
    count = len(names) if names is not None else int(lines)  # type: ignore[arg-type]  # an int
    k = marker_stride(ds, count)
    if k == 1:
        return "markers: every set point"
    if count <= 1:
        return f"markers: every {_ordinal(k)} set point, the first included"
    starts = [str(s + 1) for s in marker_starts(k, count)]
    if names is not None:
        starts = [f"{s} ({CONTROL_LABELS.get(c, c)})" for s, c in zip(starts, names)]
    return (f"markers: every {_ordinal(k)} set point, staggered so that no two controllers "
            f"mark the same one; the first at set point {', '.join(starts[:-1])} and "
            f"{starts[-1]}")


def _ordinal(k):
    """1st, 2nd, 3rd, 8th, 11th ..."""
    suffix = "th" if 10 <= k % 100 <= 20 else {1: "st", 2: "nd", 3: "rd"}.get(k % 10, "th")
    return f"{k}{suffix}"


def joint_units_of(ds: StoredControl | xr.Dataset, which: str) -> list[str]:
    """Units of q (``"q"``) or tau (``"tau"``) per joint, from the stored joint types
    (:func:`gd_analyze.ranking.labels.joint_motion_units`, ``joint_torque_units``)."""

    prismatic = StoredControl.of(ds).prismatic
    if which == "tau":
        return [joint_torque_units(bool(p)) for p in prismatic]
    return [joint_motion_units(bool(p))[0] for p in prismatic]


def noise_scales(ds: StoredControl | xr.Dataset) -> tuple[float, np.ndarray, np.ndarray]:
    """The scales against which a closed-loop quantity is integrator noise
    (:func:`noise_floors`), the same for the figures and the tables.

    Parameters
    ----------
    ds : StoredControl or xarray.Dataset
        A stored control run, or its dataset.

    Returns
    -------
    tol : float
        ``max(rtol, ROUND_OFF)`` [1].
    q_scale : ndarray, shape (n,)
        Per joint, the larger of the range and the peak |q_d| [rad or m]: a tracking error's.
    tau_scale : ndarray, shape (n,)
        Per joint, the full-model controller's peak |tau| [N m or N]: a torque difference's.
    """
    s = StoredControl.of(ds)
    names = s.controllers
    q_d = np.asarray(s.q_d, float)
    q_scale = np.maximum(np.ptp(q_d, axis=0), np.abs(q_d).max(axis=0))
    full = names.index("full") if "full" in names else 0
    tau_scale = np.nanmax(np.abs(np.asarray(s.tau[names[full]], float)), axis=0)
    rtol = float(_or(s.settings.rtol, 0.0))
    return max(rtol if np.isfinite(rtol) else 0.0, ROUND_OFF), q_scale, tau_scale


def noise_floors(ds: StoredControl | xr.Dataset) -> tuple[np.ndarray, np.ndarray]:
    """Per joint, the level at or below which a closed-loop quantity is integrator noise, not
    data: the same for the figures, the tables and the verdict.

    Parameters
    ----------
    ds : StoredControl or xarray.Dataset
        A stored control run, or its dataset.

    Returns
    -------
    q_floor : ndarray, shape (n,)
        A tracking error's: max(rtol, 1e-12) times the joint's scale (:func:`noise_scales`)
        [rad or m].
    tau_floor : ndarray, shape (n,)
        The closed-loop torque difference's: the stored ``tau_difference_floor`` (measured,
        :attr:`gd_analyze.jobs.control.ControlResult.tau_noise_floor`); in a file without
        one, max(rtol, 1e-12) times the full-model controller's peak |tau| [N m or N].
    """
    s = StoredControl.of(ds)
    tol, q_scale, tau_scale = noise_scales(s)
    if s.tau_difference_floor is not None:
        return tol * q_scale, np.asarray(s.tau_difference_floor, float)
    return tol * q_scale, tol * tau_scale


def control_figures(ds: StoredControl | xr.Dataset, width: float = PAGE_WIDTH
                    ) -> dict[str, Figure]:
    """The report's figures, drawn from a stored control dataset.

    Parameters
    ----------
    ds : StoredControl or xarray.Dataset
        A stored control run (:class:`gd_analyze.store.stored_control.StoredControl`), or a
        control dataset (:func:`gd_analyze.store.control_dataset.control_dataset`).
    width : float, optional
        :data:`PAGE_WIDTH` (two or three panels a row: :func:`page_columns`) or
        :data:`COLUMN_WIDTH` [in] (one a row).

    Returns
    -------
    dict of str to matplotlib.figure.Figure
        ``"error"`` (|e| = |q_d - q| per joint, log scale [rad or m]), ``"tau_difference"``
        (delta tau = tau_s - tau_f, the simplified-model controller's torque minus the
        full-model one's [N m or N]; absent if not stored) and ``"tau"`` (applied torques
        [N m or N]). Integrator noise (at or below
        :func:`noise_floors`) is never drawn as data.
    """
    s = StoredControl.of(ds)
    names = s.controllers
    q_floor, tau_floor = noise_floors(s)
    import matplotlib

    with matplotlib.rc_context(FIGURE_RC):  # type: ignore[arg-type]  # keys typed as literals
        figs = {"error": _joint_panels(
            s, {c: s.error[c] for c in names},
            _TRACKING_ERROR, "Tracking error per joint", log=True, floor=q_floor,
            width=width)}
        if s.tau_difference is not None:
            figs["tau_difference"] = _joint_panels(
                s, {"simplified": s.tau_difference}, _TAU_DIFFERENCE,
                "Closed-loop torque difference: simplified-model minus full-model computed "
                "torque", floor=tau_floor, which="tau", width=width)
        figs["tau"] = _joint_panels(s, {c: s.tau[c] for c in names},
                                    "\u03c4 [{u}]", "Applied joint torques", which="tau",
                                    width=width)
    return figs
