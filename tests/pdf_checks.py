"""Reading a written PDF as a reader's tools see it: poppler's pdfinfo, pdffonts and pdftotext.

Shared by the tests of the typeset reports (tests/report/test_typeset.py and the report
tests): the document information, the fonts and their types, the text, and every word's box on
its page (``pdftotext -bbox``).
"""

from __future__ import annotations

import html
import re
import subprocess

__all__ = ["info", "font_types", "text", "words"]


def _run(*args):
    return subprocess.run(args, check=True, capture_output=True, text=True).stdout


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
