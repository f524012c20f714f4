"""Sweep report: a stored sweep as one self-contained HTML file and a PDF.

:func:`write_sweep_report` reads a ``sweep.h5`` written by :func:`gd_analyze.store.schema.write_dataset`
and never recomputes the dynamics: every number comes from the dataset's variables and global
attributes. The report has these parts:

1. settings and provenance (robot, thresholds s and e, inputs, seed, cluster, elapsed time);
2. the distribution of share_tran over the trajectories for each element of D, as box plots in
   the upper-triangle layout of Fig. 3.10 of Fu, Gonzalez & Lee (1987), Sec. 3.4.1, with the
   thresholds s and 1 - s drawn;
3. the same for the elements of h (layout of Fig. 3.11);
4. the envelope: per element the fraction of trajectories in each dominance class and the
   min/median/max share, as a figure and a table;
5. the merged simplified model (budget rule: within EPS x s_i, proved at every state of the
   robot's joint-limit region, the swept trajectories outside it named, or guaranteed on every
   swept trajectory; chapter rule: no error bound): what it keeps of D, h and c, its torque error
   and its operations per set point against the exact recursive model, the full explicit
   model and Newton-Euler;
6. optionally, a payload sweep (:func:`gd_analyze.jobs.payload.payload_sweep`): share_tran and class
   of every element vs payload (:func:`gd_analyze.report.main_figures.payload_figure`).

One module for the report's figures (:func:`make_sweep_figures`), its words and tables
(:func:`sweep_context`) and what it says of the merged model (:func:`merged_claim`).

``sweep_report.html`` has no external resources (inline SVG figures, inline style sheet; the
Jinja2 template is ``templates/sweep_report.html.j2``). ``sweep_report.pdf`` is typeset by
Typst from the same section list (:mod:`gd_analyze.report.typeset`). Both are written atomically (:func:`gd_analyze.files.atomic_path`).
"""

from __future__ import annotations

import functools
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from .._version import VERSION as __version__
from ..ranking.ranking import (
    CLASSES,
    ROUND_OFF,
    arm_scales,
    is_round_off,
    joint_units_text,
)
from ..store.schema import open_sweep
from ..store.sweep_view import MergedModel, PayloadSweep, StoredSweep
from . import markup
from .common import CLASS_COLOURS as _CLASS_COLOURS
from .common import attr_text as _text
from .common import (
    check_formats,
    cost_table,
    count,
    fmt_column,
    joints_text,
    other_rows,
    pct_column,
    say,
    settings_table,
    torque_units,
    utc_now,
)
from .common import fmt as _fmt
from .common import or_default as _or
from .common import pct as _pct
from .common import share as _share_text
from .common import table as _table
from .drawing import draw_figures, write_report_files
from .figure_style import SUPTITLE_RC as _RC
from .figure_style import gridspec as _gridspec
from .figure_style import new_figure
from .main_context import command_row, gravity_row, guarantee_row, run_row, software_row
from .main_figures import CLASS_LETTER as _LETTER
from .main_figures import COLUMN_WIDTH, PAGE_WIDTH, payload_figure
from .main_text import StoredModel, weightless
from .markup import label as _math
from .markup import scope as scope_markup
from .markup import sub as _sub
from .numbers import decade_formatter, decade_label, joint_ticks
from .sections import Outline
from .simplified_section import region_pruning
from .typeset import MIN_PRINTED_PT, TABLE_COLOURS, check_paper, printed_scale

if TYPE_CHECKING:
    import os

    import xarray as xr
    from matplotlib.figure import Figure
    from numpy.typing import ArrayLike

# The choices of the merged model in the colours of their classes.
_CHOICE_COLOURS = {"tran": _CLASS_COLOURS["translational"], "rot": _CLASS_COLOURS["rotational"],
                   "both": _CLASS_COLOURS["both"], "none": _CLASS_COLOURS["negligible"],
                   "pruned": TABLE_COLOURS["pruned"]}
#: Panel titles: the part of the element the merged model keeps, said as such ("D16
#: → rot" would read as a class).
KEPT = {"tran": "keeps tran", "rot": "keeps rot", "both": "keeps both", "none": "dropped",
        "pruned": "pruned"}
_OWN_COLOUR, _MERGED_COLOUR = "#009E73", "#000000"
#: Relative torque errors at or below this are round-off (:data:`ROUND_OFF`): not drawn.
ERROR_FLOOR = ROUND_OFF


#: The reports' rule for round-off, in words (:func:`gd_analyze.ranking.ranking.is_round_off`).
ROUND_OFF_WORDS = f"at most {decade_label(ROUND_OFF)} of its own scale or 64 \u03b5 of the arm's"
#: The rule for a torque error's round-off, in words (:func:`torque_error_round_off`).
TORQUE_ROUND_OFF_WORDS = f"at most {decade_label(ROUND_OFF)} of its own scale or of the arm's"


def torque_error_round_off(ds: MergedModel | xr.Dataset, peak: ArrayLike, tau_peak: ArrayLike
                           ) -> np.ndarray:
    """Whether a torque error is round-off: at most 1e-12 (:data:`ROUND_OFF`) of the joint's
    own peak |tau| or of the arm's (the largest peak |tau| among the joints of the same type,
    :func:`gd_analyze.ranking.ranking.arm_scales`).

    The arm's term is :func:`gd_analyze.ranking.ranking.is_round_off`'s 64 machine
    epsilons raised to 1e-12 for an explicit model's error: its terms carry the rounding of
    the robot file's decimals, not only the arithmetic's. The UR5's URDF writes pi/2 as
    1.57079632679, which tilts three joint axes by 4.9e-12 rad; the merged model drops the
    couplings this adds to joints 5 and 6 (1.6e-11 N m against the arm's 64 N m, 2.5e-13 of
    it), and with pi/2 exact the same sweep's error there is 2e-16 N m.

    Parameters
    ----------
    ds : MergedModel or xarray.Dataset
        The sweep's merged model (:class:`gd_analyze.store.sweep_view.MergedModel`), or the sweep
        (for the joint types).
    peak, tau_peak : array_like, shape (n,) or (K, n)
        Peak error and peak |tau| per joint (per trajectory if 2-D), in N m or N.

    Returns
    -------
    ndarray of bool, the shape of ``peak``
    """
    peak, tau_peak = np.asarray(peak, float), np.asarray(tau_peak, float)
    units = torque_units(ds)
    arm = (arm_scales(tau_peak, units) if tau_peak.ndim == 1 else
           np.array([arm_scales(row, units) for row in tau_peak]))
    return is_round_off(peak, tau_peak, arm_scale=arm) | is_round_off(peak, arm)


def _thresholds(w):
    """s and e as stored (NaN where missing)."""
    st = w.settings
    return tuple(float(np.nan if v is None else v)
                 for v in (st.dominance_threshold, st.negligible_threshold))


#: The most a line's width can differ from the sum of its pieces' widths, each measured
#: alone, per join [em]: kerning across the join and the rounding of hinted advances. Agg
#: lays out DejaVu Sans by advances, and a piece that starts with a space joins with none (0
#: on every pair of the 108 characters the sweep report writes, at 7, 7.5 and 8 pt).
_JOIN_EM = 0.5
#: The font settings a text's measured width depends on, beside its size.
_FONT_RC = ("font.family", "font.sans-serif", "font.serif", "font.monospace", "font.cursive",
            "font.fantasy", "font.style", "font.variant", "font.weight", "font.stretch",
            "font.enable_last_resort", "text.hinting", "text.hinting_factor",
            "text.kerning_factor", "text.language", "figure.dpi")


def _width(text, size):
    """The width [in] of one line of text at ``size`` [pt], in the current font, as Agg lays
    it out at the figures' resolution (its hinting makes it resolution-dependent); each text
    measured once per font setting (:func:`_measured`)."""
    import matplotlib

    return _measured(text, float(size), tuple(
        tuple(v) if isinstance(v := matplotlib.rcParams.get(k), list) else v for k in _FONT_RC))


@functools.lru_cache(maxsize=4096)
def _measured(text, size, setting):
    """:func:`_width` of ``text`` under ``setting`` (the values of :data:`_FONT_RC`, which
    the current settings are)."""
    from matplotlib.backends.backend_agg import RendererAgg
    from matplotlib.font_manager import FontProperties

    dpi = float(setting[-1])
    width, _, _ = RendererAgg(1, 1, dpi).get_text_width_height_descent(
        text, FontProperties(size=size), ismath=False)
    return width / dpi


