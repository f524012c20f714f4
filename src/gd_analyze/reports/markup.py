"""Mathematics in the reports' text: subscripts and superscripts, written once, shown as HTML
tags in ``report.html`` and in ``report.pdf`` as Unicode sub- and superscript characters, or,
for a span with a letter that has none (the d of q_d, the b of Y_b), as a run of smaller,
lowered or raised glyphs that the PDF page engine draws (:func:`runs`).

A string of a report's context may hold spans marked with :func:`sub` and :func:`sup` (private
use characters; :func:`clean` drops them from the dataset's text attributes that
:func:`gd_analyze.reports.common.attr` reads, such as robot and file names). The HTML
renderer turns them into ``<sub>``/``<sup>`` (:func:`html`, every other character escaped);
the PDF page engine into the Unicode characters of DejaVu Sans where every character of the
span has one (:func:`unicode`), else it keeps the span marked and draws it as a run
(:func:`runs`); :func:`plain` drops the marks (tests, search).

Examples
--------
>>> s = "peak |" + element("D", "ij", "tran") + "|"
>>> plain(s)
'peak |Dijtran|'
>>> unicode(s)
'peak |Dᵢⱼᵗʳᵃⁿ|'
>>> str(html(s))
'peak |D<sub>ij</sub><sup>tran</sup>|'
>>> runs(unicode("q" + sub("d") + "(0)"))
[('q', None), ('d', 'sub'), ('(0)', None)]
"""

from __future__ import annotations

import re

__all__ = ["SUB", "SUP", "END", "sub", "sup", "element", "tau", "html", "unicode", "runs",
           "plain", "clean", "label", "scope", "TRAN", "ROT", "RUN_SIZE", "RUN_SHIFT"]

#: Start of a subscript, start of a superscript, end of either (Unicode private use area).
SUB, SUP, END = "\ue000", "\ue001", "\ue002"
_MARKS = re.compile(f"([{SUB}{SUP}])([^{END}]*){END}")
_SUBSCRIPT = dict(zip("0123456789ijsnkmtxaeorplhuv+-=()\u2212,",
                      "\u2080\u2081\u2082\u2083\u2084\u2085\u2086\u2087\u2088\u2089"
                      "\u1d62\u2c7c\u209b\u2099\u2096\u2098\u209c\u2093\u2090\u2091\u2092"
                      "\u1d63\u209a\u2097\u2095\u1d64\u1d65\u208a\u208b\u208c\u208d\u208e"
                      "\u208b,"))
_SUPERSCRIPT = dict(zip("0123456789tranoim+-\u2212",
                        "\u2070\u00b9\u00b2\u00b3\u2074\u2075\u2076\u2077\u2078\u2079"
                        "\u1d57\u02b3\u1d43\u207f\u1d52\u2071\u1d50\u207a\u207b\u207b"))


def sub(text):
    """``text`` marked as a subscript.

    Parameters
    ----------
    text : str

    Returns
    -------
    str
    """
    return f"{SUB}{text}{END}"


def sup(text):
    """``text`` marked as a superscript.

    Parameters
    ----------
    text : str

    Returns
    -------
    str
    """
    return f"{SUP}{text}{END}"


def scope(statement):
    """A guarantee's statement (plain text, ``s_i``) as the reports write it: s with subscript i.

    Parameters
    ----------
    statement : str
        :meth:`~gd_analyze.core.selection.guarantee.Guarantee.statement`.

    Returns
    -------
    str

    Examples
    --------
    >>> scope("within 1 % of s_i") == "within 1 % of s" + sub("i")
    True
    """
    return re.sub(r"\bs_i\b", sub("i").join(("s", "")), statement)


def element(symbol, index, part=None):
    """An element symbol with its index as a subscript and its part as a superscript.

    Parameters
    ----------
    symbol : str
        ``"D"``, ``"h"``, ``"c"`` or ``"\u03c4"``.
    index : str
        ``"ij"``, ``"i"``, ``"12"`` ... (a label's digits, "1,10" for n >= 10).
    part : {None, "tran", "rot", "arm"}, optional
        The G-D part (Eqs. (3.4-25) to (3.4-28) of Fu, Gonzalez & Lee 1987), or the drives'
        armature.

    Returns
    -------
    str
        E.g. D_ij^tran, marked.
    """
    return symbol + (sub(index) if index else "") + (sup(part) if part else "")


def tau(index=None, simplified=False):
    """The torque symbol: \u03c4, \u03c4_i, or \u03c4_s (the simplified model's torque).

    Parameters
    ----------
    index : str, optional
        The joint index ("i", "3").
    simplified : bool, optional
        The simplified model's torque \u03c4\u209b.

    Returns
    -------
    str
    """
    return "\u03c4" + (sub("s") if simplified else "") + (sub(index) if index else "")


