"""Reading the HTML reports back in tests: the text outside the figures, and tables' cells.

One reading for every report test (main, sweep and control reports): tags stripped, entities
decoded, the inline SVG figures left out (their lettering is the figures' business).
"""

import re
from html import unescape


def without_figures(html):
    """The HTML without its inline SVG figures."""
    return re.sub(r"<svg.*?</svg>", "", html, flags=re.S)


def html_text(html, nbsp=False):
    """The document's text outside the figures: tags stripped, runs of white space made one
    space, entities decoded; no-break spaces made plain spaces if ``nbsp``."""
    text = unescape(re.sub(r"\s+", " ", re.sub(r"<[^>]+>", " ", without_figures(html))))
    return text.replace("\u00a0", " ") if nbsp else text


def row_cells(row, nbsp=False, cell=r"t[dh]"):
    """The texts of a table row's cells (``cell``: the tag pattern, td or th by default)."""
    cells = [unescape(re.sub(r"<[^>]+>", "", c)) for c in
             re.findall(rf"<{cell}[^>]*>(.*?)</{cell}>", row, flags=re.S)]
    return [(c.replace("\u00a0", " ") if nbsp else c).strip() for c in cells]


def table_rows(table, nbsp=False, cell=r"t[dh]"):
    """Every row of an HTML fragment as the texts of its cells."""
    return [row_cells(r, nbsp, cell) for r in re.findall(r"<tr[^>]*>(.*?)</tr>", table,
                                                         flags=re.S)]


def html_table(html, start, cell=r"t[dh]", nbsp=False):
    """Rows of cells, the header row first, of the first table at or after the text ``start``
    (a caption's first words, or ``id="..."`` of the table's section); no-break spaces made
    plain spaces if ``nbsp``."""
    rest = html[html.index(start):]
    return table_rows(rest[:rest.index("</table>")], nbsp, cell=cell)


def html_tables(html):
    """Every ``<table>`` of the document as rows of cell texts."""
    return [table_rows(t) for t in re.findall(r"<table.*?</table>", html, flags=re.S)]


def context_texts(value):
    """Every text of a report's context (the dict its HTML and PDF are rendered from), in
    order: its strings, those of its lists, tuples and dicts at any depth."""
    if isinstance(value, str):
        return [value]
    items = value.values() if isinstance(value, dict) else value if isinstance(
        value, (list, tuple)) else []
    return [s for v in items for s in context_texts(v)]
