"""Control report: the stored closed-loop comparison as one self-contained HTML file and a PDF.

:func:`write_control_report` reads a control dataset written by
:func:`gd_analyze.io.control_dataset.write_control_dataset` (``control.h5``) and never recomputes anything:
every number and curve comes from the dataset's variables and global attributes. The report
holds the set-up and gains, the tracking error per joint of the three controllers (figure and
peak/RMS table), the torque difference between the simplified-model and the full-model
computed-torque controllers, the applied torques, the evaluation cost of the simplified model
against the full one, the model's choices and the provenance.

``control_report.html`` has no external resources (inline CSS, inline SVG figures, Jinja2
template ``templates/control_report.html.j2``); ``control_report.pdf`` is written with
matplotlib's PdfPages from :class:`matplotlib.figure.Figure` objects (no pyplot). Both are
written atomically (:func:`gd_analyze.files.atomic_path`).
"""

from __future__ import annotations

import contextlib
import functools
from pathlib import Path

import numpy as np

from .common import strings as _strings, table as _table
from .common import attr, fmt, render_template, utc_now
from ..core.ranking import element_label
from .control_figures import COLUMN_WIDTH, PAGE_WIDTH, control_figures
from .control_figures import _LABELS, _RC, _joint_units
from .pages import PAPER, Document
from .drawing import draw_figures, figure_svg, no_gc, write_figure_files

__all__ = ["CONTROL_REPORT_FILES", "REQUIRED_VARIABLES", "make_control_figures",
           "render_control_html", "render_control_pdf", "write_control_report"]

#: Names of the files written into the output folder.
CONTROL_REPORT_FILES = ("control_report.html", "control_report.pdf")
#: Variables a control dataset must have.
REQUIRED_VARIABLES = ("is_setpoint", "q_d", "error", "tau", "error_peak_setpoints",
                      "error_rms_setpoints", "error_peak_grid", "error_rms_grid", "Kp", "Kv",
                      "Kp_pd", "Kv_pd", "wn", "zeta", "inertia_scale", "choice", "nfev")

# Numbers in e-notation outside [1e-3, 1e5), 3 significant digits unless told; attributes
# with 6 digits, arrays without parentheses, booleans as 0/1.
_SCI = (1e-3, 1e5)
_fmt = functools.partial(fmt, digits=3, sci_outside=_SCI)
_attr = functools.partial(attr, parens=False, bools=True, sci_outside=_SCI)


def _check(ds, path):
    from ..errors import InputError

    missing = [v for v in REQUIRED_VARIABLES if v not in ds.variables]
    if missing or "controller" not in ds.dims or "time" not in ds.dims:
        raise InputError(f"not a gd-analyze control dataset (missing {missing[:3] or 'dims'})",
                         str(path))


# --------------------------------------------------------------------------------------------
# Figures (reports/control_figures.py)
# --------------------------------------------------------------------------------------------

def make_control_figures(ds, width=PAGE_WIDTH):
    """The report's figures, drawn from a stored control dataset.

    Parameters
    ----------
    ds : xarray.Dataset
        A control dataset (:func:`gd_analyze.io.control_dataset.control_dataset`).
    width : float, optional
        7.2 in (a page, default) or 3.5 in (a column, one panel a row).

    Returns
    -------
    dict of str to matplotlib.figure.Figure
        As :func:`gd_analyze.reports.control_figures.control_figures`: ``"error"``,
        ``"tau_difference"`` (if stored) and ``"tau"``.

    Raises
    ------
    InputError
        If the dataset lacks a variable of a control dataset.
    """
    _check(ds, "<dataset>")
    return control_figures(ds, width)


# --------------------------------------------------------------------------------------------
# Content shared by the HTML and the PDF
# --------------------------------------------------------------------------------------------