def label(text):
    """An element's label as figures letter it: mathematics in Unicode sub- and superscript
    characters (no mathtext to parse), from the label of
    :func:`gd_analyze.core.selection.labels.element_label`.

    Parameters
    ----------
    text : str
        ``"D12"``, ``"D1,10"`` (n >= 10: the comma of the label rule stays), ``"h3"``, or a
        symbol with its part and index, ``"D_ij^tran"`` (index after ``_``, part after ``^``).

    Returns
    -------
    str
        ``"D\u2081\u2082"``, ``"D\u2081,\u2081\u2080"``, ``"h\u2083"``,
        ``"D\u1d62\u2c7c\u1d57\u02b3\u1d43\u207f"``; any other text unchanged.

    Examples
    --------
    >>> label("D12"), label("D1,10"), label("h3"), label("D_ij^tran"), label("joint 1")
    ('D₁₂', 'D₁,₁₀', 'h₃', 'Dᵢⱼᵗʳᵃⁿ', 'joint 1')
    """
    m = _LABEL.fullmatch(str(text))
    if m is None:
        return str(text)
    return unicode(element(m.group(1), m.group(2) or m.group(3) or "", m.group(4)))


_LABEL = re.compile(r"([Dhc\u03c4X])(?:([1-9][0-9]*(?:,[1-9][0-9]*)?)|_([a-z0-9,]+))?"
                    r"(?:\^(tran|rot))?")


def html(text):
    """The marked string as HTML: escaped, with ``<sub>`` and ``<sup>`` tags.

    Parameters
    ----------
    text : str

    Returns
    -------
    markupsafe.Markup
    """
    from markupsafe import Markup, escape

    out, pos = [], 0
    for m in _MARKS.finditer(text):
        out.append(str(escape(text[pos:m.start()])))
        tag = "sub" if m.group(1) == SUB else "sup"
        out.append(f"<{tag}>{escape(m.group(2))}</{tag}>")
        pos = m.end()
    out.append(str(escape(text[pos:])))
    return Markup("".join(out).replace(SUB, "").replace(SUP, "").replace(END, ""))


#: A run's type size, a fraction of its line's, and its baseline shift [fraction of the
#: line's size]: subscripts lowered, superscripts raised (as LaTeX's \scriptsize runs).
RUN_SIZE = 0.7
RUN_SHIFT = {"sub": -0.22, "sup": 0.38}


def unicode(text):
    """The marked string with its marked spans as Unicode sub- and superscript characters; a
    span with a character that has none (such as the d of q_d) stays marked, for the PDF page
    engine to draw as a run of smaller glyphs (:func:`runs`), never as ``_d``.

    Parameters
    ----------
    text : str

    Returns
    -------
    str
    """
    if SUB not in text and SUP not in text:
        return text.replace(END, "")

    def one(m):
        table = _SUBSCRIPT if m.group(1) == SUB else _SUPERSCRIPT
        if all(c in table for c in m.group(2)):
            return "".join(table[c] for c in m.group(2))
        return _KEEP[m.group(1)] + m.group(2) + _KEEP[END]       # no such characters: a run

    out = _MARKS.sub(one, text).replace(SUB, "").replace(SUP, "").replace(END, "")
    return out.translate({ord(v): k for k, v in _KEEP.items()})


#: Stand-ins for the marks of a kept span while :func:`unicode` drops stray marks.
_KEEP = {SUB: "\ue003", SUP: "\ue004", END: "\ue005"}


def runs(text):
    """The pieces of a string as the PDF page engine draws them.

    Parameters
    ----------
    text : str
        As :func:`unicode` returns it (marked spans left only where Unicode has no
        characters).

    Returns
    -------
    list of (str, {None, "sub", "sup"})
        The text in order: plain pieces, and sub- or superscript runs (drawn at
        :data:`RUN_SIZE` of the line's size, shifted by :data:`RUN_SHIFT`).
    """
    out, pos = [], 0
    for m in _MARKS.finditer(text):
        if m.start() > pos:
            out.append((clean(text[pos:m.start()]), None))
        out.append((m.group(2), "sub" if m.group(1) == SUB else "sup"))
        pos = m.end()
    if pos < len(text) or not out:
        out.append((clean(text[pos:]), None))
    return [(t, k) for t, k in out if t] or [("", None)]


def plain(text):
    """The marked string without its marks.

    Parameters
    ----------
    text : str

    Returns
    -------
    str
    """
    return clean(text)


def clean(text):
    """Text without the marks of this module: what a name read from a file becomes before it
    reaches a report.

    Parameters
    ----------
    text : str

    Returns
    -------
    str
    """
    return str(text).replace(SUB, "").replace(SUP, "").replace(END, "")


#: The translational and rotational parts of an element X, as figures letter them.
TRAN, ROT = label("X^tran"), label("X^rot")
