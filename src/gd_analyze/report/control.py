"""Control report: the stored closed-loop comparison as one self-contained HTML file and a PDF.

:func:`write_control_report` reads a control dataset written by
:func:`gd_analyze.store.control_dataset.write_control_dataset` (``control.h5``) and never recomputes anything:
every number and curve comes from the dataset's variables and global attributes. The report
holds the set-up and gains, the tracking error per joint of the three controllers (figure and
peak/RMS table), the torque difference between the simplified-model and the full-model
computed-torque controllers, the applied torques, the evaluation cost of the simplified model
against the full one, the model's choices and the provenance. One module for the report's
figures (:func:`control_figures`, integrator noise never drawn as data: :func:`noise_floors`),
its words and tables (:func:`control_context`) and its verdict (:func:`control_verdict`: does
the simplified-model controller track as well as the full-model one, per joint type).

``control_report.html`` has no external resources (inline CSS, inline SVG figures, Jinja2
template ``templates/control_report.html.j2``); ``control_report.pdf`` is typeset by
Typst from the same section list (:mod:`gd_analyze.report.typeset`). Both are written
atomically (:func:`gd_analyze.files.atomic_path`).
"""

from __future__ import annotations

import functools
import textwrap
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from .._version import VERSION as __version__
from ..config import defaults
from ..ranking.ranking import (
    ROUND_OFF,
    element_label,
    is_round_off,
    joint_motion_units,
    joint_torque_units,
)
from ..store.control_dataset import pd_name
from ..store.datasets import joint_units
from ..store.names import ControlVar as V
from ..store.schema import open_results
from ..store.stored_control import REQUIRED_VARIABLES, ModelFacts, StoredControl
from .common import (
    attr_text,
    cost_table,
    fmt,
    fmt_column,
    fmt_columns,
    joints_text,
    say,
    settings_table,
    utc_now,
)
from .common import or_default as _or
from .common import table as _table
from .drawing import draw_figures, write_report_files
from .figure_style import BASE_RC, grid_shape, joint_axes, markevery, panel_markevery
from .main_context import DERIVATIVES, command_row, gravity_row, run_row, software_row
from .main_text import StoredModel, weightless
from .markup import scope as scope_markup
from .markup import sub
from .numbers import decade_formatter, label_axes, set_ticks, time_origin
from .sections import Outline
from .typeset import check_paper

if TYPE_CHECKING:
    import os

    import xarray as xr
    from matplotlib.figure import Figure
    from numpy.typing import ArrayLike

__all__ = ["VERDICT_TOLERANCE", "control_verdict", "control_figures", "noise_scales",
           "noise_floors", "PAGE_WIDTH", "COLUMN_WIDTH", "CONTROLLER_LABELS",
           "controller_labels",
           "CONTROLLER_STYLES", "marker_starts", "marker_stride", "markers_words", "noise_words",
           "control_context", "dataset_verdict", "REQUIRED_VARIABLES",
           "write_control_report"]

# Numbers in e-notation outside [1e-3, 1e5), 3 significant digits unless told; attributes
# with 6 digits, arrays without parentheses, booleans as 0/1.
_SCI = (1e-3, 1e5)
fmt_number = functools.partial(fmt, digits=3, sci_outside=_SCI)
stored_text = functools.partial(attr_text, parens=False, bools=True, sci_outside=_SCI)


#: Default tolerance of the verdict on the simplified-model controller's peak tracking error:
#: (revolute joints [rad], prismatic joints [m]) (:data:`gd_analyze.config.defaults`); the
#: verdict takes the larger of it and twice the full-model controller's error (its integrator
#: floor); ``control --verdict-tolerance`` sets it.
VERDICT_TOLERANCE = tuple(defaults["verdict_tolerance"])
#: A tracking error that is integrator noise on every joint, as the text says it.
NOISE = "\u2261 0 (integrator noise)"


def _value(value, unit):
    """A number and its unit, never split over two lines; 0 (integrator noise) as \u2261 0."""
    return ((fmt_number(value) if value else "\u2261 0") + f"\u00a0{unit}").replace(" ", "\u00a0")


def _by_type(values, prismatic, which):
    """Each joint type present, as (unit, largest value, one-based joints), revolute first."""
    values, prismatic = np.asarray(values, float), np.asarray(prismatic, bool)
    out = []
    for kind in (False, True):
        ks = np.nonzero(prismatic == kind)[0]
        if ks.size:
            unit = joint_torque_units(kind) if which == "tau" else joint_motion_units(kind)[0]
            out.append((unit, float(np.nanmax(values[ks])), [int(k) + 1 for k in ks]))
    return out


def by_type_text(values: ArrayLike, prismatic: ArrayLike, which: str) -> str:
    """``"2.63e-04 rad"``, or per joint type ``"2.63e-04 rad, 6.20e-05 m"`` (revolute, then
    prismatic joints): a maximum is never taken across units."""
    return ", ".join(_value(v, u) for u, v, _ in _by_type(values, prismatic, which))