def _context(ds):
    from .._version import __version__

    names = _strings(ds["controller"].values)
    n = int(ds.sizes["joint"])
    joints = [f"J{j + 1}" for j in range(n)]
    desc = (_strings(ds["controller_description"].values) if "controller_description" in ds
            else names)
    peak_grid = ds["error_peak_grid"]
    worst = {c: float(np.nanmax(peak_grid.sel(controller=c).values)) for c in names}
    summary = "; ".join(f"{_LABELS.get(c, c)}: peak |e| {_fmt(worst[c])} rad" for c in names)
    summary = (f"{_attr(ds, 'robot')} along {_attr(ds, 'trajectory_file')}, "
               f"wn = {_attr(ds, 'wn')} rad/s, zeta = {_attr(ds, 'zeta')}. {summary}.")
    if "tau_difference_peak" in ds:
        summary += (" Largest closed-loop torque difference |tau_simplified - tau_full| (two "
                    "closed-loop runs, each along its own motion): "
                    f"{_fmt(float(ds['tau_difference_peak'].max()))} N m; not the open-loop "
                    "error tau_s - tau of the main report (one model against the other along "
                    "the desired trajectory).")
    verdict = _verdict(worst, ds)
    setup = _table(["item", "value"], [
        ["robot", f"{_attr(ds, 'robot')} (SHA-256 {_attr(ds, 'robot_sha256')})"],
        ["trajectory", f"{_attr(ds, 'trajectory_file')} (SHA-256 "
                       f"{_attr(ds, 'trajectory_sha256')})"],
        ["simplified model", f"{_attr(ds, 'model_file')} (SHA-256 {_attr(ds, 'model_sha256')})"],
        ["plant", _attr(ds, "plant")],
        ["controllers", "; ".join(f"{c}: {d}" for c, d in zip(names, desc))],
        ["control laws", _attr(ds, "control_laws")],
        ["desired motion", _attr(ds, "interpolation")],
        ["integrator", f"{_attr(ds, 'integrator')}, rtol = {_attr(ds, 'rtol')}, "
                       f"atol = {_attr(ds, 'atol')}"],
        ["samples", f"{_attr(ds, 'samples')} ({_attr(ds, 'setpoints')} set points + fine grid "
                    f"of {_attr(ds, 'grid_points')})"],
        ["initial offset q(0) - q_d(0) [rad]",
         ", ".join(_fmt(v) for v in ds["q0_offset"].values) if "q0_offset" in ds else "0"],
    ], align=["left", "left"])
    gains = _table(["joint", "wn [rad/s]", "zeta", "Kp [1/s\u00b2]", "Kv [1/s]",
                    "D_ii(q_d(0)) [kg m\u00b2]", "Kp_pd [N m/rad]", "Kv_pd [N m s/rad]"],
                   [[joints[j]] + [_fmt(ds[v].values[j], digits=4) for v in
                                   ("wn", "zeta", "Kp", "Kv", "inertia_scale", "Kp_pd", "Kv_pd")]
                    for j in range(n)], align="right")
    err_rows = []
    for c in names:
        for key, where in (("setpoints", "set points"), ("grid", "fine grid")):
            pk = ds[f"error_peak_{key}"].sel(controller=c).values
            rm = ds[f"error_rms_{key}"].sel(controller=c).values
            err_rows.append([c, where, "peak"] + [_fmt(v) for v in pk])
            err_rows.append([c, where, "RMS"] + [_fmt(v) for v in rm])
    q_u, tau_u = _joint_units(ds, "q"), _joint_units(ds, "tau")
    errors = _table(["controller", "sampled at", "figure"]
                    + [f"{j} [{u}]" for j, u in zip(joints, q_u)],
                    err_rows, align=["left", "left", "left"] + ["right"] * n)
    tau_diff = _table(["figure"] + [f"{j} [{u}]" for j, u in zip(joints, tau_u)], [],
                      align="right")

    def fmt_all(name, **sel):
        return [_fmt(v) for v in ds[name].sel(**sel).values]

    if "tau_difference_peak" in ds:
        tau_diff["rows"] = [["peak, fine grid"] + fmt_all("tau_difference_peak"),
                            ["RMS, fine grid"] + fmt_all("tau_difference_rms")]
        if "tau_difference_peak_setpoints" in ds:
            tau_diff["rows"] += [["peak, set points"] + fmt_all("tau_difference_peak_setpoints"),
                                 ["RMS, set points"] + fmt_all("tau_difference_rms_setpoints")]
    tau_rows = []
    for c in names:
        if "tau_peak" in ds:
            tau_rows.append([c, "peak |tau|"] + fmt_all("tau_peak", controller=c))
            tau_rows.append([c, "RMS tau"] + fmt_all("tau_rms", controller=c))
    tau_table = _table(["controller", "figure"] + [f"{j} [{u}]" for j, u in zip(joints, tau_u)],
                       tau_rows,
                       align=["left", "left"] + ["right"] * n)
    cost = None
    if "evaluator" in ds.dims:
        ev = _strings(ds["evaluator"].values)
        mul, add = ds["multiplications"].values, ds["additions"].values
        ref = len(ev) - 1            # the last: Newton-Euler, the recursive reference
        cost = _table(["evaluator", "multiplications", "additions", "operations",
                       "operations vs Newton-Euler"],
                      [[e, str(int(mul[k])), str(int(add[k])), str(int(mul[k] + add[k])),
                        f"{(mul[k] + add[k]) / (mul[ref] + add[ref]):.3f}"]
                       for k, e in enumerate(ev)], align="right")
    what = str(ds.attrs.get("cost_parts_what", "")) or \
        "translational/rotational parts of D and h"
    recursive = what.startswith("(base parameter")
    cost_note = ("Operations per set point, counted (not timed): the emitted models on their "
                 "expressions (constants and structural 0/±1 free, a square one "
                 "multiplication), the project's Newton-Euler on its counting scalar "
                 "(gd_analyze.formulations.opcount). The simplified model drops "
                 f"{_attr(ds, 'cost_dropped_parts')} of {_attr(ds, 'cost_parts')} {what}.")
    model_note = (
        "The simplified model is the customized recursive Newton-Euler model on the base "
        "parameters; it keeps every element of D and h and drops these (base parameter, part) "
        "pairs: " + (str(ds.attrs.get("model_dropped_pairs", "")) or "none (exact)") + "."
        if recursive else
        "Part of each element of D (i \u2264 j, mirrored) and h kept by the simplified model, "
        "which keeps the terms of c its rule keeps.")
    labels = _strings(ds["element"].values)
    choice = dict(zip(labels, _strings(ds["choice"].values)))
    rows = [[f"D, row {i + 1}"] + [choice.get(element_label("D", i, j), "") if j >= i else ""
                                   for j in range(n)] for i in range(n)]
    rows.append(["h"] + [choice.get(element_label("h", j), "") for j in range(n)])
    choices = None if recursive else _table(["element"] + [f"column {j + 1}"
                                                          for j in range(n)], rows,
                                           align=["left"] * (n + 1))
    prov = _table(["attribute", "value"], [[k, _attr(ds, k)] for k in (
        "gd_analyze_version", "history", "robot", "robot_source", "robot_sha256",
        "trajectory_file", "trajectory_path", "trajectory_sha256", "trajectory_derivatives",
        "model_file", "model_path", "model_sha256", "model_trajectory_sha256",
        "trajectory_is_models", "gains", "references", "Conventions")],
        align=["left", "left"])
    floor = ("Integrator noise (at most the integrator's rtol times the joint's scale) is not "
             "drawn: a log axis starts at that floor.")
    return {
        "version": __version__,
        "created": utc_now().isoformat(),
        "title": f"Computed-torque control with the simplified G-D model: {_attr(ds, 'robot')}",
        "summary": summary, "verdict": verdict,
        "intro": ("The arm, simulated with its full generalized d'Alembert dynamics (Fu, Gonzalez "
                  "& Lee 1987, Eq. 3.4-24), tracks the trajectory under computed-torque control "
                  "(Ch. 5) with the full model, with the simplified model of Sec. 3.4.1, and "
                  "under PD control with gravity compensation."),
        "setup": setup, "gains": gains,
        "gains_note": ("Computed torque: v = qdd_d + Kv (qd_d - qd) + Kp (q_d - q), "
                       "Kp = wn\u00b2, Kv = 2 zeta wn, so the full-model closed loop is "
                       "e'' + Kv e' + Kp e = 0. PD + gravity: tau = Kp_pd e + Kv_pd ed + c, "
                       "gains scaled by the diagonal of D at the start of the motion."),
        "errors": errors,
        "error_note": ("Tracking error e = q_d - q per joint, peak |e| and RMS, at the set "
                       "points of the trajectory and on the fine grid (set points included)."),
        "floor_note": floor,
        "tau_diff": tau_diff,
        "diff_note": ("Closed-loop torque difference: torque of the simplified-model "
                      "computed-torque controller minus that of the full-model one, each along "
                      "its own closed-loop run, at the same times. It is not the open-loop "
                      "error of the main report (\u03c4\u209b \u2212 \u03c4 of the two models "
                      "along the desired trajectory)."),
        "tau_table": tau_table,
        "cost": cost, "cost_note": cost_note,
        "choices": choices, "model_note": model_note, "provenance": prov,
        "keywords": (f"robot {_attr(ds, 'robot')} sha256 {_attr(ds, 'robot_sha256')}; "
                     f"trajectory {_attr(ds, 'trajectory_file')} sha256 "
                     f"{_attr(ds, 'trajectory_sha256')}; model {_attr(ds, 'model_file')} sha256 "
                     f"{_attr(ds, 'model_sha256')}"),
    }