def _wrapped(parts, room, size, sep=" "):
    """``parts`` joined by ``sep`` into lines no wider than ``room`` [in] at ``size`` [pt].

    A line's width is taken as its first part's plus each further ``sep + part``'s, each
    measured once (:func:`_width`); only where that sum is within :data:`_JOIN_EM` a join
    of ``room`` is the line measured whole. So every line breaks where measuring it whole
    at each part would break it, with a few short measurements instead of one of the whole
    line so far per part.
    """
    lines: list[str] = []
    last = slack = 0.0                # the last line's width and how far it may be off [in]
    for part in parts:
        if lines:
            width, error = last + _width(sep + part, size), slack + _JOIN_EM * size / 72
            if abs(width - room) <= error:          # too near to tell: measured whole
                width, error = _width(lines[-1] + sep + part, size), 0.0
            if width <= room:
                lines[-1] += sep + part
                last, slack = width, error
                continue
        lines.append(part)
        last, slack = _width(part, size), 0.0
    return "\n".join(lines)


def _fraction_text(fractions, room=np.inf, size=7.0):
    """The fractions of trajectories per class (``T 94% \u00b7 N 6%``), on as many lines as
    keep each within ``room`` [in] at ``size`` [pt]."""
    return _wrapped([f"{_LETTER[c]} {100 * f:.0f}%" if f >= 0.01 else
                     f"{_LETTER[c]} {100 * f:.1g}%" for c, f in zip(CLASSES, fractions) if f > 0],
                    room, size, " \u00b7 ")


#: Font size of a share panel's class fractions [pt], at its drawn size.
_FRACTION_PT = 7.0
#: Room kept between two panels' class fractions [in].
_FRACTION_GAP = 0.08
#: Height of a further line of a panel's class fractions, added to each gap between rows [in].
_SECOND_LINE = 0.13


def _share_panel(ax, w, label, two_lines=False, room=np.inf, size=_FRACTION_PT):
    """One element of the stored sweep ``w``: a box of its share_tran over the trajectories,
    thresholds s and 1 - s; trajectories on which the element is round-off are left out of the
    box, and an element round-off on every trajectory has no share (it would be noise). The
    class fractions below go on as many lines as keep each within ``room`` [in] at ``size``
    [pt] (its printed size)."""
    k = list(w.elements).index(label)
    merged, zero, s = w.merged.choice[k], w.round_off[:, k], _thresholds(w)[0]
    colour = _CHOICE_COLOURS.get(merged, "black")
    values = w.share_tran[:, k][~zero]
    if zero.all():
        ax.text(0.5, 0.5, "\u2261 0", transform=ax.transAxes, ha="center", va="center",
                fontsize=10, color="0.35")
    else:
        ax.axhspan(s, 1.0, color=_CLASS_COLOURS["translational"], alpha=0.09, lw=0)
        ax.axhspan(0.0, 1.0 - s, color=_CLASS_COLOURS["rotational"], alpha=0.09, lw=0)
        for y in (s, 1.0 - s):
            ax.axhline(y, color="0.35", lw=0.6, ls="--")
    finite = values[np.isfinite(values)]
    if finite.size:
        whisker = {"color": "black", "linewidth": 0.7}
        ax.boxplot([finite], positions=[0.0], widths=0.55, whis=(0, 100), showfliers=False,
                   patch_artist=True, manage_ticks=False, whiskerprops=whisker, capprops=whisker,
                   boxprops={"facecolor": "white", "edgecolor": "black", "linewidth": 0.8},
                   medianprops={"color": colour, "linewidth": 1.6})
        if finite.size <= 60:
            jitter = np.linspace(-0.18, 0.18, finite.size) if finite.size > 1 else [0.0]
            ax.plot(np.asarray(jitter) + 0.45, finite, ".", ms=2.0, color="0.3")
    elif not zero.all():
        ax.text(0.5, 0.5, "no data", transform=ax.transAxes, ha="center", va="center")
    # the share [1] from 0 to 1, ticks at 0, 0.5 and 1, no x ticks
    ax.set_xlim(-0.6, 0.8)
    ax.set_ylim(-0.03, 1.03)
    ax.set_xticks([])
    ax.set_yticks([0.0, 0.5, 1.0])
    ax.yaxis.set_major_formatter("{x:.2g}")
    ax.tick_params(length=2.0, pad=1.5)
    if zero.all():
        ax.grid(False)
        ax.set_title(f"{_math(label)}: \u2261 0", color=colour, pad=2.5)
        return
    ax.set_title(f"{_math(label)}:{chr(10) if two_lines else ' '}{KEPT.get(merged, merged)}",
                 color=colour, pad=2.5, linespacing=1.0)           # a narrow panel: two lines
    ax.set_xlabel(_fraction_text(w.class_fraction[k], room, size), fontsize=_FRACTION_PT,
                  labelpad=1.5, color="0.15", linespacing=1.0)


#: Most joints whose D figure keeps the upper-triangle layout of Fig. 3.10 across a page
#: (every shipped arm); beyond, its panels go in reading order, six a row, in parts.
TRIANGLE_JOINTS = 7
#: The tallest a share or class figure is drawn [in], so that it prints with its caption on
#: one page at its size; more panels or rows go into further parts (``D_2``, ``h_2``,
#: ``classes_2``, ...).
MOST_HEIGHT = 8.6


