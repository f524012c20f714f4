"""Control report: the stored closed-loop comparison as one self-contained HTML file and a PDF.

:func:`write_control_report` reads a control dataset written by
:func:`gd_analyze.store.control_dataset.write_control_dataset` (``control.h5``) and never recomputes anything:
every number and curve comes from the dataset's variables and global attributes. The report
holds the set-up and gains, the tracking error per joint of the three controllers (figure and
peak/RMS table), the torque difference between the simplified-model and the full-model
computed-torque controllers, the applied torques, the evaluation cost of the simplified model
against the full one, the model's choices and the provenance.

``control_report.html`` has no external resources (inline CSS, inline SVG figures, Jinja2
template ``templates/control_report.html.j2``); ``control_report.pdf`` is typeset by
Typst from the same section list (:mod:`gd_analyze.report.typeset`). Both are written
atomically (:func:`gd_analyze.files.atomic_path`).
"""

from __future__ import annotations

import functools
from pathlib import Path
from typing import TYPE_CHECKING

from ..store.schema import open_results
from ..store.stored_control import REQUIRED_VARIABLES, StoredControl
from .control_figures import COLUMN_WIDTH, FIGURE_RC, control_figures
from .control_text import control_context as _context
from .control_verdict import VERDICT_TOLERANCE, control_verdict
from .drawing import draw_figures, html_document, write_documents
from .sections import Outline
from .typeset import PAPER

if TYPE_CHECKING:                       # for the type hints only
    import os


__all__ = ["CONTROL_REPORT_FILES", "REQUIRED_VARIABLES", "VERDICT_TOLERANCE", "control_verdict", "make_control_figures",
           "write_control_report"]

#: Names of the files written into the output folder.
CONTROL_REPORT_FILES = ("control_report.html", "control_report.pdf")


#: The report's figures (:func:`gd_analyze.report.control_figures.control_figures`).
make_control_figures = control_figures


_FIGURE_FILES = {"error": "fig_control_tracking_error",
                 "tau_difference": "fig_control_torque_difference",
                 "tau": "fig_control_applied_torque"}
#: Each figure also 3.5 in wide, as ``figures/<name>_column.pdf`` and ``.svg`` (not in the
#: report).
_FIGURE_FILES.update({f"{k}_column": f"{v}_column" for k, v in list(_FIGURE_FILES.items())})


def _next_figure(o):
    """"Fig. N": how the text cites the next figure of the outline ``o``."""
    return f"Fig. {o.n_figures + 1}"


def _outline(ctx, figures):
    """The control report's sections, once, for the HTML and the PDF
    (:class:`gd_analyze.report.sections.Outline`)."""
    o = Outline(ctx["title"], figures)
    o.paragraph(ctx["verdict"], "lead")
    o.paragraph(ctx["summary"], "summary")
    o.paragraph(ctx["intro"] + f" Report created {ctx['created']} by gd-analyze "
                f"{ctx['version']} from the stored control dataset; nothing was recomputed.",
                "note")
    o.section("1", "Set-up and gains", "setup")
    o.table(ctx["setup"], "The closed-loop run.", kv=True)
    o.paragraph(ctx["gains_note"], "note")
    o.table(ctx["gains"], "Gains per joint.")
    # each figure right under the sentence citing it, its table after it: a figure that does
    # not fit there goes to the next page's top, and the table fills this page
    o.section("2", "Tracking error", "tracking")
    o.paragraph(f"{ctx['error_note']}: along the run in {_next_figure(o)}, its peak |e| and "
                "RMS at the set points of the trajectory and on the fine grid (set points "
                "included) in Table 2.1.", "note")
    o.figure("error", ctx["captions"]["error"])
    o.table(ctx["errors"], "Tracking error per controller and joint; \u2261 0: integrator "
                           f"noise ({ctx['noise_rule']['q']}), not data.", size=7)
    o.section("3", "Torques", "torque")
    drawn = "tau_difference" in o.available
    o.paragraph(f"{ctx['diff_note']} ({_next_figure(o) + ', ' if drawn else ''}Table 3.1). "
                f"{ctx['diff_not']}", "note")
    if drawn:
        o.figure("tau_difference", ctx["captions"]["tau_difference"])
    else:
        o.paragraph("No torque difference stored.", "body")
    o.table(ctx["tau_diff"], "Closed-loop torque difference per joint, simplified-model "
                             "controller minus full-model controller; \u2261 0: integrator "
                             f"noise ({ctx['noise_rule']['tau']}), not data.")
    o.paragraph(f"Applied torques: the torque each controller applies along its own "
                f"closed-loop run in {_next_figure(o)}, its peak |\u03c4| and RMS per joint "
                "in Table 3.2.", "note")
    o.figure("tau", ctx["captions"]["tau"])
    o.table(ctx["tau_table"], "Applied torques per controller and joint.", size=7)
    o.section("4", "Evaluation cost of the model", "cost")
    o.paragraph(ctx["cost_note"], "note")
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
                         paper: str = "a4", latex: bool = False) -> list[Path]:
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

    Returns
    -------
    list of pathlib.Path
        ``outdir/control_report.html`` and ``outdir/control_report.pdf``, then every figure as
        ``outdir/figures/fig_control_*.pdf`` and ``.svg``, then every table of the report as
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
    if paper not in PAPER:
        raise ValueError(f"paper must be one of {sorted(PAPER)}, got {paper!r}")
    s = StoredControl.from_dataset(open_results(str(control_path)), str(control_path))
    ctx = _context(s)
    figures = make_control_figures(s)
    column = control_figures(s, COLUMN_WIDTH)
    drawn = draw_figures({**figures, **{f"{k}_column": f for k, f in column.items()}}, FIGURE_RC)
    pdf = {"metadata": {"Author": f"gd-analyze {ctx['version']}",
                        "Subject": "Computed-torque control with the simplified G-D model (Fu, "
                                   "Gonzalez & Lee 1987, Sec. 3.4.1 and Ch. 5)",
                        "Keywords": ctx["keywords"]},
           "footer": f"gd-analyze {ctx['version']}: control report"}
    return write_documents(
        Path(outdir), drawn, _FIGURE_FILES, functools.partial(_outline, ctx),
        lambda o, d: html_document("control_report.html.j2", ctx, o, d), pdf,
        stem="control_report", paper=paper, latex=latex, prefix="control")
