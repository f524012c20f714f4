"""Drawing the reports' figures once, as SVG, and writing a report's files from them: the
figure files, the HTML and the PDF documents and the tables.

:func:`draw_figures` renders each matplotlib figure a single time, as SVG (text kept as text,
``svg.fonttype`` "none"); Typst turns that SVG into each figure's PDF file
(:func:`gd_analyze.report.typeset.figure_pdfs`), as it embeds it in the PDF reports, so every
PDF sets the figures' text in a TrueType subset of DejaVu Sans and none holds a Type 3 font.
:func:`write_figure_files` writes them to ``OUTDIR/figures/``; :func:`write_documents` writes
every file of a report, staged together.
"""

from __future__ import annotations

import contextlib
import io
import re
from collections.abc import Callable, Collection, Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

from ..files import atomic_path
from .common import render_template
from .figure_style import raise_small_text, text_extent
from .table_export import write_tables
from .typeset import MIN_PRINTED_PT, figure_pdfs, printed_scale, write_pdf

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from .sections import Outline

__all__ = ["figure_svg", "svg_size", "draw_figures", "write_figure_files", "prefix_ids", "html_document",
           "write_documents"]

#: A drawn figure: its SVG text, its PDF (None if not typeset) and its size [in].
Drawn = tuple[str, bytes | None, tuple[float, float]]


def figure_svg(fig: Figure, rc: Mapping[str, Any] | None = None) -> str:
    """A figure as SVG text, without XML declaration, DOCTYPE or date metadata.

    Parameters
    ----------
    fig : matplotlib.figure.Figure
        The figure.
    rc : dict, optional
        rcParams to draw with.

    Returns
    -------
    str
        Starts with ``<svg``: fit to be a file of its own and to be inlined in HTML.
    """
    import matplotlib

    meta = {"Date": None, "Creator": None, "Format": None, "Type": None}
    extent = []         # measured on the drawing itself: its text laid out once

    def measure(event: Any) -> None:    # a DrawEvent (typed as a bare Event by some versions)
        extent.append(text_extent(fig, event.renderer))

    cid = fig.canvas.mpl_connect("draw_event", measure)
    buf = io.BytesIO()
    with matplotlib.rc_context(rc or {}):  # type: ignore[arg-type]  # keys typed as literals
        # every text at least MIN_PRINTED_PT where the PDF report prints the figure smallest
        raise_small_text(fig, MIN_PRINTED_PT / printed_scale(tuple(fig.get_size_inches())))
        try:
            fig.savefig(buf, format="svg", metadata=meta)
        finally:
            fig.canvas.mpl_disconnect(cid)
        if extent[0].height > fig.bbox_inches.height:   # text sticks out: drawn again, taller
            buf = io.BytesIO()
            fig.savefig(buf, format="svg", bbox_inches=extent[0], metadata=meta)
    text = buf.getvalue().decode("utf-8")
    start = text.find("<svg")
    return text[start:] if start >= 0 else text


def svg_size(svg: str) -> tuple[float, float]:
    """The width and height [in] of an SVG written by matplotlib (sizes in pt).

    Parameters
    ----------
    svg : str
        Starts with the ``<svg`` element.

    Returns
    -------
    (float, float)
    """
    head = svg[:svg.index(">")]
    w, h = (float(re.search(rf'\b{a}="([0-9.]+)pt"', head).group(1)) / 72.0  # type: ignore[union-attr]
            for a in ("width", "height"))
    return w, h


def draw_figures(figures: Mapping[str, Figure], rc: Mapping[str, Any], pdf: bool = True,
                 created: str | None = None) -> dict[str, tuple[str, bytes | None, tuple[float, float]]]:
    """Draw each figure once, as SVG, and (if asked) typeset its PDF from that SVG.

    Parameters
    ----------
    figures : dict of str to matplotlib.figure.Figure
        The figures by key.
    rc : dict
        rcParams to draw with.
    pdf : bool, optional
        Also make each figure's PDF (:func:`gd_analyze.report.typeset.figure_pdfs`).
    created : str, optional
        The PDFs' creation time, ISO 8601 UTC (the report's); the time of the run if not given.

    Returns
    -------
    dict of str to (str, bytes or None, (float, float))
        SVG text, PDF bytes (None without ``pdf``) and size [in] of each figure.

    Raises
    ------
    RuntimeError
        If Typst cannot typeset a figure's SVG.

    Notes
    -----
    One drawing per figure (layout, ticks, text): the PDF is the SVG typeset, so the figure
    files, the HTML and the PDF report show the same drawing.
    """
    out = {k: (svg, svg_size(svg)) for k, svg in ((k, figure_svg(f, rc))
                                                   for k, f in figures.items())}
    pdfs = figure_pdfs(out, created) if pdf else {}
    return {k: (svg, pdfs.get(k), size) for k, (svg, size) in out.items()}