def control_verdict(peaks: Mapping[str, np.ndarray], prismatic: ArrayLike,
                    tau_difference: np.ndarray | None = None,
                    tolerance: tuple[float, float] = VERDICT_TOLERANCE,
                    quiet: Mapping[str, bool] | None = None, noise_rule: str | None = None,
                    covered: bool | None = None, pd: str = "PD + gravity",
                    departure: Mapping[str, np.ndarray] | None = None) -> str:
    """One sentence: does the simplified model control the arm as well as the full one?

    Parameters
    ----------
    peaks : dict of str to ndarray, shape (n,)
        Per controller (``"full"``, ``"simplified"``, ``"pd_gravity"``), each joint's peak
        tracking error |q_d - q| [rad, or m for a prismatic joint].
    prismatic : ndarray of bool, shape (n,)
        Which joints are prismatic.
    tau_difference : ndarray, shape (n,), optional
        Each joint's peak closed-loop torque difference, simplified-model controller minus
        full-model controller [N m, or N for a prismatic joint].
    tolerance : tuple of (float, float), optional
        Revolute [rad] and prismatic [m] tolerance
        (:data:`VERDICT_TOLERANCE`).
    quiet : dict of str to bool, optional
        Per controller, whether its error is integrator noise on every joint, and under
        ``"tau_difference"`` whether the torque difference is: said as
        "\u2261 0 (integrator noise)" instead of its digits.
    noise_rule : str, optional
        The rule by which a joint's torque difference is integrator noise, in words
        (:func:`gd_analyze.report.control.noise_words`), said after the torque
        difference.
    covered : bool, optional
        Whether the model's guarantee covers the run: a region guarantee that covers the
        desired motion and the closed loop (``model_guarantee_covered``; a trajectory-kind
        guarantee holds at the trajectory's set points only, never at the closed loop's
        states); where not, a run within the tolerance is said to be within it in this run
        only, never "good enough"; None: not said.
    pd : str, optional
        The PD controller's name (:func:`controller_labels`): ``"PD"`` where the controlled
        arm has no gravity.
    departure : dict of str to ndarray, shape (n,), optional
        Where the run starts off the trajectory (an initial offset q(0) - q_d(0)): per
        controller (``"simplified"``, ``"pd_gravity"``), each joint's peak departure of its
        closed loop from the full-model controller's, |q - q_full| over the run [rad, or m
        for a prismatic joint] (0 where integrator noise). Every controller's peak tracking
        error is then the offset's own, so the verdict judges the departure instead.

    Returns
    -------
    str
        The verdict: the simplified model holds if, for every joint type, its largest peak
        error is within the larger of the tolerance and twice the full model's; from an
        initial offset, if its largest departure is within the tolerance. Values of revolute
        and prismatic joints are stated apart, each in its unit.

    Examples
    --------
    >>> v = control_verdict({"full": np.array([1e-9, 1e-9]),
    ...                      "simplified": np.array([2e-4, 5e-4])}, np.array([False, True]))
    >>> print(v[:v.index(" (tolerance")])
    Verdict: the simplified model is good enough for computed-torque control along this trajectory: joint 1 revolute (rad, N m); joint 2 prismatic (m, N): peak tracking error 2.00e-04\xa0rad, 5.00e-04\xa0m against 1.00e-09\xa0rad, 1.00e-09\xa0m with the full model
    """
    full, simp = peaks.get("full"), peaks.get("simplified")
    if full is None or simp is None:
        return "Verdict: not available (the run lacks the full or the simplified controller)."
    pd_peaks, quiet = peaks.get("pd_gravity"), quiet or {}

    def said(c, values):
        return NOISE if quiet.get(c) else by_type_text(values, prismatic, "q")

    groups = {k: _by_type(v, prismatic, "q") for k, v in peaks.items()}
    tol = {False: tolerance[0], True: tolerance[1]}
    kinds = [u != joint_motion_units(False)[0] for u, _, _ in groups["full"]]
    judged = groups             # from an offset: the loops' departure from the full one's
    if departure is not None:
        judged = {k: _by_type(v, prismatic, "q") for k, v in departure.items()}
        bounds = [tol[kind] for kind in kinds]
    else:
        bounds = [max(2.0 * f, tol[kind]) for (_, f, _), kind in zip(groups["full"], kinds)]
    holds = all(s <= b for (_, s, _), b in zip(judged["simplified"], bounds))
    beats_pd = pd_peaks is not None and all(s < p for (_, s, _), (_, p, _) in
                                      zip(judged["simplified"], judged["pd_gravity"]))
    units = [u for u, _, _ in groups["full"]]      # each joint type apart
    verdict = ("holds" if covered in (None, True) else "measured") if holds else \
        "beats_pd" if beats_pd else "fails"
    # for a mixed arm, which joints are revolute and which prismatic, said once
    types = "" if len(kinds) < 2 else "; ".join(
        f"{joints_text(js)} {'prismatic' if kind else 'revolute'} ({u}, {joint_torque_units(kind)})"
        for (u, _, js), kind in zip(groups["full"], kinds)) + ": "
    return say("control_verdict", verdict=verdict, types=types,
               simplified=said('simplified', simp), full=said('full', full), pd=said('pd_gravity', pd_peaks) if pd_peaks is not None else "", pd_name=pd,
               bounds=[(fmt_number(b), u, "prismatic" if kind else "revolute")
                       for b, u, kind in zip(bounds, units, kinds)],
               tols=[f"{tol[kind]:g} {u}" for u, kind in zip(units, kinds)],
               difference="" if tau_difference is None else (
                   NOISE if quiet.get("tau_difference") else
                   by_type_text(tau_difference, prismatic, 'tau')), noise_rule=noise_rule,
               departure=None if departure is None else NOISE if not np.any(
                   departure["simplified"]) else by_type_text(departure["simplified"],
                                                              prismatic, "q"),
               pd_departure=by_type_text(departure["pd_gravity"], prismatic, "q")
               if departure is not None and "pd_gravity" in departure else "")


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
CONTROLLER_LABELS = {"full": "computed torque, full model", "simplified": "computed torque, simplified "
           "model", "pd_gravity": "PD + gravity"}


