"""The report's "Simplified model" section, from the stored dataset only.

:func:`simplified_context` gives the tables and text, :func:`error_figure` the per-joint plots
of tau_s - tau with the guaranteed bound, and the figures of what the error budget acts on
(:func:`budget_makers`): the torque contributions, the budget against the bound, the costs
against accuracy. Everything is read from the variables
and attributes that :func:`gd_analyze.jobs.simplified_dataset.simplified_dataset` stored at analysis
time; nothing is recomputed.
"""

from __future__ import annotations

import math
import textwrap
from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from ..ranking.ranking import ROUND_OFF, arm_scales, is_round_off, joint_units_text
from ..store.stored_simplified import InertiaCheck, StoredSimplified
from .common import count, fmt, joints_text, pct, pct_column, say, table, torque_units
from .figure_style import grid_boxes, markevery, new_figure
from .markup import powers, sub
from .markup import scope as scope_markup
from .numbers import joint_ticks, label_axes, set_ticks, tick_label_width, time_origin
from .typeset import MIN_PRINTED_PT, printed_scale

if TYPE_CHECKING:
    from collections.abc import Mapping

    import numpy.typing as npt
    import xarray as xr
    from matplotlib.figure import Figure

    from ..store.results_view import Results
    from .main_figures import PlotData

__all__ = ["budget_caption",
           "joint_sum_lower", "CONTRIBUTIONS", "fig_torque_contributions", "fig_error_budget",
           "fig_cost_ladder", "budget_makers", "contribution_series", "simplified_context",
           "error_figure", "ROUND_OFF", "simplified_caption",
           "region_pruning", "bound_ways"]

#: The five G-D contributions to tau_i: series key of the plot data, label, colour, line
#: style, marker (told apart in greyscale by line style and marker).
CONTRIBUTIONS = (
    ("D_tran_qdd", "D\u1d57\u02b3\u1d43\u207f q\u0308", "#0072B2", "-", "o"),
    ("D_rot_qdd", "D\u02b3\u1d52\u1d57 q\u0308", "#D55E00", (0, (4.0, 1.6)), "x"),
    ("h_tran", "h\u1d57\u02b3\u1d43\u207f", "#009E73", (0, (5.0, 1.5, 1.0, 1.5)), "s"),
    ("h_rot", "h\u02b3\u1d52\u1d57", "#CC79A7", (0, (1.0, 1.3)), "D"),
    ("c", "c", "#E69F00", (0, (7.0, 2.0)), "v"),
)
_SIMPLIFIED = ("tau_simplified", "simplified model's torque", "#000000", "-", None)
_DRIVES = ("drives", "drives (armature, friction)", "0.45", (0, (2.0, 2.0)), "+")
_PAGE = 7.2
#: Width of the column versions [in].
COLUMN = 3.5

#: The simplified model's torque tau_s and the joint's scale s_i, their subscripts set as such
#: (8 pt at least in the PDF). The figures write no subscript (Unicode's small letters print
#: under 8 pt): s for s_i and delta tau for tau_s - tau, which the captions define.
_TAU_S, _S_I = "\u03c4" + sub("s"), "s" + sub("i")

def contribution_series(data: PlotData, drives: bool = False) -> dict[str, npt.NDArray[np.float64]]:
    """The series of :func:`fig_torque_contributions`, by key.

    Parameters
    ----------
    data : PlotData
        With ``D_tran_qdd``, ``D_rot_qdd``, ``h_tran``, ``h_rot``, ``c``, ``tau`` and
        ``tau_simplified`` (M, n) [N m, N for a prismatic joint].
    drives : bool, optional
        Add ``drives`` = tau - (the five), the armature's and friction's part of tau.

    Returns
    -------
    dict of str to ndarray, shape (M, n)
        The five contributions of :data:`CONTRIBUTIONS`, ``tau_simplified`` and, with
        ``drives``, ``drives``.
    """
    out = {key: np.asarray(data.series[key]) for key, *_ in CONTRIBUTIONS}
    out["tau_simplified"] = np.asarray(data.series["tau_simplified"])
    if drives:
        out["drives"] = np.asarray(data.series["tau"]) - sum(
            out[key] for key, *_ in CONTRIBUTIONS)
    return out


def _time_panel(ax, i, t, y, nbins, t_label="t [s]", **xlabel):
    """Joint i's panel against time: t from t[0] to t[1] (a second long where they meet), y
    from y[0] to y[1] with 8 % of their span added each side, round ticks (the y ones labelled
    by the figure: :func:`gd_analyze.report.numbers.label_axes`), its title and t label
    (:func:`gd_analyze.report.numbers.time_origin`)."""
    (lo, hi), (t0, t1) = y, t
    pad = 0.08 * (hi - lo)
    ax.set_ylim(lo - pad, hi + pad)
    set_ticks(ax.yaxis, lo, hi, nbins, labels=False)
    t1 = t1 if t1 > t0 else t0 + 1.0
    ax.set_xlim(t0, t1)
    set_ticks(ax.xaxis, t0, t1, 4)
    ax.set_title(f"joint {i + 1}", fontsize=8)
    ax.set_xlabel(t_label, labelpad=1.0, **xlabel)