#: The simplified model "holds" if its peak tracking error is within this [rad] or within twice
#: the full model's.
VERDICT_TOLERANCE = 1e-3


def _verdict(worst, ds):
    """One sentence: does the simplified model control the arm as well as the full one?"""
    full, simp = worst.get("full"), worst.get("simplified")
    if full is None or simp is None:
        return "Verdict: not available (the run lacks the full or the simplified controller)."
    pd = worst.get("pd_gravity")
    bound = max(2.0 * full, VERDICT_TOLERANCE)
    tail = ""
    if "tau_difference_peak" in ds:
        tail = (f"; its closed-loop torque differs from the full-model controller's (two "
                f"closed-loop runs) by at most "
                f"{_fmt(float(ds['tau_difference_peak'].max()))} N m")
    pd_text = f", PD + gravity {_fmt(pd)} rad" if pd is not None else ""
    if simp <= bound:
        head = ("Verdict: the simplified model is good enough for computed-torque control "
                "along this trajectory")
    elif pd is not None and simp < pd:
        head = ("Verdict: the simplified model degrades tracking beyond the tolerance, though "
                "it still beats PD + gravity")
    else:
        head = "Verdict: the simplified model is NOT good enough for computed-torque control"
    return (f"{head}: peak tracking error {_fmt(simp)} rad against {_fmt(full)} rad with the "
            f"full model{pd_text} (tolerance: {_fmt(bound)} rad, the larger of "
            f"{VERDICT_TOLERANCE:g} rad and twice the full model's){tail}.")


