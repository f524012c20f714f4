"""Short strings written straight into matplotlib's PDF content stream (the text pages).

matplotlib's ``RendererPdf.draw_text`` shapes every string anew with libraqm and loads each of
its glyphs; a report's text pages hold over a thousand short strings in two fonts and a few
sizes, which made them a fifth of the main job. :class:`PdfText` looks each glyph and each
kerning pair up once and writes the same PDF operators (:mod:`gd_analyze.reports.pages` uses it
for every string of a page).
"""

from __future__ import annotations

__all__ = ["PdfText"]


class PdfText:
    """Strings of the text pages written straight into matplotlib's PDF content stream.

    matplotlib's ``RendererPdf.draw_text`` shapes every string anew (libraqm) and loads each
    glyph; a report's pages hold over a thousand short strings in two fonts and a few sizes.
    Here each glyph's advance (FreeType) and each pair's kerning (libraqm, on the two
    characters: the font's GPOS kerning that ``draw_text`` applies) are looked up once per font
    and size, the glyphs are recorded with the PDF file's own character tracker (so the Type 3 fonts embed exactly the glyphs used), and
    the same operators as ``draw_text`` are written (a text object, font and size, one TJ of
    glyph codes and kerns). Used only where the renderer offers the interfaces of matplotlib
    >= 3.11 with Type 3 fonts; otherwise (and for any string with a glyph the font lacks)
    :meth:`layout` returns None and the string goes through ``draw_text``.

    Parameters
    ----------
    renderer : matplotlib.backends.backend_pdf.RendererPdf
        The page's renderer (use :meth:`for_renderer`, which checks that it applies).
    font_path : type
        ``matplotlib.font_manager.FontPath``.
    op : type
        ``matplotlib.backends.backend_pdf.Op`` (the PDF operators).
    flags : matplotlib.ft2font.LoadFlags
        How glyphs are loaded (no hinting, as ``draw_text``).
    """

    def __init__(self, renderer, font_path, op, flags):
        self.renderer = renderer
        self.file = renderer.file
        self.tracker = renderer.file._character_tracker
        self.FontPath, self.Op, self.flags = font_path, op, flags

    #: (size, weight) -> {char: (font, glyph, advance [pt])}, kept across pages and reports
    metrics = {}
    #: ((size, weight), char, char) -> kern [pt]
    kerns = {}

    @classmethod
    def for_renderer(cls, renderer):
        """The direct path for a renderer, or None where it does not apply.

        Parameters
        ----------
        renderer : matplotlib.backend_bases.RendererBase
            The renderer of a page (a ``RendererPdf``, possibly inside a
            ``MixedModeRenderer``).

        Returns
        -------
        PdfText or None
        """
        import matplotlib as mpl

        try:
            from matplotlib.backends.backend_pdf import Op, RendererPdf
            from matplotlib.font_manager import FontPath, FontProperties
            from matplotlib.ft2font import LoadFlags
        except ImportError:
            return None
        renderer = getattr(renderer, "_renderer", renderer)     # inside a MixedModeRenderer
        if (not isinstance(renderer, RendererPdf) or mpl.rcParams["pdf.fonttype"] != 3
                or mpl.rcParams["pdf.use14corefonts"]
                or not hasattr(getattr(renderer.file, "_character_tracker", None),
                               "track_glyph")):
            return None
        if not hasattr(renderer._get_font_ttf(FontProperties(family="DejaVu Sans")), "_layout"):
            return None
        return cls(renderer, FontPath, Op, LoadFlags.NO_HINTING)

    def layout(self, s, prop):
        """Place the glyphs of one string.

        Parameters
        ----------
        s : str
            The string (one line).
        prop : matplotlib.font_manager.FontProperties
            Its font and size.

        Returns
        -------
        tuple or None
            (glyphs, width [pt]): glyphs as (font, glyph index, char, x [pt], advance [pt]);
            None if a character is missing from the font (draw it with ``draw_text``).
        """
        key = (prop.get_size_in_points(), prop.get_weight())
        table = self.metrics.setdefault(key, {})
        font = None
        glyphs, x, prev = [], 0.0, None
        for ch in s:
            m = table.get(ch)
            if m is None:
                if font is None:
                    font = self.renderer._get_font_ttf(prop)
                gi = font.get_char_index(ord(ch))
                if gi == 0:
                    return None
                g = font.load_glyph(gi, flags=self.flags)
                m = table[ch] = (font, gi, g.linearHoriAdvance / 65536)
            ft, gi, adv = m
            if prev is not None:
                k = self.kerns.get((key, prev, ch))
                if k is None:
                    if font is None:
                        font = self.renderer._get_font_ttf(prop)
                    pair = list(font._layout(prev + ch, self.flags))
                    k = self.kerns[(key, prev, ch)] = \
                        float(pair[1].prev_kern) if len(pair) == 2 else 0.0
                x += k
            glyphs.append((ft, gi, ch, x, adv))
            x += adv
            prev = ch
        return glyphs, x

    def draw(self, gc, x, y, run, size):
        """Write the glyphs of a string as one PDF text object.

        Parameters
        ----------
        gc : matplotlib.backend_bases.GraphicsContextBase
            Its colour.
        x, y : float
            Left end of its baseline [pt from the page's bottom left].
        run : tuple
            From :meth:`layout`.
        size : float
            Type size [pt].
        """
        Op, out = self.Op, self.file.output
        self.renderer.check_gc(gc, gc._rgb)
        out(Op.gsave)
        out(1, 0, 0, 1, x, y, Op.concat_matrix)
        out(Op.begin_text)
        chunk, font_key, start, last_end = [], None, 0.0, 0.0

        def flush():
            if chunk:
                parts, codes = [], []
                for item in chunk:
                    if isinstance(item, float):
                        if codes:
                            parts.append(bytes(codes))
                            codes = []
                        parts.append(-1000 * item / size)
                    else:
                        codes.append(item)
                if codes:
                    parts.append(bytes(codes))
                out(parts, Op.showkern)
                chunk.clear()

        for ft, gi, ch, gx, adv in run[0]:
            subset, code = self.tracker.track_glyph(ft, ch, gi)
            if (ft, subset) != font_key:
                flush()
                name = self.file.fontName(self.FontPath(ft.fname, ft.face_index), subset)
                out(name, size, Op.selectfont)
                out(gx - start, 0, Op.textpos)
                font_key, start = (ft, subset), gx
            elif abs(gx - last_end) > 1e-9:
                chunk.append(float(gx - last_end))
            chunk.append(code)
            last_end = gx + adv
        flush()
        out(Op.end_text)
        out(Op.grestore)
