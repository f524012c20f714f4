"""The PDF reports, typeset by Typst from the one section list the HTML renders.

:func:`write_pdf` hands a report's :class:`gd_analyze.report.sections.Outline` to the Typst
compiler (the ``typst`` package: the compiler in a wheel, run in-process) as *data*: a JSON
document read by the fixed template ``templates/report.typ`` that ships with the package, and
each figure as SVG text. No markup is generated: every string of the report (robot and file
names, descriptions, paths) reaches Typst as a JSON string and is set as text, so ``#panic()``
or ``*bold*`` in a robot's name is printed as it is.

Typst numbers the sections, tables (within their section, "Table 5.2") and figures ("Figure
3."), checks each section's number against the outline's (the HTML and the sentences of the
report cite them), sets each figure where the outline puts it (beside the text citing it) if it
fits there, else at the top of the next page with the text after it filling the page (a figure
that opens its section stays under its heading; the figures keep their order), never splits a
paragraph over two pages, keeps each heading with
what follows it, breaks long tables over pages with their header repeated, sets a report whose
last page would hold a figure alone again with no figure floating past the next heading (the
figure heads that page with the rest of its section), sets a report whose
last page would hold a few lines (:data:`NEAR_EMPTY`) again with less space between lines,
blocks and table rows if that saves the page and Typst's layout converges, and, if it still
would, with its last section (begun in its page's lower half) starting a page, sets the sub- and
superscripts of :mod:`gd_analyze.report.markup` as such and code in monospace. The figures are
embedded as vector graphics from their SVG; their text (``svg.fonttype`` "none") is set in
DejaVu Sans, the font matplotlib measured it in, embedded as a TrueType subset: the PDF holds
no Type 3 font. The text is set in DejaVu Sans too (one family on the page, shipped with
matplotlib; Libertinus Serif's marks gave a text layer with "q̇q̇" for q̇), no text under
:data:`MIN_PRINTED_PT` (figures are drawn so that their text prints at that size or more:
:func:`printed_scale`, :func:`gd_analyze.report.figure_style.raise_small_text`).
"""

from __future__ import annotations

import functools
import json
import os
import re
import warnings
from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Any

from . import markup
from .common import keep_units

if TYPE_CHECKING:
    from .sections import Outline

__all__ = ["PAPER", "check_paper", "MIN_PRINTED_PT", "NEAR_EMPTY", "printed_scale", "TABLE_COLOURS",
           "PARAGRAPH_STYLES", "document_data", "write_pdf", "figure_rooms", "printed_width",
           "body_height", "FLOAT_GAP",
           "figure_pdfs", "fonts_loaded"]

#: Page sizes [in] and their Typst names.
PAPER = {"a4": (210 / 25.4, 297 / 25.4), "letter": (8.5, 11.0)}
_TYPST_PAPER = {"a4": "a4", "letter": "us-letter"}


def check_paper(paper: str) -> None:
    """Raise unless ``paper`` is a page size of :data:`PAPER`.

    Parameters
    ----------
    paper : str
        ``"a4"`` or ``"letter"``.

    Raises
    ------
    ValueError
        Naming the page sizes there are.
    """
    if paper not in PAPER:
        raise ValueError(f"paper must be one of {sorted(PAPER)}, got {paper!r}")
#: Margins [in]: left and right, top, bottom (the footer sits in the bottom margin).
MARGINS = (0.75, 0.7, 0.85)
#: Colours of the class and yes/no cells of every table.
TABLE_COLOURS = {"translational": "#0072B2", "rotational": "#D55E00", "both": "#6A3D9A",
                 "negligible": "#555555", "yes": "#007A4D", "no": "#B00020",
                 "passed": "#007A4D", "FAILED": "#B00020", "tran": "#0072B2",
                 "rot": "#D55E00", "none": "#555555", "pruned": "#CC79A7"}
#: The paragraph styles of the outline (the HTML's classes of the same names).
PARAGRAPH_STYLES = ("lead", "summary", "body", "note", "strong")
#: Room kept under a figure for its caption [in]: a figure is scaled down to leave it.
_CAPTION_ROOM = 0.9


@functools.cache
def fonts_loaded() -> Any:
    """The fonts every Typst document of the process is set in, loaded once (a worker thread
    may load them while the figures are drawn): matplotlib's DejaVu folder (the reports use
    DejaVu Sans and DejaVu Sans Mono; the figures' text is set in the font matplotlib measured
    it in) and Typst's own; never the system's.

    Returns
    -------
    typst.Fonts
    """
    import matplotlib
    import typst

    return typst.Fonts(include_system_fonts=False, include_embedded_fonts=True,
                       font_paths=[str(Path(matplotlib.get_data_path()) / "fonts" / "ttf")])