def controller_labels(ds: StoredControl | xr.Dataset, short: bool = False) -> dict[str, str]:
    """The controllers' names in a report, true of the run's controlled arm.

    Parameters
    ----------
    ds : StoredControl or xarray.Dataset
        A stored control run, or its dataset (its ``gravity``: the controlled arm's).
    short : bool, optional
        The names of a table's rows (``"full model"``) rather than of the figures' keys
        (:data:`CONTROLLER_LABELS`).

    Returns
    -------
    dict of str to str
        Controller key -> name; the PD controller's
        (:func:`gd_analyze.store.control_dataset.pd_name`) is ``"PD"`` where the controlled
        arm has no gravity, so that its law adds no gravity term.
    """
    return {**(_SHORT if short else CONTROLLER_LABELS),
            "pd_gravity": pd_name(StoredControl.of(ds).run.gravity)}
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


def _joint_panels(s, values, ylabel, title, log=False, floor=None, which="q",
                  width=PAGE_WIDTH):
    """A figure with one panel per joint; values: name -> (M, n) array along the stored
    control run's time.

    ``ylabel`` is formatted with each joint's units (``{u}``). With ``floor`` (n,)
    (:func:`noise_floors`), no point at or below a joint's floor is drawn, and a controller
    whose curve on a joint is all integrator noise is not drawn there: the panel says so; a
    log axis starts at the floor, a linear one shades the band within +-floor.
    """
    from matplotlib.lines import Line2D
    from matplotlib.ticker import LogLocator, NullFormatter

    origin, t_label = time_origin(s.time, "time t")
    t = np.asarray(s.time, dtype=float) - origin
    is_set = s.is_setpoint
    n = s.n
    units = joint_units(s.prismatic, which)
    column = width < PAGE_WIDTH
    # a page's row: two panels for up to four joints, else three (six joints in two rows)
    rows, cols = grid_shape(n, 1 if column else 2 if n <= 4 else 3)
    top = (0.5 if floor is None else 0.72) + ((0.25 if floor is None else 0.54) if column
                                              else 0.0)     # column: a note of 3 lines
    bottom = 0.62 + 0.14 * len(values) if column else 0.85     # the key, one entry a line
    height = (1.35 if column else _ROW_HEIGHT[cols]) * rows + bottom - 0.35 + top
    fig, axes = joint_axes(n, cols, (width, height), top, bottom,
                           0.3 if column else _WSPACE[cols], 0.35, t_label)
    # every k-th sample and every set point drawn
    keep = is_set | (np.arange(t.size) % markevery(t.size, _MAX_LINE_POINTS) == 0)
    every = marker_stride(s, len(values))
    handles = {}
    labels = controller_labels(s)
    quiet = {}                          # controller -> [(joint, peak)] of noise-only curves
    linear = []
    for j, ax in enumerate(axes):
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
                  "label": labels.get(name, name), "zorder": 2 + order}
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
            ax.set(yticks=[], xlim=(t[0], t[-1]))       # the run's times, as drawn panels
        ax.set_title(f"joint {j + 1}")
        ax.set_ylabel(ylabel.format(u=units[j]))
    label_axes(linear)                  # one tick notation for the figure
    if handles:
        fig.legend(list(handles.values()), list(handles), loc="lower center",
                   ncols=1 if column else min(3, len(handles)), frameon=False,
                   bbox_to_anchor=(0.5, 0.0))
    # the curves said as noise (their digits are not data), wrapped by the width drawn (at the
    # size it prints at, 8 pt)
    quiet_said = [(labels.get(name, name), "every joint" if len(where) == n else
                   joints_text([j + 1 for j, _ in where])) for name, where in quiet.items()]
    note = "" if floor is None else textwrap.fill(say(
        "control_noise_note", rule=noise_words(s, which, figure=True), quiet=quiet_said),
        70 if column else _NOTE_CHARS)
    extra = 0.0 if column else _NOTE_LINE * note.count("\n")
    if extra:                           # a page-width note of more lines: room above the panels
        height += extra
        fig.set_size_inches(width, height)
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
    stored = which == "tau" and s.tau_difference_floor is not None
    times = tighten = ""
    if stored:                          # a measured floor: its factor and tighter tolerances
        factor = float(s.settings.noise_factor)
        times = {1.0: "", 2.0: "twice "}.get(factor, f"{factor:g} times ")
        tighten = f"{float(s.settings.rtol) / float(s.settings.noise_rtol):g}"
    return say("noise_words", which=which, figure=figure, tol=f"{tol:g}", stored=stored,
               times=times, tighten=tighten)


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


