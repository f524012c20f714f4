"""Drawing the reports' figures: once, for both the HTML (SVG) and the PDF, and as files.

:func:`draw_figures` renders each matplotlib figure a single time into both formats (a tee of
the renderer); :func:`write_figure_files` writes them to ``OUTDIR/figures/``. The PDF reports
(:mod:`gd_analyze.reports.typeset`) embed the SVG of each figure.
"""

from __future__ import annotations

import io

__all__ = ["FIGURE_FONTS", "PAGE_RC", "figure_pdf", "figure_svg", "draw_figures",
           "write_figure_files"]

#: matplotlib settings of every figure's PDF file (``figures/*.pdf``): DejaVu Sans (the font
#: type is set by :data:`FIGURE_FONTS`).
PAGE_RC = {"pdf.fonttype": 3, "font.family": "DejaVu Sans", "path.simplify": True}
#: How the figures' PDF files embed their font, by name: ``type3`` (glyphs as drawings: fast,
#: the default) or ``truetype`` (a TrueType subset, Type 42: what journals that refuse Type 3
#: fonts, e.g. IEEE PDF eXpress, ask for; each figure takes about 0.15 s more). The reports'
#: PDFs embed the figures' SVG, whose text is set in a TrueType subset either way.
FIGURE_FONTS = {"type3": 3, "truetype": 42}


def _save(fig, fmt, rc, metadata):
    import matplotlib

    buf = io.BytesIO()
    with matplotlib.rc_context(rc or {}):
        fig.savefig(buf, format=fmt, metadata=metadata)
    return buf.getvalue()


def figure_pdf(fig, rc=None):
    """A figure as the bytes of a one-page PDF, without date metadata.

    Parameters
    ----------
    fig : matplotlib.figure.Figure
        The figure.
    rc : dict, optional
        rcParams to draw with.

    Returns
    -------
    bytes
    """
    return _save(fig, "pdf", rc, {"CreationDate": None, "Creator": None, "Producer": None})


def figure_svg(fig, rc=None):
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
    text = _save(fig, "svg", rc, {"Date": None, "Creator": None, "Format": None,
                                  "Type": None}).decode("utf-8")
    start = text.find("<svg")
    return text[start:] if start >= 0 else text


def draw_figures(figures, rc, svg=True, pdf=True, fonts="type3"):
    """Draw each figure once, into SVG and PDF at the same time.

    Parameters
    ----------
    figures : dict of str to matplotlib.figure.Figure
        The figures by key.
    rc : dict
        rcParams to draw with (the PDF adds :data:`PAGE_RC`: Type 3 fonts).
    svg, pdf : bool, optional
        Which formats to make.
    fonts : {"type3", "truetype"}, optional
        How the PDFs embed their font (:data:`FIGURE_FONTS`).

    Returns
    -------
    dict of str to (str or None, bytes or None, (float, float))
        SVG text, PDF bytes and size [in] of each figure.

    Notes
    -----
    With both formats, one traversal of the figure (layout, ticks, transforms, text metrics)
    feeds an SVG and a PDF renderer together (:func:`_draw_both`); only the writing of the two
    files is done twice. Should that fail on some matplotlib version, each format is drawn on
    its own as :meth:`matplotlib.figure.Figure.savefig` does.

    Raises
    ------
    ValueError
        If ``fonts`` is not one of :data:`FIGURE_FONTS`.
    """
    if fonts not in FIGURE_FONTS:
        raise ValueError(f"fonts must be one of {sorted(FIGURE_FONTS)}, got {fonts!r}")
    pdf_rc = {**rc, **PAGE_RC, "pdf.fonttype": FIGURE_FONTS[fonts]}
    out = {}
    for k, f in figures.items():
        size = tuple(float(v) for v in f.get_size_inches())
        if svg and pdf:
            try:
                out[k] = (*_draw_both(f, pdf_rc), size)
                continue
            except Exception:           # noqa: BLE001 - any failure: the two-pass way below
                pass
        out[k] = (figure_svg(f, rc) if svg else None,
                  figure_pdf(f, pdf_rc) if pdf else None, size)
    return out


