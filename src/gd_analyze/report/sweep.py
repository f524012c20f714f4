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
   of every element vs payload (:func:`gd_analyze.report.figures.payload_figure`).

``sweep_report.html`` has no external resources (inline SVG figures, inline style sheet; the
Jinja2 template is ``templates/sweep_report.html.j2``). ``sweep_report.pdf`` is typeset by
Typst from the same section list (:mod:`gd_analyze.report.typeset`). Both are written atomically (:func:`gd_analyze.files.atomic_path`).
"""


from __future__ import annotations

import functools
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING

from ..ranking.ranking import ROUND_OFF
from ..store.schema import open_sweep
from ..store.sweep_view import PayloadSweep, StoredSweep
from . import markup
from .common import CLASS_COLOURS as _CLASS_COLOURS
from .common import SUPTITLE_RC as _RC
from .common import check_formats
from .drawing import draw_figures, html_document, write_documents
from .numbers import decade_label
from .sections import Outline
from .sweep_figures import make_sweep_figures
from .sweep_text import SHARE_TEXT, SWEEP_CAPTIONS
from .sweep_text import sweep_context as _context
from .typeset import PAPER, TABLE_COLOURS

if TYPE_CHECKING:                       # for the type hints only
    import os

    import xarray as xr

#: The round-off threshold as the text writes it (10⁻¹², not the code-like 1e-12).
_TINY = decade_label(ROUND_OFF)

__all__ = ["SWEEP_REPORT_FORMATS", "write_sweep_report"]

#: The formats :func:`write_sweep_report` can write.
SWEEP_REPORT_FORMATS = ("html", "pdf")


# --------------------------------------------------------------------------------------------
# HTML and PDF
# --------------------------------------------------------------------------------------------

def _cites(o, ctx, key):
    """The sentence citing the outline ``o``'s next figure, ``key`` ("Fig. 2 shows ..."), or
    "" if that figure was not drawn."""
    if key not in o.available:
        return ""
    return f"Fig. {o.n_figures + 1} {ctx['figure_text'][key]}"


def _outline(ctx, figures):
    """The sweep report's sections, once, for the HTML and the PDF
    (:class:`gd_analyze.report.sections.Outline`): each figure right under the paragraph
    citing it ("Fig. 2 shows ..."), its table after it; Sec. 5.1's table, which its paragraph
    describes first, comes before its figure."""
    o = Outline(ctx["title"], figures)
    o.paragraph(ctx["worst"], "lead")
    o.paragraph(ctx["summary"], "summary")
    o.paragraph(ctx["intro"], "note")
    o.section("1", "Settings and provenance", "settings")
    o.table(ctx["settings"], "Settings of the sweep and its provenance, each once.", kv=True,
            size=7)
    o.section("2", "Translational share of the elements of D (layout of Fig. 3.10)", "D")
    o.paragraph(SHARE_TEXT.format(s=ctx["s"], e=ctx["e"]) + " " + _cites(o, ctx, "D"), "note")
    o.figure("D", ctx["captions"]["D"])
    o.section("3", "Translational share of the elements of h (layout of Fig. 3.11)", "h")
    o.paragraph(_cites(o, ctx, "h"), "note")
    o.figure("h", ctx["captions"]["h"])
    o.section("4", "Envelope per element", "envelope")
    o.paragraph("Fraction of the trajectories in which each class holds, and the smallest, "
                "median and largest translational share over the trajectories (Table 4.1). "
                + ctx["captions"]["none"] + " " + _cites(o, ctx, "classes"), "note")
    o.figure("classes", ctx["captions"]["classes"])
    o.table(ctx["envelope"], "Fraction of the trajectories per class, the range of the "
                             "translational share, and the merged model's choice. A share is "
                             "0 or 1 where one part is round-off (at most "
                             f"{_TINY} of the element's scale or 64 \u03b5 of the arm's); "
                             "\u2261 0: the element is round-off on every trajectory, it has no "
                             "share.")
    number, title = ctx["merged_heading"].split(" ", 1)
    o.section(number.rstrip("."), title, "merged")
    o.paragraph(ctx["merged_text"], "note")
    o.counts(ctx["counts"])
    o.section("5.1", "Open-loop torque error over all trajectories")
    o.paragraph(ctx["error_text"] + " " + _cites(o, ctx, "error"), "note")
    o.table(ctx["error"], "Open-loop torque error of the merged model per joint, over all set points "
                          "of all trajectories; \u2261 0: round-off (at most "
                          f"{_TINY} of the joint's peak |\u03c4| or of the arm's), not data.")
    o.figure("error", ctx["captions"]["error"])
    if ctx["cost"] is not None:
        o.section("5.2", "Evaluation cost of the merged model")
        o.table(ctx["cost"], "Operations per set point of the merged model, the exact "
                             "recursive model, the full explicit model and the project's "
                             "Newton-Euler, counted on their code (not timed).")
    if ctx["payload"] is not None:
        o.section("6", "Payload sweep", "payload")
        o.table(ctx["payload"]["settings"], "Settings of the payload sweep.", kv=True)
        o.paragraph("Elements whose class changes with the payload: "
                    f"{ctx['payload']['changed']}. " + _cites(o, ctx, "payload"), "strong")
        o.figure("payload", SWEEP_CAPTIONS["payload"])
        o.table(ctx["payload"]["table"], "Class of each element per payload mass.")
    return o


def _html(ctx):
    return lambda outline, drawn: html_document(
        "sweep_report.html.j2", ctx, outline, drawn,
        {"class_colours": _CLASS_COLOURS, "pruned_colour": TABLE_COLOURS["pruned"]})


_FIGURE_FILES = {"D": "fig_sweep_share_D", "h": "fig_sweep_share_h",
                 "classes": "fig_sweep_class_fractions", "error": "fig_sweep_torque_error",
                 "payload": "fig_payload_dominance"}
#: Column-width (3.5 in) versions: ``figures/<name>_column.pdf`` and ``.svg`` (not in the
#: report).
_FIGURE_FILES.update({f"{k}_column": f"{_FIGURE_FILES[k]}_column"
                      for k in ("D", "h", "classes", "error", "payload")})


#: The settings of the sweep whose values are the PDF's keywords: its provenance.
_KEYWORD_ROWS = ("robot file", "dominance threshold s, negligibility threshold e",
                 "SHA-256 of all inputs", "merge rule")


def _keywords(ctx):
    """The provenance in the PDF's document information: the inputs' SHA-256 and the
    settings, from the settings table (one fact in one place)."""
    rows = dict((markup.plain(k), markup.plain(v)) for k, v in ctx["settings"]["rows"])
    return "; ".join(["G-D dominance sweep", f"gd-analyze {ctx['version']}"]
                     + [f"{k}: {rows[k]}" for k in _KEYWORD_ROWS if k in rows])


def write_sweep_report(sweep_path: str | os.PathLike[str], outdir: str | os.PathLike[str],
                       payload: str | os.PathLike[str] | xr.Dataset | None = None,
                       formats: Sequence[str] = SWEEP_REPORT_FORMATS,
                       paper: str = "a4", latex: bool = False) -> list[Path]:
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
        :func:`~gd_analyze.report.figures.payload_figure`.
    formats : sequence of str, optional
        Any of ``"html"`` and ``"pdf"``.
    paper : {"a4", "letter"}, optional
        Page size of the PDF.
    latex : bool, optional
        Also write every table as LaTeX, ``outdir/tables/sweep_table_<section>_<k>.tex``.

    Returns
    -------
    list of pathlib.Path
        The files written (``outdir/sweep_report.html``, ``outdir/sweep_report.pdf``), then
        every figure as ``outdir/figures/fig_sweep_*.pdf`` and ``.svg``, then every table of
        the report as ``outdir/tables/sweep_table_<section>_<k>.csv`` (and ``.tex`` with ``latex``:
        :func:`gd_analyze.report.table_export.table_files`).

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
    if paper not in PAPER:
        raise ValueError(f"paper must be one of {sorted(PAPER)}, got {paper!r}")
    if payload is not None and not hasattr(payload, "data_vars"):
        payload = open_sweep(payload, "payload")
    stored, part = _views(open_sweep(sweep_path, "sweep"), payload)  # type: ignore[arg-type]
    ctx = _context(stored, part)
    drawn = draw_figures(make_sweep_figures(stored, part, column=True), _RC)
    pdf = {"metadata": {"Author": f"gd-analyze {ctx['version']}",
                        "Subject": "Dominance of the translational and rotational G-D terms "
                                   "over a sweep of trajectories (Fu, Gonzalez & Lee 1987, "
                                   "Sec. 3.4.1)",
                        "Keywords": _keywords(ctx)},
           "footer": f"gd-analyze {ctx['version']}: {ctx['title']}"}
    return write_documents(Path(outdir), drawn, _FIGURE_FILES, functools.partial(_outline, ctx),
                           _html(ctx), pdf, formats, "sweep_report", paper, latex, "sweep")


def _views(ds, payload):
    """The typed views of a sweep and of its payload sweep (None without one), each read
    once."""
    return StoredSweep.of(ds), None if payload is None else PayloadSweep.of(payload)
