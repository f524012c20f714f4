"""The sweep report's figures: share_tran over the trajectories in the layout of Figs. 3.10 and
3.11 of Fu, Gonzalez & Lee (1987), Sec. 3.4.1, the class fractions and the torque errors.

Drawn from a stored sweep dataset (:func:`gd_analyze.store.schema.open_sweep`); nothing is
recomputed.
"""

from __future__ import annotations

import textwrap
from typing import TYPE_CHECKING

import numpy as np

from ..ranking.ranking import CLASSES, ROUND_OFF, arm_scales, element_label, is_round_off
from ..store.sweep_view import REQUIRED, PayloadSweep, StoredSweep
from .common import CLASS_COLOURS as _CLASS_COLOURS
from .common import SUPTITLE_RC as _RC
from .common import grid_shape, torque_units
from .common import gridspec as _gridspec
from .figures import CLASS_LETTER as _LETTER
from .figures import payload_figure
from .markup import ROT as _ROT
from .markup import TRAN as _TRAN
from .markup import label as _math
from .numbers import decade_label
from .ticks import decade_formatter
from .typeset import TABLE_COLOURS

if TYPE_CHECKING:                       # for the type hints only
    import xarray as xr
    from matplotlib.figure import Figure
    from numpy.typing import ArrayLike

    from ..store.sweep_view import MergedModel

__all__ = ["make_sweep_figures", "error_marks", "REQUIRED", "KEPT", "ERROR_FLOOR"]


# The choices of the merged model in the colours of their classes.
_CHOICE_COLOURS = {"tran": _CLASS_COLOURS["translational"], "rot": _CLASS_COLOURS["rotational"],
                   "both": _CLASS_COLOURS["both"], "none": _CLASS_COLOURS["negligible"],
                   "pruned": TABLE_COLOURS["pruned"]}
#: Panel titles: the part of the element the merged model keeps, said as such ("D16
#: → rot" would read as a class).
KEPT = {"tran": "keeps tran", "rot": "keeps rot", "both": "keeps both", "none": "dropped",
        "pruned": "pruned"}
_OWN_COLOUR, _MERGED_COLOUR = "#009E73", "#000000"
#: Width of every figure: the text of a page [in]; the column versions' [in].
_PAGE_WIDTH, COLUMN_WIDTH = 7.2, 3.5
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


def _fraction_text(fractions):
    parts = [f"{_LETTER[c]} {100 * f:.0f}%" if f >= 0.01 else f"{_LETTER[c]} {100 * f:.1g}%"
             for c, f in zip(CLASSES, fractions) if f > 0]
    return " \u00b7 ".join(parts)


def _zero_share_panel(ax, label, merged):
    """An element that is round-off on every trajectory: no share (it would be noise)."""
    ax.text(0.5, 0.5, "\u2261 0", transform=ax.transAxes, ha="center", va="center",
            fontsize=10, color="0.35")
    ax.set_xlim(-0.6, 0.8)
    ax.set_ylim(-0.03, 1.03)
    ax.set_xticks([])
    ax.set_yticks([0.0, 0.5, 1.0])
    ax.yaxis.set_major_formatter("{x:.2g}")
    ax.tick_params(length=2.0, pad=1.5)
    ax.grid(False)
    ax.set_title(f"{_math(label)}: \u2261 0", color=_CHOICE_COLOURS.get(merged, "black"), pad=2.5)


