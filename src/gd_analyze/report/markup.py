"""Mathematics and code in the reports' text: subscripts, superscripts and code, written once,
shown as HTML tags in ``report.html`` and typeset as such by Typst in ``report.pdf``
(:func:`spans`); figures write an element's index in parentheses, D(1,2), and its part as Unicode
superscript characters (:func:`label`): Unicode's subscript characters print under 8 pt.

A string of a report's context may hold spans marked with :func:`sub`, :func:`sup` and
:func:`code` (private use characters; :func:`clean` drops them from the dataset's text
attributes that :func:`gd_analyze.report.common.attr_text` writes, such as robot and file names).
The HTML renderer turns them into ``<sub>``/``<sup>``/``<code>`` (:func:`html`, every other
character escaped); the PDF renderer (:mod:`gd_analyze.report.typeset`) takes the spans of
:func:`spans` as data; :func:`unicode` gives the Unicode characters of a span where every
character has one (figures); :func:`plain` drops the marks (tests, search).

Examples
--------
>>> s = "peak |" + element("D", "ij", "tran") + "|"
>>> plain(s)
'peak |Dijtran|'
>>> unicode(s)
'peak |Dᵢⱼᵗʳᵃⁿ|'
>>> str(html(s))
'peak |D<sub>ij</sub><sup>tran</sup>|'
>>> spans("q" + sub("d") + "(0) in " + code("PREFIX_tau"))
[('q', None), ('d', 'sub'), ('(0) in ', None), ('PREFIX_tau', 'code')]
"""

from __future__ import annotations

import re
import unicodedata
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from markupsafe import Markup

__all__ = ["SUB", "SUP", "CODE", "END", "sub", "sup", "code", "element", "tau", "html",
           "unicode", "spans", "plain", "clean", "visible", "label", "marked", "scope", "powers"]

#: Start of a subscript, of a superscript, end of either, start of code (Unicode private use
#: area).
SUB, SUP, END, CODE = "\ue000", "\ue001", "\ue002", "\ue006"
_MARKS = re.compile(f"([{SUB}{SUP}{CODE}])([^{END}]*){END}")
_KIND = {SUB: "sub", SUP: "sup", CODE: "code"}
_SUBSCRIPT = dict(zip("0123456789ijsnkmtxaeorplhuv+-=()\u2212,",
                      "\u2080\u2081\u2082\u2083\u2084\u2085\u2086\u2087\u2088\u2089"
                      "\u1d62\u2c7c\u209b\u2099\u2096\u2098\u209c\u2093\u2090\u2091\u2092"
                      "\u1d63\u209a\u2097\u2095\u1d64\u1d65\u208a\u208b\u208c\u208d\u208e"
                      "\u208b,"))
_SUPERSCRIPT = dict(zip("0123456789tranoim+-\u2212",
                        "\u2070\u00b9\u00b2\u00b3\u2074\u2075\u2076\u2077\u2078\u2079"
                        "\u1d57\u02b3\u1d43\u207f\u1d52\u2071\u1d50\u207a\u207b\u207b"))


def sub(text: str) -> str:
    """``text`` marked as a subscript (nothing for an empty ``text``).

    Parameters
    ----------
    text : str

    Returns
    -------
    str
    """
    return f"{SUB}{text}{END}" if text else ""


def sup(text: str) -> str:
    """``text`` marked as a superscript.

    Parameters
    ----------
    text : str

    Returns
    -------
    str
    """
    return f"{SUP}{text}{END}"


def code(text: str) -> str:
    """``text`` marked as code: an identifier, a file name or a command, set in monospace.

    Parameters
    ----------
    text : str
        Set as it is: no sub- or superscripts inside.

    Returns
    -------
    str
        The marked span.

    Examples
    --------
    >>> str(html("in " + code("PREFIX_tau"))), plain(code("PREFIX_tau"))
    ('in <code>PREFIX_tau</code>', 'PREFIX_tau')
    """
    return f"{CODE}{text}{END}"


#: The simplified model's symbols as the core's plain-text statements write them, and the
#: letter each is set as with its subscript (s_i: the joint's torque scale), or qd, qdd dotted.
_STATEMENT_SYMBOLS = re.compile(r"\b(s_i|D_s|h_s|c_s|tau_s|tau_i|qdd|qd)\b")