def _compile(template, inputs, created, end=False):
    """PDF bytes of a fixed template compiled with the given sys.inputs (all data), and with
    ``end`` where its text ends (the template's ``<gd-end>`` metadata: page, fill, and
    ``warnings``, Typst's messages, for the caller to issue if it keeps this layout), else None.

    Typst's warnings (a layout that did not converge: the figures' placement reads the
    positions of the previous layout pass) are issued as :class:`RuntimeWarning` (with ``end``:
    by the caller).
    """
    from importlib import resources

    import typst

    source = resources.files("gd_analyze.report").joinpath(f"templates/{template}")
    with resources.as_file(source) as path:           # a file: a query reuses the layout
        compiler = typst.Compiler(input=str(path), sys_inputs=inputs, font_paths=fonts_loaded(),
                                  ignore_system_fonts=True)
        try:
            pdf, found = compiler.compile_with_warnings(timestamp=_timestamp(created))
            where = {**json.loads(compiler.query("<gd-end>", field="value", one=True)),
                     "warnings": [w.message for w in found]} if end else None
        except typst.TypstError as exc:
            raise RuntimeError(f"typst: {exc.message}") from None
    for w in [] if end else found:
        warnings.warn(f"typst: {w.message}", RuntimeWarning, stacklevel=3)
    return pdf, where


def _runs(text):
    """A marked string as [text, kind] pairs: kind "" (plain), "sub", "sup" or "code"."""
    return [[t, k or ""] for t, k in markup.spans(str(text))]


def body_height(paper: str) -> float:
    """The height of a page's text area, between the top and the bottom margins [in].

    Parameters
    ----------
    paper : {"a4", "letter"}
        The page size.

    Returns
    -------
    float
        [in]
    """
    return PAPER[paper][1] - MARGINS[1] - MARGINS[2]


def printed_width(size: tuple[float, float], paper: str) -> float:
    """The width a figure is set at in a PDF report: its own, or less so that it and its
    caption fit the text area.

    Parameters
    ----------
    size : (float, float)
        The figure's width and height [in].
    paper : {"a4", "letter"}
        The page size.

    Returns
    -------
    float
        [in]; the figure keeps its aspect.
    """
    w, h = size
    width = PAPER[paper][0] - 2 * MARGINS[0]
    height = PAPER[paper][1] - MARGINS[1] - MARGINS[2] - _CAPTION_ROOM
    return w * min(1.0, width / w, height / h)


#: A last page whose text fills less than this share of its body is "near-empty": the report
#: is set again with less space between lines, blocks and table rows, and that setting kept
#: if it ends a page earlier.
NEAR_EMPTY = 1 / 3

#: The least size [pt] of any text of a printed report, figures' text included.
MIN_PRINTED_PT = 8.0


def printed_scale(size: tuple[float, float]) -> float:
    """The least scale a figure of this size is printed at, over the papers of :data:`PAPER`.

    Parameters
    ----------
    size : (float, float)
        The figure's width and height [in].

    Returns
    -------
    float
        Printed size / drawn size, at most 1 (:func:`printed_width` over the drawn width).
    """
    return min(printed_width(size, paper) / float(size[0]) for paper in PAPER)


def _block(b, paper, sizes):
    if b.kind == "paragraph":
        return {"kind": "paragraph", "style": b.style if b.style in PARAGRAPH_STYLES else "body",
                "text": _runs(keep_units(b.content))}
    if b.kind == "counts":
        return {"kind": "counts", "counts": [[str(c), int(k)] for c, k in b.content.items()]}
    number, caption = b.number, b.text
    if b.kind == "table":
        t = b.content
        return {"kind": "table", "number": number, "caption": _runs(caption),
                "kv": b.style == "kv", "size": float(b.size),
                "header": [_runs(h) for h in t["header"]],
                "rows": [[_runs(c) for c in row] for row in t["rows"]],
                "align": list(t["align"]), "colour": [int(k) for k in t.get("colour_cols", [])]}
    return {"kind": "figure", "number": number, "caption": _runs(caption), "key": b.content,
            "width": printed_width(sizes[b.content], paper)}


