"""Report: the stored analysis as one self-contained HTML file and a PDF.

The report reads a results file written by :func:`gd_analyze.jobs.analyze.analyze_to_file` and never
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
sheet is inline. ``report.pdf`` is typeset by Typst from the same section list, the figures
embedded from their SVG (:mod:`gd_analyze.report.typeset`), both from one outline
(:func:`main_outline`). Both are written atomically (:func:`gd_analyze.files.atomic_path`).

Long trajectories are drawn from series read in chunks and reduced, past
:data:`ENVELOPE_THRESHOLD` points, to their min/max envelope
(:func:`gd_analyze.report.main_figures.plot_data`), one pair per pixel column of the panel at
300 dpi and at most :data:`ENVELOPE_COLUMNS` columns, without markers, so
the figures, and the HTML, stay small whatever the number of set points (about 0.7 MB of HTML
for 100,000 set points of a 6-joint arm).
"""

from __future__ import annotations

import functools
import os
from collections.abc import Callable, Collection, Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

from ..store.results_view import Results
from ..store.schema import open_results
from .common import CLASS_COLOURS as _CLASS_COLOURS
from .common import check_formats, prismatic_joints, say
from .drawing import draw_each, svg_size, write_report_files
from .main_context import report_context, zero_mask
from .main_figures import (
    COLUMN_WIDTH,
    ENVELOPE_COLUMNS,
    ENVELOPE_THRESHOLD,
    PAGE_WIDTH,
    d_panels,
    d_size,
    element_parts,
    fig_D,
    fig_h,
    fig_joints,
    fig_torque,
    part_rows,
    payload_figure,
    plot_data,
)
from .main_figures import RC as FIG_RC
from .markup import code
from .numbers import decade_formatter, scaled_formatter
from .sections import Outline
from .simplified_section import budget_makers, error_figure
from .typeset import body_height, check_paper, figure_rooms, printed_width

if TYPE_CHECKING:
    import xarray as xr
    from matplotlib.figure import Figure

    from .main_figures import PlotData

__all__ = ["main_outline", "REPORT_FORMATS", "ENVELOPE_THRESHOLD",
           "ENVELOPE_COLUMNS", "FIGURE_FILES", "COLUMN_FIGURES", "FIGURE_PARTS",
           "make_figures", "figure_makers", "write_report"]