# --------------------------------------------------------------------------------------------
# HTML and PDF
# --------------------------------------------------------------------------------------------

def render_control_html(ds, figures=None):
    """Render the control report as one self-contained HTML document.

    Parameters
    ----------
    ds : xarray.Dataset
        A stored control dataset.
    figures : dict of str to matplotlib.figure.Figure, optional
        :func:`make_control_figures` of it; made here if not given.

    Returns
    -------
    str
        The HTML: inline CSS, figures as inline SVG, no external resources (Jinja2 template
        ``templates/control_report.html.j2``, autoescape on).

    Raises
    ------
    InputError
        If the dataset lacks a variable of a control dataset.
    """
    _check(ds, "<dataset>")
    ctx = _context(ds)
    if figures is None:
        figures = make_control_figures(ds)
    return _html(ctx, {k: (figure_svg(f, _RC), None, None) for k, f in figures.items()})


_CAPTIONS = {
    "error": "Tracking error |q_d \u2212 q| per joint along the run, log scale (markers: set "
             "points, at most 12 per line). Integrator noise, at most the integrator's rtol "
             "times the joint's range of motion, is not drawn: the axis starts there, and a "
             "controller whose error is all noise is named above the panels.",
    "tau_difference": "Closed-loop torque difference: torque of the simplified-model "
                      "controller minus torque of the full-model controller, each along its "
                      "own closed-loop run, per joint (markers: set points); a joint whose "
                      "difference is integrator noise (at most rtol times the full "
                      "controller's peak |\u03c4|) reads so instead of a curve.",
    "tau": "Torques applied by the three controllers, per joint.",
}
_FIGURE_FILES = {"error": "fig_control_tracking_error",
                 "tau_difference": "fig_control_torque_difference",
                 "tau": "fig_control_applied_torque"}
#: Each figure also 3.5 in wide, as ``figures/<name>_column.pdf`` and ``.svg`` (not in the
#: report).
_FIGURE_FILES.update({f"{k}_column": f"{v}_column" for k, v in list(_FIGURE_FILES.items())})


def _numbered(figures):
    return {k: f"Figure {m + 1}. {_CAPTIONS[k]}" for m, k in enumerate(figures)}


def _html(ctx, drawn):
    from markupsafe import Markup

    svgs = {k: Markup(svg) for k, (svg, _, _) in drawn.items()}
    return render_template("control_report.html.j2", {**ctx, "figures": svgs,
                                                      "captions": _numbered(drawn)})


def render_control_pdf(ds, path, figures=None, paper="a4"):
    """Write the control report as a PDF document.

    Parameters
    ----------
    ds : xarray.Dataset
        A stored control dataset.
    path : str or os.PathLike
        The PDF to write (not atomically; :func:`write_control_report` passes a temporary
        name).
    figures : dict of str to matplotlib.figure.Figure, optional
        :func:`make_control_figures` of it; made here if not given.
    paper : {"a4", "letter"}, optional
        The size of every page.

    Returns
    -------
    int
        Number of pages written.

    Raises
    ------
    InputError
        If the dataset lacks a variable of a control dataset.
    OSError
        If the file cannot be written.
    """
    _check(ds, "<dataset>")
    ctx = _context(ds)
    if figures is None:
        figures = make_control_figures(ds)
    return _pdf(ctx, draw_figures(figures, _RC), path, paper)


