"""Sweep report: a stored sweep as one self-contained HTML file and a PDF.

:func:`write_sweep_report` reads a ``sweep.h5`` written by :func:`gd_analyze.io.datasets.write_dataset`
and never recomputes the dynamics: every number comes from the dataset's variables and global
attributes. The report has these parts:

1. settings and provenance (robot, thresholds s and e, inputs, seed, cluster, elapsed time);
2. the distribution of share_tran over the trajectories for each element of D, as box plots in
   the upper-triangle layout of Fig. 3.10 of Fu, Gonzalez & Lee (1987), Sec. 3.4.1, with the
   thresholds s and 1 - s drawn;
3. the same for the elements of h (layout of Fig. 3.11);
4. the envelope: per element the fraction of trajectories in each dominance class and the
   min/median/max share, as a figure and a table;
5. the conservative merged simplified model: its choice per element and its torque error;
6. optionally, a payload sweep (:func:`gd_analyze.workflows.payload.payload_sweep`): share_tran and class
   of every element vs payload (:func:`gd_analyze.reports.figures.payload_figure`).

``sweep_report.html`` has no external resources (inline SVG figures, inline style sheet; the
Jinja2 template is ``templates/sweep_report.html.j2``). ``sweep_report.pdf`` is written with
matplotlib's PdfPages. Both are written atomically (:func:`gd_analyze.files.atomic_path`).
"""

from __future__ import annotations

import contextlib
import textwrap
from pathlib import Path

import numpy as np

from .common import CLASS_COLOURS as _CLASS_COLOURS, SUPTITLE_RC as _RC
from .common import attr as _attr, check as _check, fmt as _fmt, pct as _pct
from .common import gridspec as _gridspec, strings as _strings, style as _style
from .common import table as _table, thresholds as _thresholds
from .common import check_formats, grid_shape, render_template
from .common import utc_now
from .figures import CLASS_LETTER as _LETTER, PAYLOAD_REQUIRED as _PAYLOAD_REQUIRED
from .figures import payload_figure
from .main_figures import element_label
from .pages import PAPER, Document, draw_figures, figure_svg, no_gc, write_figure_files
from ..core.ranking import CLASSES

__all__ = ["SWEEP_REPORT_FORMATS", "make_sweep_figures", "render_sweep_html",
           "render_sweep_pdf", "write_sweep_report"]

#: The formats :func:`write_sweep_report` can write.
SWEEP_REPORT_FORMATS = ("html", "pdf")

# The choices of the merged model in the colours of their classes.
_CHOICE_COLOURS = {"tran": _CLASS_COLOURS["translational"], "rot": _CLASS_COLOURS["rotational"],
                   "both": _CLASS_COLOURS["both"], "none": _CLASS_COLOURS["negligible"]}
_CHOICE_CLASS = {"tran": "translational", "rot": "rotational", "both": "both",
                 "none": "negligible"}
_OWN_COLOUR, _MERGED_COLOUR = "#009E73", "#000000"
#: Width of every figure: the text of a page [in].
_PAGE_WIDTH = 7.2
_REQUIRED = ("share_tran", "dominance", "choice", "source", "duration", "tau_peak",
             "tau_error_relative_peak", "class_fraction", "share_tran_min", "share_tran_median",
             "share_tran_max", "merged_choice", "merged_tau_error_relative_peak",
             "merged_error_peak", "merged_error_rms", "merged_error_tau_peak",
             "merged_error_relative_peak", "merged_error_relative_rms")
#: Floor of the logarithmic torque-error axis (errors below it are drawn at it).
_ERROR_FLOOR = 1e-16


# --------------------------------------------------------------------------------------------
# Figures
# --------------------------------------------------------------------------------------------

def _fraction_text(fractions):
    parts = [f"{_LETTER[c]} {100 * f:.0f}%" if f >= 0.01 else f"{_LETTER[c]} {100 * f:.1g}%"
             for c, f in zip(CLASSES, fractions) if f > 0]
    return " \u00b7 ".join(parts)