def scope(statement: str) -> str:
    """A statement of the core (plain text: a guarantee's, a screen's, a proof's) as the
    reports write it: ``s_i`` as s with subscript i, ``D_s``, ``h_s``, ``c_s`` and ``tau_s``
    as D, h, c and tau with subscript s, ``tau_i`` as tau with subscript i; qd and qdd as q with one or two dots; a space
    before % as a non-breaking one (no line break between "1" and "%").

    Parameters
    ----------
    statement : str
        :meth:`~gd_analyze.simplify.guarantee.Guarantee.statement`, or a screen's or an
        inertia check's statement.

    Returns
    -------
    str

    Examples
    --------
    >>> scope("within 1 % of s_i") == "within 1\u00a0% of s" + sub("i")
    True
    >>> scope("the proof that D_s is positive definite") == (
    ...     "the proof that D" + sub("s") + " is positive definite")
    True
    >>> scope("|qd| and |qdd|, not qd_max") == "|q\u0307| and |q\u0308|, not qd_max"
    True
    """
    def symbol(m: re.Match[str]) -> str:
        letter, _, index = m.group(1).partition("_")
        return {"qd": "q\u0307", "qdd": "q\u0308", "tau": "\u03c4"}.get(letter, letter) + sub(index)
    return _STATEMENT_SYMBOLS.sub(symbol, statement).replace(" %", "\u00a0%")


def powers(text: str) -> str:
    """Unit powers written with a caret (``s^-1``, ``deg/s^2``) as superscripts, for the
    reports; nothing else changes.

    Parameters
    ----------
    text : str
        Plain text (already cleaned of markup when it came from a file).

    Returns
    -------
    str

    Examples
    --------
    >>> powers("2 s^-1 x qd max [deg/s^2]") == ("2 s" + sup("\u22121") + " x qd max [deg/s"
    ...                                          + sup("2") + "]")
    True
    """
    return re.sub(r"\^(-?\d+)", lambda m: sup(m.group(1).replace("-", "\u2212")), text)


def element(symbol: str, index: str, part: str | None = None) -> str:
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


def tau(index: str | None = None, simplified: bool = False) -> str:
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


def marked(text: str) -> str:
    """An element's label as the text and tables of the reports write it: its index marked as
    a subscript and its part as a superscript (set as such: 8 pt at least in the PDF), from
    the label of :func:`gd_analyze.ranking.labels.element_label`.

    Parameters
    ----------
    text : str
        ``"D12"``, ``"D1,10"`` (n >= 10: the comma of the label rule stays), ``"h3"``, or a
        symbol with its part and index, ``"D_ij^tran"`` (index after ``_``, part after ``^``).

    Returns
    -------
    str
        The marked label (:func:`element`); any other text unchanged.

    Examples
    --------
    >>> marked("D12") == "D" + sub("12"), marked("joint 1")
    (True, 'joint 1')
    """
    m = _LABEL.fullmatch(str(text))
    if m is None:
        return str(text)
    return element(m.group(1), m.group(2) or m.group(3) or "", m.group(4))


def label(text: str) -> str:
    """An element's label as figures letter it, without subscripts: the index in parentheses,
    as a matrix's entry, D(1,2), h(3), D(i,j) (Unicode's small subscript characters, and
    mathtext's scripts at 70 % of their text, print under the reports' 8 pt); a part as
    Unicode superscript characters. No mathtext to parse.

    Parameters
    ----------
    text : str
        ``"D12"``, ``"D1,10"`` (n >= 10), ``"h3"``, or a symbol with its part and index,
        ``"D_ij^tran"`` (index after ``_``, part after ``^``).

    Returns
    -------
    str
        ``"D(1,2)"``, ``"D(1,10)"``, ``"h(3)"``, ``"D(i,j)\u1d57\u02b3\u1d43\u207f"``; any
        other text unchanged.

    Examples
    --------
    >>> label("D12"), label("D1,10"), label("h3"), label("D_ij^tran"), label("joint 1")
    ('D(1,2)', 'D(1,10)', 'h(3)', 'D(i,j)ᵗʳᵃⁿ', 'joint 1')
    """
    m = _LABEL.fullmatch(str(text))
    if m is None:
        return str(text)
    index = m.group(2) or m.group(3) or ""
    if index and "," not in index and (m.group(1) == "D" or m.group(3)) and len(index) == 2:
        index = ",".join(index)                         # D12 -> 1,2; D_ij -> i,j
    return (m.group(1) + (f"({index})" if index else "")
            + unicode(sup(m.group(4)) if m.group(4) else ""))


