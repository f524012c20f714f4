"""The text pages of the PDF reports (gd_analyze.reports.text_pages)."""

import io

import pytest

from gd_analyze.reports.markup import END, SUB
from gd_analyze.reports.text_pages import draw_text_pages, text_width


def _matplotlib_width(s, size, bold=False):
    """Width [in] matplotlib measures for a string (glyph advances plus kerning)."""
    from matplotlib.font_manager import FontProperties
    from matplotlib.textpath import text_to_path

    prop = FontProperties(family="DejaVu Sans", size=size, weight="bold" if bold else "normal")
    return text_to_path.get_text_width_height_descent(s, prop, ismath=False)[0] / 72


@pytest.mark.parametrize("s", ["mmm", "min", "0.001857", "D12 tau", "||||"])
@pytest.mark.parametrize("bold", [False, True])
def test_width_is_the_glyph_advances_matplotlib_measures(s, bold):
    # strings without a kerning pair: matplotlib's width is the sum of the same advances
    assert text_width(s, 9.0, bold) == pytest.approx(_matplotlib_width(s, 9.0, bold), rel=2e-3)


def test_width_scales_with_the_size_and_adds_over_characters():
    assert text_width("abc", 18.0) == pytest.approx(2 * text_width("abc", 9.0), rel=1e-12)
    assert text_width("ab", 9.0) == pytest.approx(text_width("a", 9.0) + text_width("b", 9.0))
    assert text_width("a", 9.0, bold=True) > text_width("a", 9.0)
    assert text_width("", 9.0) == 0.0


def test_a_run_is_measured_at_its_smaller_size():
    from gd_analyze.reports.markup import RUN_SIZE

    s = f"D{SUB}12{END}"
    assert text_width(s, 10.0) == pytest.approx(text_width("D", 10.0)
                                                + text_width("12", 10.0 * RUN_SIZE))


def _fonts(pdf_bytes):
    from pypdf import PdfReader

    reader = PdfReader(io.BytesIO(pdf_bytes))
    subtypes = set()
    for page in reader.pages:
        for font in page["/Resources"].get("/Font", {}).values():
            font = font.get_object()
            subtypes.add(str(font["/Subtype"]))
            for d in font.get("/DescendantFonts", []):
                subtypes.add(str(d.get_object()["/Subtype"]))
    return reader, subtypes


def test_pages_hold_their_text_in_an_embedded_truetype_subset():
    page = [("rect", 0.5, 1.0, 7.0, 0.2, 0.94),
            ("rule", 0.5, 7.5, 1.3, 0.8),
            ("text", 0.5, 1.0, "τₛ − τ ≡ 0 at joint 3 [N]", 9.0, "black", False, False),
            ("text", 7.5, 1.0, "right", 9.0, "#0072B2", True, True),
            ("text", 0.5, 2.0, f"D{SUB}12{END} in kg m²", 9.0, "0.4", False, False)]
    pdf = draw_text_pages([page, page[:2]], (8.27, 11.69), "A title")
    reader, subtypes = _fonts(pdf)
    assert len(reader.pages) == 2
    assert {round(float(v), 1) for v in reader.pages[0].mediabox[2:]} == {595.4, 841.7}
    assert "/Type3" not in subtypes and "/CIDFontType2" in subtypes
    text = reader.pages[0].extract_text()
    for piece in ("τₛ − τ ≡ 0 at joint 3 [N]", "right", "kg m²", "12"):
        assert piece in text, (piece, text)
