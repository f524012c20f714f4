"""Drawing the reports' figures: once, as SVG, for the HTML, the PDF and the figure files.

:func:`draw_figures` renders each matplotlib figure a single time, as SVG (text kept as text,
``svg.fonttype`` "none"); Typst turns that SVG into each figure's PDF file
(:func:`gd_analyze.report.typeset.figure_pdfs`), as it embeds it in the PDF reports, so every
PDF sets the figures' text in a TrueType subset of DejaVu Sans and none holds a Type 3 font.
:func:`write_figure_files` writes them to ``OUTDIR/figures/``.
"""

from __future__ import annotations

import contextlib
import io
import re
from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Any

from ..files import atomic_path
from .figure_style import raise_small_text, text_extent
from .typeset import MIN_PRINTED_PT, figure_pdfs, printed_scale

if TYPE_CHECKING:
    from matplotlib.figure import Figure

__all__ = ["figure_svg", "svg_size", "draw_figures", "write_figure_files"]


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
    cid = fig.canvas.mpl_connect("draw_event", lambda e: extent.append(text_extent(fig, e.renderer)))
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