def document_data(outline: Outline, sizes: Mapping[str, tuple[float, float]], paper: str = "a4",
                  metadata: Mapping[str, Any] | None = None, footer: str = "") -> dict[str, Any]:
    """The data the template ``templates/report.typ`` typesets.

    Parameters
    ----------
    outline : gd_analyze.report.sections.Outline
        The report's sections.
    sizes : dict of str to (float, float)
        The size [in] of each figure of the outline, by key.
    paper : {"a4", "letter"}, optional
        The page size.
    metadata : dict, optional
        ``Author``, ``Subject``, ``Keywords`` of the PDF's document information.
    footer : str, optional
        The text at the foot of every page, before "page k of K".

    Returns
    -------
    dict
        JSON-ready: strings, numbers and lists only; each text a list of [text, kind] runs.

    Raises
    ------
    ValueError
        If ``paper`` is unknown or a caption is not numbered as the outline numbers them.

    Examples
    --------
    >>> from gd_analyze.report.sections import Outline
    >>> o = Outline("R " + markup.sub("1"), figures={"D"})
    >>> o.section("1", "Robot")
    >>> o.figure("D", "elements of D")
    >>> d = document_data(o, {"D": (7.0, 14.0)})
    >>> d["title"], d["sections"][1]["number"], d["sections"][1]["blocks"][0]["number"]
    ([['R ', ''], ['1', 'sub']], '1', '1')
    >>> round(d["sections"][1]["blocks"][0]["width"], 2)        # scaled to fit the page
    4.62
    """
    check_paper(paper)
    metadata = dict(metadata or {})
    sections = [{"number": s.number, "level": 0 if s.level == 0 else 1 + s.number.count("."),
                 "title": _runs(s.title), "blocks": [_block(b, paper, sizes) for b in s.blocks],
                 "flush": bool(s.flush)} for s in outline.sections]
    return {"paper": _TYPST_PAPER[paper], "margins": list(MARGINS),
            "title": _runs(outline.title), "plain_title": markup.plain(outline.title),
            "author": markup.plain(metadata.get("Author", "")),
            "subject": markup.plain(metadata.get("Subject", "")),
            "keywords": [markup.plain(metadata["Keywords"])] if metadata.get("Keywords")
            else [],
            "footer": markup.plain(footer), "colours": TABLE_COLOURS, "sections": sections}


def write_pdf(outline: Outline, figures: Mapping[str, tuple[str, tuple[float, float]]],
              path: str | os.PathLike[str], paper: str = "a4",
              metadata: Mapping[str, Any] | None = None, footer: str = "",
              created: str | None = None) -> int:
    """Typeset a report's outline and write it as a PDF.

    Parameters
    ----------
    outline : gd_analyze.report.sections.Outline
        The report's sections (the HTML renders the same).
    figures : dict of str to (str, (float, float))
        Each figure of the outline: its SVG text and its size [in].
    path : str or os.PathLike
        The PDF file (written as given: the caller stages it).
    paper : {"a4", "letter"}, optional
        The size of every page.
    metadata : dict, optional
        ``Author``, ``Subject``, ``Keywords`` (the provenance: version, inputs' SHA-256,
        settings) of the document information; Typst names itself as its creator.
    footer : str, optional
        Text at the foot of every page, before "page k of K".
    created : str, optional
        The creation time, ISO 8601 UTC ("2026-11-24T21:21:10Z"); none recorded if not given.

    Returns
    -------
    int
        The number of pages.

    Raises
    ------
    ValueError
        If ``paper`` is unknown.
    RuntimeError
        If Typst fails (a section numbered otherwise than the outline numbers it).
    OSError
        If the file cannot be written.

    Notes
    -----
    Typst lays a document out again until what its figures' placement reads (positions,
    pages) stops changing, at most five times. Where the plain setting does not settle (a
    figure set inline in one pass and at the next page's top in the next, as in the SO-101's
    report of example-robot-data), the tighter setting is tried, then the one with no figure
    floating past a heading; the first that settles is kept (its warnings issued only if none
    does).
    """
    data = document_data(outline, {k: size for k, (_, size) in figures.items()}, paper,
                         metadata, footer)
    svgs = {f"gd-figure-{k}": svg for k, (svg, _) in figures.items()}

    def typeset(**flags):
        inputs = {"gd-data": json.dumps({**data, **flags}, ensure_ascii=False), **svgs}
        return _compile("report.typ", inputs, created, end=True)

    pdf, end = typeset()
    kept: dict[str, bool] = {}

    def again(better, **flags):
        # set again with these flags too, kept if better and Typst's layout settled (a
        # figure's placement may differ between its last two passes)
        nonlocal pdf, end
        tried, where = typeset(**kept, **flags)
        if better(where) and not where["warnings"]:
            pdf, end = tried, where
            kept.update(flags)

    for flags in ({"tight": True}, {"barrier": True}):
        if end["warnings"]:     # a layout that did not settle: tighter, else no float past a heading
            again(lambda e: True, **flags)
    if end["page"] > 1 and end["alone"]:
        # a last page holding a figure alone: no figure floating past the next heading (the
        # figure heads its page with the rest of its section), if that ends no later
        again(lambda e: e["page"] <= end["page"] and not e["alone"], barrier=True)
    if end["page"] > 1 and end["fill"] < NEAR_EMPTY:
        # a last page of a few lines: set tighter, if that saves the page
        again(lambda e: e["page"] < end["page"], tight=True)
    if end["fill"] < NEAR_EMPTY and end["last"][0] == end["page"] - 1 and end["last"][1] >= .5:
        # still a few lines, of a last section begun in its page's lower half: that section
        # starts a page, if that fills the last page
        again(lambda e: e["page"] <= end["page"] and e["fill"] >= NEAR_EMPTY, turn=True)
    for message in end["warnings"]:
        warnings.warn(f"typst: {message}", RuntimeWarning, stacklevel=2)
    Path(path).write_bytes(pdf)
    return len(re.findall(rb"/Type\s*/Page\b", pdf))