def fig_torque_contributions(data: PlotData, units: Sequence[str], drives: bool = False,
                             width: float = _PAGE) -> Figure:
    """Per joint against time: the five G-D contributions to tau and the simplified torque.

    Parameters
    ----------
    data : PlotData
        As for :func:`contribution_series`, time x [s].
    units : sequence of str, length n
        Each joint's torque units (N m or N).
    drives : bool, optional
        Draw the drives' part of tau (armature and friction) as a sixth curve.
    width : float, optional
        Figure width [in]: three panels a row at page width, four for ten joints or more.

    Returns
    -------
    matplotlib.figure.Figure
        One panel per joint, ``"joint i"`` above it, y axis ``[N m]`` times the power of ten
        it shows; each contribution its own colour, line style and marker (markers thinned
        to about eight a line, none on a min/max envelope), tau_s thick and black; the legend
        above the panels.
    """
    series = contribution_series(data, drives)
    keys = [c[0] for c in CONTRIBUTIONS] + ["tau_simplified"] + (["drives"] if drives else [])
    style = {c[0]: c for c in CONTRIBUTIONS + (_SIMPLIFIED, _DRIVES)}
    origin, t_label = time_origin(data.x)
    x = np.asarray(data.x, dtype=float) - origin
    n = series["c"].shape[1]
    column = width < _PAGE
    # page width: three panels a row, four from ten joints on, in rows lower from four rows on:
    # the figure of a 10- to 15-joint arm leaves room under it on its page for what follows
    cols = min(n, 2 if column else 3 if n <= 9 else 4)
    rows = math.ceil(n / cols)
    left, right, gap, top, hgap = 0.55, 0.08, 0.55, 0.62 + 0.32 * column, 0.55
    h = 1.1 if column else min(1.35, 4.05 / rows)
    w = (width - left - right - (cols - 1) * gap) / cols
    H = top + rows * h + (rows - 1) * hgap + 0.4
    fig = new_figure(width, H)
    every = markevery(x.size, 8)
    ys = []
    for i, box in enumerate(grid_boxes(fig, n, cols, (left, top), (w, h), (gap, hgap))):
        ax = fig.add_axes(box)
        for k, key in enumerate(keys):
            _, name, colour, ls, marker = style[key]
            kw: dict[str, Any] = {"color": colour, "linestyle": ls, "label": name,
                  "linewidth": 1.3 if key == "tau_simplified" else 0.9,
                  "zorder": 3 if key == "tau_simplified" else 2}
            if marker and not data.enveloped:
                kw.update(marker=marker, markersize=3.0, markerfacecolor="none",
                          markeredgewidth=0.7,
                          markevery=((k * max(1, every // 6)) % every, every)
                          if every > 1 else 1)
            ax.plot(x, series[key][:, i], **kw)
        vals = np.concatenate([series[key][:, i] for key in keys])
        vals = vals[np.isfinite(vals)]
        lo, hi = (float(vals.min()), float(vals.max())) if vals.size else (-1.0, 1.0)
        if hi - lo <= 1e-300:
            lo, hi = lo - 1.0, hi + 1.0
        _time_panel(ax, i, (float(x[0]), float(x[-1])), (lo, hi), 4, t_label)
        ax.set_ylabel(f"[{units[i]}]", labelpad=1.0)
        ys.append(ax.yaxis)
    label_axes(ys)
    # room for the widest tick labels, the tick marks and the axis label left of each panel
    room = max(tick_label_width(y) for y in ys) + 0.30
    if room > left:
        left, gap = room, max(gap, room)
        w = (width - left - right - (cols - 1) * gap) / cols
        for ax, box in zip(fig.axes, grid_boxes(fig, n, cols, (left, top), (w, h), (gap, hgap))):
            ax.set_position(box)
    fig.legend(*fig.axes[0].get_legend_handles_labels(), loc="upper center",
               ncol=2 if column else (4 if len(keys) > 6 else 3), frameon=False, fontsize=7,
               handlelength=3.0,
               columnspacing=1.2, bbox_to_anchor=(0.5, 1 - 0.04 / H))
    return fig


#: The parts of the bound, stacked (field of the stored record, label, colour, hatch).
_BOUND_PARTS = (("bound_inertia", "dropped terms of D q\u0308", "#0072B2", ""),
                ("bound_coriolis", "dropped terms of h", "#D55E00", "//"),
                ("bound_gravity", "dropped terms of c", "#E69F00", ".."),
                ("bound_whole", "base parameters dropped whole", "#CC79A7", "xx"))


def _stored_parts(s: StoredSimplified) -> dict[str, np.ndarray]:
    """The stored parts of the bound, by field, those stored only."""
    parts = {k: getattr(s, k) for k, *_ in _BOUND_PARTS}      # the fields of _BOUND_PARTS
    return {k: np.asarray(v, float) for k, v in parts.items() if v is not None}


def budget_parts(ds: StoredSimplified | xr.Dataset) -> dict[str, npt.NDArray[np.float64]]:
    """The stacked parts of :func:`fig_error_budget`, relative to each joint's scale s_i.

    Parameters
    ----------
    ds : StoredSimplified or xarray.Dataset
        The simplified model's record (:class:`gd_analyze.store.stored_simplified.StoredSimplified`),
        or a results dataset with ``simplified_scale`` (n,) and the ``simplified_bound_*``
        parts (n,) [N m].

    Returns
    -------
    dict of str to ndarray, shape (n,)
        Each stored part / s_i [1] (NaN where s_i is 0), by field of the record
        (``"bound_inertia"``, ``"bound_coriolis"``, ``"bound_gravity"``, ``"bound_whole"``).
    """
    s = StoredSimplified.of(ds)
    scale = np.asarray(s.scale, float)
    safe = np.where(scale > 0, scale, np.nan)
    return {k: np.nan_to_num(v) / safe for k, v in _stored_parts(s).items()}


def budget_caption(ds: StoredSimplified | xr.Dataset) -> str:
    """The error-budget figure's caption, from the kind of the model's guarantee.

    Parameters
    ----------
    ds : StoredSimplified or xarray.Dataset
        The simplified model's record, or a results dataset with it.

    Returns
    -------
    str
        For a bound proved over the region (the bars are proved bounds, and a triangle marks
        a joint's bound proved on the dropped terms' sum: :func:`joint_sum_lower`), else for
        peaks on the trajectory.
    """
    s = StoredSimplified.of(ds)
    region = s.guarantee_kind == "region"
    return say("budget_caption", key="budget", region=region,
               joint_sum=region and bool(joint_sum_lower(s).any()))


def joint_sum_lower(ds: StoredSimplified | xr.Dataset) -> npt.NDArray[np.bool_]:
    """The joints whose stated bound is below the sum of the dropped terms' own bounds.

    Parameters
    ----------
    ds : StoredSimplified or xarray.Dataset
        The simplified model's record, or a results dataset with ``simplified_bound`` and the
        ``simplified_bound_*`` parts (n,) [N m].

    Returns
    -------
    ndarray of bool, shape (n,)
        True where the bound was proved on the dropped set's joint sum
        (:func:`gd_analyze.certify.certify.region_bound`): where the guarantee states how
        each joint's bound was proved, the joints bounded on their sum at the same state
        (``guarantee.bound_method``: ``"joint sum"``, ``"branch and bound"``,
        ``"decomposition"``); in an older file, where ``simplified_bound`` < (1 - 1e-9) x
        the parts' sum.
    """
    s = ds if isinstance(ds, StoredSimplified) else StoredSimplified.from_dataset(ds)
    if s is None:
        return np.zeros(0, bool)
    method = (s.guarantee or {}).get("bound_method") or ()
    if method:
        return np.array([m in ("joint sum", "branch and bound", "decomposition")
                         for m in method], bool)
    bound = np.asarray(s.bound, float)
    total = sum((np.nan_to_num(v) for v in _stored_parts(s).values()), np.zeros_like(bound))
    return bound < (1 - 1e-9) * total


def fig_error_budget(ds: StoredSimplified | xr.Dataset, width: float = _PAGE) -> Figure:
    """Per joint: the dropped terms' peaks stacked against the budget EPS s_i, and the
    measured peak error.

    Parameters
    ----------
    ds : StoredSimplified or xarray.Dataset
        The simplified model's record, or a results dataset with it (``simplified_scale``,
        ``simplified_bound_*``, ``tau_error_peak`` (n,) [N m], attribute
        ``simplified_tolerance``).
    width : float, optional
        Figure width [in].

    Returns
    -------
    matplotlib.figure.Figure
        One panel, joints across; bars: the peaks of the dropped terms by where they sit
        (D qdd, h, c, base parameters dropped whole), each / s_i [%], stacked; a dash at
        EPS (the budget); a diamond at the measured peak |tau_s - tau| / s_i; under a region
        guarantee, a triangle at the stated bound where it was proved on the dropped terms'
        sum at the same state, below the bars (:func:`joint_sum_lower`). A joint with
        nothing dropped reads "nothing dropped".
    """
    s = StoredSimplified.of(ds)
    eps = s.tolerance
    scale = np.asarray(s.scale, float)
    measured = np.asarray(s.tau_error_peak, float) / np.where(scale > 0, scale, np.nan)
    parts = budget_parts(s)
    n = scale.size
    column = width < _PAGE
    H, top = (3.3, 0.95) if column else (2.7, 0.6)      # top: the legend's four rows, or two
    fig = new_figure(width, H)
    ax = fig.add_axes((0.7 / width, 0.7 / H, (width - 0.9) / width, (H - 0.7 - top) / H))
    x = np.arange(1, n + 1)
    bottom: np.ndarray = np.zeros(n)
    for var, name, colour, hatch in _BOUND_PARTS:
        if var not in parts:
            continue
        v = 100 * parts[var]
        if not np.nan_to_num(v).any():          # no bar: no legend entry
            continue
        ax.bar(x, v, bottom=bottom, width=0.55, color=colour, alpha=0.85, hatch=hatch,
               edgecolor="white", linewidth=0.4, label=f"bound: {name}")
        bottom = bottom + np.nan_to_num(v)
    ax.hlines(np.full(n, 100 * eps), x - 0.38, x + 0.38, colors="black", linewidth=1.4,
              label=f"budget \u03b5 s (\u03b5 = {eps:g})")
    lower = joint_sum_lower(s) if s.guarantee_kind == "region" else np.zeros(0, bool)
    if lower.any():
        stated = np.asarray(s.bound, float) / np.where(scale > 0, scale, np.nan)
        ax.plot(x[lower], 100 * stated[lower], linestyle="none", marker="v", markersize=6,
                color="#009E73", markeredgecolor="black", markeredgewidth=0.6, zorder=5,
                label="bound proved on the dropped terms' sum")
    ax.plot(x, 100 * measured, linestyle="none", marker="D", markersize=4.5,
            markerfacecolor="white", markeredgecolor="black", markeredgewidth=0.9,
            label="measured peak |\u0394\u03c4|", zorder=4)
    ymax = max(100 * eps, float(np.nanmax(bottom)) if n else 0.0,
               float(np.nanmax(np.nan_to_num(100 * measured))) if n else 0.0) * 1.25 or 1.0
    ax.set_xlim(0.4, n + 0.6)
    # "joint i" across, or "i" where those would touch (a column, or 12 joints and more)
    least, slot = MIN_PRINTED_PT / printed_scale((width, H)), (width - 0.9) / max(n, 1)
    short = joint_ticks(ax.xaxis, n, slot, least, short=column)
    # "nothing dropped" beside the budget's dash, on the side with more room (raised to the
    # printed minimum it would reach the dash from below when the dash sits low), turned on
    # its side where the joints are numbered short or "dropped" (4.2 em) leaves no gap in a
    # joint's room; named in the note below where even its two lines on their side do not
    above, size = 100 * eps < 0.5 * ymax, max(7.0, least) / 72
    listed = 2.3 * size > 0.85 * slot               # (then it would be turned: 2.3 < 4.2)
    for i in range(n):
        if bottom[i] == 0 and not listed:
            ax.annotate("nothing\ndropped", (x[i], 100 * eps), xytext=(0, 3 if above else -3),
                        textcoords="offset points", ha="center", va="bottom" if above else "top",
                        fontsize=7, color="0.35", linespacing=1.1,
                        rotation=90 if short or 4.2 * size > 0.85 * slot else 0)
    ax.set_ylim(0, ymax)
    set_ticks(ax.yaxis, 0, ymax / 1.25, 4)
    ax.tick_params(axis="x", length=0)
    ax.set_ylabel("relative to s [%]", labelpad=1.0)
    ax.grid(axis="x", visible=False)
    pairs = sorted(zip(*ax.get_legend_handles_labels()),
                   key=lambda p: (not p[1].startswith("bound"), not p[1].startswith("budget")))
    fig.legend(*zip(*pairs), loc="upper center", ncol=2 if width >= _PAGE else 1, frameon=False, fontsize=7,
               handlelength=2.0, columnspacing=1.2, bbox_to_anchor=(0.5, 1 - 0.04 / H))
    note = say("budget_note", units=sorted(set(s.tau_units)), lower=lower.any(),
               region=s.guarantee_kind == "region",
               quiet=[i + 1 for i in range(n) if bottom[i] == 0] if listed else [])
    note = textwrap.fill(note, int((width - 0.2) / 0.058))
    fig.text(0.1 / width, 0.04 / H, note, fontsize=7, va="bottom", color="0.25")
    # the panel raised above the note, its tick labels and axis label at their printed size
    need = 0.04 + (note.count("\n") + 1) * 1.25 * size + (0.45 if short else 0.3)
    box = ax.get_position()
    if need > box.y0 * H:
        ax.set_position((box.x0, need / H, box.width, box.y1 - need / H))
    return fig


#: Markers of the cost figure: measured worst error (filled) or a bound or stated figure
#: (open).
#: Below this worst error [%] the cost figure's y axis is linear (symmetric log above).
_COST_LINEAR = 0.01
_COST_STYLE = {"exact": ("o", "#000000"), "model": ("*", "#D55E00"),
               "ladder": ("s", "#0072B2"), "chapter": ("^", "#009E73"),
               "bound": ("s", "#0072B2"), "akb": ("P", "#CC79A7")}


def cost_points(ds: StoredSimplified | xr.Dataset) -> list[tuple[Any, ...]]:
    """The points of :func:`fig_cost_ladder`: (label, operations, worst error [1], kind).

    Parameters
    ----------
    ds : StoredSimplified or xarray.Dataset
        The simplified model's record, or a results dataset with ``cost_model`` and ``cost_total``; ``simplified_scale``, ``tau_error_peak``,
        ``tau_peak``; optionally ``ladder_operations`` and ``ladder_worst_error`` (dim
        ``ladder_tolerance``) and ``other_rule_error_relative_peak``.

    Returns
    -------
    list of tuple
        The worst error is max over joints of peak |tau_s - tau| / s_i as measured on the
        trajectory (kind ``model``, ``ladder``, ``chapter``); 0 for an exact model
        (``exact``); for a model whose error is bounded but not measured (``bound``), EPS
        times its own scale over s_i (EPS where its scale is s_i);
        the stated 1 % of AKB's simplified model (``akb``, PUMA 560 only).
    """
    s = StoredSimplified.of(ds)
    if s.costs is None:
        raise ValueError("no cost table stored")
    total = dict(zip(s.costs.models, s.costs.total.astype(float)))
    scale = np.asarray(s.scale, float)
    safe = np.where(scale > 0, scale, np.inf)
    worst = float(np.max(np.asarray(s.tau_error_peak, float) / safe))
    eps = s.tolerance
    ladder = s.ladder
    laddered = ladder is not None
    rungs = ("recursive N-E" if s.ladder_form == "recursive" else "explicit") + ", budget"
    points = []
    for label, ops in total.items():
        if label.startswith(("Table 3.5", "project L-E", "project G-D")):
            continue
        if "(this model)" in label:
            points.append((label.replace(" (this model)", ""), ops, worst, "model"))
        elif label.startswith("AKB") and "simplified" in label:
            points.append((label, ops, 0.01, "akb"))
        elif "chapter" in label and s.other_rule_error_relative_peak is not None:
            rel = np.asarray(s.other_rule_error_relative_peak, float)
            err = rel * np.asarray(s.tau_peak, float) / safe
            if np.isfinite(err).any():          # no torque at all: nothing measured
                points.append((label, ops, float(np.nanmax(err)), "chapter"))
        elif "budget" in label and not (laddered and label.startswith(rungs)):
            # its bound, EPS times its own scale, relative to the deployed model's s_i: the
            # explicit model is pruned on this trajectory, its scale max(peak |tau_i|, floor);
            # under a region guarantee s_i is the region's, larger
            own = np.maximum(np.asarray(s.tau_peak, float), s.torque_floor)
            bound = (float(np.max(eps * own / safe)) if label.startswith("explicit")
                     and s.guarantee_kind == "region" else eps)
            points.append((label + " (bound)", ops, bound, "bound"))
        elif "exact" in label or "full" in label or "N-E as implemented" in label:
            points.append((label, ops, 0.0, "exact"))
    if ladder is not None:
        built = {p[1] for p in points if p[3] == "model"}
        exact = {p[1] for p in points if p[3] == "exact"}
        for tol, ops, err in zip(ladder.tolerance, ladder.operations, ladder.worst_error):
            if (float(tol) == eps and float(ops) in built) or (float(tol) == 0
                                                              and float(ops) in exact):
                continue                  # the model built, or an exact one: said once
            rung = f"{rungs} \u03b5 = {float(tol):g}"
            same = [k for k, p in enumerate(points) if p[1] == float(ops)
                    and abs(p[2] - float(err)) <= 1e-12]
            if same:                      # the same model as a point drawn: one point
                k = same[0]
                points[k] = (f"{points[k][0]} (= {rung})", *points[k][1:])
            else:
                points.append((rung, float(ops), float(err), "ladder"))
    return points


def _place_numbers(fig, ax, numbers):
    """Each point's number beside it, at the first of eight places around the point whose box
    meets no number placed before (the axes' limits fixed first).

    Parameters
    ----------
    fig : matplotlib.figure.Figure
    ax : matplotlib.axes.Axes
    numbers : list of (str, float, float)
        The text and the point's x and y in data coordinates.
    """
    from matplotlib.backends.backend_agg import RendererAgg

    width, height = fig.bbox.size       # text extents measured as the Agg renderer draws them
    renderer = RendererAgg(int(width), int(height), fig.dpi)
    places = ((5, 3), (-5, 3), (5, -11), (-5, -11), (5, 14), (-5, 14), (5, -22), (-5, -22))
    placed = []
    for text, x, y in numbers:
        for dx, dy in places:
            note = ax.annotate(text, (x, y), xytext=(dx, dy), textcoords="offset points",
                               fontsize=7, color="0.15", va="bottom",
                               ha="left" if dx > 0 else "right")
            box = note.get_window_extent(renderer).expanded(1.15, 1.1)
            if not any(box.overlaps(other) for other in placed) or (dx, dy) == places[-1]:
                placed.append(box)
                break
            note.remove()


def fig_cost_ladder(ds: StoredSimplified | xr.Dataset, width: float = _PAGE) -> Figure:
    """Operations per set point against the worst error of each model of the dataset.

    Parameters
    ----------
    ds : StoredSimplified or xarray.Dataset
        As for :func:`cost_points`.
    width : float, optional
        Figure width [in].

    Returns
    -------
    matplotlib.figure.Figure
        x: operations per set point (multiplications + additions, log scale); y: worst
        relative error [%] (symmetric log: linear below 0.01 %); the ladder's models joined
        by a line; each point numbered, the
        numbers named in a key below.
    """
    from matplotlib.ticker import FixedLocator, LogLocator, NullFormatter

    # a log axis: a model of no operations (nothing to compute) or an error not measured has
    # no place on it
    s = StoredSimplified.of(ds)
    points = [p for p in cost_points(s) if p[1] > 0 and np.isfinite(p[2])]
    column = width < _PAGE
    points = sorted(points, key=lambda p: (p[1], -p[2]))
    key = textwrap.fill("; ".join(f"{k + 1}: " + p[0].replace("EPS=", "\u03b5\u00a0=\u00a0")
                                  for k, p in enumerate(points)),
                        int((width - 0.3) / 0.058))
    H, top, bottom = (3.4, 0.7, 0.8) if not column else (4.6, 1.0, 1.5)
    fig = new_figure(width, H)
    ax = fig.add_axes((0.7 / width, bottom / H, (width - 0.9) / width, (H - bottom - top) / H))
    ax.set_xscale("log")
    names = {"exact": "exact model (error 0)", "model": "model built (measured)",
             "ladder": "\u03b5 ladder (measured)", "chapter": "chapter rule (measured)",
             "bound": "budget model (its bound, not measured)",
             "akb": "Armstrong, Khatib & Burdick 1986 (stated)"}
    seen = set()
    if s.ladder is not None:        # the rungs joined, the model built among them
        order = np.argsort(s.ladder.operations)
        ax.plot(s.ladder.operations[order],
                100 * s.ladder.worst_error[order], color="#0072B2",
                linewidth=0.8, linestyle="--")
    # a symmetric log axis: the ladder's small errors apart from the chapter rule's large one
    # (linear below _COST_LINEAR %, where 0 sits)
    ax.set_yscale("symlog", linthresh=_COST_LINEAR, linscale=0.5)
    top = max([100 * p[2] for p in points] + [10 * _COST_LINEAR]) * 2.5
    for (label, ops, err, kind) in points:
        marker, colour = _COST_STYLE[kind]
        filled = kind not in ("bound", "akb")
        ax.plot([ops], [100 * err], linestyle="none", marker=marker, color=colour,
                markersize=7 if kind == "model" else 5,
                markerfacecolor=colour if filled else "white", markeredgewidth=0.9,
                label=names[kind] if kind not in seen else None, zorder=3)
        seen.add(kind)
    numbers = [(str(k + 1), ops, 100 * err) for k, (_, ops, err, _) in enumerate(points)]
    # the key hangs from a fixed line below the axis label: wrapped again when its size is
    # raised for print (more lines), it grows downwards, and the saved figure with it
    # (figure_style.text_extent), never up into the label
    fig.text((0.1 if column else 0.7) / width, (bottom - 0.42) / H, key, fontsize=7,
             va="top", ha="left", color="0.2", linespacing=1.2)
    ops = [p[1] for p in points] or [10.0]
    lo, hi = min(ops) / 1.6, max(ops) * 2.2
    ax.set_xlim(lo, hi)
    ax.xaxis.set_major_locator(LogLocator(subs=(1.0, 2.0, 5.0), numticks=99))  # 1, 2, 5 x 10^k
    ax.xaxis.set_major_formatter("{x:,.0f}")                                    # 1,000
    ax.xaxis.set_minor_formatter(NullFormatter())
    ax.set_ylim(-0.25 * _COST_LINEAR, top)
    ax.yaxis.set_major_locator(FixedLocator(
        [0.0] + [_COST_LINEAR * 10.0 ** k for k in range(8) if _COST_LINEAR * 10.0 ** k < top]))
    ax.yaxis.set_major_formatter("{x:g}")
    ax.yaxis.set_minor_locator(FixedLocator([]))
    _place_numbers(fig, ax, numbers)
    ax.set_xlabel("operations per set point" + ("" if column else
                                                 " (multiplications + additions)"),
                  labelpad=1.0)
    ax.set_ylabel("worst peak |\u0394\u03c4| / s [%]", labelpad=1.0)
    fig.legend(loc="upper center", ncol=1 if column else 2, frameon=False, fontsize=7,
               handlelength=1.5,                # two columns: within the page at 8.5 pt
               bbox_to_anchor=(0.5, 1 - 0.04 / H))
    return fig


def budget_makers(results: Results, data: PlotData) -> dict[str, Callable[..., Figure]]:
    """Makers of the figures of this module that the results can draw.

    Parameters
    ----------
    results : Results
        The main job's results (:class:`gd_analyze.store.results_view.Results`).
    data : PlotData
        Its series (:func:`gd_analyze.report.main_figures.plot_data`).

    Returns
    -------
    dict of str to callable
        ``"contributions"`` (with the series it needs), ``"budget"`` (with a simplified
        model), ``"cost_ladder"`` (with a cost table), and each as ``"<key>_column"``,
        :data:`COLUMN` wide.
    """
    import functools

    makers: dict[str, Callable[..., Figure]] = {}
    if all(k in data.series for k, *_ in CONTRIBUTIONS) and "tau_simplified" in data.series:
        armature = results.robot_record.armature
        drives = armature is not None and bool(np.any(np.asarray(armature) > 0))
        makers["contributions"] = functools.partial(fig_torque_contributions, data,
                                                    torque_units(results), drives)
    s = results.simplified
    if s is not None and s.scale is not None:
        makers["budget"] = functools.partial(fig_error_budget, s)
        if s.costs is not None:
            makers["cost_ladder"] = functools.partial(fig_cost_ladder, s)
    makers.update({f"{k}_column": functools.partial(make, width=COLUMN)
                   for k, make in list(makers.items())})
    return makers


def simplified_caption(ds: StoredSimplified | xr.Dataset) -> str:
    """The caption of :func:`error_figure`, with the units of each joint's torque.

    Parameters
    ----------
    ds : StoredSimplified or xarray.Dataset
        The simplified model's record (:class:`gd_analyze.store.stored_simplified.StoredSimplified`),
        or a results dataset holding it.

    Returns
    -------
    str
        In N m, or N m and N for an arm with a prismatic joint, saying where the bound holds
        from the stored guarantee's kind.
    """
    s = StoredSimplified.of(ds)
    quiet = _quiet(s, np.asarray(s.tau_error_peak, float)[None])
    return say("simplified_caption", units=joint_units_text(s.tau_units),
               region=s.guarantee_kind == "region", quiet=len(quiet), n=s.n)


def _int(v):
    """A count as every table prints it (1,212), "\u2014" where it was not counted."""
    return count(v) if np.isfinite(float(v)) else "\u2014"


def _num(v):
    return fmt(v) if np.isfinite(float(v)) else "\u2014"


def inertia_check_text(check: InertiaCheck | Mapping[str, Any] | None) -> str:
    """The sentence on the proof that D_s is positive definite, from the stored figures.

    Parameters
    ----------
    check : InertiaCheck, Mapping or None
        The stored check (:class:`gd_analyze.store.stored_simplified.InertiaCheck`), or a results
        dataset's attributes holding it (``simplified_inertia_check_*``, written by
        :func:`gd_analyze.jobs.simplified_dataset.inertia_check_attrs`).

    Returns
    -------
    str
        " " and the sentences, or "" when no check is stored.

    Examples
    --------
    >>> inertia_check_text({})
    ''
    """
    if check is not None and not isinstance(check, InertiaCheck):
        check = InertiaCheck.from_attrs(check)
    if check is None:
        return ""
    return say("inertia_check", proved=check.proved, region=check.where == "region",
               lower=fmt(check.lower_bound, 3), ratio=fmt(check.ratio, 3),
               restored=check.restored, statement=scope_markup(check.statement),
               samples=check.samples, sampled=fmt(check.sampled_min_eigenvalue, 3),
               positive=check.sampled_min_eigenvalue > 0)


def simplified_context(ds: StoredSimplified | xr.Dataset) -> dict[str, Any]:
    """Tables and text of the "Simplified model" section.

    Parameters
    ----------
    ds : StoredSimplified or xarray.Dataset
        The simplified model's record (:class:`gd_analyze.store.stored_simplified.StoredSimplified`),
        or a results dataset with the ``simplified_*``, ``cost_*`` and ``ladder_*`` variables.

    Returns
    -------
    dict
        ``text`` (str), ``bound`` (table: per joint scale, bound, its split by D/h/c, measured
        error), ``costs`` (table), ``ladder`` (table), ``files`` (list of str), ``prefix``
        (the emitted C symbols' prefix, setting ``c_prefix``; "" if not stored), ``rule``,
        ``tolerance``.
    """
    s = StoredSimplified.of(ds)
    n = s.n
    rule, eps = s.rule, s.tolerance
    floor = s.torque_floor
    choice = s.choice
    dropped = sum({"both": 0, "tran": 1, "rot": 1, "none": 2}.get(c, 0) for c in choice)
    form = s.form
    if form == "recursive":             # its rule, what it keeps and its guarantee
        exact = s.pairs_dropped == 0 or s.guarantee_kind == "region"
        g = s.guarantee or {}
        text = say("recursive_rule", b=s.base_parameters, eps=f"{eps:g}",
                   floor=f"{floor:g}" if floor else "", pairs=s.pairs, dropped=s.pairs_dropped,
                   region=s.guarantee_kind == "region", drives=s.has_drives,
                   scope=_scope(s, exact=exact), ways=bound_ways(g.get("bound_method") or ()),
                   arithmetic=g.get("joint_sum_arithmetic", ""),
                   source=scope_markup(g.get("scale_source", "")))
    else:
        text = say("explicit_rule", rule=rule, eps=f"{eps:g}", floor=f"{floor:g}" if floor else "",
                   scope=_scope(s))
        text += say("model_kept", terms=s.terms_kept, dropped=dropped, parts=2 * len(choice))
    text += say("emitted_cost", mult=s.multiplications, add=s.additions, sin=s.sin, cos=s.cos)
    text += inertia_check_text(s.inertia_check)
    other = s.other_rule
    if other and s.other_rule_error_relative_peak is not None:
        rel = np.asarray(s.other_rule_error_relative_peak, float)
        rel = rel[np.isfinite(rel)]     # a joint without torque has no relative error
        text += say("other_rule", rule=other, mult=s.other_rule_multiplications,
                    add=s.other_rule_additions, worst=pct(rel.max()) if rel.size else None,
                    round_off=bool(rel.size) and bool(is_round_off(rel, 1.0).all())) \
            + _dearer_than_full(s, other)
    measured = np.asarray(s.tau_error_peak, float)
    parts = ("from D", "from h", "from c") if form != "recursive" else (
        "inertial (D)", "velocity (h)", "gravity (c)", "whole parameters")
    whole = s.bound_whole
    units = s.tau_units
    scale = np.asarray(s.scale, float)

    arm = arm_scales(scale, units)

    def off(v, i):                   # round-off of joint i's or the arm's scale
        return bool(is_round_off(v, scale[i], arm_scale=arm[i]))

    def num(v, i):                   # a bound that is round-off bounds nothing: 0, as an
        return "0" if off(v, i) else _num(v)      # exact 0 (one mark per column)

    measured_off = np.array([off(measured[i], i) for i in range(n)], bool)
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = pct_column(np.where(scale > 0, measured / scale, np.nan), measured_off)
    parts_bound = [np.asarray(v, float) for v in (s.bound_inertia, s.bound_coriolis,
                                                  s.bound_gravity)]
    bound = table(
        ["joint", "units", f"scale {_S_I}", "bound", *parts,
         f"measured peak |{_TAU_S}\u00a0\u2212\u00a0\u03c4|", f"measured / {_S_I}"],
        [[str(i + 1), units[i], _num(scale[i]),
          num(s.bound[i], i), *(num(part[i], i) for part in parts_bound),
          *([] if whole is None else [num(whole[i], i)]),
          "\u2261 0" if measured_off[i] or measured[i] == 0 else _num(measured[i]),
          ratio[i] if scale[i] > 0 else "\u2014"] for i in range(n)],
        align=["left", "left"] + ["right"] * (7 + (whole is not None)))
    costs = ladder = None
    if s.costs is not None:
        c = s.costs
        costs = table(["model", "multiplications", "additions", "total"],
                      [[str(lab).replace("EPS=", "\u03b5 = "), _int(m), _int(ad),
                        _int(tot)] for lab, m, ad, tot in
                       zip(c.models, c.multiplications, c.additions, c.total)],
                      align=["left", "right", "right", "right"], widths=[3, 1, 1, 1])
    lad = s.ladder
    if lad is not None:
        region = s.guarantee_kind == "region"
        has_bound = lad.worst_bound is not None
        ladder = table(["\u03b5", "operations", "sin + cos",
                        say("ladder_column", which="worst", has_bound=has_bound)]
                       + ([say("ladder_column", which="bound", region=region)] if has_bound else []),
                       [[f"{e:g}", _int(o), _int(tr), w, *b] for e, o, tr, w, *b in
                        zip(lad.tolerance, lad.operations, lad.trig,
                            pct_column(lad.worst_error,   # relative: own scale 1
                                       is_round_off(lad.worst_error, 1.0)),
                            *([pct_column(lad.worst_bound, is_round_off(lad.worst_bound, 1.0))]
                              if lad.worst_bound is not None else []))],
                       align=["right"] * (4 + has_bound))
    skipped = s.ladder_skipped if ladder is None else ""
    region_rows, region_text = region_table(s)
    return {"text": text, "bound": bound, "costs": costs, "ladder": ladder, "files": list(s.files),
            "prefix": s.c_prefix,
            "region": region_rows, "region_text": region_text,
            "rule": rule, "tolerance": eps,
            "form_note": s.form_note,
            "screen_note": _screen_note(s.region_screen, s.region_screen_proved),
            "ladder_heading": "5.5 Tolerance ladder" + (
                f" of the {s.ladder_form} form" if ladder is not None else ""),
            "ladder_note": f"Tolerance ladder {skipped}." if skipped else ""}


def _screen_note(said, proved=False):
    """The screen that chose the exact recursive model, as a sentence, or "": the sampled
    pre-screen that skipped the region's certification, or (``proved``) the screen of the
    pairs searched under the proved bounds, whose pruned model was not built."""
    return say("screen_note", said=scope_markup(said), proved=proved) if said else ""


def region_table(ds: StoredSimplified | xr.Dataset) -> tuple[dict[str, Any] | None, str]:
    """The region of the model's guarantee as a table, and whether it covers this trajectory.

    Parameters
    ----------
    ds : StoredSimplified or xarray.Dataset
        The simplified model's record, or a results dataset with it and the ``region_*``
        variables (:func:`gd_analyze.store.datasets.region_fields`).

    Returns
    -------
    table : dict or None
        Per joint the position range (degrees for a revolute joint, metres for a prismatic
        one; "any angle (full turn)"), qd max, qdd max and whether qdd max is assumed; None
        without a region.
    text : str
        Where the limits come from, which acceleration limits are assumed, and whether this
        trajectory lies in the region (where not: the joint, the quantity and the amount, and
        that the guarantee does not cover it); "" without a region.
    """
    s = StoredSimplified.of(ds)
    r = s.region
    if r is None:
        return None, ""
    pris = list(s.prismatic)
    rows = []
    for j in range(len(r["qd_max"])):
        conv = (lambda v: v) if pris[j] else math.degrees
        unit = "m" if pris[j] else "deg"
        q = ("any angle (full turn)" if r["q_full_turn"][j] else
             f"[{_num(conv(r['q_min'][j]))}, {_num(conv(r['q_max'][j]))}]")
        rows.append([str(j + 1), unit, q, _num(conv(r["qd_max"][j])),
                     _num(conv(r["qdd_max"][j])),
                     "assumed" if r["qdd_max_assumed"][j] else "given"])
    tab = table(["joint", "units of q", "q range", *map(scope_markup, ["qd max [/s]",
                 "qdd max [/s²]", "qdd max"])], rows, align=["left"] * 3 + ["right"] * 2 + ["left"])
    lines = r["lines"]
    note = lines[-1].partition(" (")[2].partition(")")[0] if "(assumed" in lines[-1] else ""
    text = say("region_text", source=s.region_source, assumed=note, notes=s.region_notes,
               covered=r["covered"], coverage=scope_markup(r["coverage"]),
               region=s.guarantee_kind == "region")
    return tab, powers(text)               # s^-1, deg/s^2 as superscripts


def bound_ways(method: Sequence[str]) -> list[tuple[str, str]]:
    """Each way a model's joints' bounds were proved, with the joints in words.

    Parameters
    ----------
    method : sequence of str, length n
        Per joint, a name of :data:`gd_analyze.certify.certify.BOUND_METHODS` as the model
        built stored it (``guarantee.bound_method``); empty where none is stored.

    Returns
    -------
    list of (str, str)
        (the joints, the way), in the order of each way's first joint.

    Examples
    --------
    >>> bound_ways(["branch and bound", "branch and bound", "pairs", "none", "none", "none"])
    [('joints 1, 2', 'branch and bound'), ('joint 3', 'pairs'), ('joints 4, 5, 6', 'none')]
    """
    ways: dict[str, list[int]] = {}
    for j, m in enumerate(method):
        ways.setdefault(str(m), []).append(j + 1)
    return [(joints_text(js), m) for m, js in ways.items()]


def region_pruning(pairs: int, dropped: int, bound: str = "the bound below", drives: bool = False,
                   floor: str = "", method: Sequence[str] = (), arithmetic: str = "",
                   source: str = "") -> str:
    """How a recursive model was pruned over the joint-limit region, in the words of every
    report (the main report's Sec. 5.3, the sweep report's Sec. 5).

    Parameters
    ----------
    pairs, dropped : int
        The (parameter, part) pairs that contribute over the region, and those dropped.
    bound : str, optional
        The bound, named where the sentence ends.
    drives : bool, optional
        The robot has drives (armature or friction): s_i is said to leave them out.
    floor : str, optional
        The torque floor with its units; empty for none (s_i is then not said to be raised
        to it).
    method : sequence of str, optional
        Per joint, how its bound was proved (:func:`bound_ways`), as the model stored it;
        empty (an older file): not said.
    arithmetic : str, optional
        The joint sums' enclosures as stored (``"both"``, ``"ball"``).
    source : str, optional
        How s_i was found, as the model stored it
        (:meth:`gd_analyze.simplify.guarantee.Guarantee.scale_source`, marked up); empty:
        "found over the region".

    Returns
    -------
    str
        The sentences.
    """
    return say("region_pruning", pairs=pairs, dropped=dropped, bound=bound, drives=drives,
               floor=floor, ways=bound_ways(method), arithmetic=arithmetic, source=source)


def _scope(s, exact=False):
    """Where the bound holds: on this trajectory (the table's bound), and the model's
    guarantee as stored from the model built (:func:`gd_analyze.store.datasets.stored_guarantee`);
    an older dataset's sentence where none is stored."""
    g = s.guarantee
    return say("bound_scope", statement=None if g is None else scope_markup(g["statement"]),
               exact=exact)


def _dearer_than_full(s, other):
    """Why the other rule's explicit model costs more than the full one, from the stored
    counts (:func:`gd_analyze.jobs.simplified_dataset.coefficient_structure`), or ""."""
    if s.costs is None or s.structure is None:
        return ""
    full = s.costs.totals().get("explicit, full")
    mine = sum(int(-1 if v is None else v)
               for v in (s.other_rule_multiplications, s.other_rule_additions))
    if full is None or mine <= full:
        return ""
    fh, fc, oh, oc = s.structure
    return say("dearer_than_full", mine=mine, full=int(full), fh=fh, fc=fc, oh=oh, oc=oc,
               chapter=other == "chapter")


def _round_off(diff, bound, scale, arm_scale=None):
    """Whether a joint's tau_s - tau is floating-point round-off only: its bound (what was
    dropped for the joint) and its peak both by the one rule
    (:func:`gd_analyze.ranking.ranking.is_round_off`), with ``arm_scale`` the largest
    scale among the joints of the same units
    (:func:`gd_analyze.ranking.ranking.arm_scales`)."""
    if diff.size == 0 or not np.isfinite(diff).all() or not np.isfinite(bound):
        return False
    return bool(is_round_off(bound, scale, arm_scale=arm_scale)
                and is_round_off(float(np.max(np.abs(diff))), scale, arm_scale=arm_scale))


def _quiet(s, diff):
    """The joints whose tau_s - tau (``diff``, shape (N, n) [N m; N], or the peaks |tau_s -
    tau| as one row) and bound are both round-off (:func:`_round_off`): no panel of theirs in
    :func:`error_figure`."""
    scale = np.asarray(s.scale if s.scale is not None else s.tau_peak, float)
    arm = arm_scales(scale, s.tau_units)
    return [i for i in range(s.n) if _round_off(diff[:, i], s.bound[i], scale[i], arm[i])]


def error_figure(ds: StoredSimplified | xr.Dataset, width: float = 7.2,
                 data: PlotData | None = None) -> Figure:
    """Per-joint plots of tau_s - tau against time, with the guaranteed band +- bound.

    Parameters
    ----------
    ds : StoredSimplified or xarray.Dataset
        The simplified model's record, or a results dataset with ``t``, ``tau``,
        ``tau_simplified`` (N, n) [N m] and ``simplified_bound`` (n,).
    width : float, optional
        Figure width [in]; narrower than 5 in (a 3.5-in column) gives one panel a row, else
        two.
    data : gd_analyze.report.main_figures.PlotData, optional
        The series as the report reads them, with ``tau_error`` (tau_s - tau per set point,
        or its min/max envelope for a long trajectory: the stored series are then never read
        whole); without it, the whole series are read from ``ds``.

    Returns
    -------
    matplotlib.figure.Figure
        One panel per joint whose difference is not round-off, on a fixed grid (no layout
        engine: the margins are set for the 7-pt tick labels, the 8-pt axis labels and the
        panel titles; no figure title, which the numbered caption gives); ticks placed once,
        in one notation for the figure (:func:`gd_analyze.report.numbers.label_axes`), every y
        range padded so that neither the error nor the bound touches the frame; the legend
        above the panels, clear of every curve. The joints whose difference and bound are
        round-off (:func:`_round_off`, :data:`gd_analyze.ranking.ranking.ROUND_OFF`)
        get no panel: a note below names them ("nothing dropped: Δτ = 0 up to round-off")
        with their peak difference.
    """
    s = StoredSimplified.of(ds)
    units = s.tau_units
    t, diff = ((data.x, data.series["tau_error"]) if data is not None and "tau_error" in data.series
               else (s.t, s.torque_difference()))
    bound = s.bound
    quiet = _quiet(s, diff)
    shown = [i for i in range(s.n) if i not in quiet]
    W = width
    column = W < 5.0
    cols = 2 if len(shown) > 1 and not column else 1
    rows = -(-len(shown) // cols)
    left, right, gap, bottom = 0.62, 0.1, 0.75, 0.42
    top, hgap, h = (0.45, 0.5, 1.0) if column else (0.5, 0.62, 1.6)
    note = ""
    if quiet:                       # wrapped for 8.5 pt (the least printed size's text)
        peaks = [f"{float(np.max(np.abs(diff[:, i]))):.1e}".replace("-", "\u2212")
                 + f" {units[i]}" for i in quiet]
        note = textwrap.fill(say("nothing_dropped", joints=[i + 1 for i in quiet], peaks=peaks),
                             int((W - 0.3) / 0.075))
    note_h = 0.12 + 0.16 * (note.count("\n") + 1) if quiet else 0.0
    H = (top + rows * h + (rows - 1) * hgap + bottom if shown else 0.1) + note_h
    w = (W - left - right - (cols - 1) * gap) / cols
    fig = new_figure(W, H)
    if data is not None and data.enveloped:     # the set points' range, not the columns'
        t = np.asarray(t, float)
        t0, t1 = s.time_span()
    else:
        t0, t1 = (float(t[0]), float(t[-1])) if t.size else (0.0, 1.0)
    origin, t_label = time_origin([t0, t1])
    t, t0, t1 = np.asarray(t, float) - origin, t0 - origin, t1 - origin
    handles = None
    ys = []
    for i, box in zip(shown, grid_boxes(fig, len(shown), cols, (left, top), (w, h),
                                        (gap, hgap))):
        ax = fig.add_axes(box)
        ax.tick_params(labelsize=7)
        which = "" if column else f" (joint {i + 1})"   # a column's panels are short
        ax.set_ylabel(f"\u0394\u03c4{which} [{units[i]}]", fontsize=8,
                      labelpad=1.0)
        line, = ax.plot(t, diff[:, i], color="#D55E00", linewidth=1.1,
                        label="\u0394\u03c4")
        span = [0.0]
        if diff.size and np.isfinite(diff[:, i]).any():
            span += [float(np.nanmin(diff[:, i])), float(np.nanmax(diff[:, i]))]
        if np.isfinite(bound[i]):
            b, = ax.plot([t0, t1], [bound[i]] * 2, color="0.4", linestyle=":", linewidth=1,
                         label="guaranteed bound \u00b1")
            ax.axhline(-bound[i], color="0.4", linestyle=":", linewidth=1)
            span += [float(bound[i]), -float(bound[i])]
            handles = handles or [line, b]
        ax.axhline(0.0, color="0.8", linewidth=0.6)
        lo, hi = min(span), max(span)
        if hi - lo <= 1e-300:
            lo, hi = -1.0, 1.0
        _time_panel(ax, i, (t0, t1), (lo, hi), 4 if h > 1.2 else 3, t_label, fontsize=8)
        ys.append(ax.yaxis)
    label_axes(ys)
    if handles:                     # above the panels: no curve or bound runs through it
        fig.legend(handles, [str(hd.get_label()) for hd in handles], loc="upper center",
                   ncol=2, frameon=False, fontsize=7, handlelength=2.6,
                   bbox_to_anchor=(0.5, 1 - 0.08 / H))
    if quiet:
        fig.text(0.1 / W, (note_h - 0.06) / H, note, fontsize=7, va="top", ha="left",
                 color="0.25")
    return fig                      # no title inside: the numbered caption says it