def _share_panel(ax, values, label, merged, fractions, s, small, zero=None, two_lines=False):
    """One element: a box of its share_tran over the trajectories, thresholds s and 1 - s;
    trajectories on which the element is round-off (``zero``) are left out of the box."""
    if zero is not None:
        if zero.all():
            return _zero_share_panel(ax, label, merged)
        values = values[~zero]
    ax.axhspan(s, 1.0, color=_CLASS_COLOURS["translational"], alpha=0.09, lw=0)
    ax.axhspan(0.0, 1.0 - s, color=_CLASS_COLOURS["rotational"], alpha=0.09, lw=0)
    for y in (s, 1.0 - s):
        ax.axhline(y, color="0.35", lw=0.6, ls="--")
    finite = values[np.isfinite(values)]
    if finite.size:
        bp = ax.boxplot([finite], positions=[0.0], widths=0.55, whis=(0, 100), showfliers=False,
                        patch_artist=True, manage_ticks=False)
        for box in bp["boxes"]:
            box.set(facecolor="white", edgecolor="black", linewidth=0.8)
        for key in ("whiskers", "caps"):
            for line in bp[key]:
                line.set(color="black", linewidth=0.7)
        for line in bp["medians"]:
            line.set(color=_CHOICE_COLOURS.get(merged, "black"), linewidth=1.6)
        if finite.size <= 60:
            jitter = np.linspace(-0.18, 0.18, finite.size) if finite.size > 1 else [0.0]
            ax.plot(np.asarray(jitter) + 0.45, finite, ".", ms=2.0, color="0.3")
    else:
        ax.text(0.5, 0.5, "no data", transform=ax.transAxes, ha="center", va="center")
    ax.set_xlim(-0.6, 0.8)
    ax.set_ylim(-0.03, 1.03)
    ax.set_xticks([])
    ax.set_yticks([0.0, 0.5, 1.0])
    ax.yaxis.set_major_formatter("{x:.2g}")
    ax.tick_params(length=2.0, pad=1.5)
    ax.set_title(f"{_math(label)}:{chr(10) if two_lines else ' '}{KEPT.get(merged, merged)}",
                 color=_CHOICE_COLOURS.get(merged, "black"), pad=2.5,
                 linespacing=1.0)           # a narrow panel: two lines
    ax.set_xlabel(_fraction_text(fractions), fontsize=7.0, labelpad=1.5,
                  color="0.15")


def _shares(w):
    """What the share figures draw: n, the elements' labels, share_tran (K, M), the merged
    choice by label, the class fractions (M, C), the round-off marks (K, M) and s."""
    labels = list(w.elements)
    return (w.joints, labels, w.share_tran, dict(zip(labels, w.merged.choice)),
            w.class_fraction, w.round_off, _thresholds(w)[0])


def _key_text(w, K):
    s, e = _thresholds(w)
    return textwrap.fill(
        f"Box: translational share \u03a3|{_TRAN}| / (\u03a3|{_TRAN}| + \u03a3|{_ROT}|) of the "
        f"element X over the {K} trajectories (box: quartiles; whiskers: min and max; coloured bar: median). "
        f"Dashed lines: s = {s:g} and 1 \u2212 s; blue band: translational, orange band: "
        f"rotational. Title: element and the part the merged model keeps (keeps tran, "
        f"keeps rot, keeps both, or dropped"
        + ("; pruned: changed by dropped base-parameter parts" if "pruned" in
           w.merged.choice else "") + "). Bottom: fraction of "
        f"trajectories per class (T translational, R rotational, B both, N negligible, "
        f"e = {e:g}). \u2261 0: round-off ({ROUND_OFF_WORDS}) in every part on every "
        f"trajectory, no share drawn; on the trajectories where an element is round-off its "
        f"share is left out of the box. Grey dots: the share on each trajectory, one dot per "
        f"trajectory (up to 60).", 52)


def _fig_D(w, width=_PAGE_WIDTH):
    from matplotlib.figure import Figure

    if width < _PAGE_WIDTH:
        return _fig_D_column(w, width)
    n, labels, share, merged, frac, zero, s = _shares(w)
    W = _PAGE_WIDTH
    H = 0.98 + n * 0.56 + (n - 1) * 0.46                # titles of two lines
    fig = Figure(figsize=(W, H))
    gs = _gridspec(fig, n, n, left=0.5, right=0.08, top=0.68, bottom=0.3, wgap=0.28, hgap=0.46)
    for i in range(n):
        for j in range(i, n):
            label = element_label("D", i, j)
            k = labels.index(label)
            ax = fig.add_subplot(gs[i, j])
            _share_panel(ax, share[:, k], label, merged[label], frac[k], s, small=True,
                         zero=zero[:, k], two_lines=True)
            ax.tick_params(labelleft=(i == j))
    if n > 1:
        k = n // 2
        lax = fig.add_subplot(gs[k:, :k])
        lax.axis("off")
        lax.text(0.0, 0.9, _key_text(w, w.trajectories), transform=lax.transAxes,
                 va="top", ha="left", fontsize=7.5, linespacing=1.35)
    fig.supylabel("translational share [1]", x=0.05 / W, ha="left")
    fig.suptitle("Translational share of the elements of D over the sweep "
                 "(layout of Fig. 3.10)", y=1 - 0.15 / H, va="top")
    return fig


