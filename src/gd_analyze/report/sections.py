"""One list of sections per report, rendered by the Jinja template and typeset by Typst.

A report (main, sweep, control) builds its structure once as an :class:`Outline`: the title
block, then sections (number, title, level) each holding blocks: paragraphs, tables with a
numbered caption ("Table 5.2: ..."), figures with a numbered caption ("Figure 3. ..."), and
class counts. :func:`gd_analyze.report.typeset.write_pdf` typesets the outline as a PDF
(Typst numbers its sections, tables and figures, and checks them against the outline's); the
HTML templates render the same outline with the macros of ``templates/sections.j2``. Text may
hold the sub-, superscript and code marks of :mod:`gd_analyze.report.markup`.
"""

from __future__ import annotations

from collections.abc import Collection, Iterable, Mapping
from dataclasses import dataclass, field
from typing import Any

__all__ = ["Block", "Section", "Outline"]


@dataclass(frozen=True)
class Block:
    """One block of a section.

    Attributes
    ----------
    kind : {"paragraph", "table", "figure", "counts"}
    content : object
        The paragraph's text (str); the table (dict of :func:`gd_analyze.report.common.table`);
        the figure's key; the counts (dict class -> number).
    style : str
        Paragraph style, one of :data:`gd_analyze.report.typeset.PARAGRAPH_STYLES` (the PDF
        sets their sizes, ``templates/report.typ``; the HTML's classes have the same names);
        ``"kv"`` for an item/value table.
    number : str
        A table's number within its top-level section ("5.2") or a figure's ("3").
    text : str
        What a table or figure shows: its caption without the number.
    size : float
        A table's type size in the PDF [pt].
    """

    kind: str
    content: object
    style: str = "body"
    number: str = ""
    text: str = ""
    size: float = 7.5

    @property
    def caption(self) -> str:
        """str: a table's or figure's caption, numbered ("Table 5.2: ...", "Figure 3. ...")."""
        if self.kind == "table":
            return f"Table {self.number}: {self.text}"
        return f"Figure {self.number}. {self.text}" if self.kind == "figure" else ""


@dataclass
class Section:
    """A numbered section or subsection and its blocks.

    Attributes
    ----------
    number : str
        "5" or "5.1"; "" for the title block.
    title : str
    level : int
        0: the title block (the document's title); 1: a section; 2: a subsection.
    anchor : str
        The HTML id.
    blocks : list of Block
    flush : bool
        In the PDF, the figures still waiting are set before its heading (a section after a
        figure in several parts starts after its last part).
    """

    number: str
    title: str
    level: int
    anchor: str
    blocks: list = field(default_factory=list)
    flush: bool = False

    @property
    def heading(self) -> str:
        """str: "5. Title" or "5.1 Title" (the title alone for the title block)."""
        number = self.number + ("." if self.number and "." not in self.number else "")
        return f"{number} {self.title}".strip()


class Outline:
    """A report's sections in order, built once and rendered as HTML and PDF.

    Parameters
    ----------
    title : str
        The document's title (the title block's heading).
    figures : collection of str
        The keys of the figures that were drawn; a figure block for any other key is left out,
        so that HTML and PDF number the same figures.
    opening : iterable of (str, str), optional
        The paragraphs under the title, each (text, style) as :meth:`paragraph` takes them.

    Examples
    --------
    >>> o = Outline("Report", figures={"D"})
    >>> o.section("1", "Robot")
    >>> o.table({"header": ["a"], "rows": [], "align": ["left"], "widths": [1],
    ...          "colour_cols": []}, "joint placements")
    >>> o.figure("D", "elements of D")
    >>> o.figure("h", "not drawn")
    >>> [b.caption for b in o.sections[1].blocks]
    ['Table 1.1: joint placements', 'Figure 1. elements of D']
    """

    def __init__(self, title: str, figures: Collection[str] = (),
                 opening: Iterable[tuple[str, str]] = ()) -> None:
        self.title = title
        self.available = set(figures)
        self.sections = [Section("", title, 0, "top")]
        self._tables: dict[str, int] = {}
        self.n_figures = 0
        for text, style in opening:
            self.paragraph(text, style)

    def section(self, number: str, title: str, anchor: str | None = None,
                level: int | None = None, flush: bool = False) -> None:
        """Start a section ("5") or a subsection ("5.1").

        Parameters
        ----------
        number : str
            Its number.
        title : str
            Its title.
        anchor : str, optional
            The HTML id; from the number if not given.
        level : {1, 2}, optional
            From the number's dots if not given.
        flush : bool, optional
            In the PDF, set the figures still waiting before its heading.
        """
        level = level or (1 + str(number).count("."))
        self.sections.append(Section(str(number), title, level,
                                     anchor or "s" + str(number).replace(".", "-"),
                                     flush=flush))

    def _add(self, block):
        self.sections[-1].blocks.append(block)

    def paragraph(self, text: str, style: str = "body") -> None:
        """A paragraph; nothing if ``text`` is empty.

        Parameters
        ----------
        text : str
            May hold the marks of :mod:`gd_analyze.report.markup`.
        style : str, optional
            One of :data:`gd_analyze.report.typeset.PARAGRAPH_STYLES`.
        """
        if text:
            self._add(Block("paragraph", text, style))

    def table(self, table: dict[str, Any], caption: str, kv: bool = False,
              size: float = 7.5) -> None:
        """A table with its caption, numbered within its top-level section ("Table 5.2: ...").

        Parameters
        ----------
        table : dict
            As :func:`gd_analyze.report.common.table` makes it.
        caption : str
            What the table shows.
        kv : bool, optional
            An item/value table (its first column in bold in the HTML).
        size : float, optional
            Type size in the PDF [pt].
        """
        top = next((s.number.split(".")[0] for s in reversed(self.sections) if s.level == 1),
                   "0")
        k = self._tables[top] = self._tables.get(top, 0) + 1
        self._add(Block("table", table, "kv" if kv else "body", f"{top}.{k}", caption, size))

    def figure(self, key: str, caption: str) -> None:
        """A figure with its caption, numbered in document order.

        Parameters
        ----------
        key : str
            The figure's key; the block is left out if the figure was not drawn.
        caption : str
            What the figure shows.
        """
        if key in self.available:
            self.n_figures += 1
            self._add(Block("figure", key, number=str(self.n_figures), text=caption))

    def counts(self, counts: Mapping[str, int]) -> None:
        """The number of elements per class, each in its class colour.

        Parameters
        ----------
        counts : dict of str to int
            Class -> number of elements.
        """
        self._add(Block("counts", dict(counts)))