def main_outline(ctx: Mapping[str, Any], figures: Collection[str]) -> Outline:
    """The main report's sections.

    Parameters
    ----------
    ctx : dict
        :func:`gd_analyze.report.main_context.report_context` of the dataset.
    figures : collection of str
        The keys of the drawn figures (:data:`gd_analyze.report.main.FIGURE_FILES`).

    Returns
    -------
    Outline
        Title block, then Secs. 1 to 8: Sec. 6, the comparison with the chapter, only for
        the chapter's PUMA 560 (the payload sweep is 6.1 there, else Sec. 6; the later
        sections move up when neither is there).

    Notes
    -----
    Source of the sections: Sec. 3.4.1, Figs. 3.10-3.11 and Table 3.5 of Fu, Gonzalez & Lee
    (1987).
    """
    caps = ctx["captions"]
    o = Outline(ctx["title"], figures, [(ctx["summary"], "summary"), (ctx["facts"], "body"),
                                        (ctx["intro"], "note")])

    o.section("1", "Robot and trajectory", "robot")
    o.section("1.1", "Robot")
    o.table(ctx["robot_kv"], "The robot.", kv=True)
    if ctx["dh"] is not None:
        prismatic = any(row[1].startswith("q") for row in ctx["dh"]["rows"])
        o.table(ctx["dh"], say("main_outline", key="dh", prismatic=prismatic))
    if ctx.get("placements") is not None:
        o.table(ctx["placements"], say("main_outline", key="placements"))
    o.table(ctx["link"], say("main_outline", key="link"))
    if ctx.get("drives"):
        o.paragraph(ctx["drives"]["note"], "note")
        o.table(ctx["drives"]["table"], "The drives: armature and friction per joint.")
    o.section("1.2", "Trajectory")
    o.table(ctx["traj_kv"], "The trajectory.", kv=True)
    o.table(ctx["joints"], "Range of motion per joint.")
    if ctx.get("effort"):
        o.paragraph(ctx["effort_text"], "note")
        o.table(ctx["effort"], say("main_outline", key="effort"))
    o.paragraph(ctx["envelope_note"], "note")
    o.figure("joints", caps["joints"])

    o.section("2", "Acceleration-related elements of D (analogue of Fig. 3.10)", "D")
    o.paragraph(ctx["D_text"], "note")
    o.figure("D", caps["D"])
    for part in range(2, _MOST_PARTS + 1):      # the panels that did not fit on one page
        o.figure(f"D_{part}", f"{caps['D']} (Part {part}.)")
    o.section("3", "Coriolis and centrifugal elements of h (analogue of Fig. 3.11)", "h")
    o.figure("h", caps["h"])

    o.section("4", "Dominance ranking", "ranking")
    o.paragraph(say("ranking_text", s=ctx["s"], e=ctx["e"], arm=bool(ctx.get("armature"))),
                "note")
    o.counts(ctx["counts"])
    o.table(ctx["ranking"], say("main_outline", key="ranking"))

    o.section("5", "Simplified model and torque error", "simplified")
    o.paragraph(ctx["simplified_intro"], "note")
    o.figure("contributions", say("budget_caption", key="contributions"))
    o.section("5.1", "Torque error along the trajectory")
    o.table(ctx["error"], say("main_outline", key="error"))
    o.figure("torque", caps["torque"])
    o.section(*ctx["choices_heading"].split(" ", 1))
    o.paragraph(ctx.get("choices_note", ""), "note")
    o.table(ctx["choices"], say("main_outline", key="base_parameters" if ctx["choices"][
        "header"][0] == "base parameter" else "choices"))
    sm = ctx.get("simplified_model")
    if sm:
        o.section(*ctx["model_heading"].split(" ", 1))
        o.paragraph(sm["text"], "note")
        o.paragraph(sm["screen_note"], "note")
        o.table(sm["bound"], say("main_outline", key="bound"))
        if sm.get("region"):
            o.paragraph(sm["region_text"], "note")
            o.table(sm["region"], say("main_outline", key="region"))
        o.figure("budget", caps.get("budget", say("budget_caption", key="budget")))
        if sm["costs"]:
            o.section("5.4", "Cost per set point (counted)")
            o.table(sm["costs"], "Operations per set point, counted on each model's code.")
            o.paragraph(sm["form_note"], "note")
            o.figure("cost_ladder", say("budget_caption", key="cost_ladder"))
        if sm["ladder"] or sm["ladder_note"]:
            o.section(*sm["ladder_heading"].split(" ", 1))
            if sm["ladder"]:
                o.table(sm["ladder"], say("main_outline", key="ladder"))
            else:
                o.paragraph(sm["ladder_note"], "note")
        o.paragraph("Emitted source files: " + ", ".join(code(f) for f in sm["files"])
                    + say("main_outline", key="files", prefix=sm["prefix"]), "note")

    compare = ctx["compare"]
    top = 6                                  # the chapter comparison only for its PUMA 560
    if compare["applicable"]:
        o.section("6", "Comparison with the chapter's PUMA 560", "chapter")
        for sentence in compare["conclusions"]:
            o.paragraph(sentence)
        o.paragraph(compare["note"], "note")
        o.paragraph(say("main_outline", key="agreement", n_agree=compare["n_agree"],
                        n_compared=compare["n_compared"]), "strong")
        o.table(compare["table"], say("main_outline", key="chapter"))
    payload = ctx["payload"]
    if payload["applicable"]:
        o.section(f"{top}.1" if compare["applicable"] else str(top),
                  "Dominance against the payload", "payload", level=1)
        o.paragraph(payload["note"], "note")
        if payload["table"]["rows"]:
            o.table(payload["table"], "Elements whose class changes with the payload.")
        o.figure("payload", caps["payload"])
    top += compare["applicable"] or payload["applicable"]

    forms = ctx["formulations"]
    o.section(str(top), "Formulations: Lagrange-Euler, Newton-Euler, G-D", "formulations")
    o.paragraph(forms["note"], "note")
    if forms["applicable"]:
        o.section(f"{top}.1", "Largest relative disagreement per pair")
        o.table(forms["agreement"], say("main_outline", key="disagreement"))
        o.section(f"{top}.2", "Operations per set point")
        if forms["costs"]["rows"]:       # none where the counts stop short of the arm's n
            o.table(forms["costs"], say("main_outline", key="operations"))
        o.figure("formulations", caps["formulations"])

    o.section(str(top + 1), "Provenance", "provenance")
    o.table(ctx["provenance"], say("main_outline", key="provenance"), kv=True, size=7)
    return o


