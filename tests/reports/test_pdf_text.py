"""Strings written straight into the PDF content stream (gd_analyze.reports.pdf_text)."""

import io

import pytest

from gd_analyze.reports.common import table
from gd_analyze.reports.pages import Document


def _text_pages(doc, fast):
    from gd_analyze.reports import pdf_text

    pages, _ = doc._layout()
    if fast:
        return doc._text_pages(pages)
    saved = pdf_text.PdfText.for_renderer
    pdf_text.PdfText.for_renderer = classmethod(lambda cls, renderer: None)
    try:
        return doc._text_pages(pages)
    finally:
        pdf_text.PdfText.for_renderer = saved


def test_direct_text_matches_matplotlibs_draw_text():
    """The text pages written straight into the content stream (PdfText) read back as the
    same text as matplotlib's own draw_text writes, and its widths agree with matplotlib's
    measure of each string (right-aligned cells end where they should)."""
    import matplotlib
    from matplotlib.backends.backend_pdf import PdfFile, RendererPdf
    from matplotlib.font_manager import FontProperties
    from pypdf import PdfReader

    from gd_analyze.reports import pdf_text
    from gd_analyze.reports.pages import PAGE_RC

    doc = Document("Direct text", metadata={"Author": "me"})
    doc.heading("1. Symbols \u03c4 \u2261 0, \u221a(D_ii D_jj), \u2212 0.25, kg m\u00b2")
    doc.paragraph("Translational share_tran = \u03a3|tran| / (\u03a3|tran| + \u03a3|rot|); "
                  "AVAT Wave, fi fl ff \u03b8 \u03c9 " * 8, bold=True)
    doc.table(table(["element", "class", "share"],
                    [[f"D{i}{j}", "translational", f"{0.1 * i * j:.3f}"]
                     for i in range(1, 7) for j in range(i, 7)], align=["left", "left",
                                                                         "right"]))
    fast, slow = _text_pages(doc, True), _text_pages(doc, False)
    with matplotlib.rc_context(PAGE_RC):
        available = pdf_text.PdfText.for_renderer(
            RendererPdf(PdfFile(io.BytesIO()), 72, 11, 8)) is not None
    if not available:
        # matplotlib < 3.11 has no interfaces for the direct path: the pages must then be
        # exactly matplotlib's own (the fallback), byte for byte
        assert fast == slow
        return
    assert fast != slow                     # the direct path was taken
    read = [[p.extract_text() for p in PdfReader(io.BytesIO(b)).pages] for b in (fast, slow)]
    assert read[0] == read[1]
    assert "\u221a(D_ii D_jj)" in read[0][0]
    # widths against matplotlib's own text measure
    with matplotlib.rc_context(PAGE_RC):
        renderer = RendererPdf(PdfFile(io.BytesIO()), 72, 11, 8)
        direct = pdf_text.PdfText.for_renderer(renderer)
        assert direct is not None
        for size, weight in ((7.5, "normal"), (9.0, "bold"), (13.0, "bold")):
            prop = FontProperties(family="DejaVu Sans", size=size, weight=weight)
            for s in ("0.125", "translational", "AVAT Wave", "\u03c4\u2081 [N m]",
                      "peak |\u03c4| 42.4 N m"):
                width = direct.layout(s, prop)[1]
                ref = renderer.get_text_width_height_descent(s, prop, ismath=False)[0]
                assert width == pytest.approx(ref, abs=0.02 * size), (s, size, weight)
