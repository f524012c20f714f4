"""The page engine of the three PDF reports: one page size, flowing text, one table style,
numbered figures with captions, bookmarks and "page k of K" footers.

A :class:`Document` is filled with headings, paragraphs, tables and figures, then
:meth:`Document.write` lays them out on pages of one size (A4 or US letter): text and tables
flow from page to page (a heading stays with what follows it, a long table repeats its header),
a figure goes where it fits, or on the next page if it does not. The text pages are drawn
with fpdf2 (:mod:`gd_analyze.reports.text_pages`); each figure is drawn once, as its own PDF (the file the report also writes in
``figures/``), and placed unscaled on its page with pypdf, which also writes the bookmarks
(one per heading) and the document information.
"""

from __future__ import annotations

import io
import re
import textwrap
from dataclasses import dataclass, field

from .markup import plain
from .table_layout import column_widths as _column_widths
from .table_layout import wrap_cell as _wrap_cell
from .text_pages import draw_text_pages, text_width

__all__ = ["PAPER", "PAGE_RC", "FIGURE_FONTS", "Document", "TABLE_COLOURS",
           "continued_caption"]

#: Page sizes [in].
PAPER = {"a4": (8.27, 11.69), "letter": (8.5, 11.0)}
#: Colours of the class and yes/no cells of every table.
TABLE_COLOURS = {"translational": "#0072B2", "rotational": "#D55E00", "both": "#6A3D9A",
                 "negligible": "#555555", "yes": "#007A4D", "no": "#B00020",
                 "passed": "#007A4D", "FAILED": "#B00020", "tran": "#0072B2",
                 "rot": "#D55E00", "none": "#555555"}

#: matplotlib settings of every figure's PDF: DejaVu Sans, the text pages' font (the font type
#: is set by :data:`FIGURE_FONTS`).
PAGE_RC = {"pdf.fonttype": 3, "font.family": "DejaVu Sans", "path.simplify": True}
#: How the figures' PDFs embed their font, by name: ``type3`` (glyphs as drawings: fast, the
#: default) or ``truetype`` (a TrueType subset, Type 42: what journals that refuse Type 3
#: fonts, e.g. IEEE PDF eXpress, ask for; each figure takes about 0.15 s more).
FIGURE_FONTS = {"type3": 3, "truetype": 42}

_MARGIN_X, _MARGIN_TOP, _MARGIN_BOTTOM = 0.53, 0.6, 0.75
_CHAR = 0.55            # mean character width of DejaVu Sans [em]
#: Headings and a lead-in at the top of a page [in]: a figure below them shrinks to fit
#: rather than leave them alone on the page.
_TOP_GROUP = 1.0
#: A figure that does not fit floats past the following text when more than this fraction of
#: the page's body would otherwise stay blank.
_FLOAT_ROOM = 0.25
#: A table split over pages puts at least this many rows on its last page.
_MIN_ROWS = 3
_HEADING = {1: 13.0, 2: 10.5, 0: 15.0}
#: The number of a table's caption ("Table 5.2"), repeated on each page the table continues on.
_TABLE_NUMBER = re.compile(r"^(Table\s+[0-9A-Za-z.]*[0-9A-Za-z])[:.]?(\s|$)")


def continued_caption(caption):
    """The caption over a table's rows on the pages after its first: ``"Table 5.2
    (continued)"``.

    Parameters
    ----------
    caption : str
        The table's caption, e.g. ``"Table 5.2: Ranking ..."``; empty for a table without.

    Returns
    -------
    str
        Its number and "(continued)"; a caption without a number: "(continued)" alone.

    Examples
    --------
    >>> continued_caption("Table 5.2: Ranking of the elements.")
    'Table 5.2 (continued)'
    >>> continued_caption("")
    '(continued)'
    """
    match = _TABLE_NUMBER.match(plain(caption or "").strip())
    return f"{match.group(1)} (continued)" if match else "(continued)"