def _pdf(ctx, drawn, path, paper="a4"):
    metadata = {"Author": f"gd-analyze {ctx['version']}",
                "Subject": "Computed-torque control with the simplified G-D model (Fu, Gonzalez "
                           "& Lee 1987, Sec. 3.4.1 and Ch. 5)",
                "Keywords": ctx["keywords"], "Creator": f"gd-analyze {ctx['version']}"}
    doc = Document(ctx["title"], paper=paper, metadata=metadata,
                   footer=f"gd-analyze {ctx['version']}: control report")

    def fig(key):
        if key in drawn:
            doc.figure(drawn[key][1], drawn[key][2], _CAPTIONS[key])

    doc.heading(ctx["title"], level=0)
    doc.paragraph(ctx["verdict"], size=9.5, bold=True)
    doc.paragraph(ctx["summary"], size=9)
    doc.paragraph(ctx["intro"] + f" Report created {ctx['created']} by gd-analyze "
                  f"{ctx['version']} from the stored control dataset; nothing was recomputed.",
                  size=8.5, colour="0.25")
    doc.heading("1. Set-up and gains")
    doc.table(ctx["setup"])
    doc.paragraph(ctx["gains_note"], size=8.5)
    doc.table(ctx["gains"])
    doc.heading("2. Tracking error")
    doc.paragraph(ctx["error_note"], size=8.5)
    doc.table(ctx["errors"], size=7)
    fig("error")
    doc.heading("3. Torques")
    doc.paragraph(ctx["diff_note"], size=8.5)
    doc.table(ctx["tau_diff"])
    fig("tau_difference")
    doc.table(ctx["tau_table"], size=7)
    fig("tau")
    doc.heading("4. Evaluation cost of the model")
    doc.paragraph(ctx["cost_note"], size=8.5)
    if ctx["cost"]:
        doc.table(ctx["cost"])
    else:
        doc.paragraph("Not measured.", size=8.5)
    doc.heading("5. Simplified model")
    doc.paragraph(ctx["model_note"], size=8.5)
    if ctx["choices"]:
        doc.table(ctx["choices"])
    doc.heading("6. Provenance")
    doc.table(ctx["provenance"], size=7)
    return doc.write(path)


def write_control_report(control_path, outdir, paper="a4", fonts="type3"):
    """Write control_report.html and control_report.pdf for a stored control dataset.

    Parameters
    ----------
    control_path : str or os.PathLike
        A control dataset written by :func:`gd_analyze.io.control_dataset.write_control_dataset`
        (``control.h5``). Only read: nothing is recomputed.
    outdir : str or os.PathLike
        Output folder; made if missing.
    paper : {"a4", "letter"}, optional
        Page size of the PDF.
    fonts : {"type3", "truetype"}, optional
        How the figures' PDFs embed their font
        (:data:`gd_analyze.reports.pages.FIGURE_FONTS`).

    Returns
    -------
    list of pathlib.Path
        ``outdir/control_report.html`` and ``outdir/control_report.pdf``, then every figure as
        ``outdir/figures/fig_control_*.pdf`` and ``.svg``.

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
    from ..files import atomic_path
    from ..io.schema import open_results

    if paper not in PAPER:
        raise ValueError(f"paper must be one of {sorted(PAPER)}, got {paper!r}")
    ds = open_results(str(control_path))
    _check(ds, control_path)
    ctx = _context(ds)
    outdir = Path(outdir)
    (outdir / "figures").mkdir(parents=True, exist_ok=True)
    with no_gc():
        figures = make_control_figures(ds)
        column = control_figures(ds, COLUMN_WIDTH)
        drawn = draw_figures({**figures, **{f"{k}_column": f for k, f in column.items()}}, _RC,
                             fonts=fonts)
    html_path, pdf_path = (outdir / name for name in CONTROL_REPORT_FILES)
    files = []
    with contextlib.ExitStack() as stack:
        files = write_figure_files(stack, drawn, outdir / "figures", _FIGURE_FILES)
        drawn = {k: drawn[k] for k in figures}          # the report shows the page versions
        Path(stack.enter_context(atomic_path(html_path))).write_text(_html(ctx, drawn),
                                                                     encoding="utf-8")
        _pdf(ctx, drawn, stack.enter_context(atomic_path(pdf_path)), paper)
    return [html_path, pdf_path] + files