def write_figure_files(stack: contextlib.ExitStack,
                       drawn: Mapping[str, tuple[str, bytes | None, tuple[float, float]]],
                       folder: Path, names: Mapping[str, str]) -> list[Path]:
    """Write every drawn figure as ``folder/<name>.pdf`` and ``.svg``, staged.

    Parameters
    ----------
    stack : contextlib.ExitStack
        The files are renamed into place when it closes without an exception
        (:func:`gd_analyze.files.atomic_path`).
    drawn : dict
        From :func:`draw_figures`.
    folder : pathlib.Path
        The figures' folder (made if missing).
    names : dict of str to str
        File name without extension, by figure key.

    Returns
    -------
    list of pathlib.Path
        The files, PDF then SVG of each figure in turn.
    """

    folder.mkdir(parents=True, exist_ok=True)
    files = []
    for key, (svg_text, pdf_bytes, _) in drawn.items():
        assert pdf_bytes is not None            # drawn with pdf=True
        for ext, data in (("pdf", pdf_bytes), ("svg", svg_text.encode("utf-8"))):
            dest = folder / f"{names[key]}.{ext}"
            with open(stack.enter_context(atomic_path(dest)), "wb") as fh:
                fh.write(data)
            files.append(dest)
    return files


def prefix_ids(svg: str, prefix: str) -> str:
    """An SVG with ``prefix-`` put before every id and every reference to one, so that several
    figures share one HTML document without clashing ids.

    Parameters
    ----------
    svg : str
        The SVG text (:func:`figure_svg`).
    prefix : str
        E.g. ``"fig-D"``.

    Returns
    -------
    str
    """
    text = re.sub(r'\bid="', f'id="{prefix}-', svg)
    text = re.sub(r'\bhref="#', f'href="#{prefix}-', text)
    return re.sub(r"url\(#", f"url(#{prefix}-", text)


def html_document(template: str, context: Mapping[str, Any], outline: Outline,
                  drawn: Mapping[str, Drawn], env_globals: Mapping[str, Any] | None = None
                  ) -> str:
    """A report as one HTML document, its figures inline SVG.

    Parameters
    ----------
    template : str
        The Jinja2 template (:func:`gd_analyze.report.common.render_template`).
    context : dict
        The template's variables; ``figures`` and ``outline`` are added.
    outline : gd_analyze.report.sections.Outline
        The report's sections.
    drawn : dict
        The figures the report shows (:func:`draw_figures`).
    env_globals : dict, optional
        Globals of the template's environment.

    Returns
    -------
    str
        The document; the ids of figure ``k`` start with ``fig-k-`` so that no two figures'
        ids clash.
    """
    from markupsafe import Markup

    figures = {k: Markup(prefix_ids(svg, f"fig-{k}")) for k, (svg, _, _) in drawn.items()}
    return render_template(template, {**context, "figures": figures, "outline": outline},
                           env_globals)


def write_documents(folder: Path, drawn: Mapping[str, Drawn], names: Mapping[str, str],
                    outline: Callable[[Collection[str]], Outline], html: Callable[..., str],
                    pdf: Mapping[str, Any], formats: Sequence[str] = ("html", "pdf"),
                    stem: str = "report", paper: str = "a4", latex: bool = False,
                    prefix: str = "", shown: Sequence[str] | None = None) -> list[Path]:
    """Write a report's files, staged together: every figure, the documents, every table.

    Parameters
    ----------
    folder : pathlib.Path
        The output folder: ``figures/`` and ``tables/`` are made in it.
    drawn : dict
        Every figure drawn (:func:`draw_figures`), the column-width files' too.
    names : dict of str to str
        File name of each figure (:func:`write_figure_files`).
    outline : callable
        The report's sections from the keys of the figures it shows.
    html : callable
        ``html(outline, drawn)``: the HTML document (:func:`html_document`).
    pdf : dict
        ``metadata``, ``footer`` and ``created`` of :func:`gd_analyze.report.typeset.write_pdf`.
    formats : sequence of {"html", "pdf"}, optional
        The documents, ``folder/<stem>.<format>``, in this order.
    stem : str, optional
        The documents' file name.
    paper : {"a4", "letter"}, optional
        The PDF's page size.
    latex, prefix
        As for :func:`gd_analyze.report.table_export.write_tables`.
    shown : sequence of str, optional
        The figures the report shows, in order; those of ``drawn`` not ending in ``_column``
        if not given.

    Returns
    -------
    list of pathlib.Path
        The documents, then the figures' files, then the tables' files.

    Raises
    ------
    OSError
        If a file cannot be written: then none is (:func:`gd_analyze.files.atomic_path`).
    """
    if shown is None:
        shown = [k for k in drawn if not k.endswith("_column")]
    with contextlib.ExitStack() as stack:
        files = write_figure_files(stack, drawn, folder / "figures", names)
        drawn = {k: drawn[k] for k in shown if k in drawn}
        sections = outline(drawn)
        docs = [folder / f"{stem}.{fmt}" for fmt in formats]
        for path in docs:
            tmp = stack.enter_context(atomic_path(path))
            if path.suffix == ".html":
                Path(tmp).write_text(html(sections, drawn), encoding="utf-8")
            else:
                write_pdf(sections, {k: (d[0], d[2]) for k, d in drawn.items()}, tmp, paper,
                          **pdf)
        tables = write_tables(stack, sections, folder / "tables", latex, prefix)
    return docs + files + tables