def _place(writer, target, pdf_bytes, name, x, y, scale, turned_width=None):
    """Put page 1 of ``pdf_bytes`` on ``target`` as a form XObject at (x, y) [pt], scaled,
    and turned a quarter anticlockwise if ``turned_width`` (its width on the page [pt]).

    The figure's content stream is reused as it is (still compressed), not parsed: placing is
    as cheap as copying bytes.
    """
    from pypdf import PdfReader
    from pypdf.generic import ArrayObject, DecodedStreamObject, DictionaryObject, NameObject

    src = PdfReader(io.BytesIO(pdf_bytes)).pages[0]
    contents = src["/Contents"].get_object()
    form = contents.clone(writer)
    form[NameObject("/Type")] = NameObject("/XObject")
    form[NameObject("/Subtype")] = NameObject("/Form")
    form[NameObject("/BBox")] = ArrayObject(src.mediabox).clone(writer)
    form[NameObject("/Resources")] = src["/Resources"].get_object().clone(writer)
    ref = writer._add_object(form)
    resources = target["/Resources"].get_object()
    if "/XObject" not in resources:
        resources[NameObject("/XObject")] = DictionaryObject()
    resources["/XObject"].get_object()[NameObject(name)] = ref
    op = DecodedStreamObject()
    if turned_width is None:
        matrix = f"{scale:.6f} 0 0 {scale:.6f} {x:.3f} {y:.3f}"
    else:
        matrix = f"0 {scale:.6f} {-scale:.6f} 0 {x + turned_width:.3f} {y:.3f}"
    op.set_data(f"q {matrix} cm {name} Do Q\n".encode())
    op_ref = writer._add_object(op)
    old = target["/Contents"]
    if isinstance(old.get_object(), ArrayObject):
        old.get_object().append(op_ref)
    else:
        target[NameObject("/Contents")] = ArrayObject([old, op_ref])


def _line_width(s, size):
    """Drawn width [in] of one line of DejaVu Sans at ``size`` [pt] (its glyphs' advances;
    sub- and superscript runs at their size), as :mod:`gd_analyze.reports.text_pages` draws it."""
    return text_width(s, size)


def _fit_line(s, size, width):
    """The line ``s``, cut and ended by an ellipsis if wider than ``width`` [in]: a footer
    holding a long robot name stops short of the page number instead of running over it."""
    if _line_width(s, size) <= width:
        return s
    lo, hi = 0, len(s)                                  # longest prefix that fits
    while lo < hi:
        mid = (lo + hi + 1) // 2
        lo, hi = (mid, hi) if _line_width(s[:mid] + "\u2026", size) <= width else (lo, mid - 1)
    return s[:lo] + "\u2026"


@dataclass
class _Page:
    ops: list = field(default_factory=list)          # (kind, payload) drawn in order
    figures: list = field(default_factory=list)      # (pdf bytes, x, y_top, w, h) [in]
    used: float = 0.0