#: The formats :func:`write_report` can write.
REPORT_FORMATS = ("html", "pdf")


# --------------------------------------------------------------------------------------------
# Figures
# --------------------------------------------------------------------------------------------

#: File names (without extension) of the figures in ``OUTDIR/figures/``, by figure key.
FIGURE_FILES = {"joints": "fig_joints_q_qd_qdd", "D": "fig_3_10_D", "h": "fig_3_11_h",
                "torque": "fig_torque_full_vs_simplified", "payload": "fig_payload_dominance",
                "formulations": "fig_table_3_5_operation_counts",
                "contributions": "fig_torque_contributions", "budget": "fig_error_budget",
                "cost_ladder": "fig_cost_ladder"}
#: Further parts of the D and h figures when their panels fill more than a page
#: (:func:`gd_analyze.report.main_figures.element_parts`): ``D_2`` is
#: ``fig_3_10_D_part2``, ...
#: ``fig_3_10_D_part2``, ...: up to :data:`_MOST_PARTS` parts of D (a 15-joint arm's 120
#: panels, a first part of two rows under the text citing it: seven), five of h.
_MOST_PARTS = 12
_D_PARTS = tuple(f"D_{p}" for p in range(2, _MOST_PARTS + 1))
_D_GROUP = ("D", *_D_PARTS)
FIGURE_PARTS = _D_PARTS + tuple(f"h_{p}" for p in range(2, 6))
FIGURE_FILES.update({k: f"{FIGURE_FILES[k[0]]}_part{k[2:]}" for k in FIGURE_PARTS})
_FIGURE_ORDER = ("joints", "D", *_D_PARTS, "h", *FIGURE_PARTS[len(_D_PARTS):], "contributions",
                 "torque", "budget", "cost_ladder", "payload", "formulations")
#: Figures also made 3.5 in wide for a one-column layout when asked for
#: (``--column-figures``), as ``<key>_column``, written to ``figures/<name>_column.pdf`` and
#: ``.svg`` beside the page-width files (not in the report).
COLUMN_FIGURES = ("joints", "D", "h", "contributions", "torque", "budget", "cost_ladder",
                  "payload", "formulations")
FIGURE_FILES.update({f"{k}_column": f"{FIGURE_FILES[k]}_column" for k in COLUMN_FIGURES})
_FILE_ORDER = _FIGURE_ORDER + tuple(f"{k}_column" for k in COLUMN_FIGURES)


def make_figures(ds: Results | xr.Dataset, data: PlotData | None = None,
                 keys: Collection[str] | None = None, column: bool = False) -> dict[str, Figure]:
    """Make the report's figures from a stored analysis.

    Parameters
    ----------
    ds : Results or xarray.Dataset
        The results view (:class:`gd_analyze.store.results_view.Results`) or a dataset as
        :func:`gd_analyze.store.datasets.with_setpoints` makes it (N set points, n joints):
        t (N,) [s]; q, qd, qdd (N, n) [rad, rad/s, rad/s^2]; D_tran, D_rot, D (N, n, n)
        [kg m^2]; h_tran, h_rot, h, c, tau, tau_simplified (N, n) [N m]; the ranking (M,).
    data : PlotData, optional
        The series to draw (:func:`gd_analyze.report.main_figures.plot_data`); read from
        ``ds`` if not given.
    keys : collection of str, optional
        Make only these of the figures below (those the dataset holds), column-width ones
        included if named; all page-width ones if not given.
    column : bool, optional
        Also make the 3.5-in column-width versions (``"<key>_column"``) of
        :data:`COLUMN_FIGURES`.

    Returns
    -------
    dict of str to matplotlib.figure.Figure
        ``"joints"``, ``"D"`` (analogue of Fig. 3.10, with ``"D_2"``, ... if its panels fill
        more than a page), ``"h"`` (Fig. 3.11), ``"contributions"``, ``"torque"``,
        ``"budget"`` and ``"cost_ladder"`` (of a model that drops terms),  and ``"payload"``
        and ``"formulations"`` if the dataset holds them; sized for print (7.2 in wide,
        type >= 7 pt), time [s] on x. Plain figures with matplotlib's own ticks, free to be
        restyled (the report draws its ticks once, :func:`write_report`).

    Raises
    ------
    KeyError
        If a variable the figures need is missing from ``ds``.

    Notes
    -----
    All the figures at once, as :func:`figure_makers` makes them one by one.
    Source: Sec. 3.4.1 and Figs. 3.10-3.11 of Fu, Gonzalez & Lee (1987).
    """
    return {k: make() for k, make in figure_makers(ds, data, keys, column).items()}