#: Room kept between two figures at a page's top [in]: Typst's clearance of a float (1.5 em
#: of 10 pt text, 0.21 in) and some more.
FLOAT_GAP = 0.3


def figure_rooms(outline: Outline, figures: Mapping[str, tuple[str, tuple[float, float]]],
                 paper: str = "a4") -> dict[str, tuple[float, float]]:
    """The figures that go to the top of a later page than the text citing them, for want of
    room under that text, as the report is first set (:func:`write_pdf`).

    Parameters
    ----------
    outline : gd_analyze.report.sections.Outline
        The report's sections.
    figures : dict of str to (str, (float, float))
        Each figure of the outline: its SVG text and its size [in].
    paper : {"a4", "letter"}, optional
        The page size.

    Returns
    -------
    dict of str to (float, float)
        By figure key: the room left on the page under the text citing it and the height the
        figure needs there with its caption [in], the figure set at its printed width
        (:func:`printed_width`). A figure that waits for an earlier one (the figures keep
        their order) gets the room that one leaves on the page it heads, less
        :data:`FLOAT_GAP`.

    Raises
    ------
    ValueError
        If ``paper`` is unknown.
    RuntimeError
        If Typst fails.
    """
    data = document_data(outline, {k: size for k, (_, size) in figures.items()}, paper)
    inputs = {"gd-data": json.dumps({**data, "rooms": True}, ensure_ascii=False),
              **{f"gd-figure-{k}": svg for k, (svg, _) in figures.items()}}
    end = _compile("report.typ", inputs, None, end=True)[1]
    rooms: dict[str, tuple[float, float]] = {}
    for r in end["rooms"]:
        if r["after"] is None:
            rooms[r["key"]] = (float(r["room"]), float(r["need"]))
        elif r["after"] in rooms:       # under the figure it waits for, at a page's top
            rooms[r["key"]] = (body_height(paper) - rooms[r["after"]][1] - FLOAT_GAP,
                               float(r["need"]))
    return rooms


def figure_pdfs(figures: Mapping[str, tuple[str, tuple[float, float]]],
                created: str | None = None) -> dict[str, bytes]:
    """Each figure as a one-page PDF of its own size, typeset by Typst from its SVG.

    Parameters
    ----------
    figures : dict of str to (str, (float, float))
        Each figure's SVG text (from :func:`gd_analyze.report.drawing.figure_svg`) and its
        size [in], by key; the key is the PDF's title.
    created : str, optional
        The creation time, ISO 8601 UTC; the time of the run if not given.

    Returns
    -------
    dict of str to bytes
        The PDF of each figure: the SVG embedded as vector graphics, as the reports embed it,
        its text set in DejaVu Sans (the font matplotlib measured it in) as a TrueType subset,
        so that no figure file holds a Type 3 font.

    Raises
    ------
    RuntimeError
        If Typst fails (an SVG it cannot read).

    Notes
    -----
    The fixed template ``templates/figure.typ`` reads the SVG, the size and the title as data
    (``sys.inputs``); the fonts are loaded once per process (:func:`fonts_loaded`).
    """
    return {k: _compile("figure.typ", {"gd-figure": svg, "gd-width": repr(float(size[0])),
                                       "gd-height": repr(float(size[1])), "gd-title": str(k)},
                        created)[0]
            for k, (svg, size) in figures.items()}


def _timestamp(created):
    """A timezone-aware datetime from an ISO 8601 time, or None."""
    if not created:
        return None
    from datetime import datetime, timezone

    t = datetime.fromisoformat(str(created).replace("Z", "+00:00"))
    return t if t.tzinfo else t.replace(tzinfo=timezone.utc)