class _TeeGC:
    """A graphics context that sets its properties on the SVG and the PDF renderer's own."""

    def __init__(self, a, b):
        self._pair = (a, b)

    def __getattr__(self, name):
        a, b = self._pair
        first = getattr(a, name)
        if not callable(first):
            return first
        second = getattr(b, name)

        def both(*args, **kwargs):
            result = first(*_side(args, 0), **_side_kw(kwargs, 0))
            second(*_side(args, 1), **_side_kw(kwargs, 1))
            return result
        return both


def _side(args, k):
    return [a._pair[k] if isinstance(a, _TeeGC) else a for a in args]


def _side_kw(kwargs, k):
    return {n: (v._pair[k] if isinstance(v, _TeeGC) else v) for n, v in kwargs.items()}


class _TeeRenderer:
    """Forwards every drawing call to two renderers; answers queries from the first."""

    _QUERIES = {"get_text_width_height_descent", "points_to_pixels", "get_canvas_width_height",
                "flipy", "option_image_nocomposite", "option_scale_image",
                "get_image_magnification", "get_texmanager"}

    def __init__(self, a, b):
        self._pair = (a, b)

    def new_gc(self):
        return _TeeGC(self._pair[0].new_gc(), self._pair[1].new_gc())

    def draw_text(self, gc, x, y, s, prop, angle, ismath=False, mtext=None):
        a, b = self._pair
        a.draw_text(gc._pair[0], x, y, s, prop, angle, ismath=ismath, mtext=mtext)
        if a.flipy() != b.flipy():          # Text placed y for the first renderer's origin
            y = b.get_canvas_width_height()[1] - y
        b.draw_text(gc._pair[1], x, y, s, prop, angle, ismath=ismath, mtext=mtext)

    def __getattr__(self, name):
        a, b = self._pair
        first = getattr(a, name)
        if not callable(first) or name in self._QUERIES:
            return first
        second = getattr(b, name)

        def both(*args, **kwargs):
            result = first(*_side(args, 0), **_side_kw(kwargs, 0))
            second(*_side(args, 1), **_side_kw(kwargs, 1))
            return result
        return both


def _draw_both(fig, rc):
    """One traversal of ``fig`` into a PDF renderer and an SVG renderer: (svg text, pdf
    bytes), as :meth:`~matplotlib.figure.Figure.savefig` writes them (points, 72 per in)."""
    import matplotlib
    from matplotlib.backends.backend_pdf import PdfFile, RendererPdf
    from matplotlib.backends.backend_svg import RendererSVG

    pdf_buf, svg_buf = io.BytesIO(), io.StringIO()
    dpi = fig.dpi
    with matplotlib.rc_context(rc):
        fig.dpi = 72                        # as savefig draws a vector format
        pdf_file = PdfFile(pdf_buf, metadata={"CreationDate": None, "Creator": None,
                                              "Producer": None})
        try:
            w, h = fig.get_size_inches()
            pdf_file.newPage(w, h)
            r_pdf = RendererPdf(pdf_file, dpi, h, w)
            r_svg = RendererSVG(w * 72, h * 72, svg_buf, image_dpi=dpi,
                                metadata={"Date": None, "Creator": None, "Format": None,
                                          "Type": None})
            fig.draw(_TeeRenderer(r_pdf, r_svg))
            r_pdf.finalize()
            r_svg.finalize()
            pdf_file.finalize()
        finally:
            pdf_file.close()
            fig.dpi = dpi
    text = svg_buf.getvalue()
    start = text.find("<svg")
    return (text[start:] if start >= 0 else text), pdf_buf.getvalue()


def write_figure_files(stack, drawn, folder, names):
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
    from ..files import atomic_path

    folder.mkdir(parents=True, exist_ok=True)
    files = []
    for key, (svg_text, pdf_bytes, _) in drawn.items():
        for ext, data in (("pdf", pdf_bytes), ("svg", svg_text.encode("utf-8"))):
            dest = folder / f"{names[key]}.{ext}"
            with open(stack.enter_context(atomic_path(dest)), "wb") as fh:
                fh.write(data)
            files.append(dest)
    return files