def figure_makers(ds: Results | xr.Dataset, data: PlotData | None = None,
                  keys: Collection[str] | None = None, column: bool = False,
                  first_rows: int | None = None,
                  rows: Sequence[int] | None = None) -> dict[str, Callable[[], Figure]]:
    """The report's figures as makers, in file order: each figure made when it is called.

    A caller that draws each figure as soon as it is made (:func:`_write`) holds one figure
    at a time, not all of them (fewer live objects for the garbage collector to walk).

    Parameters
    ----------
    ds, data, keys, column
        As for :func:`make_figures`.
    first_rows, rows : int, optional
        Rows of panels of the first part of the D figure, when its panels go in parts (the
        rows that fit under the text citing it), and of each later part (those a page holds):
        :func:`gd_analyze.report.main_figures.element_parts`.

    Returns
    -------
    dict of str to callable
        By figure key (:data:`FIGURE_FILES`), a function of no arguments returning that
        figure (:class:`matplotlib.figure.Figure`), made with the report's rcParams.

    Raises
    ------
    KeyError
        As :func:`make_figures`: a variable the figures need is missing.

    Notes
    -----
    The figures of Sec. 3.4.1, Figs. 3.10-3.11 (Fu, Gonzalez & Lee 1987), and the report's.
    """

    results = Results.of(ds)
    ds = results.dataset
    if data is None:
        data = plot_data(ds)
    labels, marks = zero_mask(results)          # the marks stored at analysis
    zero = dict(zip(labels, marks))
    dom = {r.label: r.dominance for r in results.ranking.rows}
    s, e = results.dominance_threshold, results.negligible_threshold
    order = _FILE_ORDER if column or keys is not None else _FIGURE_ORDER   # keys: as named
    wanted = set(order if keys is None else keys)
    arm = results.robot_record.armature
    prismatic = prismatic_joints(results)
    D = functools.partial(fig_D, data, dom, zero, s, e, prismatic, armature=arm,
                          first_rows=first_rows, rows=rows)
    page: dict[str, Callable[..., Figure]] = {
        "joints": functools.partial(fig_joints, data, prismatic), "D": D,
        "h": functools.partial(fig_h, data, dom, zero, prismatic),
        "torque": functools.partial(_fig_error, results, data)}
    if results.payload is not None:
        page["payload"] = functools.partial(payload_figure, results.payload)
    if results.formulations is not None:
        page["formulations"] = functools.partial(_fig_formulations, results.formulations)
    makers = {**page, **{f"{k}_column": functools.partial(make, width=COLUMN_WIDTH,
                                                          **({"first_rows": None} if k == "D"
                                                             else {}))
                         for k, make in page.items()}}
    d_labels = [p[0] for p in d_panels(data, dom, zero, prismatic, arm)[0]]
    for k in range(1, len(element_parts(d_labels, first_rows=first_rows, rows=rows))):
        makers[f"D_{k + 1}"] = functools.partial(D, part=k)
    makers.update(budget_makers(results, data))
    return {k: functools.partial(_made, makers[k]) for k in order
            if k in makers and k in wanted}


def _made(make):
    """One figure made with the report's rcParams."""
    import matplotlib

    with matplotlib.rc_context(FIG_RC):
        return make()


def _fig_error(results, data, width=PAGE_WIDTH):
    if results.simplified is not None:          # tau_s - tau and its bound
        return error_figure(results.simplified, width, data=data)
    errors = results.torque_error
    return fig_torque(data, errors.column("relative_peak"), prismatic_joints(results))



_FORMULATION_STYLE = {"lagrange-euler": ("L-E", "#0072B2", "o", "-"),
                      "newton-euler": ("N-E", "#D55E00", "s", "-"),
                      "gd": ("G-D", "#6A3D9A", "^", "-")}