_LABEL = re.compile(r"([Dhc\u03c4X])(?:([1-9][0-9]*(?:,[1-9][0-9]*)?)|_([a-z0-9,]+))?"
                    r"(?:\^(tran|rot))?")


def html(text: str) -> Markup:
    """The marked string as HTML: escaped, with ``<sub>`` and ``<sup>`` tags.

    Parameters
    ----------
    text : str

    Returns
    -------
    markupsafe.Markup
    """
    from markupsafe import Markup, escape

    return Markup("".join(f"<{tag}>{escape(t)}</{tag}>" if tag else str(escape(t))
                          for t, tag in spans(text)))


def unicode(text: str) -> str:
    """The marked string with its marked spans as Unicode sub- and superscript characters; a
    span with a character that has none (such as the d of q_d) stays marked (its marks, never
    ``_d``); code stays as it is.

    Parameters
    ----------
    text : str

    Returns
    -------
    str
    """
    if SUB not in text and SUP not in text:
        return clean(text)

    def one(m):
        if m.group(1) == CODE:
            return m.group(2)
        table = _SUBSCRIPT if m.group(1) == SUB else _SUPERSCRIPT
        if all(c in table for c in m.group(2)):
            return "".join(table[c] for c in m.group(2))
        return _KEEP[m.group(1)] + m.group(2) + _KEEP[END]       # no such characters: kept marked

    out = clean(_MARKS.sub(one, text))
    return out.translate({ord(v): k for k, v in _KEEP.items()})


#: Stand-ins for the marks of a kept span while :func:`unicode` drops stray marks.
_KEEP = {SUB: "\ue003", SUP: "\ue004", END: "\ue005"}


def spans(text: str) -> list[tuple[str, str | None]]:
    """The pieces of a marked string, as the PDF renderer typesets them.

    Parameters
    ----------
    text : str

    Returns
    -------
    list of (str, {None, "sub", "sup", "code"})
        The text in order: plain pieces, and sub- and superscripts and code; stray marks
        dropped, empty pieces left out.
    """
    out: list[tuple[str, str | None]] = []
    pos = 0
    for m in _MARKS.finditer(text):
        out.extend(((clean(text[pos:m.start()]), None), (clean(m.group(2)), _KIND[m.group(1)])))
        pos = m.end()
    out.append((clean(text[pos:]), None))
    return [(t, k) for t, k in out if t]


def clean(text: str) -> str:
    """Text without the marks of this module: what a name read from a file becomes before it
    reaches a report.

    Parameters
    ----------
    text : str

    Returns
    -------
    str
    """
    return visible(str(text).translate(_DROP))


_DROP = dict.fromkeys(map(ord, SUB + SUP + END + CODE))
#: The marked string without its marks: :func:`clean`, by the name the writers read.
plain = clean


def visible(text: str) -> str:
    """Text with every format character (Unicode category Cf: the bidirectional controls
    such as U+202E RIGHT-TO-LEFT OVERRIDE, zero-width spaces and joiners, soft hyphens, the
    byte-order mark) written as ``[U+XXXX]``, so that a name read from a file cannot reorder
    or hide what a report shows.

    Parameters
    ----------
    text : str

    Returns
    -------
    str

    Examples
    --------
    >>> visible("joint\u202e1\u200b")
    'joint[U+202E]1[U+200B]'
    """
    text = str(text)
    if text.isascii():
        return text
    shown = {ord(c): f"[U+{ord(c):04X}]" for c in set(text)
             if unicodedata.category(c) == "Cf"}  # each distinct character looked up once
    return text.translate(shown) if shown else text