class Document:
    """A report as a flow of blocks, written as one PDF of one page size.

    Parameters
    ----------
    title : str
        Document title (metadata, first heading's bookmark root and the footer).
    paper : {"a4", "letter"}, optional
        The page size of every page.
    metadata : dict, optional
        PDF document information: ``Author``, ``Subject``, ``Keywords``, ``Creator`` ...
    footer : str, optional
        Text at the foot of every page, before "page k of K".

    Raises
    ------
    ValueError
        If ``paper`` is not a key of :data:`PAPER`.

    Notes
    -----
    The text pages embed DejaVu Sans as a TrueType subset
    (:func:`gd_analyze.reports.text_pages.draw_text_pages`); how a figure embeds its font is
    the figure's own (:data:`FIGURE_FONTS`), so a report whose figures are drawn with
    ``--figure-fonts truetype`` holds no Type 3 font at all.
    """

    def __init__(self, title, paper="a4", metadata=None, footer=None):
        if paper not in PAPER:
            raise ValueError(f"paper must be one of {sorted(PAPER)}, got {paper!r}")
        self.title = title
        self.paper = paper
        self.W, self.H = PAPER[paper]
        self.metadata = dict(metadata or {})
        self.footer = footer or title
        self.blocks = []
        self.n_figures = 0

    @property
    def width(self):
        """Width of the text [in]."""
        return self.W - 2 * _MARGIN_X

    @property
    def body(self):
        """Height of the text area of a page [in]."""
        return self.H - _MARGIN_TOP - _MARGIN_BOTTOM

    # ---- blocks ------------------------------------------------------------------------
    def heading(self, text, level=1):
        """A heading, kept on a page with the start of what follows it.

        Parameters
        ----------
        text : str
            The heading, wrapped if long.
        level : {0, 1, 2}, optional
            0: the document's title (15 pt, no bookmark); 1: a section (13 pt, a bookmark);
            2: a subsection (10.5 pt, a bookmark under the last section's).
        """
        self.blocks.append(("heading", (text, level)))

    def paragraph(self, text, size=9.0, bold=False, colour="black"):
        """A paragraph of wrapped text; it may continue on the next page.

        Parameters
        ----------
        text : str
            The text.
        size : float, optional
            Type size [pt].
        bold : bool, optional
            Bold type.
        colour : str, optional
            A matplotlib colour.
        """
        self.blocks.append(("paragraph", (text, size, bold, colour)))

    def table(self, table, size=7.5, caption=""):
        """A table in the one table style of the reports: its caption above it, rules above
        and below the header and at the end, shaded every other row, cells wrapped at spaces to
        their column (each column at least as wide as its longest word).

        Parameters
        ----------
        table : dict
            As :func:`gd_analyze.reports.common.table` makes it (header, rows, align, widths,
            colour_cols: class and yes/no cells drawn in their colour).
        size : float, optional
            Type size [pt]. A short table stays on one page; a long one repeats its header on
            each page, under "Table k.m (continued)" (:func:`continued_caption`).
        caption : str, optional
            "Table 5.2: ...", kept on the page of the table's first rows.
        """
        self.blocks.append(("table", (table, size, caption)))

    def figure(self, pdf_bytes, size, caption):
        """A figure with "Figure k." and its caption below it.

        Parameters
        ----------
        pdf_bytes : bytes or str
            The figure as a one-page PDF (:func:`gd_analyze.reports.drawing.figure_pdf`), placed
            unscaled if it fits; or a key of the ``figures`` given to :meth:`write` later.
        size : (float, float)
            Its width and height [in].
        caption : str
            What the figure shows.

        Returns
        -------
        int
            The figure's number k.
        """
        self.n_figures += 1
        self.blocks.append(("figure", (pdf_bytes, size, f"Figure {self.n_figures}. {caption}")))
        return self.n_figures

    # ---- layout ------------------------------------------------------------------------
    def _wrap(self, text, size, width=None):
        chars = max(10, int((width or self.width) / (size * _CHAR / 72)))
        return textwrap.wrap(text, chars) or [""]

    def _layout(self):
        """Pages of placed blocks, and the bookmarks.

        A figure that does not fit the room left on a page, where that room is more than
        :data:`_FLOAT_ROOM` of the body, floats: the text and tables after it fill the page,
        and the figure goes to the top of the next page (figures keep their order), as LaTeX
        places a float; a page is not left three-quarters blank.

        A heading keeps with what follows it (keep with next): with the start of its first
        block, a short lead-in paragraph with the figure or table after it
        (:meth:`_first_height`). If that group does not fit below a float placed at the top
        of the next page, it starts the page after: no page ends with a heading and its
        lead-in whose figure or table is on a later page.
        """
        pages = [_Page()]
        bookmarks = []
        body = self.body
        pending = []                                   # a floating figure, at most one

        def room():
            return body - pages[-1].used

        def new_page():
            pages.append(_Page())
            while pending:                             # the float at the top of the page
                place(pending.pop(0), defer=False)

        def place(payload, defer):
            pdf_bytes, (w, h), caption = payload
            lines = self._wrap(caption, 8.0)
            pw, ph, scale, rotate, need = self._figure_box(w, h, caption)
            page = pages[-1]
            if need > room() and page.used > _TOP_GROUP:
                if defer and room() > _FLOAT_ROOM * body:
                    pending.append(payload)
                    return
                new_page()
                page = pages[-1]
            if need > room():            # under its heading at the top: shrink to fit
                pw, ph, scale, rotate, need = self._figure_box(w, h, caption, room())
            x = _MARGIN_X + (self.width - pw * scale) / 2
            page.figures.append((pdf_bytes, x, page.used + 0.05, pw, ph, scale, rotate))
            page.used += ph * scale + 0.1
            for line in lines:
                page.ops.append(("text", (page.used, line, 8.0, False, "0.15")))
                page.used += 8.0 * 1.38 / 72
            page.used += 0.15

        blocks = self.blocks
        for k, (kind, payload) in enumerate(blocks):
            page = pages[-1]
            if kind == "heading":
                text, level = payload
                size = _HEADING.get(level, 10.0)
                lines = self._wrap(text, size / 0.92)          # bold type is wider
                lead = 0.12 if page.used > 0 else 0.0
                h = len(lines) * size * 1.45 / 72 + 0.05
                follow = self._first_height(blocks[k + 1:]) if k + 1 < len(blocks) else 0.0
                follow = min(follow, body - _TOP_GROUP)    # a page-high figure shrinks
                floats = 0.0
                if pending and any(b[0] == "figure" for b in blocks[k + 1:k + 3]):
                    # its figure comes after the floating one: both below the heading, or
                    # the heading under the float on the next page, never alone at the foot
                    floats = sum(self._figure_box(*f[1], f[2])[4] for f in pending)
                if lead + h + follow + floats > room() and page.used > 0:
                    new_page()
                    page = pages[-1]
                    lead = 0.0 if page.used == 0 else lead
                    # keep with next: the float placed at the top of the new page may leave
                    # no room for the heading's group; then the group starts the page after
                    if lead + h + follow > room() and page.used > 0:
                        new_page()
                        page = pages[-1]
                        lead = 0.0
                page.used += lead
                for line in lines:
                    page.ops.append(("text", (page.used, line, size, True, "black")))
                    page.used += size * 1.45 / 72
                page.used += 0.05
                if level in (1, 2):
                    bookmarks.append((plain(text), level, len(pages) - 1))
            elif kind == "paragraph":
                text, size, bold, colour = payload
                lh = size * 1.38 / 72
                for line in self._wrap(text, size):
                    if lh > room():
                        new_page()
                        page = pages[-1]
                    page.ops.append(("text", (page.used, line, size, bold, colour)))
                    page.used += lh
                page.used += 0.07
            elif kind == "table":
                self._layout_table(payload, pages, new_page)
            elif kind == "figure":
                if pending:                                    # figures keep their order
                    place(pending.pop(0), defer=False)
                place(payload, defer=True)
        while pending:
            place(pending.pop(0), defer=False)
        return pages, bookmarks

    def _figure_box(self, w, h, caption, room=None):
        """Size on the page of a w x h figure [in]: (width, height, scale, turned, height with
        its caption). A figure much wider than the text (shrunk below 85 %) is turned a quarter
        if it then needs less shrinking."""
        ch = len(self._wrap(caption, 8.0)) * 8.0 * 1.38 / 72 + 0.08
        room = (self.body if room is None else room) - ch - 0.15
        scale = min(1.0, self.width / w, room / h)
        turned = min(1.0, self.width / h, room / w)
        rotate = w > self.width and scale < 0.85 and turned > scale
        scale = turned if rotate else scale
        pw, ph = (h, w) if rotate else (w, h)
        return pw, ph, scale, rotate, ph * scale + ch + 0.15

    def _first_height(self, rest):
        """Height of the start of the next block (what a heading must stay with) [in]: a
        short paragraph whole, with the start of what follows it (a section's lead-in stays
        with its figure)."""
        kind, payload = rest[0]
        if kind == "paragraph":
            lines = len(self._wrap(payload[0], payload[1]))
            own = min(3, lines) * payload[1] * 1.38 / 72
            if lines <= 4 and len(rest) > 1 and rest[1][0] in ("figure", "table"):
                return lines * payload[1] * 1.38 / 72 + 0.07 + self._first_height(rest[1:])
            return own
        if kind == "table":
            return self._table_rows(payload)[3]
        if kind == "figure":
            return self._figure_box(*payload[1], payload[2])[4]
        if kind == "heading":
            return _HEADING.get(payload[1], 10.0) * 1.6 / 72 + self._first_height(rest[1:]) \
                if len(rest) > 1 else 0.3
        return 0.3

    def _table_rows(self, payload):
        """A table's column widths [in], wrapped header and rows (cells, height [in]), and
        the height that must fit where it starts [in]: the whole of a short table (at most
        35 % of the body), else its header and first three rows."""
        table, size, caption = payload
        lh, pad = size * 1.3 / 72, 0.035
        widths = _column_widths(table, self.width, size, pad)

        def wrap(row, bold=False):
            cells = [_wrap_cell(c, w - 2 * pad, size, bold) for c, w in zip(row, widths)]
            return cells, max(len(c) for c in cells) * lh + 2 * pad

        header = wrap(table["header"], True)
        rows = [wrap(r) for r in table["rows"]]
        total = header[1] + sum(h for _, h in rows) + self._caption_height(caption)
        keep = total if total <= 0.35 * self.body else (
            self._caption_height(caption) + header[1] + sum(h for _, h in rows[:3]))
        return widths, header, rows, keep

    def _caption_height(self, caption):
        return len(self._wrap(caption, 8.0)) * 8.0 * 1.38 / 72 + 0.04 if caption else 0.0

    def _layout_table(self, payload, pages, new_page):
        table, size, caption = payload
        widths, header, rows, keep = self._table_rows(payload)
        lh, pad = size * 1.3 / 72, 0.035
        page = pages[-1]
        room = self.body - page.used
        # a short table stays on one page; a long one starts where at least 3 rows fit
        if keep > room and page.used > 0:
            new_page()
            page = pages[-1]
        if caption:
            for line in self._wrap(caption, 8.0):
                page.ops.append(("text", (page.used, line, 8.0, False, "0.15")))
                page.used += 8.0 * 1.38 / 72
            page.used += 0.04
        spec = {"widths": widths, "align": table["align"], "colour": set(table["colour_cols"]),
                "size": size, "lh": lh, "pad": pad}
        page.ops.append(("rule", (page.used, 0.8)))
        page.ops.append(("row", (page.used, header[0], True, False, spec)))
        page.used += header[1]
        page.ops.append(("rule", (page.used, 0.5)))
        on_page = 0
        for k, (cells, h) in enumerate(rows):
            tail = rows[k:]
            # no last page of one or two rows: the last three rows stay together
            widow = (len(tail) == _MIN_ROWS and on_page >= _MIN_ROWS
                     and page.used + sum(r[1] for r in tail) > self.body)
            if page.used + h > self.body or widow:
                on_page = 0
                page.ops.append(("rule", (page.used, 0.8)))
                new_page()
                page = pages[-1]
                page.ops.append(("text", (page.used, continued_caption(caption), 8.0, False,
                                          "0.15")))
                page.used += 8.0 * 1.38 / 72 + 0.04
                page.ops.append(("rule", (page.used, 0.8)))
                page.ops.append(("row", (page.used, header[0], True, False, spec)))
                page.used += header[1]
                page.ops.append(("rule", (page.used, 0.5)))
            page.ops.append(("row", (page.used, cells, False, k % 2 == 1, spec)))
            page.used += h
            on_page += 1
        page.ops.append(("rule", (page.used, 0.8)))
        page.used += 0.16

    # ---- drawing -----------------------------------------------------------------------
    def _draw(self, page, number, total, footer):
        """The drawing operations of one page (:func:`gd_analyze.reports.text_pages.draw_text_pages`)."""
        ops = []

        def text(x, y, s, size, colour="black", bold=False, right=False):
            ops.append(("text", x, _MARGIN_TOP + y, s, size, colour, bold, right))

        for kind, p in page.ops:
            if kind == "text":
                y, s, size, bold, colour = p
                text(_MARGIN_X, y, s, size, colour, bold)
            elif kind == "rule":
                y, lw = p
                ops.append(("rule", _MARGIN_X, self.W - _MARGIN_X, _MARGIN_TOP + y, lw))
            elif kind == "row":
                y, cells, bold, shade, spec = p
                widths, pad, lh = spec["widths"], spec["pad"], spec["lh"]
                height = max(len(c) for c in cells) * lh + 2 * pad
                if shade:
                    ops.append(("rect", _MARGIN_X, _MARGIN_TOP + y, self.width, height, 0.94))
                x = _MARGIN_X
                for k, (lines, w) in enumerate(zip(cells, widths)):
                    right = spec["align"][k] == "right"
                    colour = "black"
                    if k in spec["colour"] and not bold:
                        colour = TABLE_COLOURS.get(lines[0], "black")
                    for m, line in enumerate(lines):
                        text(x + (w - pad if right else pad), y + pad + m * lh, line,
                             spec["size"], colour, bold, right)
                    x += w
        foot = self.H - 0.4 - 7 * 1.2 / 72 - _MARGIN_TOP
        text(_MARGIN_X, foot, footer, 7, "0.4")
        text(self.W - _MARGIN_X, foot, f"page {number} of {total}", 7, "0.4", right=True)
        return ops

    def write(self, path, figures=None):
        """Lay out, draw and write the document.

        Parameters
        ----------
        path : str or os.PathLike
            The PDF file (written as given: the caller stages it).
        figures : dict of str to bytes, optional
            The PDF of each figure whose block holds a key in place of its bytes (a document
            laid out before its figures are drawn).

        Returns
        -------
        int
            The number of pages.
        """
        pages, bookmarks = self._layout()
        return self._finish(self._text_pages(pages), pages, bookmarks, path, figures)

    def _text_pages(self, pages):
        """The text, rules and shading of every page (no figures) as PDF bytes."""
        K = len(pages)
        last = f"page {K} of {K}"                   # the widest page number (digits: one width)
        footer = _fit_line(self.footer, 7, self.width - _line_width(last, 7) - 0.15)
        return draw_text_pages([self._draw(page, k + 1, K, footer)
                                for k, page in enumerate(pages)], (self.W, self.H),
                               plain(self.title))

    def _finish(self, text_pdf, pages, bookmarks, path, figures=None):
        """Place the figures on the text pages, add bookmarks and information, write."""
        from pypdf import PdfReader, PdfWriter

        figures = figures or {}
        writer = PdfWriter(clone_from=PdfReader(io.BytesIO(text_pdf)))
        count = 0
        for k, page in enumerate(pages):
            for pdf_bytes, x, y, w, h, scale, rotate in page.figures:
                count += 1
                if isinstance(pdf_bytes, str):
                    pdf_bytes = figures[pdf_bytes]
                bottom = self.H - (_MARGIN_TOP + y + h * scale)
                _place(writer, writer.pages[k], pdf_bytes, f"/GdFigure{count}",
                       72 * x, 72 * bottom, scale, 72 * w * scale if rotate else None)
        parents = {}
        for text, level, page_index in bookmarks:
            parent = parents.get(1) if level == 2 else None
            item = writer.add_outline_item(title=text, page_number=page_index, parent=parent)
            if level == 1:
                parents[1] = item
        writer.page_mode = "/UseOutlines"
        info = {"/Title": plain(self.title)}
        info.update({f"/{k}": str(v) for k, v in self.metadata.items() if v is not None})
        writer.add_metadata(info)
        with open(path, "wb") as fh:
            writer.write(fh)
        return len(pages)