def _share_panel(ax, values, label, merged, fractions, s, small):
    """One element: a box of its share_tran over the trajectories, thresholds s and 1 - s."""
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
    ax.set_title(f"{label} \u2192 {merged}", color=_CHOICE_COLOURS.get(merged, "black"), pad=2.5)
    ax.set_xlabel(_fraction_text(fractions), fontsize=7.0, labelpad=1.5,
                  color="0.15")


def _key_text(ds, K):
    s, e = _thresholds(ds)
    return textwrap.fill(
        f"Box: share_tran = \u03a3|tran| / (\u03a3|tran| + \u03a3|rot|) of the element over the "
        f"{K} trajectories (box: quartiles; whiskers: min and max; coloured bar: median). "
        f"Dashed lines: s = {s:g} and 1 \u2212 s; blue band: translational, orange band: "
        f"rotational. Title: element \u2192 choice of the merged model. Bottom: fraction of "
        f"trajectories per class (T translational, R rotational, B both, N negligible, "
        f"e = {e:g}); the share of a negligible element may compare round-off-level "
        f"values.", 52)


def _fig_D(ds):
    from matplotlib.figure import Figure

    n = ds.sizes["joint"]
    labels = _strings(ds["element"].values)
    share = ds["share_tran"].values
    merged = dict(zip(labels, _strings(ds["merged_choice"].values)))
    frac = ds["class_fraction"].values
    s, _ = _thresholds(ds)
    W = _PAGE_WIDTH
    H = 0.75 + n * 0.72 + (n - 1) * 0.42
    fig = Figure(figsize=(W, H))
    gs = _gridspec(fig, n, n, left=0.5, right=0.08, top=0.45, bottom=0.3, wgap=0.28, hgap=0.42)
    for i in range(n):
        for j in range(i, n):
            label = element_label("D", i + 1, j + 1)
            k = labels.index(label)
            ax = fig.add_subplot(gs[i, j])
            _share_panel(ax, share[:, k], label, merged[label], frac[k], s, small=True)
            ax.tick_params(labelleft=(i == j))
    if n > 1:
        k = n // 2
        lax = fig.add_subplot(gs[k:, :k])
        lax.axis("off")
        lax.text(0.0, 0.9, _key_text(ds, ds.sizes["trajectory"]), transform=lax.transAxes,
                 va="top", ha="left", fontsize=7.5, linespacing=1.35)
    fig.supylabel("share_tran [1]", x=0.05 / W, ha="left")
    fig.suptitle("Translational share of the elements of D over the sweep "
                 "(layout of Fig. 3.10)", y=1 - 0.15 / H, va="top")
    return fig


