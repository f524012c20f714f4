"""Table cells of the PDF page engine: column widths and line breaks from the drawn widths of
the words (DejaVu Sans, as :mod:`gd_analyze.reports.pages` draws them).

A cell breaks only at spaces (a no-break space holds "N\u00a0m" or
"|\u03c4\u209b\u00a0\u2212\u00a0\u03c4|" together); a column is at least as wide as its widest word, so no heading breaks mid-word and
no cell runs into its neighbour.
"""

from __future__ import annotations

import functools

import numpy as np

__all__ = ["column_widths", "wrap_cell", "words", "word_width"]


@functools.cache
def word_width(word, size, bold):
    """Drawn width of one word.

    Parameters
    ----------
    word : str
        One word (no space).
    size : float
        Type size [pt].
    bold : bool
        Bold type (a table's header).

    Returns
    -------
    float
        The width [in] of the word in DejaVu Sans, its glyphs' advances as the text pages draw
        them (:func:`gd_analyze.reports.text_pages.text_width`); a sub- or superscript run
        (:func:`gd_analyze.reports.markup.runs`) at its smaller size.
    """
    from .text_pages import text_width

    return text_width(word, size, bold)


def words(text):
    """The words of a cell, split at spaces only.

    Parameters
    ----------
    text : object
        The cell (converted with ``str``).

    Returns
    -------
    list of str
        Its words; a no-break space does not split ("N\u00a0m" is one word).

    Examples
    --------
    >>> words("peak error [N\u00a0m]")
    ['peak', 'error', '[N\u00a0m]']
    """
    return [w for w in str(text).split(" ") if w]


def wrap_cell(text, width, size, bold):
    """The lines of a table cell.

    Parameters
    ----------
    text : object
        The cell.
    width : float
        The room in its column [in].
    size : float
        Type size [pt].
    bold : bool
        Bold type.

    Returns
    -------
    list of str
        Its words, broken only at spaces, filled greedily to ``width`` by their drawn widths;
        a word wider than the column stands alone on its line (:func:`column_widths` makes
        every column wide enough for its widest word).
    """
    ws = words(text)
    if not ws:
        return [""]
    space = word_width("a a", size, bold) - 2 * word_width("a", size, bold)
    lines, line, used = [], [ws[0]], word_width(ws[0], size, bold)
    for w in ws[1:]:
        ww = word_width(w, size, bold)
        if used + space + ww <= width:
            line.append(w)
            used += space + ww
        else:
            lines.append(" ".join(line))
            line, used = [w], ww
    lines.append(" ".join(line))
    return lines


def column_widths(table, width, size, pad):
    """The widths of a table's columns on the page.

    Parameters
    ----------
    table : dict
        As :func:`gd_analyze.reports.common.table` makes it (``header``, ``rows``,
        ``widths``: relative widths).
    width : float
        The width of the text [in].
    size : float
        Type size [pt].
    pad : float
        Padding on either side of a cell [in].

    Returns
    -------
    ndarray, shape (columns,)
        Widths [in] summing to ``width``: the relative widths, each column raised to hold its
        widest word (drawn widths, the header in bold) and the others shrunk in proportion,
        never below their own widest word; in proportion to the widest words if even those do
        not fit.
    """
    share = np.asarray(table["widths"], float)
    share = share / share.sum()
    need = np.array([max([word_width(w, size, True) for w in words(table["header"][k])]
                         + [word_width(w, size, False) for row in table["rows"]
                            for w in words(row[k])] + [0.0]) + 2 * pad + 1e-3
                     for k in range(share.size)])
    if need.sum() >= width:                 # no room: in proportion to the widest words
        return need / need.sum() * width
    widths = share * width
    fixed = np.zeros(share.size, bool)
    for _ in range(share.size):             # raise the narrow ones, take it from the rest
        fixed |= widths < need
        if fixed.all():
            return need + (width - need.sum()) * share
        free = width - need[fixed].sum()
        widths = np.where(fixed, need, share / share[~fixed].sum() * free)
        if not np.any(widths < need - 1e-12):
            break
    return widths
