"""Identify report: the stored identification as one self-contained HTML file and a PDF.

:func:`write_identify_report` reads the datasets of ``identification.h5`` (the root group and
one group per recording, as ``read_identification`` of the identify command's
``gd_analyze.store.stored_identification`` returns them) and never recomputes a model: the measured against the
predicted torque per joint on each validation recording and the residuals (figures), the
errors per recording and joint beside the robot file's as shipped, the parameter table with
standard deviations in % and identifiability, the links' physical consistency, the
preprocessing steps as stated by the run, and the provenance.

``report.html`` has no external resources (inline CSS and SVG figures; the Jinja2 template of
the control report, ``templates/control_report.html.j2``, autoescape on); ``report.pdf`` is
typeset by Typst from the same section list (:mod:`gd_analyze.report.typeset`). Both, and
each figure as ``figures/fig_identify_*.pdf`` and ``.svg``, are written atomically
(:func:`gd_analyze.files.atomic_path`).
"""

from __future__ import annotations

import functools
import os
from collections.abc import Collection
from pathlib import Path
from typing import TYPE_CHECKING

from ..store.stored_identification import StoredIdentification
from .drawing import draw_figures, html_document, write_documents
from .identify_figures import FIGURE_RC, figure_key, identify_figures
from .identify_text import identify_context
from .sections import Outline
from .typeset import PAPER

if TYPE_CHECKING:
    import xarray as xr

__all__ = ["IDENTIFY_REPORT_FILES", "write_identify_report", "identify_outline"]

#: Names of the report files written into the output folder.
IDENTIFY_REPORT_FILES = ("report.html", "report.pdf")


def identify_outline(ctx: dict, figures: Collection[str]) -> Outline:
    """The report's sections, once, for the HTML and the PDF.

    Parameters
    ----------
    ctx : dict
        :func:`gd_analyze.report.identify_text.identify_context`.
    figures : collection of str
        The keys of the figures drawn.

    Returns
    -------
    Outline
    """
    o = Outline(ctx["title"], figures)
    o.paragraph(ctx["lead"], "lead")
    o.paragraph(ctx["summary"], "summary")
    o.paragraph(f"Report created by gd-analyze {ctx['version']} from the stored "
                "identification; no model was recomputed.", "note")
    o.section("1", "Torque errors", "errors")
    o.table(ctx["recordings"], "Total relative torque error ||E||_F / ||T||_F per recording: "
                               "the identified model beside the robot file as shipped.")
    for k, (name, table) in enumerate(ctx["joint_tables"].items()):
        o.table(table, f"Errors per joint on {ctx['files'][name]} ({ctx['roles'][name]}): "
                       "RMS of tau_measured - tau_predicted and ||tau_meas,i - tau_i|| / "
                       "||tau_meas,i||.", size=7)
    o.section("2", "Measured and predicted torque", "torque")
    o.paragraph(ctx["shown_note"], "note")
    for k, name in enumerate(ctx["shown"]):
        o.figure(figure_key("torque", k), f"Measured and predicted torque per joint on "
                                          f"{ctx['files'][name]} ({ctx['roles'][name]}).")
        o.figure(figure_key("residual", k), f"Residual, measured minus identified model, per "
                                            f"joint on {ctx['files'][name]}.")
    o.section("3", "Parameters", "parameters")
    o.paragraph(ctx["parameter_note"], "note")
    o.table(ctx["parameters"], "Identified parameters, standard deviations and "
                               "identifiability.", size=7)
    if ctx["links"] is not None:
        o.table(ctx["links"], "Physical consistency of each link's standard parameters: its "
                              "pseudo-inertia (Wensing, Kim & Slotine 2017) is positive "
                              "semidefinite.")
    if ctx["noise"] is not None:
        o.table(ctx["noise"], "Residual standard deviation per joint of the ordinary fit: "
                              "the weights of the weighted fit.")
    o.section("4", "Preprocessing", "preprocessing")
    for sentence in ctx["preprocessing"] or ["The run states no preprocessing."]:
        o.paragraph(sentence, "body")
    for name, notes in ctx["notes"].items():
        if notes:
            o.paragraph(f"{ctx['files'][name]}: " + " ".join(notes), "note")
    o.section("5", "Provenance", "provenance")
    o.table(ctx["provenance"], "Provenance: the files and settings of the run.", kv=True,
            size=7)
    return o


def write_identify_report(root: xr.Dataset, groups: dict[str, xr.Dataset],
                          folder: str | os.PathLike[str], paper: str = "a4",
                          latex: bool = False) -> list[Path]:
    """Write report.html, report.pdf and the figures of a stored identification.

    Parameters
    ----------
    root : xarray.Dataset
        The root group of ``identification.h5``: ``value`` and ``std`` over ``parameter``
        (required), and what :func:`gd_analyze.report.identify_text.identify_context` reads.
    groups : dict of str to xarray.Dataset
        One dataset per recording, by group name, in order: ``t`` [s], ``tau_measured`` and
        ``tau_predicted`` (t, joint) [N m or N] (required), the errors and the role.
    folder : str or os.PathLike
        The output folder (made if missing; the identify command's staged folder).
    paper : {"a4", "letter"}, optional
        Page size of the PDF.
    latex : bool, optional
        Also write every table as LaTeX, ``folder/tables/table_<section>_<k>.tex``.

    Returns
    -------
    list of pathlib.Path
        ``folder/report.html``, ``folder/report.pdf``, then each figure's
        ``folder/figures/fig_identify_<kind>_<k>.pdf`` and ``.svg`` (k: the recording's place
        among those shown, never its name), then every table of the report as
        ``folder/tables/table_<section>_<k>.csv`` (and ``.tex`` with ``latex``).

    Raises
    ------
    InputError
        If a required variable is missing.
    ValueError
        If ``paper`` is unknown.
    OSError
        If a file cannot be written.
    """

    if paper not in PAPER:
        raise ValueError(f"paper must be one of {sorted(PAPER)}, got {paper!r}")
    stored = StoredIdentification.from_dataset(root, groups)
    ctx = identify_context(stored)
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    drawn = draw_figures(identify_figures(stored), FIGURE_RC)
    pdf = {"metadata": {"Author": f"gd-analyze {ctx['version']}",
                        "Subject": "Identification of a robot's base parameters and drives "
                                   "from recorded torques",
                        "Keywords": ctx["keywords"]},
           "footer": f"gd-analyze {ctx['version']}: identify report"}
    html = {"title": ctx["title"], "version": ctx["version"]}
    return write_documents(
        folder, drawn, {k: f"fig_identify_{k}" for k in drawn},
        functools.partial(identify_outline, ctx),
        lambda o, d: html_document("control_report.html.j2", html, o, d), pdf, paper=paper,
        latex=latex)