def markers_words(ds: StoredControl | xr.Dataset, lines: Sequence[str],
                  drawn: Sequence[str] | None = None) -> str:
    """What a figure's markers are, in words.

    Parameters
    ----------
    ds : StoredControl or xarray.Dataset
        A stored control run, or its dataset.
    lines : sequence of str
        The controllers drawn, in the order they are drawn (:func:`controller_labels` names
        them): the lines with markers on each panel (:func:`marker_stride`).
    drawn : sequence of str, optional
        Of those controllers, the ones drawn on some panel: only they are named (a curve
        that is integrator noise on every joint is not drawn). Default all.

    Returns
    -------
    str
        "markers: every set point", "markers: every 8th set point, the first included", or
        for several lines "markers: every 8th set point, staggered so that no two controllers
        mark the same one; the first at set point 1 (computed torque, full model), 3 (...) and
        6 (...)" (:func:`marker_starts`).
    """
    names = [str(c) for c in lines]
    k = marker_stride(ds, len(names))
    labels = controller_labels(ds)
    starts = [f"{s + 1} ({labels.get(c, c)})" for s, c in zip(marker_starts(k, len(names)), names)
              if drawn is None or c in drawn]
    if not starts:
        return "no curve drawn"
    return say("markers_words", k=k, starts=starts, lines=len(names))


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
    stored = s.tau_difference_floor
    return tol * q_scale, tol * tau_scale if stored is None else np.asarray(stored, float)