def _fig_D_column(w, W):
    """The share boxes of D in reading order, three a row, the key below (a column)."""
    from matplotlib.figure import Figure

    n, labels, share, merged, frac, zero, s = _shares(w)
    elements = [element_label("D", i, j) for i in range(n) for j in range(i, n)]
    cols = 3
    rows = -(-len(elements) // cols)
    H = 0.74 + rows * 1.08 + 1.55           # titles of two lines
    fig = Figure(figsize=(W, H))
    gs = _gridspec(fig, rows, cols, left=0.55, right=0.08, top=0.74, bottom=1.75, wgap=0.3,
                   hgap=0.55)
    for m, label in enumerate(elements):
        k = labels.index(label)
        ax = fig.add_subplot(gs[m // cols, m % cols])
        _share_panel(ax, share[:, k], label, merged[label], frac[k], s, small=True,
                     zero=zero[:, k], two_lines=True)
        ax.tick_params(labelleft=(m % cols == 0))
    fig.text(0.1 / W, 1.5 / H, textwrap.fill(_key_text(w, w.trajectories)
                                             .replace("\n", " "), 68),
             va="top", ha="left", fontsize=7, linespacing=1.25)
    fig.supylabel("translational share [1]", x=0.05 / W, ha="left")
    fig.suptitle("Translational share of the elements of D\nover the sweep (layout of Fig. "
                 "3.10)", y=1 - 0.08 / H, va="top", fontsize=9)
    return fig


def _fig_h(w, width=_PAGE_WIDTH):
    from matplotlib.figure import Figure

    n, labels, share, merged, frac, zero, s = _shares(w)
    column = width < _PAGE_WIDTH
    rows, cols = grid_shape(n, 2 if column else 3)
    W = width
    H = (2.3 + 1.6 * rows) if column else (2.45 + 1.55 * rows)
    fig = Figure(figsize=(W, H))
    # the key below the panels takes up to six lines at the printed 8 pt, under the last
    # row's tick and class labels
    gs = _gridspec(fig, rows, cols, left=0.65, right=0.1, top=0.55 if column else 0.5,
                   bottom=1.75, wgap=0.6, hgap=0.5)
    for i in range(n):
        label = element_label("h", i)
        k = labels.index(label)
        ax = fig.add_subplot(gs[i // cols, i % cols])
        _share_panel(ax, share[:, k], label, merged[label], frac[k], s, small=False,
                     zero=zero[:, k])
        ax.set_ylabel("translational share [1]")
    key = textwrap.fill(_key_text(w, w.trajectories).replace("\n", " "),
                        68 if column else 120)
    fig.text(0.1 / W if column else 0.3 / W, 0.1 / H, key, ha="left", va="bottom",
             fontsize=7.0, linespacing=1.25 if column else 1.3)
    fig.suptitle("Translational share of the elements of h over the sweep "
                 "(layout of Fig. 3.11)" if not column else
                 "Translational share of the elements of h\nover the sweep (layout of Fig. "
                 "3.11)", y=1 - 0.15 / H if not column else 1 - 0.08 / H, va="top",
                 fontsize=None if not column else 9)
    return fig


def _fig_classes(w, width=_PAGE_WIDTH):
    from matplotlib.figure import Figure
    from matplotlib.patches import Patch

    labels = list(w.elements)
    frac = w.class_fraction
    merged = list(w.merged.choice)
    M = len(labels)
    column = width < _PAGE_WIDTH
    W, H = width, (1.9 if column else 1.5) + (0.17 if column else 0.14) * M
    fig = Figure(figsize=(W, H))
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
    fig.suptitle(f"Dominance class per element{chr(10) if column else ' '}over "
                 f"{w.trajectories} trajectories",
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
    tau = w.tau_peak
    own = np.where(torque_error_round_off(m, w.tau_error_peak, tau), 0.0, own)
    merged = np.where(torque_error_round_off(m, w.merged_tau_error_peak, tau), 0.0,
                      merged)
    overall = np.where(torque_error_round_off(m, w.merged_error_peak,
                                              w.merged_error_tau_peak), 0.0, overall)
    return own, merged, overall, region


def _fig_error(w, width=_PAGE_WIDTH):
    from matplotlib.figure import Figure
    from matplotlib.lines import Line2D
    from matplotlib.ticker import NullFormatter

    m = w.merged
    n = w.joints
    own, merged, overall, region = error_marks(w)
    column = width < _PAGE_WIDTH
    W, H = width, (3.9 if column else 3.1)
    fig = Figure(figsize=(W, H))
    ax = fig.add_axes((0.75 / W, (1.25 if column else 0.9) / H, (W - 0.95) / W,
                       (H - (2.05 if column else 1.6)) / H))
    for j in range(n):
        for off, data, colour in ((-0.18, own[:, j], _OWN_COLOUR),
                                  (0.18, merged[:, j], _MERGED_COLOUR)):
            vals = data[np.isfinite(data) & (data > ERROR_FLOOR)]     # round-off: not drawn
            if not vals.size:
                continue
            bp = ax.boxplot([vals], positions=[j + 1 + off], widths=0.3, whis=(0, 100),
                            showfliers=False, manage_ticks=False)
            for key in ("boxes", "whiskers", "caps", "medians"):
                for line in bp[key]:
                    line.set(color=colour, linewidth=0.9)
        if np.isfinite(overall[j]) and overall[j] > ERROR_FLOOR:
            ax.plot(j + 1.18, overall[j], marker="D", ms=4, color="#CC79A7", ls="none")
        finite = np.concatenate([own[:, j], merged[:, j]])
        finite = finite[np.isfinite(finite)]
        if finite.size and (finite <= ERROR_FLOOR).all():
            ax.text(j + 1, 0.5, "round-off\nonly", transform=ax.get_xaxis_transform(),
                    ha="center", va="center", fontsize=7, color="0.35")
    ax.set_yscale("log")
    # decades written 10⁻⁶ in the tick labels' own size (mathtext's exponents: 0.7 of it)
    ax.yaxis.set_major_formatter(decade_formatter())
    ax.yaxis.set_minor_formatter(NullFormatter())
    ax.set_xticks(np.arange(1, n + 1), [f"{j + 1}" if column else f"joint {j + 1}"
                                         for j in range(n)])
    if column:
        ax.set_xlabel("joint", labelpad=1.0)
    ax.set_xlim(0.4, n + 0.6)
    ax.set_ylabel("peak |\u0394\u03c4| / peak |\u03c4| [1]" if not region else
                  "peak |\u0394\u03c4| / s [1]")    # one scale for all
    own_rule, rule = m.own_rule, m.rule
    no_bound = {"chapter": ", no bound"}
    merged_rule = (f"budget rule, \u03b5 = {float(m.tolerance):g}"
                   + ("; / s over the region" if region else "")
                   if rule == "budget" else f"{rule} rule{no_bound.get(rule, '')}")
    ax.legend(handles=[Line2D([], [], color=_OWN_COLOUR, label=f"own models ({own_rule} rule"
                              f"{no_bound.get(own_rule, '')}"
                              + ("; / s over the region" if region else "")
                              + "), per trajectory"),
                       Line2D([], [], color=_MERGED_COLOUR,
                              label=f"merged model ({merged_rule}), per trajectory"),
                       Line2D([], [], color="#CC79A7", marker="D", ls="none",
                              label="merged model, over all trajectories")],
              loc="upper center", bbox_to_anchor=(0.5, -0.2 if column else -0.08),
              ncol=1 if column else 2, frameon=False, fontsize=7)
    fig.suptitle("Relative peak torque error per joint\n(box: quartiles, whiskers: min/max;\n"
                 "round-off not drawn)" if column else
                 "Relative peak torque error per joint (box: quartiles, whiskers: min/max;\n"
                 f"round-off, {TORQUE_ROUND_OFF_WORDS}, not drawn)", y=1 - 0.08 / H,
                 va="top", fontsize=8.5)
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
        and of the merged model; ``"payload"`` (if given): :func:`payload_figure`.

    Raises
    ------
    InputError
        If a variable the figures need is missing.
    """
    w = StoredSweep.of(ds)
    import matplotlib

    with matplotlib.rc_context(_RC):  # type: ignore[arg-type]  # keys typed as literals
        figs = {"D": _fig_D(w), "h": _fig_h(w), "classes": _fig_classes(w),
                "error": _fig_error(w)}
        if column:
            figs.update({f"{k}_column": make(w, COLUMN_WIDTH) for k, make in
                         (("D", _fig_D), ("h", _fig_h), ("classes", _fig_classes),
                          ("error", _fig_error))})
    if payload is not None:
        figs["payload"] = payload_figure(payload)
        if column:
            figs["payload_column"] = payload_figure(payload, COLUMN_WIDTH)
    return figs
