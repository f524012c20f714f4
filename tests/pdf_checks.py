"""Reading a written PDF as a reader's tools see it: poppler's pdfinfo, pdffonts and pdftotext.

Shared by the tests of the typeset reports (tests/report/test_typeset.py and the report
tests): the document information, the fonts and their types, the text, and every word's box on
its page (``pdftotext -bbox``).
"""

from __future__ import annotations

import functools
import html
import os
import re
import subprocess

__all__ = ["info", "font_types", "text", "words", "page_texts", "printed_sizes", "page_lines",
           "figure_pages", "last_page_fill", "CITATION"]


def _version(path):
    """(time [ns], size) of a file as it is now, or None if there is none: a file written
    again is read again by the cached readers below."""
    if not os.path.isfile(path):
        return None
    st = os.stat(path)
    return st.st_mtime_ns, st.st_size


def _run(*args):
    """A poppler tool's output on the file among its arguments, run once per file version and
    process (the report tests read the same shared reports many times)."""
    return _run_once(args, _version(next((a for a in args if os.path.isfile(a)), "")))


@functools.lru_cache(maxsize=128)
def _run_once(args, version):
    try:
        return subprocess.run(args, check=True, capture_output=True, text=True).stdout
    except FileNotFoundError:       # one clear line, not a traceback per test
        import pytest

        pytest.fail(f"poppler's {args[0]} is not installed: run `bash .ci/system-packages` "
                    "(apt-get install poppler-utils)", pytrace=False)


def info(path):
    """pdfinfo's fields, e.g. ``{"Creator": "Typst 0.15.1", "Pages": "8", ...}``."""
    out = {}
    for line in _run("pdfinfo", str(path)).splitlines():
        key, sep, value = line.partition(":")
        if sep:
            out[key.strip()] = value.strip()
    return out


def font_types(path):
    """{font name: type} of every font pdffonts lists ("CID TrueType", "Type 3" ...)."""
    lines = _run("pdffonts", str(path)).splitlines()
    if len(lines) < 2:
        return {}
    cols = [m.span() for m in re.finditer(r"-+", lines[1])]
    return {line[slice(*cols[0])].strip(): line[slice(*cols[1])].strip() for line in lines[2:]}


def text(path):
    """The text pdftotext extracts (pages separated by form feeds)."""
    return _run("pdftotext", str(path), "-")


def words(path):
    """Per page: (width, height, [(word, x0, y0, x1, y1), ...]) [pt, from the top left]."""
    pages = []
    for page in re.finditer(r'<page width="([\d.]+)" height="([\d.]+)">(.*?)</page>',
                            _run("pdftotext", "-bbox", str(path), "-"), flags=re.S):
        ws = [(html.unescape(m.group(5)), *map(float, m.group(1, 2, 3, 4)))
              for m in re.finditer(r'<word xMin="([\d.]+)" yMin="([\d.]+)" xMax="([\d.]+)" '
                                   r'yMax="([\d.]+)">(.*?)</word>', page.group(3))]
        pages.append((float(page.group(1)), float(page.group(2)), ws))
    return pages


def page_texts(path):
    """Each page's text as pypdf extracts it (a tuple of str), parsed once per file and
    process: pypdf's extraction takes about half a second a report, and the report tests read
    the same shared reports many times. A file written again (another size or time) is read
    again."""
    return _page_texts(os.fspath(path), _version(path))


@functools.lru_cache(maxsize=64)
def _page_texts(path, version):
    from pypdf import PdfReader

    return tuple(page.extract_text() for page in PdfReader(path).pages)


def printed_sizes(path):
    """(page, size [pt], font, text) of every text the PDF shows, its size the font size times
    the text and current transformation matrices' vertical scale (as printed, figures' scale
    included), read with pypdf."""
    from pypdf import PdfReader

    def mul(a, b):
        return [a[0] * b[0] + a[1] * b[2], a[0] * b[1] + a[1] * b[3],
                a[2] * b[0] + a[3] * b[2], a[2] * b[1] + a[3] * b[3]]

    out = []
    for p, page in enumerate(PdfReader(str(path)).pages, 1):
        def visit(t, cm, tm, font, size, p=p):
            if t.strip():
                m = mul(tm, cm)
                name = str(font.get("/BaseFont", "?")) if font else "?"
                out.append((p, size * (m[2] ** 2 + m[3] ** 2) ** 0.5, name.split("+")[-1],
                            t.strip()))
        page.extract_text(visitor_text=visit)
    return out


#: "Fig. 2" cites the report's own Fig. 2; "Fig. 3.10" (the book's) does not.
CITATION = re.compile(r"\bFig\. (\d+)(?![.\d]*\d)")


def page_lines(path, bottom_margin):
    """Per page: its lines of text above the footer (the bottom margin [in]), in reading
    order, from pdftotext's word boxes (a line: the words whose tops lie within 2 pt)."""
    pages = []
    for _, height, ws in words(path):
        foot = height - 72 * bottom_margin
        lines = []
        for word, x0, y0, _, y1 in sorted((w for w in ws if w[4] < foot),
                                          key=lambda w: (round(w[2] / 2), w[1])):
            if lines and abs(lines[-1][0] - y0) <= 2.0:
                lines[-1][1].append((x0, word))
            else:
                lines.append((y0, [(x0, word)]))
        pages.append([" ".join(w for _, w in sorted(ws_)) for _, ws_ in lines])
    return pages


def figure_pages(pages):
    """({figure: page of its first citation}, {figure: page of its caption}) of a report's
    :func:`page_lines`; pages from 1."""
    cited, placed = {}, {}
    for k, lines in enumerate(pages, 1):
        for line in lines:
            m = re.match(r"Figure (\d+)\. ", line)
            if m:
                placed.setdefault(int(m.group(1)), k)
            else:
                for n in CITATION.findall(line):
                    cited.setdefault(int(n), k)
    return cited, placed


def last_page_fill(path, margins):
    """How full the last page's body is: the foot of its lowest word above the footer, from
    the top margin, over the body's height; ``margins`` [in]: (left and right, top, bottom)."""
    _, height, ws = words(path)[-1]
    top, foot = 72 * margins[1], height - 72 * margins[2]
    lowest = max((w[4] for w in ws if w[4] < foot), default=top)
    return (lowest - top) / (foot - top)