def _fig_formulations(counted, width=PAGE_WIDTH):
    from matplotlib.figure import Figure
    from matplotlib.ticker import FixedLocator, LogLocator, NullFormatter


    n, names = counted.dof, counted.names
    column = width < PAGE_WIDTH             # the two panels one above the other
    W, H = (width, 5.0) if column else (PAGE_WIDTH, 2.9)
    fig = Figure(figsize=(W, H))
    for k, op in enumerate(("multiplications", "additions")):
        box = ((0.65, (0.95 + (1 - k) * 2.05), W - 0.8, 1.6) if column else
               (0.65 + k * 3.55, 0.75, 2.85, H - 1.0))        # x, y from the bottom, w, h [in]
        ax = fig.add_axes((box[0] / W, box[1] / H, box[2] / W, box[3] / H))
        ax.set_yscale("log")
        ops = (getattr(counted, op), getattr(counted, f"{op}_table_3_5"))   # counted, the book's
        for name, (short, colour, marker, ls) in _FORMULATION_STYLE.items():
            if name not in names:
                continue
            j = names.index(name)
            ax.plot(n, ops[0][:, j], color=colour, marker=marker,
                    markersize=3.5, linestyle=ls, linewidth=1.0,
                    label=f"{short} as implemented")
            ax.plot(n, ops[1][:, j], color=colour,
                    linestyle="--", linewidth=0.9, label=f"{short} Table 3.5")
        # joints counted one by one on x; decades with unlabelled 2x and 5x marks on y (few
        # Tick objects: each costs an Axes draw)
        ax.xaxis.set_major_locator(FixedLocator(n))
        ax.yaxis.set_minor_locator(LogLocator(subs=(2.0, 5.0)))
        for axis in (ax.xaxis, ax.yaxis):       # plain labels: no mathtext to parse
            axis.set_major_formatter(scaled_formatter() if axis is ax.xaxis
                                     else decade_formatter())      # 10⁶, not 1e6
            axis.set_minor_formatter(NullFormatter())
        ax.set_title(f"{op} per set point")
        ax.set_xlabel("number of joints n", labelpad=1.0)
        ax.set_ylabel(op, labelpad=1.0)
        ax.grid(True, which="major", linewidth=0.3)
    fig.legend(*fig.axes[0].get_legend_handles_labels(), loc="lower center",
               ncol=2 if column else 3, frameon=False, bbox_to_anchor=(0.5, 0.0),
               fontsize=7 if column else None)
    return fig


# --------------------------------------------------------------------------------------------
# Entry point
# --------------------------------------------------------------------------------------------

def write_report(results: Results | str | os.PathLike[str], outdir: str | os.PathLike[str],
                 formats: Sequence[str] = REPORT_FORMATS, paper: str = "a4",
                 progress: Callable[[int], object] | None = None, column_figures: bool = False,
                 latex: bool = False) -> list[Path]:
    """Write report.html and/or report.pdf, and every figure as PDF and SVG, for an analysis.

    Parameters
    ----------
    results : Results, str or os.PathLike
        The analysis in memory, typed (:class:`gd_analyze.store.results_view.Results`, with the
        per-set-point series: the main job's own result), or a results file written by
        :func:`gd_analyze.jobs.analyze.analyze_to_file`, only read (long series in
        chunks). The dynamics are never recomputed.
    outdir : str or os.PathLike
        Output folder; made if missing.
    formats : sequence of str, optional
        Any of ``"html"`` and ``"pdf"``.
    paper : {"a4", "letter"}, optional
        Page size of the PDF.
    progress : callable, optional
        Called with a number of set points read (for a progress bar).
    column_figures : bool, optional
        Also write the 3.5-in column-width figures (:data:`COLUMN_FIGURES`,
        ``figures/<name>_column.pdf`` and ``.svg``).
    latex : bool, optional
        Also write every table as LaTeX, ``tables/table_<section>_<k>.tex``.

    Returns
    -------
    list of pathlib.Path
        The files written: ``outdir/report.html``, ``outdir/report.pdf`` (in the order of
        ``formats``), then ``outdir/figures/<name>.pdf`` and ``.svg`` per figure
        (:data:`FIGURE_FILES`), then every table of the report as
        ``outdir/tables/table_<section>_<k>.csv`` (and ``.tex`` with ``latex``:
        :func:`gd_analyze.report.drawing.table_files`).

    Raises
    ------
    InputError
        If the results file is missing, unreadable or not a gd-analyze dataset.
    ValueError
        If a format is not one of :data:`REPORT_FORMATS`, none is given, or the paper is
        unknown.
    OSError
        If a file cannot be written.

    Notes
    -----
    Each figure is drawn once as SVG: inlined in the HTML, embedded in the PDF report and written to
    ``figures/``, with its PDF typeset from it by Typst. Every file is written to a
    temporary name beside its destination and renamed (:func:`gd_analyze.files.atomic_path`).
    Source: Sec. 3.4.1 and Figs. 3.10-3.11 of Fu, Gonzalez & Lee (1987).
    """
    formats = check_formats(formats, REPORT_FORMATS)
    check_paper(paper)
    if isinstance(results, Results):                        # in memory: nothing read again
        return _write(results, Path(outdir), formats, paper, progress, column_figures, latex)
    with open_results(results, lazy=True) as ds:            # long series: in chunks
        return _write(Results.from_dataset(ds, source=str(results)), Path(outdir), formats,
                      paper, progress, column_figures, latex)