def _fig_h(ds):
    from matplotlib.figure import Figure

    n = ds.sizes["joint"]
    labels = _strings(ds["element"].values)
    share = ds["share_tran"].values
    merged = dict(zip(labels, _strings(ds["merged_choice"].values)))
    frac = ds["class_fraction"].values
    s, _ = _thresholds(ds)
    rows, cols = grid_shape(n, 3)
    W, H = _PAGE_WIDTH, 1.9 + 1.9 * rows
    fig = Figure(figsize=(W, H))
    gs = _gridspec(fig, rows, cols, left=0.65, right=0.1, top=0.5, bottom=1.2, wgap=0.6,
                   hgap=0.5)
    for i in range(n):
        label = f"h{i + 1}"
        k = labels.index(label)
        ax = fig.add_subplot(gs[i // cols, i % cols])
        _share_panel(ax, share[:, k], label, merged[label], frac[k], s, small=False)
        ax.set_ylabel("share_tran [1]")
    key = textwrap.fill(_key_text(ds, ds.sizes["trajectory"]).replace("\n", " "), 120)
    fig.text(0.3 / W, 0.1 / H, key, ha="left", va="bottom", fontsize=7.0, linespacing=1.3)
    fig.suptitle("Translational share of the elements of h over the sweep "
                 "(layout of Fig. 3.11)", y=1 - 0.15 / H, va="top")
    return fig


def _fig_classes(ds):
    from matplotlib.figure import Figure
    from matplotlib.patches import Patch

    labels = _strings(ds["element"].values)
    frac = ds["class_fraction"].values
    merged = _strings(ds["merged_choice"].values)
    M = len(labels)
    W, H = _PAGE_WIDTH, 1.5 + 0.17 * M
    fig = Figure(figsize=(W, H))
    ax = fig.add_axes((1.0 / W, 0.8 / H, (W - 2.6) / W, (H - 1.4) / H))
    y = np.arange(M)
    left = np.zeros(M)
    for c_idx, cls in enumerate(CLASSES):
        ax.barh(y, frac[:, c_idx], left=left, color=_CLASS_COLOURS[cls], height=0.75,
                label=cls, edgecolor="white", linewidth=0.3)
        left += frac[:, c_idx]
    ax.set_yticks(y, labels)
    ax.set_ylim(M - 0.5, -0.5)
    ax.set_xlim(0, 1)
    ax.set_xlabel("fraction of trajectories [1]")
    ax.grid(axis="y", visible=False)
    for k, ch in enumerate(merged):
        ax.text(1.02, k, f"merged: {ch}", transform=ax.get_yaxis_transform(), va="center",
                ha="left", fontsize=7, color=_CHOICE_COLOURS.get(ch, "black"))
    fig.legend(handles=[Patch(color=_CLASS_COLOURS[c], label=c) for c in CLASSES],
               loc="lower center", ncol=4, frameon=False, bbox_to_anchor=(0.5, 0.0))
    fig.suptitle(f"Dominance class per element over {ds.sizes['trajectory']} trajectories",
                 y=1 - 0.12 / H, va="top")
    return fig


def _fig_error(ds):
    from matplotlib.figure import Figure
    from matplotlib.lines import Line2D

    n = ds.sizes["joint"]
    own = ds["tau_error_relative_peak"].values
    merged = ds["merged_tau_error_relative_peak"].values
    overall = ds["merged_error_relative_peak"].values
    W, H = _PAGE_WIDTH, 3.6
    fig = Figure(figsize=(W, H))
    ax = fig.add_axes((0.9 / W, 0.9 / H, (W - 1.2) / W, (H - 1.6) / H))
    for j in range(n):
        for off, data, colour in ((-0.18, own[:, j], _OWN_COLOUR),
                                  (0.18, merged[:, j], _MERGED_COLOUR)):
            vals = data[np.isfinite(data)]
            if not vals.size:
                continue
            vals = np.maximum(vals, _ERROR_FLOOR)
            bp = ax.boxplot([vals], positions=[j + 1 + off], widths=0.3, whis=(0, 100),
                            showfliers=False, manage_ticks=False)
            for key in ("boxes", "whiskers", "caps", "medians"):
                for line in bp[key]:
                    line.set(color=colour, linewidth=0.9)
        if np.isfinite(overall[j]):
            ax.plot(j + 1.18, max(overall[j], _ERROR_FLOOR), marker="D", ms=4, color="#CC79A7",
                    ls="none")
    ax.set_yscale("log")
    ax.set_xticks(np.arange(1, n + 1), [f"joint {j + 1}" for j in range(n)])
    ax.set_xlim(0.4, n + 0.6)
    ax.set_ylabel("peak |\u03c4\u209b \u2212 \u03c4| / peak |\u03c4| [1]")
    ax.legend(handles=[Line2D([], [], color=_OWN_COLOUR, label="own simplified model, per "
                              "trajectory"),
                       Line2D([], [], color=_MERGED_COLOUR, label="merged model, per trajectory"),
                       Line2D([], [], color="#CC79A7", marker="D", ls="none",
                              label="merged model, over all trajectories")],
              loc="upper center", bbox_to_anchor=(0.5, -0.08), ncol=3, frameon=False,
              fontsize=7)
    fig.suptitle("Relative peak torque error per joint (box: quartiles, whiskers: min/max;\n"
                 f"values below {_ERROR_FLOOR:g} drawn at it)", y=1 - 0.08 / H, va="top",
                 fontsize=8.5)
    return fig


def make_sweep_figures(ds, payload=None):
    """Make the sweep report's figures from a stored sweep.

    Parameters
    ----------
    ds : xarray.Dataset
        A sweep dataset from :func:`gd_analyze.workflows.sweep.run_sweep` (K trajectories, M elements,
        n joints).
    payload : xarray.Dataset, optional
        A payload sweep from :func:`gd_analyze.workflows.payload.payload_sweep`.

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
    _check(ds, _REQUIRED, "sweep")
    with _style(_RC):
        figs = {"D": _fig_D(ds), "h": _fig_h(ds), "classes": _fig_classes(ds),
                "error": _fig_error(ds)}
    if payload is not None:
        figs["payload"] = payload_figure(payload)
    return figs


# --------------------------------------------------------------------------------------------
# Content shared by the HTML and the PDF
# --------------------------------------------------------------------------------------------

def _context(ds, payload=None):
    from .._version import __version__

    _check(ds, _REQUIRED, "sweep")
    K = ds.sizes["trajectory"]
    n = ds.sizes["joint"]
    labels = _strings(ds["element"].values)
    frac = ds["class_fraction"].values
    merged = _strings(ds["merged_choice"].values)
    s, e = _thresholds(ds)
    robot = _attr(ds, "robot")
    kind = str(ds.attrs.get("input_kind", ""))
    if kind == "random" and "seed" in ds.attrs:
        inputs = f"{K} random quintic trajectories (seed {_attr(ds, 'seed')})"
    else:
        inputs = f"{K} trajectories ({kind or 'given'})"
    durations = ds["duration"].values
    setpoints = ds["setpoints"].values if "setpoints" in ds.variables else np.array([])
    settings = [
        ("robot", robot), ("robot description", _attr(ds, "robot_description")),
        ("robot source", _attr(ds, "robot_source")), ("robot SHA-256", _attr(ds, "robot_sha256")),
        ("gravity [m/s\u00b2]", _attr(ds, "gravity")),
        ("dominance threshold s", f"{s:g}"), ("negligibility threshold e", f"{e:g}"),
        ("inputs", inputs), ("seed", _attr(ds, "seed")),
        ("input files", _attr(ds, "input_files")),
        ("SHA-256 of all inputs", _attr(ds, "inputs_sha256")),
        ("set points", f"{_attr(ds, 'setpoints_total')} in all"
                       + (f" ({int(setpoints.min())}\u2013{int(setpoints.max())} per trajectory)"
                          if setpoints.size else "")),
        ("duration [s]", f"{_fmt(np.min(durations))} \u2013 {_fmt(np.max(durations))} "
                         f"(median {_fmt(np.median(durations))})"),
        ("merge rule", _attr(ds, "merge_rule")),
        ("cluster", f"{_attr(ds, 'cluster')}; {_attr(ds, 'n_workers')} worker(s) at "
                    f"{_attr(ds, 'scheduler_address')}"),
        ("tasks", f"{_attr(ds, 'n_tasks')} ({_attr(ds, 'batch_size')} trajectories per task)"),
        ("elapsed [s]", f"{_attr(ds, 'elapsed_s')} (computing {_attr(ds, 'compute_s')})"),
        ("computed", _attr(ds, "history")),
        ("gd-analyze version", _attr(ds, "gd_analyze_version")),
        ("conventions", _attr(ds, "Conventions")),
    ]
    extra = sorted(set(ds.attrs) - {
        "robot", "robot_description", "robot_source", "robot_sha256", "gravity",
        "gravity_units", "dominance_threshold", "negligible_threshold", "seed", "input_files",
        "inputs_sha256", "setpoints_total", "merge_rule", "cluster", "n_workers",
        "scheduler_address", "n_tasks", "batch_size", "elapsed_s", "compute_s", "history",
        "gd_analyze_version", "Conventions", "title", "source", "references", "input_kind",
        "trajectories", "started"})
    settings += [(key, _attr(ds, key)) for key in extra]
    envelope = _table(
        ["element", "translational", "rotational", "both", "negligible", "min share",
         "median share", "max share", "merged choice"],
        [[lab, *(f"{f:.3f}" for f in frac[k]), _fmt(ds["share_tran_min"].values[k], 3),
          _fmt(ds["share_tran_median"].values[k], 3), _fmt(ds["share_tran_max"].values[k], 3),
          merged[k]] for k, lab in enumerate(labels)],
        align=["left"] + ["right"] * 7 + ["left"], colour_cols=[8])
    err = _table(
        ["joint", "peak |\u03c4| [N m]", "peak error [N m]", "RMS error [N m]",
         "peak error / peak |\u03c4|", "RMS error / peak |\u03c4|",
         "own models (worst)"],
        [[str(j + 1), _fmt(ds["merged_error_tau_peak"].values[j]),
          _fmt(ds["merged_error_peak"].values[j]), _fmt(ds["merged_error_rms"].values[j]),
          _pct(ds["merged_error_relative_peak"].values[j]),
          _pct(ds["merged_error_relative_rms"].values[j]),
          _pct(np.nanmax(ds["tau_error_relative_peak"].values[:, j])
               if np.isfinite(ds["tau_error_relative_peak"].values[:, j]).any() else np.nan)]
         for j in range(n)],
        align=["left"] + ["right"] * 6)
    counts = {c: sum(_CHOICE_CLASS[m] == c for m in merged) for c in CLASSES}
    kept = sum(m != "none" for m in merged)
    single = sum(m in ("tran", "rot") for m in merged)
    worst = _worst_cases(ds, labels)
    summary = (f"{robot}: share_tran of the {len(labels)} ranked elements of D and h over "
               f"{inputs}, s = {s:g}, e = {e:g}. The conservative merged model keeps both parts "
               f"of {counts['both']} elements, one part of {single}, and drops "
               f"{len(labels) - kept}; its largest relative peak torque error over all "
               f"trajectories is {_pct(np.nanmax(ds['merged_error_relative_peak'].values))} "
               f"(joint {int(np.nanargmax(ds['merged_error_relative_peak'].values)) + 1}).")
    ctx = {"version": __version__, "title": f"G-D dominance sweep: {robot}, {K} trajectories",
           "summary": summary, "settings": _table(["item", "value"], settings),
           "worst": worst,
           "intro": _INTRO.format(K=K, created=utc_now().isoformat(), version=__version__),
           "envelope": envelope, "error": err, "counts": counts, "s": f"{s:g}", "e": f"{e:g}",
           "K": K,
           "created": utc_now().isoformat(),
           "payload": None}
    if payload is not None:
        _check(payload, _PAYLOAD_REQUIRED, "payload sweep")
        masses = payload["payload"].values
        plabels = _strings(payload["element"].values)
        dom = np.array(_strings(payload["dominance"].values)).reshape(payload["share_tran"].shape)
        rows = [[lab, *(dom[p, k] for p in range(len(masses)))] for k, lab in enumerate(plabels)]
        changed = [lab for k, lab in enumerate(plabels) if len(set(dom[:, k])) > 1]
        ctx["payload"] = {
            "table": _table(["element", *(f"{m:g} kg" for m in masses)], rows,
                            colour_cols=list(range(1, len(masses) + 1))),
            "settings": _table(["item", "value"], [
                ("trajectory", _attr(payload, "input_file")),
                ("trajectory SHA-256", _attr(payload, "input_sha256")),
                ("payload masses [kg]", ", ".join(f"{m:g}" for m in masses)),
                ("payload centre of mass [m]", _attr(payload, "payload_com")),
                ("payload inertia [kg m\u00b2]", _attr(payload, "payload_inertia")),
                ("s, e", f"{_attr(payload, 'dominance_threshold')}, "
                         f"{_attr(payload, 'negligible_threshold')}")]),
            "changed": ", ".join(changed) if changed else "none",
        }
    return ctx


def _worst_cases(ds, labels):
    """The sweep's worst cases, first: trajectories with the largest merged-model error, and
    the elements whose share_tran varies most over the trajectories."""
    rel = ds["merged_tau_error_relative_peak"].values          # (K, n)
    sources = _strings(ds["source"].values)
    per_traj = np.where(np.isfinite(rel), rel, -np.inf).max(axis=1)
    order = [k for k in np.argsort(per_traj)[::-1][:3] if np.isfinite(per_traj[k])]
    parts = []
    for k in order:
        j = int(np.nanargmax(rel[k]))
        parts.append(f"{sources[k]} ({_pct(rel[k, j])} of peak |\u03c4| at joint {j + 1})")
    spread = ds["share_tran_max"].values - ds["share_tran_min"].values
    top = [k for k in np.argsort(np.nan_to_num(spread, nan=-1.0))[::-1][:3]
           if np.isfinite(spread[k])]
    elems = [f"{labels[k]} ({_fmt(ds['share_tran_min'].values[k], 3)}\u2013"
             f"{_fmt(ds['share_tran_max'].values[k], 3)})" for k in top]
    text = "Worst cases: "
    text += ("the merged model's largest torque errors are on " + "; ".join(parts) + ". "
             if parts else "no torque error is defined. ")
    text += ("The classes vary most for " + ", ".join(elems) + " (share_tran range over the "
             "trajectories)." if elems else "")
    return text


_INTRO = ("The generalized d'Alembert (G-D) equations of motion split the inertia matrix D and "
          "the Coriolis and centrifugal vector h into a translational and a rotational part (Fu, "
          "Gonzalez & Lee 1987, Robotics, Sec. 3.4). Sec. 3.4.1 ranks which part dominates each "
          "element along one trajectory and notes that the simplification depends on the "
          "trajectory; this report repeats the ranking over {K} trajectories. Report created "
          "{created} by gd-analyze {version} from the stored sweep; nothing was recomputed.")


# --------------------------------------------------------------------------------------------
# HTML and PDF
# --------------------------------------------------------------------------------------------

def render_sweep_html(ds, payload=None, figures=None):
    """Render the sweep report as one self-contained HTML document.

    Parameters
    ----------
    ds : xarray.Dataset
        A sweep dataset (:func:`gd_analyze.workflows.sweep.run_sweep`).
    payload : xarray.Dataset, optional
        A payload sweep (:func:`gd_analyze.workflows.payload.payload_sweep`).
    figures : dict of str to matplotlib.figure.Figure, optional
        From :func:`make_sweep_figures`; made here if not given.

    Returns
    -------
    str
        HTML with inline CSS and inline SVG figures, no external resources; from the Jinja2
        template ``templates/sweep_report.html.j2`` (autoescape on).

    Raises
    ------
    InputError
        If ``ds`` (or ``payload``) lacks a variable the report needs.

    Notes
    -----
    Source: Sec. 3.4.1 and Figs. 3.10-3.11 of Fu, Gonzalez & Lee (1987).
    """
    ctx = _context(ds, payload)
    if figures is None:
        figures = make_sweep_figures(ds, payload)
    return _html(ctx, {k: (figure_svg(f, _RC), None, None) for k, f in figures.items()})


def _html(ctx, figures):
    from markupsafe import Markup

    svgs = {k: Markup(svg) for k, (svg, _, _) in figures.items()}
    return render_template("sweep_report.html.j2", {**ctx, "figures": svgs,
                                                    "captions": _numbered(figures)},
                           {"class_colours": _CLASS_COLOURS})


#: Captions of the sweep report's figures (the same in the HTML and the PDF).
_CAPTIONS = {
    "D": "Distribution of share_tran of the elements of D over the sweep (layout of Fig. 3.10): "
         "box of the quartiles, whiskers at the minimum and maximum, coloured bar at the median, "
         "thresholds s and 1 \u2212 s dashed. Panel title: element and the merged model's "
         "choice; bottom line: fraction of trajectories per class.",
    "h": "Distribution of share_tran of the Coriolis and centrifugal elements h_i over the "
         "sweep (layout of Fig. 3.11); same conventions as for D.",
    "classes": "Fraction of the trajectories in each class, per element; the merged model's "
               "choice on the right.",
    "error": "Relative peak torque error per joint: of each trajectory's own simplified model "
             "(green) and of the merged model (black), per trajectory; diamond: merged model over "
             "all trajectories.",
    "payload": "share_tran of every element against the payload mass on the last link, with "
               "the class of each cell (T, R, B, N); below, peak |\u03c4| per joint.",
}
_FIGURE_FILES = {"D": "fig_sweep_share_D", "h": "fig_sweep_share_h",
                 "classes": "fig_sweep_class_fractions", "error": "fig_sweep_torque_error",
                 "payload": "fig_payload_dominance"}


def _numbered(figures):
    return {k: f"Figure {m + 1}. {_CAPTIONS[k]}" for m, k in enumerate(figures)}


def render_sweep_pdf(ds, path, payload=None, figures=None, paper="a4"):
    """Write the sweep report as a PDF document.

    Parameters
    ----------
    ds : xarray.Dataset
        A sweep dataset.
    path : str or os.PathLike
        The PDF file (written as is; :func:`write_sweep_report` passes a temporary name).
    payload : xarray.Dataset, optional
        A payload sweep.
    figures : dict of str to matplotlib.figure.Figure, optional
        From :func:`make_sweep_figures`; made here if not given.
    paper : {"a4", "letter"}, optional
        The size of every page.

    Returns
    -------
    int
        Number of pages.

    Raises
    ------
    InputError
        If a dataset lacks a variable the report needs.
    OSError
        If the file cannot be written.
    """
    ctx = _context(ds, payload)
    if figures is None:
        figures = make_sweep_figures(ds, payload)
    return _pdf(ctx, draw_figures(figures, _RC), path, paper)


def _pdf(ctx, drawn, path, paper="a4"):
    metadata = {"Author": f"gd-analyze {ctx['version']}",
                "Subject": "Dominance of the translational and rotational G-D terms over a "
                           "sweep of trajectories (Fu, Gonzalez & Lee 1987, Sec. 3.4.1)",
                "Creator": f"gd-analyze {ctx['version']}"}
    doc = Document(ctx["title"], paper=paper, metadata=metadata,
                   footer=f"gd-analyze {ctx['version']}: {ctx['title']}")

    def fig(key):
        if key in drawn:
            doc.figure(drawn[key][1], drawn[key][2], _CAPTIONS[key])

    doc.heading(ctx["title"], level=0)
    doc.paragraph(ctx["worst"], size=9.5, bold=True)
    doc.paragraph(ctx["summary"], size=9.5)
    doc.paragraph(ctx["intro"], size=8.5, colour="0.25")
    doc.heading("1. Settings and provenance")
    doc.table(ctx["settings"], size=7)
    doc.heading("2. Translational share of the elements of D (layout of Fig. 3.10)")
    doc.paragraph(_SHARE_TEXT.format(s=ctx["s"], e=ctx["e"]), size=8.5)
    fig("D")
    doc.heading("3. Translational share of the elements of h (layout of Fig. 3.11)")
    fig("h")
    doc.heading("4. Envelope per element")
    doc.paragraph("Fraction of the trajectories in which each class holds, and the smallest, "
                  "median and largest share_tran over the trajectories.", size=8.5)
    fig("classes")
    doc.table(ctx["envelope"])
    doc.heading("5. Conservative merged model and its torque error")
    doc.paragraph(_MERGED_TEXT, size=8.5)
    doc.paragraph("   ".join(f"{c}: {k}" for c, k in ctx["counts"].items()), size=8.5,
                  bold=True)
    doc.heading("5.1 Torque error over all trajectories", level=2)
    doc.paragraph(_ERROR_TEXT, size=8.5)
    doc.table(ctx["error"])
    fig("error")
    if ctx["payload"] is not None:
        doc.heading("6. Payload sweep")
        doc.table(ctx["payload"]["settings"])
        doc.paragraph(f"Elements whose class changes with the payload: "
                      f"{ctx['payload']['changed']}.", size=9, bold=True)
        fig("payload")
        doc.table(ctx["payload"]["table"])
    return doc.write(path)


_SHARE_TEXT = ("For each trajectory and element, share_tran = \u03a3|tran| / (\u03a3|tran| + "
               "\u03a3|rot|) over its set points. A share above s = {s} is translational, below "
               "1 \u2212 s rotational, in between both, unless the element is negligible (peak "
               "below e = {e} times its scale).")
_MERGED_TEXT = ("Each trajectory has its own simplified model (keep the dominant part of each "
                "element, both if neither dominates, nothing if negligible). The merged model is "
                "valid for the whole sweep: a part of an element is dropped only where every "
                "trajectory's model drops it. Gravity c is kept whole: "
                "\u03c4\u209b = D\u209b q\u0308 + h\u209b + c.")
_ERROR_TEXT = ("Per joint, over all set points of all trajectories: peak and RMS of "
               "|\u03c4_merged \u2212 \u03c4| [N m], and both relative to the peak |\u03c4| "
               "over all trajectories. Last column: the largest relative peak error of any "
               "trajectory's own simplified model along that trajectory.")


def write_sweep_report(sweep_path, outdir, payload=None, formats=SWEEP_REPORT_FORMATS,
                       paper="a4"):
    """Write sweep_report.html and sweep_report.pdf for a stored sweep.

    Parameters
    ----------
    sweep_path : str or os.PathLike
        A ``sweep.h5`` written by :func:`gd_analyze.io.datasets.write_dataset`. Only read: nothing is
        recomputed.
    outdir : str or os.PathLike
        Output folder; made if missing.
    payload : str or os.PathLike or xarray.Dataset, optional
        A payload sweep (file written by :func:`gd_analyze.io.datasets.write_dataset`, or the dataset
        of :func:`gd_analyze.workflows.payload.payload_sweep`); adds its section and :func:`payload_figure`.
    formats : sequence of str, optional
        Any of ``"html"`` and ``"pdf"``.
    paper : {"a4", "letter"}, optional
        Page size of the PDF.

    Returns
    -------
    list of pathlib.Path
        The files written (``outdir/sweep_report.html``, ``outdir/sweep_report.pdf``), then
        every figure as ``outdir/figures/fig_sweep_*.pdf`` and ``.svg``.

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
    from ..files import atomic_path
    from ..io.datasets import open_sweep

    formats = check_formats(formats, SWEEP_REPORT_FORMATS)
    if paper not in PAPER:
        raise ValueError(f"paper must be one of {sorted(PAPER)}, got {paper!r}")
    ds = open_sweep(sweep_path, "sweep")
    if payload is not None and not hasattr(payload, "data_vars"):
        payload = open_sweep(payload, "payload")
    ctx = _context(ds, payload)
    with no_gc():
        drawn = draw_figures(make_sweep_figures(ds, payload), _RC)
    outdir = Path(outdir)
    (outdir / "figures").mkdir(parents=True, exist_ok=True)
    written, files = [], []
    with contextlib.ExitStack() as stack:
        files = write_figure_files(stack, drawn, outdir / "figures", _FIGURE_FILES)
        for fmt in formats:
            path = outdir / f"sweep_report.{fmt}"
            tmp = stack.enter_context(atomic_path(path))
            if fmt == "html":
                with open(tmp, "w", encoding="utf-8") as fh:
                    fh.write(_html(ctx, drawn))
            else:
                _pdf(ctx, drawn, tmp, paper)
            written.append(path)
    return written + files
