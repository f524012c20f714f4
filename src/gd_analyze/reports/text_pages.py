"""The text pages of the PDF reports, drawn with fpdf2: strings, rules and table shading.

The page engine (:mod:`gd_analyze.reports.pages`) lays a document out as a list of pages, each
a list of drawing operations; :func:`draw_text_pages` draws them, one PDF page each, in DejaVu
Sans (the font matplotlib ships and draws the figures in), embedded as a TrueType subset: no
Type 3 font, whatever the figures use. The figures are placed afterwards, with pypdf.

:func:`text_width` measures a string exactly as it is drawn here (the glyphs' advances, no
kerning), so that the engine's line breaks, right alignment and column widths agree with the
page.
"""

from __future__ import annotations

import functools

from .markup import RUN_SHIFT, RUN_SIZE, SUB, SUP, runs

__all__ = ["ASCENT", "draw_text_pages", "font_files", "text_width"]

#: Ascent of DejaVu Sans [em]: the distance from the top of a line to its baseline.
ASCENT = 0.928
_FAMILY = "dejavu"


def font_files():
    """The DejaVu Sans files drawn: regular and bold, from matplotlib's data folder.

    Returns
    -------
    dict of str to pathlib.Path
        ``""`` (regular) and ``"B"`` (bold), fpdf2's style names.

    Raises
    ------
    FileNotFoundError
        If matplotlib's data folder lacks them.
    """
    from pathlib import Path

    import matplotlib

    folder = Path(matplotlib.get_data_path()) / "fonts" / "ttf"
    files = {"": folder / "DejaVuSans.ttf", "B": folder / "DejaVuSans-Bold.ttf"}
    for path in files.values():
        if not path.is_file():
            raise FileNotFoundError(path)
    return files


@functools.cache
def _face(bold):
    """matplotlib's FreeType face of the regular or bold font, and its units per em."""
    from matplotlib.ft2font import FT2Font

    font = FT2Font(str(font_files()["B" if bold else ""]))
    return font, font.units_per_EM


@functools.cache
def _advance(char, bold):
    """Advance width of one character [em], read unscaled from the font (its missing-glyph
    box for a character the font lacks)."""
    from matplotlib import ft2font

    flags = getattr(ft2font, "LoadFlags", None)
    no_scale = flags.NO_SCALE if flags is not None else ft2font.LOAD_NO_SCALE
    font, units = _face(bold)
    index = font.get_char_index(ord(char))          # 0: the missing-glyph box
    return font.load_glyph(index, flags=no_scale).horiAdvance / units


def text_width(s, size, bold=False):
    """Drawn width of one line of text.

    Parameters
    ----------
    s : str
        The line; it may hold sub- and superscript runs (:func:`gd_analyze.reports.markup.runs`),
        measured at their smaller size.
    size : float
        Type size [pt].
    bold : bool, optional
        The bold face.

    Returns
    -------
    float
        Width [in]: the sum of the glyphs' advances in DejaVu Sans, as :func:`draw_text_pages`
        draws them (a character the font lacks counts as its missing-glyph box).

    Examples
    --------
    >>> round(text_width("m", 10.0) * 72, 2)                # the advance of "m" [pt]
    9.74
    >>> text_width("ab", 9.0) == text_width("a", 9.0) + text_width("b", 9.0)
    True
    """
    if SUB in s or SUP in s:
        return sum(text_width(t, size * (RUN_SIZE if k else 1.0), bold) for t, k in runs(s) if t)
    bold = bool(bold)
    return sum(_advance(c, bold) for c in s) * size / 72.0


def _rgb(colour):
    from matplotlib.colors import to_rgb

    return tuple(round(255 * v) for v in to_rgb(colour))


def draw_text_pages(pages, size, title=""):
    """Draw pages of strings, rules and shaded rectangles as a PDF.

    Parameters
    ----------
    pages : sequence of sequence of tuple
        Per page, its operations in page coordinates [in from the top left corner]:
        ``("rect", x, y, w, h, grey)`` a filled rectangle (grey in [0, 1]);
        ``("rule", x0, x1, y, width)`` a horizontal line, width [pt];
        ``("text", x, y, s, size, colour, bold, right)`` a one-line string whose top is at y,
        starting at x (ending at x if ``right``), size [pt], colour a matplotlib colour.
        Rectangles are drawn first, then rules, then text.
    size : (float, float)
        Width and height of every page [in].
    title : str, optional
        The document's title (the caller may overwrite the information).

    Returns
    -------
    bytes
        The PDF: one page per entry, DejaVu Sans embedded as a TrueType subset.

    Raises
    ------
    FileNotFoundError
        If matplotlib's DejaVu Sans files are missing.
    """
    import warnings

    from fpdf import FPDF

    pdf = FPDF(unit="in", format=tuple(size))
    pdf.set_auto_page_break(False)
    pdf.set_margin(0)
    pdf.set_title(title)
    for style, path in font_files().items():
        pdf.add_font(_FAMILY, style, str(path))
    order = {"rect": 0, "rule": 1, "text": 2}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")             # a glyph the font lacks: its box
        for ops in pages:
            pdf.add_page()
            for op in sorted(ops, key=lambda o: order[o[0]]):
                if op[0] == "rect":
                    _, x, y, w, h, grey = op
                    pdf.set_fill_color(round(255 * grey))
                    pdf.rect(x, y, w, h, style="F")
                elif op[0] == "rule":
                    _, x0, x1, y, width = op
                    pdf.set_draw_color(0)
                    pdf.set_line_width(width / 72.0)
                    pdf.line(x0, y, x1, y)
                else:
                    _, x, y, s, pt, colour, bold, right = op
                    if s:
                        _text(pdf, x, y, s, pt, colour, bold, right)
    return bytes(pdf.output())


def _text(pdf, x, y, s, size, colour, bold, right):
    """One string, its top at y: each sub- or superscript run smaller and shifted."""
    pdf.set_text_color(*_rgb(colour))
    style = "B" if bold else ""
    if right:
        x -= text_width(s, size, bold)
    baseline = y + ASCENT * size / 72.0
    pieces = runs(s) if (SUB in s or SUP in s) else [(s, None)]
    for piece, kind in pieces:
        if not piece:
            continue
        at = size * (RUN_SIZE if kind else 1.0)
        pdf.set_font(_FAMILY, style, at)
        pdf.text(x, baseline - RUN_SHIFT.get(kind, 0.0) * size / 72.0, piece)
        x += text_width(piece, at, bold)