def _write(results, outdir, formats, paper, progress, column=False, latex=False):
    ctx = report_context(results)       # fails early on a dataset that is not ours
    data = plot_data(results.dataset, progress=progress)
    # one figure alive at a time, each typeset as PDF while the next is drawn
    makers = figure_makers(results, data, column=column)
    fit = "pdf" in formats and "D_2" in makers      # D's parts drawn last, fitted first
    drawn = draw_each({k: m for k, m in makers.items() if not fit or k not in _D_GROUP},
                      FIG_RC, ctx["created"])
    if fit:
        drawn.update(draw_each(_fit_first_part(results, data, ctx, makers, drawn, paper),
                               FIG_RC, ctx["created"]))
        drawn = {k: drawn[k] for k in _FILE_ORDER if k in drawn}
    return write_report_files(
        outdir, ctx, drawn, FIGURE_FILES, main_outline, "report.html.j2",
        "Translational and rotational dominance of the generalized d'Alembert dynamics (Fu, "
        "Gonzalez & Lee 1987, Sec. 3.4.1, Figs. 3.10-3.11)",
        f"{ctx['robot_name']}, {ctx['N']:,} set points",
        env_globals={"class_colours": _CLASS_COLOURS}, created=ctx["created"],
        formats=formats, paper=paper, latex=latex, shown=_FIGURE_ORDER)


#: Height of Sec. 3's heading and of the caption of its figure [in], beside the figure.
_AFTER_H = 1.2


def _fit_first_part(results, data, ctx, makers, drawn, paper):
    """The makers of the D figure's parts: drawn with rows that fill their pages
    (:func:`gd_analyze.report.main_figures.part_rows`) if as set its first part goes to the
    next page's top for want of room under the text citing it, as set otherwise.

    The room is measured with every other figure ``drawn`` and each D part a blank of its
    planned size (:func:`gd_analyze.report.main_figures.d_size`): the size of its drawing
    unless text sticks out of it (:func:`gd_analyze.report.drawing.figure_svg`)."""
    zero = dict(zip(*zero_mask(results)))
    prismatic, arm = prismatic_joints(results), results.robot_record.armature
    planned = {k: d_size(data, {}, zero, results.dominance_threshold,
                         results.negligible_threshold, prismatic, armature=arm, part=p)
               for p, k in enumerate(k for k in makers if k in _D_GROUP)}
    shown = [k for k in _FIGURE_ORDER if k in drawn or k in planned]
    room, need = figure_rooms(main_outline(ctx, shown), {
        k: _blank_svg(planned[k]) if k in planned else (drawn[k][0], drawn[k][2])
        for k in shown}, paper).get("D", (0.0, 0.0))
    size = planned["D"]
    panels = d_panels(data, {}, zero, prismatic, arm)[0]
    h = drawn["h"][2] if "h" in drawn else None     # what follows: Sec. 3's heading, Fig. 3
    rows = None if need <= 0.0 else part_rows(
        len(panels), room, need, printed_width(size, paper) / size[0], body_height(paper),
        0.0 if h is None else h[1] * printed_width(h, paper) / h[0] + _AFTER_H)
    if rows is None:
        return {k: m for k, m in makers.items() if k in planned}
    return figure_makers(results, data, keys=_D_GROUP, first_rows=rows[0], rows=rows[1])


def _blank_svg(size):
    """An empty SVG of a size [in] as matplotlib writes a figure's (in pt), and its size."""
    w, h = (f"{72.0 * v:f}".rstrip("0").rstrip(".") for v in size)
    svg = f'<svg xmlns="http://www.w3.org/2000/svg" width="{w}pt" height="{h}pt" viewBox="0 0 {w} {h}"></svg>'
    return svg, svg_size(svg)