def _parts(labels, per, least=1):
    """``labels`` in as few parts of at most ``per`` as they need (at least ``least``), of
    about one size."""
    labels = list(labels)
    k = min(max(least, -(-len(labels) // max(per, 1))), max(len(labels), 1))
    cuts = [len(labels) * i // k for i in range(k + 1)]      # k parts, sizes differ by <= 1
    return [labels[a:b] for a, b in zip(cuts, cuts[1:])]


def _share_layout(w, key, width):
    """The panels of D or h (``key``) in reading order (the stored elements of that matrix:
    D's upper triangle row by row, h in joint order) and how many a row."""
    labels = [lab for lab in w.elements if lab.startswith(key)]
    if key == "D":
        return labels, 3 if width < PAGE_WIDTH else 6
    return labels, min(w.joints, 2 if width < PAGE_WIDTH else 3)


def _grid_height(d, column, rows):
    """The height [in] of :func:`_share_grid`'s figure of ``rows`` rows: of D (``d``) or h,
    a column's or a page's (with the key's usual lines; :func:`_share_grid` makes it taller
    where its key takes more)."""
    return (0.74 + 1.08 * rows + 1.55 if d else 2.3 + 1.6 * rows if column
            else 2.45 + 1.55 * rows)


def _grid_parts(labels, width, cols, least=1):
    """:func:`_share_grid`'s panels in parts no taller than :data:`MOST_HEIGHT` (at least
    ``least`` of them), in whole rows: ``[labels, ...]``."""
    d, column = labels[0].startswith("D"), width < PAGE_WIDTH
    rows = _most(lambda k: _grid_height(d, column, k))
    parts = _parts(range(-(-len(labels) // cols)), rows, least)     # rows, balanced
    return [labels[p[0] * cols:(p[-1] + 1) * cols] for p in parts if p]


def _share_parts(w, key, widths):
    """How many parts the share figure of D or h takes: as many at every width in
    ``widths`` (a column twin for each part), 1 for D in the layout of Fig. 3.10."""
    if key == "D" and w.joints <= TRIANGLE_JOINTS:
        return 1
    layouts = {x: _share_layout(w, key, x) for x in widths}
    return max(len(_grid_parts(labels, x, cols)) for x, (labels, cols) in layouts.items())


def _share_figures(w, key, width, parts=1):
    """The share figures of D or h (``key``) at ``width``: one, or its ``parts`` parts
    ``key``, ``key_2``, ..."""
    labels, cols = _share_layout(w, key, width)
    if key == "D" and w.joints <= TRIANGLE_JOINTS:
        return {"D": _share_grid(w, labels, width, 3, triangle=width >= PAGE_WIDTH)}
    split = _grid_parts(labels, width, cols, parts)
    return {key if k == 0 else f"{key}_{k + 1}": _share_grid(w, part, width, cols,
                                                              (k + 1, len(split)))
            for k, part in enumerate(split)}


def _share_grid(w, labels, width, cols, part=(1, 1), triangle=False):
    """The share boxes of ``labels`` (of D or of h), the key below them or, in the
    upper-triangle layout of Fig. 3.10 (``triangle``: D_ij in row i, column j), in its empty
    lower left: D's panels with titles of two lines and y tick labels on a row's first panel
    only, h's each with its axis label; in reading order, ``cols`` a row, otherwise.
    ``part``: (this part, of how many), said in the title where more than one."""
    d, column, n = labels[0].startswith("D"), width < PAGE_WIDTH, w.joints
    if triangle:
        cells = [(i, j) for i in range(n) for j in range(i, n)]
        cols, left, right, wgap = n, 0.5, 0.08, 0.28
    else:
        cells = [divmod(m, cols) for m in range(len(labels))]
        left, right, wgap = (0.55, 0.08, 0.3) if d else (0.65, 0.1, 0.6)
    rows = cells[-1][0] + 1
    first = [c == (r if triangle else 0) for r, c in cells]   # a row's first panel
    H = 0.98 + n * 0.56 + (n - 1) * 0.46 if triangle else _grid_height(d, column, rows)
    pitch = (width - left - right + wgap) / cols            # a panel and its gap [in]
    # the class fractions at their printed size on more lines where one would reach the
    # next panel's, the panel's own tick labels (D: on a row's first; h: on each) or the
    # figure's right edge: the rows further apart (a triangle's figure taller; a grid's panels
    # shorter: the figure keeps its height, and so its printed scale)
    rooms = {}
    for label, (r, c), own in zip(labels, cells, first):
        room = pitch - wgap if own or not d else pitch - _FRACTION_GAP
        if not triangle and (c == cols - 1 or label == labels[-1]):
            room = min(room, pitch - wgap + 2 * right - 0.02)
        rooms[label] = room
    size = max(_FRACTION_PT, MIN_PRINTED_PT / printed_scale((width, H)))
    # the most lines beyond the first that a panel's class fractions take
    index = {label: k for k, label in enumerate(w.elements)}
    more = max((_fraction_text(w.class_fraction[index[label]], room, size).count("\n")
                for label, room in rooms.items()), default=0)
    if triangle:
        H, hgap, bottom, top = (H + n * more * _SECOND_LINE, 0.46 + more * _SECOND_LINE,
                                0.3 + more * _SECOND_LINE, 0.68)
        size = max(_FRACTION_PT, MIN_PRINTED_PT / printed_scale((width, H)))
    else:
        more *= _SECOND_LINE
        hgap, bottom, top = ((0.55 if d else 0.5) + more, 1.75 + more,
                             0.74 if d else 0.55 if column else 0.5)
    fig = new_figure(width, H)
    gs = _gridspec(fig, rows, cols, left=left, right=right, top=top, bottom=bottom, wgap=wgap,
                   hgap=hgap)
    for label, (r, c), own in zip(labels, cells, first):
        ax = fig.add_subplot(gs[r, c])
        _share_panel(ax, w, label, two_lines=d, room=rooms[label], size=size)
        if d:
            ax.tick_params(labelleft=own)
        else:
            ax.set_ylabel("translational share [1]")
    s, e = _thresholds(w)
    key = say("sweep_key", K=w.trajectories, s=f"{s:g}", e=f"{e:g}",
              pruned="pruned" in w.merged.choice, round_off=ROUND_OFF_WORDS).split()
    if triangle and n > 1:      # its top at row n // 2's, clear of the diagonal's tick labels
        box = gs[n // 2:, :n // 2].get_position(fig)
        fig.text(box.x0, box.y0 + box.height,
                 _wrapped(key, n // 2 * pitch - 0.3,
                          max(7.5, MIN_PRINTED_PT / printed_scale((width, H)))),
                 va="top", ha="left", fontsize=7.5, linespacing=1.35)
    elif not triangle:          # under the last row's class fractions (raised to the printed
        # size, it is wrapped again and drawn lower: the drawing is made taller, figure_svg)
        x0 = 0.3 if not (column or d) else 0.1
        fig.text(x0 / width, 1.5 / H, _wrapped(key, width - x0 - 0.1, 7.0), va="top",
                 ha="left", fontsize=7, linespacing=1.25 if column or d else 1.3)
    if d:
        fig.supylabel("translational share [1]", x=0.05 / width, ha="left")
    fig.suptitle(say("sweep_title", key=labels[0][0], column=column, part=part),
                 y=1 - (0.08 if column else 0.15) / H,
                 va="top", **({} if triangle else {"fontsize": 9 if column else None}))
    return fig


def _class_height(column, M):
    """The height [in] of a class figure of ``M`` elements, a column's or a page's."""
    return (1.9 if column else 1.5) + (0.17 if column else 0.14) * M


def _class_rows(width):
    """The most elements a class figure at ``width`` holds (:data:`MOST_HEIGHT`)."""
    return _most(lambda M: _class_height(width < PAGE_WIDTH, M))


def _most(height):
    """The most rows, at least one, whose figure's ``height(rows)`` [in] is at most
    :data:`MOST_HEIGHT`."""
    k = 1
    while height(k + 1) <= MOST_HEIGHT:
        k += 1
    return k


def _class_figures(w, width, parts=1):
    """The class figures at ``width``: one, or its parts ``classes``, ``classes_2``, ...
    (at least ``parts``) of at most :func:`_class_rows` elements."""
    split = _parts(range(len(w.elements)), _class_rows(width), parts)
    return {"classes" if k == 0 else f"classes_{k + 1}": _fig_classes(
        w, width, part, (k + 1, len(split))) for k, part in enumerate(split)}


def _fig_classes(w, width, rows, part):
    """The class fractions of the elements ``rows`` (a list of their indices) as stacked bars,
    each with the merged model's choice; ``part``: (this part, of how many)."""
    from matplotlib.patches import Patch

    labels = [w.elements[k] for k in rows]
    frac = w.class_fraction[rows]
    merged = [w.merged.choice[k] for k in rows]
    M = len(labels)
    column = width < PAGE_WIDTH
    W, H = width, _class_height(column, M)
    fig = new_figure(W, H)
    ax = fig.add_axes(((0.45 if column else 1.0) / W, (1.05 if column else 0.8) / H,
                       (W - (1.4 if column else 2.6)) / W,
                       (H - (1.6 if column else 1.4)) / H))
    y = np.arange(M)
    left = np.zeros(M)
    for c_idx, cls in enumerate(CLASSES):
        ax.barh(y, frac[:, c_idx], left=left, color=_CLASS_COLOURS[cls], height=0.75,
                label=cls, edgecolor="white", linewidth=0.3)
        left += frac[:, c_idx]
    ax.set_yticks(y, [_math(lab) for lab in labels])
    ax.set_ylim(M - 0.5, -0.5)
    ax.set_xlim(0, 1)
    ax.set_xlabel("fraction of trajectories [1]")
    ax.grid(axis="y", visible=False)
    for k, ch in enumerate(merged):
        ax.text(1.02, k, f"merged: {ch}", transform=ax.get_yaxis_transform(), va="center",
                ha="left", fontsize=7, color=_CHOICE_COLOURS.get(ch, "black"))
    fig.legend(handles=[Patch(color=_CLASS_COLOURS[c], label=c) for c in CLASSES],
               loc="lower center", ncol=2 if column else 4, frameon=False,
               bbox_to_anchor=(0.5, 0.0), fontsize=7 if column else None)
    fig.suptitle(say("sweep_title", key="classes", column=column, part=part, K=w.trajectories),
                 y=1 - 0.12 / H, va="top", fontsize=9 if column else None)
    return fig


def error_marks(ds: StoredSweep | xr.Dataset
                ) -> tuple[np.ndarray, np.ndarray, np.ndarray, bool]:
    """What the torque-error figure draws: the relative peak torque errors of the own and
    the merged models per trajectory and joint, and of the merged model over all
    trajectories, round-off (:func:`torque_error_round_off`) set to 0.

    Parameters
    ----------
    ds : StoredSweep or xarray.Dataset
        The stored sweep (K trajectories, n joints).

    Returns
    -------
    own, merged : ndarray, shape (K, n)
        Peak error / that trajectory's peak |tau| [1] (/ the merged model's s_i over the
        region for a region model).
    overall : ndarray, shape (n,)
        The merged model's peak error over all trajectories / the peak |tau| over all of them
        [1] (/ the largest s_i for a region model).
    region : bool
        Whether every mark is relative to the merged model's s_i over the region.
    """
    w = StoredSweep.of(ds)
    m = w.merged
    own = np.asarray(w.tau_error_relative_peak, float)
    merged = np.asarray(w.merged_tau_error_relative_peak, float)
    overall = np.asarray(w.merged_error_relative_peak, float)
    region = bool(m.region and m.scale is not None)
    if region:                  # one scale for every mark: the merged model's s_i (region)
        s_i = np.asarray(m.scale, float)          # (K, n): the same rows
        s_i = np.where(s_i > 0, s_i, np.inf)
        own = np.asarray(w.tau_error_peak, float) / s_i
        overall = np.asarray(w.merged_error_peak, float) / s_i.max(axis=0)
    marks = ((own, w.tau_error_peak, w.tau_peak), (merged, w.merged_tau_error_peak, w.tau_peak),
             (overall, w.merged_error_peak, w.merged_error_tau_peak))
    own, merged, overall = (np.where(torque_error_round_off(m, peak, tau), 0.0, rel)
                            for rel, peak, tau in marks)
    return own, merged, overall, region


def _fig_error(w, width=PAGE_WIDTH):
    from matplotlib.lines import Line2D
    from matplotlib.ticker import NullFormatter

    m = w.merged
    n = w.joints
    own, merged, overall, region = error_marks(w)
    column = width < PAGE_WIDTH
    W, H = width, (3.9 if column else 3.1)
    fig = new_figure(W, H)
    ax = fig.add_axes((0.75 / W, (1.25 if column else 0.9) / H, (W - 0.95) / W,
                       (H - (2.05 if column else 1.6)) / H))
    # "joint i" across, or "i" where those would touch (a column, or 12 joints and more)
    least, slot = MIN_PRINTED_PT / printed_scale((W, H)), (W - 0.95) / max(n, 1)
    short = joint_ticks(ax.xaxis, n, slot, least, short=column)
    # "round-off only" in each joint's room, on its side where the joints are numbered
    # short; named in the title where even that is wider than the room
    listed = short and 2.3 * max(7.0, least) / 72 > 0.85 * slot
    only = []
    for j in range(n):
        for off, data, colour in ((-0.18, own[:, j], _OWN_COLOUR),
                                  (0.18, merged[:, j], _MERGED_COLOUR)):
            vals = data[np.isfinite(data) & (data > ERROR_FLOOR)]     # round-off: not drawn
            if not vals.size:
                continue
            line = {"color": colour, "linewidth": 0.9}
            ax.boxplot([vals], positions=[j + 1 + off], widths=0.3, whis=(0, 100),
                       showfliers=False, manage_ticks=False, boxprops=line, whiskerprops=line,
                       capprops=line, medianprops=line)
        if np.isfinite(overall[j]) and overall[j] > ERROR_FLOOR:
            ax.plot(j + 1.18, overall[j], marker="D", ms=4, color="#CC79A7", ls="none")
        finite = np.concatenate([own[:, j], merged[:, j]])
        finite = finite[np.isfinite(finite)]
        if finite.size and (finite <= ERROR_FLOOR).all():
            only.append(str(j + 1))
            if not listed:
                ax.text(j + 1, 0.5, "round-off\nonly", transform=ax.get_xaxis_transform(),
                        ha="center", va="center", fontsize=7, color="0.35",
                        rotation=90 if short else 0)
    ax.set_yscale("log")
    # decades written 10⁻⁶ in the tick labels' own size (mathtext's exponents: 0.7 of it)
    ax.yaxis.set_major_formatter(decade_formatter())
    ax.yaxis.set_minor_formatter(NullFormatter())
    ax.set_xlim(0.4, n + 0.6)
    ax.set_ylabel("peak |\u0394\u03c4| / peak |\u03c4| [1]" if not region else
                  "peak |\u0394\u03c4| / s [1]")    # one scale for all
    said = {"eps": _eps(m) if m.rule == "budget" else "", "region": region}
    ax.legend(handles=[Line2D([], [], color=_OWN_COLOUR, label=say(
                           "sweep_error_key", which="own models", rule=m.own_rule, **said)),
                       Line2D([], [], color=_MERGED_COLOUR, label=say(
                           "sweep_error_key", which="merged model", rule=m.rule, **said)),
                       Line2D([], [], color="#CC79A7", marker="D", ls="none",
                              label="merged model, over all trajectories")]
              + ([Line2D([], [], ls="none", label=f"round-off only at {joints_text(only)}")]
                 if listed and only else []),
              loc="upper center",       # below the tick labels, and the axis label if any
              bbox_to_anchor=(0.5, -0.2 if column else -0.3 if short else -0.12),
              ncol=1 if column else 2, frameon=False, fontsize=7)
    fig.suptitle(say("sweep_title", key="error", column=column, round_off=TORQUE_ROUND_OFF_WORDS),
                 y=1 - 0.08 / H, va="top", fontsize=8.5)
    return fig


def make_sweep_figures(ds: StoredSweep | xr.Dataset,
                       payload: PayloadSweep | xr.Dataset | None = None,
                       column: bool = False) -> dict[str, Figure]:
    """Make the sweep report's figures from a stored sweep.

    Parameters
    ----------
    ds : StoredSweep or xarray.Dataset
        The stored sweep (:class:`gd_analyze.store.sweep_view.StoredSweep`), or a sweep dataset
        from :func:`gd_analyze.jobs.sweep.run_sweep` (K trajectories, M elements, n
        joints).
    payload : PayloadSweep or xarray.Dataset, optional
        A payload sweep from :func:`gd_analyze.jobs.payload.payload_sweep`, typed
        (:class:`gd_analyze.store.sweep_view.PayloadSweep`) or not.
    column : bool, optional
        Also make ``"<key>_column"``, 3.5 in wide, of ``D``, ``h``, ``classes``, ``error``
        and (with a payload sweep) ``payload``.

    Returns
    -------
    dict of str to matplotlib.figure.Figure
        ``"D"``: box plots of share_tran [1] per element of D in the upper-triangle layout of
        Fig. 3.10; ``"h"``: the same for h (Fig. 3.11); ``"classes"``: class fractions per
        element; ``"error"``: relative peak torque error per joint of the trajectories' own
        and of the merged model; ``"payload"`` (if given): :func:`payload_figure`. A share or
        class figure taller than :data:`MOST_HEIGHT` goes in parts, ``"D_2"``, ``"h_2"``,
        ``"classes_2"``, ... (as many at both widths, each with its column twin); D keeps the
        layout of Fig. 3.10 up to :data:`TRIANGLE_JOINTS` joints.

    Raises
    ------
    InputError
        If a variable the figures need is missing.
    """
    w = StoredSweep.of(ds)
    import matplotlib

    with matplotlib.rc_context(_RC):  # type: ignore[arg-type]  # keys typed as literals
        figs = {}
        widths = (PAGE_WIDTH, COLUMN_WIDTH)[:1 + column]
        parts = {key: _share_parts(w, key, widths) for key in ("D", "h")}
        classes = max(-(-len(w.elements) // _class_rows(x)) for x in widths)
        for width, end in zip(widths, ("", "_column")):      # a column twin for each part
            made = {**_share_figures(w, "D", width, parts["D"]),
                    **_share_figures(w, "h", width, parts["h"]),
                    **_class_figures(w, width, classes), "error": _fig_error(w, width)}
            figs.update({k + end: f for k, f in made.items()})
    if payload is not None:
        figs["payload"] = payload_figure(payload)
        if column:
            figs["payload_column"] = payload_figure(payload, COLUMN_WIDTH)
    return figs


def merged_claim(ds: MergedModel | xr.Dataset) -> str:
    """The summary's clause on the budget rule's merged model: what its error is guaranteed
    within and where, its bound and its largest measured error.

    Parameters
    ----------
    ds : MergedModel or xarray.Dataset
        The budget rule's merged model (:class:`gd_analyze.store.sweep_view.MergedModel`), or a
        sweep dataset with it.

    Returns
    -------
    str
        Without a leading subject ("is guaranteed within ..."); for a region model the
        guarantee's own statement and which swept trajectories lie in the region
        (:func:`coverage`).
    """
    m = MergedModel.of(ds)
    if m.region:
        return say("merged_claim", region=True, floor=_floor(m) if m.torque_floor > 0 else "",
                   bound=_worst_bound(m), statement=scope_markup(str(m.guarantee_statement)),
                   coverage=coverage(m), source=scope_markup(m.guarantee_scale_source))
    beyond = m.beyond_floor
    return say("merged_claim", region=False, floor=_floor(m), bound=_worst_bound(m),
               eps=_eps(m), worst=_measured_error(m.worst_scaled_error),
               beyond=None if beyond is None else (_pct(beyond[0]), beyond[1],
                                                   joints_text(beyond[2])))


def coverage(ds: MergedModel | xr.Dataset) -> str:
    """Which swept trajectories a region model's proof covers, and its largest measured error
    there, as a clause (:func:`gd_analyze.store.sweep_view.merged_guarantee`); the ones
    outside the region are named, at most five, with why.

    Parameters
    ----------
    ds : MergedModel or xarray.Dataset
        A merged model proved over the joint-limit region, or a sweep dataset with it.

    Returns
    -------
    str
        E.g. "every one of the 20 swept trajectories lies in the region, where its largest
        measured peak error is 0.02 % of s_i".
    """
    said = MergedModel.of(ds).guarantee
    outside = said["outside"]  # type: ignore[index]  # a merged model's
    return say("coverage", K=len(said["covered"]), peak=_measured_error(said["worst"]),  # type: ignore[index]  # a merged model's
               outside=[(src, why) for src, why, _ in outside],
               reach=_measured_error(max(w for _, _, w in outside)) if outside else "")


def _measured_error(scaled):
    """A merged model's largest measured error relative to s_i, as the text gives it: "" where
    it is round-off (at most :data:`~gd_analyze.ranking.ranking.ROUND_OFF` of s_i, the first
    term of :func:`~gd_analyze.ranking.ranking.is_round_off`)."""
    return "" if is_round_off(scaled, 1.0) else _pct(scaled)


def _region_rule(m, kept):
    """How a region model was built and what it guarantees, for Sec. 5: the main report's
    words on pruning over the region (:func:`gd_analyze.report.simplified_section.region_pruning`),
    the guarantee's statement and the swept trajectories it covers; ``kept``: its
    :class:`~gd_analyze.report.main_text.StoredModel`."""
    _, dropped, pairs = kept.recursive or (0, 0, 0)
    return say("region_rule", eps=_eps(m), form=m.form, coverage=coverage(m),
               statement=scope_markup(str(m.guarantee_statement)),
               pruning=region_pruning(pairs, dropped, bound=f"at most {_worst_bound(m)}",
                                      floor=_floor(m) if m.torque_floor > 0 else "",
                                      method=m.bound_method, arithmetic=m.joint_sum_arithmetic,
                                      source=scope_markup(m.guarantee_scale_source))
               if dropped else "")


def _merged_rule(m, kept):
    """The heading of the merged model's section and its description, in words that follow its
    rule: a bound only for the budget rule; ``kept``: its
    :class:`~gd_analyze.report.main_text.StoredModel`."""
    budget, recursive = m.rule == "budget", m.form == "recursive"
    eps = _eps(m) if budget else ""
    text = (_region_rule(m, kept) if budget and m.region else say(
        "merged_budget", recursive=recursive, eps=eps, stored=m.bound is not None,
        bound=_worst_bound(m)) if budget else say("merged_chapter", weightless=kept.weightless))
    return say("merged_heading", region=m.region, eps=eps), say(
        "merged_text", text=text, keeps=_keeps(m, kept), cost=_cost_sentence(m, table=True),
        terms=budget and not m.region and not recursive)


def _eps(m):
    """The merged model's tolerance \u03b5 as the text writes it ("0.01")."""
    return f"{float(m.tolerance):g}"


def _keeps(m, kept):
    """What the merged model keeps of D, h and c, in the words of the main and the control
    reports (:class:`gd_analyze.report.main_text.StoredModel` ``kept``), and for the
    recursive form the elements its dropped parts change."""
    text = kept.sentence("The merged model")
    if kept.recursive is None:
        return text
    return text + say("merged_keeps", pruned=[lab for lab, c in zip(m.elements, m.choice)
                                              if c == "pruned"])


def _worst_bound(m):
    """The largest guaranteed bound over the trajectories relative to their s_i, in words
    ("0.41 % of s_i (joint 2)", "0 (nothing dropped contributes)"); None without
    merged_bound."""
    if m.bound is None or m.scale is None:
        return None
    bound = np.asarray(m.bound, float)
    scale = np.asarray(m.scale, float)
    with np.errstate(divide="ignore", invalid="ignore"):
        rel = np.where(bound > 0, bound / scale, 0.0)
    rel = np.where(np.isfinite(rel), rel, np.inf)
    if not rel.size or not rel.max() > 0:
        return "0 (nothing dropped contributes)"
    k, j = np.unravel_index(np.argmax(rel), rel.shape)
    return f"{_pct(rel[k, j])} of {_SI} (joint {j + 1})"


def _held_out(m):
    """The merged model's largest error on the held-out trajectories (measured, not
    guaranteed by the sweep; a region model's proof covers those in its region), relative to
    their max(peak |tau_i|, floor), or to s_i over the region for a region model, as a
    sentence; "" if none."""
    if m.held_out_error_peak is None:
        return ""
    peak = np.asarray(m.held_out_error_peak, float)
    tau = np.asarray(m.held_out_tau_peak, float)
    with np.errstate(divide="ignore", invalid="ignore"):
        rel = peak / (np.asarray(m.scale, float)[0] if m.region else
                      np.maximum(tau, m.torque_floor))
    rel = np.where(torque_error_round_off(m, peak, tau) | ~np.isfinite(rel), 0.0, rel)
    j = int(np.argmax(rel))
    return say("held_out", k=m.held_out_trajectories, region=m.region,
               worst=_pct(rel[j]) if rel[j] > 0 else "",
               joint=j + 1, inside=m.held_out_inside_region,
               floor=_floor(m) if m.torque_floor != 0 else "") + " "


def _cost_sentence(m, table=False):
    """The merged model's operations per set point against the exact recursive model, the full
    explicit model and Newton-Euler, counted on the models (stored by
    :func:`gd_analyze.jobs.sweep_merged.with_model_cost`), with a word on why where it
    costs more than one of them; "" for a file without the counts."""
    if m.costs is None:
        return ""
    names = list(m.costs.evaluators)
    ops = dict(zip(names, (m.costs.multiplications + m.costs.additions).tolist()))
    mine = ops[names[0]]
    mul, add = int(m.costs.multiplications[0]), int(m.costs.additions[0])
    recursive, full = ops.get("exact recursive model"), ops.get("full explicit model")
    return say("merged_cost", mine=mine, mul=mul, add=add, table=table,
               others=[(n, ops[n]) for n in names[1:]], chapter=m.rule == "chapter",
               recursive_cheaper=(recursive is not None and mine > recursive
                                  and names[0].endswith("(explicit form)")
                                  and m.rule == "chapter"),
               dearer=full is not None and mine > full) + " "


def _floor(m):
    """The torque floor with the units of every joint type ("0 N m", or "0 N m (joints 1, 2),
    0 N (joint 3)" on a mixed arm)."""
    floor = f"{m.torque_floor:g}"
    return joint_units_text([f"{floor} {u}" for u in torque_units(m)])


def _models(m):
    """What the own and the merged models are, and which carries a guarantee, in words
    generated from the dataset's rules: (own, merged)."""
    said = {"own_rule": m.own_rule, "rule": m.rule,
            "eps": _eps(m) if m.rule == "budget" else "",
            "statement": scope_markup(str(m.guarantee_statement)) if m.region else ""}
    return say("sweep_model", which="own", **said), say("sweep_model", which="merged", **said)


_SI = "s" + _sub("i")


#: The merged model's choices per element, in the words of Table 4.1 and the counts line.
_CHOICES = ("tran", "rot", "both", "none")


# --------------------------------------------------------------------------------------------
# Content shared by the HTML and the PDF
# --------------------------------------------------------------------------------------------

def sweep_context(ds: StoredSweep | xr.Dataset,
                  payload: PayloadSweep | xr.Dataset | None = None) -> dict[str, Any]:
    """Everything the sweep report says, from the stored sweep (and payload sweep): the
    tables, the summary, the captions and the sentences about the models.

    Parameters
    ----------
    ds : StoredSweep or xarray.Dataset
        The stored sweep (:class:`gd_analyze.store.sweep_view.StoredSweep`), or a sweep dataset
        (:func:`gd_analyze.jobs.sweep.run_sweep`).
    payload : PayloadSweep or xarray.Dataset, optional
        A payload sweep (:func:`gd_analyze.jobs.payload.payload_sweep`), typed
        (:class:`gd_analyze.store.sweep_view.PayloadSweep`) or not.

    Returns
    -------
    dict
        The report's context, the same for the HTML and the PDF.

    Raises
    ------
    InputError
        If a dataset lacks a variable the report needs.
    """
    w = StoredSweep.of(ds)
    m, st = w.merged, w.settings
    K = w.trajectories
    labels = list(w.elements)
    merged = list(m.choice)
    s, e = _thresholds(w)
    robot = _text(st.robot)
    inputs = say("sweep_inputs", K=K, kind=str(_or(st.input_kind, "")),
                 seed=None if st.seed is None else _text(st.seed))
    settings = _settings(w, inputs, __version__)
    zero = np.asarray(w.round_off.all(axis=0))      # round-off on every trajectory
    envelope = _table(
        ["element", "translational", "rotational", "both", "negligible", "min share",
         "median share", "max share", "merged choice"],
        [[lab, *(f"{f:.3f}" for f in w.class_fraction[k]),
          *(_share(spread[k], zero[k]) for spread in (w.share_min, w.share_median,
                                                      w.share_max)),
          merged[k]] for k, lab in enumerate(labels)],
        align=["left"] + ["right"] * 7 + ["left"], colour_cols=[8])
    units = torque_units(m)
    merged_off = torque_error_round_off(m, w.merged_error_peak, w.merged_error_tau_peak)
    rel_peak = pct_column(w.merged_error_relative_peak, merged_off)   # one format
    rel_rms = pct_column(w.merged_error_relative_rms, merged_off)     # per column
    # the trajectories' own models' relative peak torque errors, round-off of that
    # trajectory's peak |\u03c4| counted as 0 (:func:`gd_analyze.ranking.ranking.is_round_off`)
    own_off = torque_error_round_off(m, w.tau_error_peak, w.tau_peak)
    own_rel = np.where(own_off, 0.0, np.asarray(w.tau_error_relative_peak, float))
    # their largest per joint, as one column in one format (:func:`pct_column`), "\u2261 0"
    # where it is round-off on every trajectory
    own_worst = pct_column(np.array([np.nanmax(col) if np.isfinite(col).any() else np.nan
                                     for col in own_rel.T]), own_off.all(axis=0))
    tau_peak = fmt_column(w.merged_error_tau_peak)     # one notation per column
    peak, rms = (fmt_column(v, off=merged_off)
                 for v in (w.merged_error_peak, w.merged_error_rms))
    err = _table(
        ["joint", "peak |\u03c4|", "peak error", "RMS error",
         "peak error / peak |\u03c4|", "RMS error / peak |\u03c4|",
         f"own models, {m.own_rule} rule (worst)", "units"],
        [[str(j + 1), tau_peak[j]]
         + (["\u2261 0 (round-off)"] * 2 + ["\u2261 0"] * 2 if merged_off[j] else
            [peak[j], rms[j], rel_peak[j], rel_rms[j]])
         + [own_worst[j], units[j]] for j in range(w.joints)],
        align=["left"] + ["right"] * 6 + ["left"])
    counts = {c: merged.count(c) for c in _CHOICES    # the table's words
              + (("pruned",) if "pruned" in merged else ())}
    worst = _worst_cases(w, labels)
    no_gravity = weightless(w.run.gravity)          # c is then 0: said once, in Sec. 5
    kept = StoredModel.of(m, m.choice, "the joint-limit region" if m.region else
                          "the swept trajectories", no_gravity)   # where its pairs were judged
    heading, merged_text = _merged_rule(m, kept)
    own_said, merged_said = _models(m)          # each model named with its rule
    own_sentence = ""       # their worst (no bound under the chapter rule), unless all round-off
    if np.isfinite(own_rel).any() and np.nanmax(own_rel) > 0:
        k, j = np.unravel_index(np.nanargmax(np.where(np.isfinite(own_rel), own_rel, -np.inf)),
                                own_rel.shape)
        own_sentence = say("own_sentence", own=own_said, worst=_pct(own_rel[k, j]), joint=j + 1)
    # the figure captions, with the models and the merged choice "none" said from the rules
    said = {"own": own_said, "merged": merged_said, "region": m.region, "rule": m.rule,
            "round_off": TORQUE_ROUND_OFF_WORDS}
    said["choice_none"] = say("sweep_caption", key="none", **said)
    gravity = "" if no_gravity or kept.gravity is None else f"It {kept.gravity}. "
    claim: str | tuple[str, int] | tuple[()]
    if m.rule == "budget":
        claim = merged_claim(m)
    else:                               # the worst error, at that joint; () if round-off
        rel = np.where(merged_off, np.nan, w.merged_error_relative_peak)
        claim = () if merged_off.all() else (_pct(np.nanmax(rel)), int(np.nanargmax(rel)) + 1)
    summary = say("sweep_summary", robot=robot, M=len(labels), inputs=inputs, s=f"{s:g}",
                  e=f"{e:g}", eps=_eps(m) if m.rule == "budget" else "",
                  kept=say("recursive_clause", facts=kept.recursive, where=kept.where)
                  if kept.recursive else say(
                      "explicit_kept", both=counts['both'], one=counts['tran'] + counts['rot'],
                      dropped=counts['none']),
                  claim=claim,
                  rest=f"{_held_out(m)}{gravity}{_cost_sentence(m)}"
                       f"{own_sentence}"
                  ).strip()
    ctx = {"version": __version__, "title": f"G-D dominance sweep: {robot}, {K} "
                                                f"trajector{'y' if K == 1 else 'ies'}",
           "summary": summary, "settings": settings_table(settings),
           "merged_heading": heading, "merged_text": merged_text,
           "worst": worst,
           "intro": say("sweep_intro", K=K, created=utc_now().isoformat(), version=__version__),
           "envelope": envelope, "error": err, "cost": cost_table(m.costs),
           # Sec. 5.1's note: the table's columns, each model named with its rule
           "error_text": say("sweep_error_text", units=joint_units_text(units), own=own_said,
                             merged=merged_said, own_rule=m.own_rule,
                             held_out=_held_out(m).strip()),
           "captions": {key: say("sweep_caption", key=key, **said)
                        for key in ("D", "h", "classes", "error", "payload", "none")},
           # each figure's sentence without its subject ("shows ..."): the report writes
           # "Fig. 2 " before it, with the number the outline gives the figure
           "figure_text": {"D": _share_sentence(w, "D", zero), "h": _share_sentence(w, "h", zero),
                           "classes": _classes_sentence(w, counts), "error": _error_sentence(w)},
           "counts": counts, "s": f"{s:g}", "e": f"{e:g}",
           "payload": None}
    if payload is not None:
        part = PayloadSweep.of(payload)
        masses = [f"{m:g}" for m in part.masses]          # as printed [kg]
        dom = part.dominance                                # (mass, element)
        changed = [lab for k, lab in enumerate(part.elements) if len(set(dom[:, k])) > 1]
        ctx["figure_text"]["payload"] = say("payload_shows", masses=masses)
        ctx["payload"] = {
            "table": _table(["element", *(f"{m} kg" for m in masses)],
                            [[lab, *dom[:, k]] for k, lab in enumerate(part.elements)],
                            colour_cols=list(range(1, len(masses) + 1))),
            "settings": settings_table([
                ("trajectory", _text(part.input_file)),
                ("trajectory SHA-256", _text(part.input_sha256)),
                ("payload masses [kg]", ", ".join(masses)),
                ("payload centre of mass [m]", _text(part.payload_com)),
                ("payload inertia [kg m\u00b2]", _text(part.payload_inertia)),
                ("s, e", f"{_text(part.dominance_threshold)}, "
                         f"{_text(part.negligible_threshold)}")]),
            "changed": ", ".join(changed) if changed else "none",
        }
    return ctx


def _settings(w, inputs, version):
    """The settings and provenance of the sweep, each once and in words
    (:mod:`gd_analyze.report.main_context` rows for the software, the run and gravity)."""
    st, m, setpoints, durations = w.settings, w.merged, w.setpoints, w.duration
    K = w.trajectories
    s, e = _thresholds(w)
    batch, tasks = int(_or(st.batch_size, 0)), int(_or(st.n_tasks, 0))
    batches = -(-K // batch) if batch else 0
    workers = int(_or(st.n_workers, 1))
    return [
        software_row(w.run, version),
        command_row(st.command),
        run_row(w.run),
        ("robot", f"{_text(st.robot)}: {_text(st.robot_description)} "
                  f"({_text(st.robot_reference)})"),
        ("robot file", f"{_text(st.robot_source)} (SHA-256 {_text(st.robot_sha256)})"),
        gravity_row(w.run),
        ("dominance threshold s, negligibility threshold e", f"{s:g}, {e:g}"),
        ("inputs", inputs),
        ("input files", None if st.input_files is None else _text(st.input_files)),
        ("SHA-256 of all inputs", _text(st.inputs_sha256)),
        ("set points", say("sweep_setpoints", total=count(_or(st.setpoints_total, '-')),
                           least=count(setpoints.min()) if setpoints.size else "",
                           most=count(setpoints.max()) if setpoints.size else "")),
        ("duration [s]", say("sweep_duration", least=_fmt(np.min(durations)),
                             most=_fmt(np.max(durations)), median=_fmt(np.median(durations)))),
        ("merge rule", say("merge_rule", rule=_or(st.merged_rule, "chapter"),
                           eps=None if m.tolerance is None else _text(m.tolerance),
                           floor=None if m.tolerance is None else _floor(m))),
        ("payload on the last link", f"{_text(st.payload_mass, '0')} kg"
         if float(_or(st.payload_mass, 0.0) or 0.0) else "none"),
        guarantee_row("guarantee of the merged model", m.guarantee_kind,
                      m.guarantee_statement),   # the merged model's scope
        ("random accelerations limited by", None if st.random_qdd_max_source is None else
         {"robot": "the robot's acceleration limits"}.get(str(st.random_qdd_max_source),
                                                          _text(st.random_qdd_max_source))),
        ("computed on", say("computed_on", cluster=_text(st.cluster), K=K, batches=batches,
                            tasks=tasks, workers=_text(st.n_workers) if workers else "",
                            many=str(st.n_workers) != "1",
                            scheduler=_text(st.scheduler_address), batch=batch)),
        ("time [s]", f"{_text(st.elapsed_s)} in all, {_text(st.compute_s)} computing"),
        *other_rows(st.others)]


def _share(value, zero):
    """A share of the envelope as printed: "\u2261 0" for an element that is round-off on
    every trajectory (its share is noise: NaN in the dataset), else four decimals."""
    return "\u2261 0" if zero or not np.isfinite(value) else _share_text(value)


def _worst_cases(w, labels):
    """The sweep's worst cases, first: trajectories with the largest merged-model error (its
    round-off, :func:`torque_error_round_off`, is no error), and the elements whose share_tran
    varies most over the trajectories."""
    m = w.merged
    off = torque_error_round_off(m, w.merged_tau_error_peak, w.tau_peak)
    rel = np.where(off, np.nan, w.merged_tau_error_relative_peak)          # (K, n)
    per_traj = np.where(np.isfinite(rel), rel, -np.inf).max(axis=1)
    order = [k for k in np.argsort(per_traj)[::-1][:3] if np.isfinite(per_traj[k])]
    worst = {k: int(np.nanargmax(rel[k])) for k in order}          # trajectory: its joint
    spread = w.share_max - w.share_min
    top = [k for k in np.argsort(np.nan_to_num(spread, nan=-1.0))[::-1][:3]
           if np.isfinite(spread[k]) and _ranges(w, k)]
    return say("worst_cases", round_off=bool(off.all()),
               scale="region" if m.region else "own" if m.scale is not None else "",
               cases=[(w.sources[k], _pct(rel[k, j]), j + 1) for k, j in worst.items()],
               elements=[(markup.marked(labels[k]), _share_text(w.share_min[k]),
                          _share_text(w.share_max[k])) for k in top])


def _ranges(w, k):
    """Whether element k's share ranges over the trajectories as printed: its smallest and
    largest differ in the digits the report gives (a difference below them is rounding)."""
    return _share_text(w.share_min[k]) != _share_text(w.share_max[k])



# --------------------------------------------------------------------------------------------
# The sentences that cite the figures ("Fig. 2 shows ..."): what each figure shows of this sweep
# --------------------------------------------------------------------------------------------

#: At most this many elements are named in a list of a figure's sentence; the rest counted.
_NAMED = 6


def _names(labels):
    """Elements as mathematics, at most :data:`_NAMED` of them named ("D11, D12 and 3
    more")."""
    said = [markup.marked(lab) for lab in labels[:_NAMED]]
    more = len(labels) - len(said)
    if more:
        return ", ".join(said) + f" and {count(more)} more"
    return said[0] if len(said) == 1 else ", ".join(said[:-1]) + " and " + said[-1]


def _steady(fractions):
    """The class an element holds on every trajectory (its class fractions), or None."""
    k = int(np.argmax(fractions))
    return CLASSES[k] if np.isclose(fractions[k], 1.0) else None


def _share_sentence(w, symbol, zero):
    """What the share figure of D or of h shows of this sweep: how many of its elements hold
    one class on every trajectory (by class), which change class, which are round-off on every
    trajectory, and the widest box; a predicate ("shows ...")."""
    labels = list(w.elements)
    mine = [k for k, lab in enumerate(labels) if lab.startswith(symbol)]
    K = w.trajectories
    frac = np.asarray(w.class_fraction, float)
    off = [k for k in mine if zero[k]]
    rest = [k for k in mine if not zero[k]]
    steady = {c: [k for k in rest if _steady(frac[k]) == c] for c in CLASSES}
    varying = [k for k in rest if _steady(frac[k]) is None]
    spread = np.asarray(w.share_max, float) - np.asarray(w.share_min, float)
    ranged = [k for k in rest if np.isfinite(spread[k])]
    box = None                  # the widest box: (element, from, to), () if none is wider
    if K > 1 and ranged:
        k = max(ranged, key=lambda k: spread[k])
        box = ((markup.marked(labels[k]), _share_text(w.share_min[k]),
                _share_text(w.share_max[k])) if _ranges(w, k) else ())
    return say("share_shows", symbol=symbol, m=len(mine), K=K,
               held=[f"{count(len(ks))} {c}" for c, ks in steady.items() if ks],
               n_held=sum(len(ks) for ks in steady.values()), n_varying=len(varying),
               varying=varying and _names([labels[k] for k in varying]), n_off=len(off),
               off=off and _names([labels[k] for k in off]), box=box)


def _classes_sentence(w, counts):
    """What the class-fraction figure shows of this sweep: how many bars are of one colour,
    and the merged model's choices beside them; a predicate."""
    frac = np.asarray(w.class_fraction, float)
    M, K = len(w.elements), w.trajectories
    one = sum(_steady(frac[k]) is not None for k in range(M))
    choices = ", ".join(f"{c} {count(k)}" for c, k in counts.items() if k)
    return say("classes_shows", K=K, M=M, choices=choices, one=one)


def _error_sentence(w):
    """What the torque-error figure shows of this sweep: the largest relative peak error of
    the merged and of the own models, and the joints where the merged model's is round-off on
    every trajectory (not drawn); from the marks the figure draws
    (:func:`gd_analyze.report.sweep.error_marks`); a predicate."""
    own, merged, _, region = error_marks(w)
    scale = f"{_SI} over the region" if region else "that trajectory's peak |\u03c4|"

    def largest(marks):
        drawn = np.where(np.isfinite(marks) & (marks > ERROR_FLOOR), marks, -np.inf)
        if not np.isfinite(drawn).any():
            return "round-off on every joint and trajectory"
        k, j = np.unravel_index(np.argmax(drawn), drawn.shape)
        return f"at most {_pct(drawn[k, j])} of {scale} (joint {j + 1})"

    quiet = [j + 1 for j in range(w.joints)
             if not (np.isfinite(merged[:, j]) & (merged[:, j] > ERROR_FLOOR)).any()]
    return say("error_shows", merged=largest(merged), own=largest(own),
               quiet=joints_text(quiet) if quiet and len(quiet) < w.joints else "")


__all__ = ["SWEEP_REPORT_FORMATS", "write_sweep_report"]

#: The formats :func:`write_sweep_report` can write.
SWEEP_REPORT_FORMATS = ("html", "pdf")


# --------------------------------------------------------------------------------------------
# HTML and PDF
# --------------------------------------------------------------------------------------------

def _cites(o, ctx, key):
    """The sentence citing the outline ``o``'s next figure, ``key`` ("Fig. 2 shows ..."), or
    "" if that figure was not drawn."""
    return f"Fig. {o.n_figures + 1} {ctx['figure_text'][key]}" if key in o.available else ""


def _figure_parts(o, key, caption):
    """Figure ``key`` and its further parts (``key_2``, ... where drawn), each captioned
    with its part."""
    k = 1 + sum(f"{key}_{p}" in o.available for p in range(2, MOST_PARTS + 1))
    o.figure(key, caption + (f" Part 1 of {k}." if k > 1 else ""))
    for p in range(2, k + 1):
        o.figure(f"{key}_{p}", f"{caption} Part {p} of {k}.")


def _outline(ctx, figures):
    """The sweep report's sections, once, for the HTML and the PDF
    (:class:`gd_analyze.report.sections.Outline`): each figure right under the paragraph
    citing it ("Fig. 2 shows ..."), its table after it; Sec. 5.1's table, which its paragraph
    describes first, comes before its figure."""
    o = Outline(ctx["title"], figures, [(ctx["worst"], "lead"), (ctx["summary"], "summary"),
                                        (ctx["intro"], "note")])
    o.section("1", "Settings and provenance", "settings")
    o.table(ctx["settings"], "Settings of the sweep and its provenance, each once.", kv=True,
            size=7)
    o.section("2", "Translational share of the elements of D (layout of Fig. 3.10)", "D")
    o.paragraph(say("share_text", s=ctx["s"], e=ctx["e"]) + " " + _cites(o, ctx, "D"), "note")
    _figure_parts(o, "D", ctx["captions"]["D"])
    o.section("3", "Translational share of the elements of h (layout of Fig. 3.11)", "h",
              flush="D_2" in figures)
    o.paragraph(_cites(o, ctx, "h"), "note")
    _figure_parts(o, "h", ctx["captions"]["h"])
    o.section("4", "Envelope per element", "envelope", flush="h_2" in figures)
    o.paragraph(say("sweep_outline", key="envelope") + " " + ctx["captions"]["none"] + " "
                + _cites(o, ctx, "classes"), "note")
    _figure_parts(o, "classes", ctx["captions"]["classes"])
    o.table(ctx["envelope"], say("sweep_outline", key="envelope_table"))
    number, title = ctx["merged_heading"].split(" ", 1)
    o.section(number.rstrip("."), title, "merged", flush="classes_2" in figures)
    o.paragraph(ctx["merged_text"], "note")
    o.counts(ctx["counts"])
    o.section("5.1", "Open-loop torque error over all trajectories")
    o.paragraph(ctx["error_text"] + " " + _cites(o, ctx, "error"), "note")
    o.table(ctx["error"], say("sweep_outline", key="error_table"))
    o.figure("error", ctx["captions"]["error"])
    if ctx["cost"] is not None:
        o.section("5.2", "Evaluation cost of the merged model")
        o.table(ctx["cost"], say("sweep_outline", key="cost_table"))
    if ctx["payload"] is not None:
        o.section("6", "Payload sweep", "payload")
        o.table(ctx["payload"]["settings"], "Settings of the payload sweep.", kv=True)
        o.paragraph("Elements whose class changes with the payload: "
                    f"{ctx['payload']['changed']}. " + _cites(o, ctx, "payload"), "strong")
        o.figure("payload", ctx["captions"]["payload"])
        o.table(ctx["payload"]["table"], "Class of each element per payload mass.")
    return o


_FIGURE_FILES = {"D": "fig_sweep_share_D", "h": "fig_sweep_share_h",
                 "classes": "fig_sweep_class_fractions", "error": "fig_sweep_torque_error",
                 "payload": "fig_payload_dominance"}
#: Column-width (3.5 in) versions: ``figures/<name>_column.pdf`` and ``.svg`` (not in the
#: report).
#: Most parts of a share or class figure (:data:`MOST_HEIGHT`): the D figure of 15 joints
#: in a column takes 7.
MOST_PARTS = 12
#: Further parts: ``figures/<name>_part2.pdf``, ...
_FIGURE_FILES.update({f"{k}_{p}": f"{_FIGURE_FILES[k]}_part{p}" for k in ("D", "h", "classes")
                      for p in range(2, MOST_PARTS + 1)})
_FIGURE_FILES.update({f"{k}_column": f"{v}_column" for k, v in list(_FIGURE_FILES.items())})


#: The settings of the sweep whose values are the PDF's keywords: its provenance.
_KEYWORD_ROWS = ("robot file", "dominance threshold s, negligibility threshold e",
                 "SHA-256 of all inputs", "merge rule")


def _keywords(ctx):
    """The provenance in the PDF's document information: the inputs' SHA-256 and the
    settings, from the settings table (one fact in one place)."""
    rows = {markup.plain(k): markup.plain(v) for k, v in ctx["settings"]["rows"]}
    return "; ".join(["G-D dominance sweep", f"gd-analyze {ctx['version']}"]
                     + [f"{k}: {rows[k]}" for k in _KEYWORD_ROWS if k in rows])


def write_sweep_report(sweep_path: str | os.PathLike[str], outdir: str | os.PathLike[str],
                       payload: str | os.PathLike[str] | xr.Dataset | None = None,
                       formats: Sequence[str] = SWEEP_REPORT_FORMATS,
                       paper: str = "a4", latex: bool = False,
                       column_figures: bool = False) -> list[Path]:
    """Write sweep_report.html and sweep_report.pdf for a stored sweep.

    Parameters
    ----------
    sweep_path : str or os.PathLike
        A ``sweep.h5`` written by :func:`gd_analyze.store.schema.write_dataset`. Only read: nothing is
        recomputed.
    outdir : str or os.PathLike
        Output folder; made if missing.
    payload : str or os.PathLike or xarray.Dataset, optional
        A payload sweep (file written by :func:`gd_analyze.store.schema.write_dataset`, or the dataset
        of :func:`gd_analyze.jobs.payload.payload_sweep`); adds its section and
        :func:`~gd_analyze.report.main_figures.payload_figure`.
    formats : sequence of str, optional
        Any of ``"html"`` and ``"pdf"``.
    paper : {"a4", "letter"}, optional
        Page size of the PDF.
    latex : bool, optional
        Also write every table as LaTeX, ``outdir/tables/sweep_table_<section>_<k>.tex``.
    column_figures : bool, optional
        Also write every figure 3.5 in wide, as ``figures/<name>_column.pdf`` and ``.svg``
        (:func:`make_sweep_figures`' ``column``).

    Returns
    -------
    list of pathlib.Path
        The files written (``outdir/sweep_report.html``, ``outdir/sweep_report.pdf``), then
        every figure as ``outdir/figures/fig_sweep_*.pdf`` and ``.svg``, then every table of
        the report as ``outdir/tables/sweep_table_<section>_<k>.csv`` (and ``.tex`` with ``latex``:
        :func:`gd_analyze.report.drawing.table_files`).

    Raises
    ------
    InputError
        If a file is missing, unreadable or not a sweep of the right kind.
    ValueError
        If a format is not one of :data:`SWEEP_REPORT_FORMATS`, or none is given.
    OSError
        If a file cannot be written.

    Notes
    -----
    Files are written to a temporary name and renamed
    (:func:`gd_analyze.files.atomic_path`). Source: Sec. 3.4.1 and Figs. 3.10-3.11 of Fu,
    Gonzalez & Lee (1987).
    """

    formats = check_formats(formats, SWEEP_REPORT_FORMATS)
    check_paper(paper)
    if payload is not None and not hasattr(payload, "data_vars"):
        payload = open_sweep(payload, "payload")
    stored = StoredSweep.of(open_sweep(sweep_path, "sweep"))
    part = None if payload is None else PayloadSweep.of(payload)  # type: ignore[arg-type]
    ctx = sweep_context(stored, part)
    drawn = draw_figures(make_sweep_figures(stored, part, column=column_figures), _RC)
    return write_report_files(
        outdir, ctx, drawn, _FIGURE_FILES, _outline, "sweep_report.html.j2",
        "Dominance of the translational and rotational G-D terms over a sweep of trajectories "
        "(Fu, Gonzalez & Lee 1987, Sec. 3.4.1)", ctx["title"], _keywords(ctx),
        {"class_colours": _CLASS_COLOURS, "pruned_colour": TABLE_COLOURS["pruned"]},
        formats=formats, stem="sweep_report", paper=paper, latex=latex, prefix="sweep")