def control_figures(ds: StoredControl | xr.Dataset, width: float = PAGE_WIDTH
                    ) -> dict[str, Figure]:
    """The report's figures, drawn from a stored control dataset.

    Parameters
    ----------
    ds : StoredControl or xarray.Dataset
        A stored control run (:class:`gd_analyze.store.stored_control.StoredControl`), or a
        control dataset (:func:`gd_analyze.store.control_dataset.control_dataset`).
    width : float, optional
        :data:`PAGE_WIDTH` (two panels a row up to four joints, else three) or
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


def dataset_verdict(ds: StoredControl | xr.Dataset) -> dict[str, Any]:
    """The control report's verdict and summary, from the stored control dataset: the same
    words for the report and the command line.

    Parameters
    ----------
    ds : StoredControl or xarray.Dataset
        A stored control run (:class:`gd_analyze.store.stored_control.StoredControl`), or a
        control dataset (:func:`gd_analyze.store.control_dataset.control_dataset`).

    Returns
    -------
    dict
        ``verdict`` and ``summary`` (str), ``rule`` (``"q"``, ``"tau"`` -> the integrator-noise
        rule in words, :func:`~gd_analyze.report.control.noise_words`) and ``floors``
        (:func:`~gd_analyze.report.control.noise_floors`: per joint [rad or m],
        [N m or N]). A tracking error or torque difference at or below its joint's floor is
        integrator noise, said as "\u2261 0 (integrator noise)".
    """
    s = StoredControl.of(ds)
    st = s.settings
    names = s.controllers
    prismatic = np.array(s.prismatic, dtype=bool)
    q_floor, tau_floor = noise_floors(s)     # a joint's integrator noise is not its largest value
    peaks = {c: np.where(is_round_off(s.error_peak_grid[c], q_floor, 1.0), 0.0,
                         s.error_peak_grid[c]) for c in names}
    rule = {k: noise_words(s, k) for k in ("q", "tau")}     # the rules, said everywhere
    quiet = {c: not peaks[c].any() for c in names}   # every joint's error is noise: not data
    labels = controller_labels(s)
    summary = say("control_summary", robot=stored_text(st.robot),
                  trajectory=stored_text(st.trajectory_file), wn=_per_joint(st.wn, " rad/s"),
                  zeta=_per_joint(st.zeta), peaks=[(labels.get(c, c), NOISE if quiet[c] else
                                                    by_type_text(peaks[c], prismatic, "q"))
                                                   for c in names])
    diff = s.tau_difference_peak
    if diff is not None:
        diff = np.where(is_round_off(diff, tau_floor, 1.0), 0.0, diff)
        quiet["tau_difference"] = not diff.any()
        summary += say("control_difference", rule=rule["tau"],
                       difference=NOISE if quiet["tau_difference"] else
                       by_type_text(diff, prismatic, 'tau'))
    tolerance = tuple(float(d if v is None else v) for v, d in
                      zip((st.verdict_tolerance_revolute, st.verdict_tolerance_prismatic),
                          VERDICT_TOLERANCE))
    covered = (str(s.model.guarantee_covered) == "1"        # a trajectory kind: its set
               and str(s.model.guarantee_kind) == "region")   # points only
    departure = None            # from an offset, every loop's peak error is the offset's
    if np.any(s.q0_offset) and {"full", "simplified"} <= set(names):
        departure = {c: np.where(is_round_off(d := np.max(np.abs(s.error[c] - s.error["full"]),
                                                          axis=0), q_floor, 1.0), 0.0, d)
                     for c in names if c != "full"}
    verdict = control_verdict(peaks, prismatic, diff,
                              tolerance,  # type: ignore[arg-type]  # (revolute, prismatic)
                              quiet, rule["tau"], covered, labels["pd_gravity"], departure)
    return {"verdict": verdict, "summary": summary, "rule": rule,
            "floors": (q_floor, tau_floor)}


def control_context(ds: StoredControl | xr.Dataset) -> dict[str, Any]:
    """Everything the control report says, from the stored control dataset.

    Parameters
    ----------
    ds : StoredControl or xarray.Dataset
        A stored control run (:class:`gd_analyze.store.stored_control.StoredControl`), or a
        control dataset (:func:`gd_analyze.store.control_dataset.write_control_dataset`).

    Returns
    -------
    dict
        The report's context, the same for the HTML and the PDF.
    """
    s = StoredControl.of(ds)
    st = s.settings
    names = s.controllers
    n = s.n
    joints = [f"joint {j + 1}" for j in range(n)]          # as the main report names them
    q_units = joint_units(s.prismatic, "q")
    judged = dataset_verdict(s)
    rule, (q_floor, tau_floor) = judged["rule"], judged["floors"]
    labels, short = controller_labels(s), controller_labels(s, short=True)
    files = {"robot": (st.robot, st.robot_sha256),         # the inputs, each with its SHA-256
             "trajectory": (st.trajectory_file, st.trajectory_sha256),
             "model": (st.model_file, st.model_sha256)}
    noise = "integrator noise of \u03c4" + sub("s") + " \u2212 \u03c4" + sub("f")
    setup = settings_table([
        *([{"model": "simplified model"}.get(k, k), f"{stored_text(file)} (SHA-256 "
           f"{stored_text(sha)})"] for k, (file, sha) in files.items()),
        ["plant", say("plant", stored=stored_text(st.plant))],
        ["controllers", "; ".join(labels.get(c, d) for c, d in zip(names, s.descriptions))
         + " (control laws below)"],
        ["desired motion", stored_text(st.interpolation).replace(
            "(q, qd, qdd)", "(q, q\u0307, q\u0308)")],        # the stored words, as mathematics
        ["integrator", f"{stored_text(st.integrator)}, rtol = {float(st.rtol):g}, "
                       f"atol = {float(st.atol):g}"],
        [noise, None if st.noise_rtol is None else say(
            "noise_measured", rtol=f"{float(st.noise_rtol):g}", atol=f"{float(st.noise_atol):g}",
            nfev=int(st.noise_nfev), factor=f"{float(st.noise_factor):g}",
            floor=f"{float(st.rtol):g}")],
        [noise, None if st.noise_unmeasured is None else say(
            "noise_unmeasured", why=str(st.noise_unmeasured))],
        ["samples", f"{stored_text(st.samples)} ({stored_text(st.setpoints)} set points + fine grid "
                    f"of {stored_text(st.grid_points)})"],
        ["initial offset q(0) \u2212 q" + sub("d") + "(0)",
         ", ".join(f"{fmt_number(v)}\u00a0{u}" for v, u in zip(s.q0_offset, q_units))],
    ])
    gains = _gains_table(s, joints)
    # each row: its leading cells, its numbers per joint, and which are integrator noise (at
    # or below the joint's noise floor: not data)
    error_rows = [([short.get(c, c), where, fig], v[c], is_round_off(peaks[c], q_floor, 1.0))
                  for c in names
                  for where, peaks, rms in (
                      ("set points", s.error_peak_setpoints, s.error_rms_setpoints),
                      ("fine grid", s.error_peak_grid, s.error_rms_grid))
                  for fig, v in (("peak", peaks), ("RMS", rms))]
    diff = []
    if s.tau_difference_peak is not None:
        pairs = [("peak, fine grid", s.tau_difference_peak, s.tau_difference_peak),
                 ("RMS, fine grid", s.tau_difference_rms, s.tau_difference_peak)]
        if s.tau_difference_peak_setpoints is not None:
            at = s.tau_difference_peak_setpoints
            pairs += [("peak, set points", at, at),
                      ("RMS, set points", s.tau_difference_rms_setpoints, at)]
        diff = [([fig], value, is_round_off(peak, tau_floor, 1.0)) for fig, value, peak in pairs]
        diff.append((["noise floor (\u2261 0 at or below)"], tau_floor, np.zeros(n, bool)))
    applied = [([short.get(c, c), fig], figures[c], np.zeros(n, bool)) for c in names
               for fig, figures in (("peak |\u03c4|", s.tau_peak), ("RMS \u03c4", s.tau_rms))]
    tau_u = [f"{j} [{u}]" for j, u in zip(joints, joint_units(s.prismatic, "tau"))]
    errors = _table(["controller", "sampled at", "figure"]
                    + [f"{j} [{u}]" for j, u in zip(joints, q_units)],
                    _with_columns(error_rows), align=["left", "left", "left"] + ["right"] * n)
    tau_diff = _table(["figure"] + tau_u, _with_columns(diff, one=True), align="right")
    tau_table = _table(["controller", "figure"] + tau_u, _with_columns(applied),
                       align=["left", "left"] + ["right"] * n)
    model_note, recursive = _model_note(s)
    choice = dict(zip(s.elements, s.choice))
    rows = [[f"D, row {i + 1}"] + [choice.get(element_label("D", i, j), "") if j >= i else ""
                                   for j in range(n)] for i in range(n)]
    rows.append(["h"] + [choice.get(element_label("h", j), "") for j in range(n)])
    choices = None if recursive else _table(["element"] + [f"column {j + 1}"
                                                          for j in range(n)], rows,
                                           align=["left"] * (n + 1))
    prov = settings_table(_provenance(s, __version__))
    created = utc_now().isoformat()
    curves = {**{c: (s.error[c], q_floor) for c in names},      # as Figs. 1 and 2 draw them
              "difference": (s.tau_difference, tau_floor)}
    drawn = [c for c, (y, floor) in curves.items() if y is not None and not is_round_off(
        np.nanmax(np.abs(np.asarray(y, float)), axis=0), floor, 1.0).all()]
    markers = {"error": markers_words(s, names, drawn), "tau": markers_words(s, names),
               "tau_difference": markers_words(s, ["difference"], drawn)}
    captions = {key: say("control_caption", key=key, markers=markers[key],
                         rule=rule.get("q" if key == "error" else "tau"))
                for key in markers}
    return {
        "version": __version__,
        "title": f"Computed-torque control with the simplified G-D model: {stored_text(st.robot)}",
        "summary": judged["summary"], "verdict": judged["verdict"],
        "intro": say("control_intro", rule=str(s.model.rule),
                     eps=f"{float(s.model.tolerance):g}", created=created,
                     version=__version__, pd=labels["pd_gravity"]),
        "setup": setup, "gains": gains, "gains_note": say("gains_note", pd=labels["pd_gravity"]),
        "errors": errors, "noise_rule": rule, "captions": captions, "tau_diff": tau_diff,
        "tau_table": tau_table, "cost": cost_table(s.costs),
        "choices": choices, "model_note": model_note, "provenance": prov,
        "keywords": "; ".join(f"{k} {stored_text(file)} sha256 {stored_text(sha)}"
                              for k, (file, sha) in files.items()),
    }


def _with_columns(entries, digits=3, one=False):
    """Table rows: each row's leading cells, then its numbers per joint, each joint's column in
    one notation (:func:`gd_analyze.report.numbers.fmt_column`: one format per
    column), or with ``one`` the whole table in one
    (:func:`~gd_analyze.report.numbers.fmt_columns`: a column whose only number is its noise
    floor never reads "0.000012" beside "5.06e-04").

    Parameters
    ----------
    entries : list of (list of str, array_like, array_like of bool), length R
        Per row: its leading cells, its numbers, one per joint [that column's units], shape
        (n,), and which of them are integrator noise by the report's rule ("\u2261 0").
    digits : int, optional
        Significant digits each entry keeps, at least.
    one : bool, optional
        One notation for every column (one quantity).

    Returns
    -------
    list of list of str
    """
    if not entries:
        return []
    rows, values, off = zip(*entries)
    v, hide = np.asarray(values, float).T, np.asarray(off, bool).T      # a row per joint
    cols = (fmt_columns(v, digits, list(hide)) if one else
            [fmt_column(c, digits, h) for c, h in zip(v, hide)])
    return [list(r) + list(c) for r, c in zip(rows, zip(*cols))]


def _per_joint(stored, unit=""):
    """A per-joint setting as the summary says it: once where every joint has the same value
    ("20 rad/s on every joint"), else the list ("20, 30, 20 rad/s")."""
    values = np.atleast_1d(np.asarray(_or(stored, np.nan), float))
    if values.size > 1 and np.all(values == values[0]):
        return f"{values[0]:g}{unit} on every joint"
    return ", ".join(f"{v:g}" for v in values) + unit


def _model_note(s):
    """Sec. 5's text: what the simplified model keeps, its rule and guarantee, generated from
    the model's facts stored by the control run (:func:`gd_analyze.jobs.control.model_facts`)
    in the words of the main report (:class:`gd_analyze.report.main_text.StoredModel`).
    Returns (text, whether the model has the recursive form)."""
    m = s.model
    where = say("model_where", region=str(m.guarantee_kind) == "region",   # pruned on bounds
                own=str(s.settings.trajectory_is_models) == "1", unknown=str(m.pairs_known) == "0")
    kept = StoredModel.of(m, s.choice, where, weightless(m.gravity))   # the model's own gravity
    text = kept.sentence()
    if kept.recursive is not None and kept.recursive[1]:
        text += f" The dropped pairs: {m.dropped_pairs}."
    return text + " " + scope_sentences(m, float(m.tolerance)), kept.recursive is not None


def scope_sentences(attrs: ModelFacts | Mapping[str, Any], eps: float) -> str:
    """The model's rule, its guarantee as the model states it, and whether that covers the
    tracked motion, from the attributes the control run stored (``model_scope``,
    ``model_guarantee_kind``, ``model_guarantee_covered``, ``model_guarantee_coverage``).

    Parameters
    ----------
    attrs : ModelFacts or dict
        The model's facts as stored (:class:`gd_analyze.store.stored_control.ModelFacts`), or the
        control dataset's attributes.
    eps : float
        The model's tolerance EPS [1].

    Returns
    -------
    str
        Sentences; "guaranteed" only where the guarantee covers the motion.

    Examples
    --------
    >>> scope_sentences({"model_rule": "budget", "model_guarantee_kind": "trajectory",
    ...                  "model_scope": "within 1 % of s_i on this trajectory only",
    ...                  "model_guarantee_covered": 0,
    ...                  "model_guarantee_coverage": "it is not the trajectory"}, 0.01)[-68:]
    'trajectory. The open-loop error along this motion is not guaranteed.'
    """
    m = attrs if isinstance(attrs, ModelFacts) else ModelFacts.from_attrs(attrs, "model_")
    return say("scope_sentences", rule=str(_or(m.rule, "")), kind=str(_or(m.guarantee_kind, "")),
               scope=scope_markup(str(_or(m.scope, ""))), eps=f"{eps:g}",
               covered=str(m.guarantee_covered) == "1",
               reason=scope_markup(attr_text(_or(m.guarantee_coverage, ""), "")))


#: Stored units of the gains (:func:`gd_analyze.ranking.labels.joint_gain_units`) and
#: of D_ii, as printed.
_GAIN_UNITS = {"N m rad-1": "N m/rad", "N m s rad-1": "N m s/rad", "N m-1": "N/m",
               "N s m-1": "N s/m", "kg m2": "kg m\u00b2", "kg": "kg"}


def _gains_table(s, joints):
    """The gains per joint. D_ii and the PD gains carry the units of their joint's type
    (the stored ``<name>_units`` per joint): in the header where every joint agrees, else in
    each cell."""
    header = ["joint", "\u03c9" + sub("n") + " [rad/s]", "\u03b6",
              "K" + sub("p") + " [1/s\u00b2]", "K" + sub("v") + " [1/s]"]
    per_joint = {}
    for name, title in ((V.INERTIA_SCALE, "D" + sub("ii") + " at the start"),
                        (V.KP_PD, "PD K" + sub("p")), (V.KV_PD, "PD K" + sub("v"))):
        units = [_GAIN_UNITS.get(u, u) for u in s.gain_units[name]]
        same = len(set(units)) == 1
        header.append(f"{title} [{units[0]}]" if same else title)
        per_joint[name] = ([""] * len(units) if same else
                           ["\u00a0" + u.replace(" ", "\u00a0") for u in units])
    cols = {v: fmt_column(s.gains[v], 4) for v in (V.WN, V.ZETA, V.KP, V.KV, V.INERTIA_SCALE,
                                                  V.KP_PD, V.KV_PD)}   # one per column
    rows = [[joints[j]] + [cols[v][j] for v in (V.WN, V.ZETA, V.KP, V.KV)]
            + [cols[v][j] + per_joint[v][j] for v in (V.INERTIA_SCALE, V.KP_PD, V.KV_PD)]
            for j in range(len(joints))]
    return _table(header, rows, align="right")


#: The controllers as a table's rows name them (the figures' keys: ``CONTROLLER_LABELS``;
#: a run's own: :func:`controller_labels`).
_SHORT = {"full": "full model", "simplified": "simplified model", "pd_gravity": "PD + gravity"}

#: The provenance rows of the control report: (item, attribute), each setting once (the gains
#: and the control laws are in Sec. 1, the robot, trajectory and model files in Table 1.1).
_PROVENANCE = (("trajectory path", "trajectory_path"),
               ("trajectory derivatives", "trajectory_derivatives"),
               ("model path", "model_path"),
               ("trajectory the model was built on (SHA-256)", "model_trajectory_sha256"),
               ("model built on this trajectory", "trajectory_is_models"),
               ("model's guarantee covers this motion", "model_guarantee_covered"),
               ("method", "references"))


def _provenance(s, version):
    """The provenance rows, each setting once and in words: the software, the command line as
    :func:`gd_analyze.cli.main` was given it (stored by the command line; an older file has
    none), the run as the main report says them (:mod:`gd_analyze.report.main_context`),
    gravity, the files, the verdict's tolerance."""
    st = s.settings
    rows = [software_row(s.run, version),
            command_row(st.command),
            run_row(s.run, "run"), gravity_row(s.run)]
    own = str(st.trajectory_is_models) == "1"
    for label, k in _PROVENANCE:
        stored = (s.model.guarantee_covered if k == "model_guarantee_covered" else
                  getattr(st, k))
        if stored is None or (k == "model_trajectory_sha256" and own):
            continue                    # the trajectory's own SHA-256, said in Table 1.1
        value = stored_text(stored)
        if k in ("trajectory_is_models", "model_guarantee_covered"):
            value = {"1": "yes", "0": "no"}.get(value, value)
        if k == "trajectory_derivatives" and value in DERIVATIVES:
            value = f"{value}: {DERIVATIVES[value]}"
        rows.append((label, value))
    if st.verdict_tolerance_revolute is not None:
        kinds = set(s.prismatic)
        rows.append(("verdict tolerance", say(
            "verdict_tolerance", both=len(kinds) > 1,
            revolute=stored_text(st.verdict_tolerance_revolute) if False in kinds else "",
            prismatic=stored_text(st.verdict_tolerance_prismatic) if True in kinds else "")))
    return rows


_FIGURE_FILES = {"error": "fig_control_tracking_error",
                 "tau_difference": "fig_control_torque_difference",
                 "tau": "fig_control_applied_torque"}
#: Each figure also 3.5 in wide, as ``figures/<name>_column.pdf`` and ``.svg`` (not in the
#: report), with ``column_figures``.
_FIGURE_FILES.update({f"{k}_column": f"{v}_column" for k, v in list(_FIGURE_FILES.items())})


def _next_figure(o):
    """"Fig. N": how the text cites the next figure of the outline ``o``."""
    return f"Fig. {o.n_figures + 1}"


def _outline(ctx, figures):
    """The control report's sections, once, for the HTML and the PDF
    (:class:`gd_analyze.report.sections.Outline`)."""
    o = Outline(ctx["title"], figures, [(ctx["verdict"], "lead"), (ctx["summary"], "summary"),
                                        (ctx["intro"], "note")])
    o.section("1", "Set-up and gains", "setup")
    o.table(ctx["setup"], "The closed-loop run.", kv=True)
    o.paragraph(ctx["gains_note"], "note")
    o.table(ctx["gains"], "Gains per joint.")
    # each figure right under the sentence citing it, its table after it: a figure that does
    # not fit there goes to the next page's top, and the table fills this page
    o.section("2", "Tracking error", "tracking")
    o.paragraph(say("control_outline", key="tracking", figure=_next_figure(o)), "note")
    o.figure("error", ctx["captions"]["error"])
    o.table(ctx["errors"], say("control_outline", key="errors", rule=ctx["noise_rule"]["q"]),
            size=7)
    o.section("3", "Torques", "torque")
    drawn = "tau_difference" in o.available
    o.paragraph(say("control_outline", key="difference",
                    figure=_next_figure(o) if drawn else ""), "note")
    if drawn:
        o.figure("tau_difference", ctx["captions"]["tau_difference"])
    else:
        o.paragraph("No torque difference stored.", "body")
    o.table(ctx["tau_diff"], say("control_outline", key="difference_table",
                                 rule=ctx["noise_rule"]["tau"]))
    o.paragraph(say("control_outline", key="applied", figure=_next_figure(o)), "note")
    o.figure("tau", ctx["captions"]["tau"])
    o.table(ctx["tau_table"], "Applied torques per controller and joint.", size=7)
    o.section("4", "Evaluation cost of the model", "cost")
    o.paragraph(say("control_outline", key="cost"), "note")
    if ctx["cost"]:
        o.table(ctx["cost"], "Operations per set point of each evaluator.")
    else:
        o.paragraph("Not measured.", "body")
    o.section("5", "Simplified model", "model")
    o.paragraph(ctx["model_note"], "note")
    if ctx["choices"]:
        o.table(ctx["choices"], "The part of each element the simplified model keeps.")
    o.section("6", "Provenance", "provenance")
    o.table(ctx["provenance"], "Provenance: the files and settings of the run, each once.",
            kv=True, size=7)
    return o


def write_control_report(control_path: str | os.PathLike[str], outdir: str | os.PathLike[str],
                         paper: str = "a4", latex: bool = False,
                         column_figures: bool = False) -> list[Path]:
    """Write control_report.html and control_report.pdf for a stored control dataset.

    Parameters
    ----------
    control_path : str or os.PathLike
        A control dataset written by :func:`gd_analyze.store.control_dataset.write_control_dataset`
        (``control.h5``). Only read: nothing is recomputed.
    outdir : str or os.PathLike
        Output folder; made if missing.
    paper : {"a4", "letter"}, optional
        Page size of the PDF.
    latex : bool, optional
        Also write every table as LaTeX, ``outdir/tables/control_table_<section>_<k>.tex``.
    column_figures : bool, optional
        Also write every figure 3.5 in wide, as ``figures/<name>_column.pdf`` and ``.svg``.

    Returns
    -------
    list of pathlib.Path
        ``outdir/control_report.html`` and ``outdir/control_report.pdf``, then every figure as
        ``outdir/figures/fig_control_*.pdf`` and ``.svg`` (with ``column_figures``, each
        followed by its column twin), then every table of the report as
        ``outdir/tables/control_table_<section>_<k>.csv`` (and ``.tex`` with ``latex``).

    Raises
    ------
    InputError
        If the file is missing, unreadable or not a control dataset.
    OSError
        If a file cannot be written.

    Notes
    -----
    Each file is written under a temporary name beside its destination and renamed
    (:func:`gd_analyze.files.atomic_path`). Sources: Fu, Gonzalez & Lee (1987), Sec. 3.4.1
    (simplified model) and Ch. 5 (computed-torque control).
    """
    check_paper(paper)
    s = StoredControl.from_dataset(open_results(str(control_path)), str(control_path))
    ctx = control_context(s)
    column = {f"{k}_column": f for k, f in control_figures(s, COLUMN_WIDTH).items()
              } if column_figures else {}
    drawn = draw_figures({**control_figures(s), **column}, FIGURE_RC)
    return write_report_files(
        outdir, ctx, drawn, _FIGURE_FILES, _outline, "control_report.html.j2",
        "Computed-torque control with the simplified G-D model (Fu, Gonzalez & Lee 1987, Sec. "
        "3.4.1 and Ch. 5)", "control report", stem="control_report", paper=paper, latex=latex,
        prefix="control")
