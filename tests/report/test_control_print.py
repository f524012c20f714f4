"""The control report of the PUMA 560 (its shipped trajectory, all defaults) as printed, read
from its PDF as a reader's tools see it (poppler's pdftotext, pypdf for the type sizes):

- every figure is cited in the text, and set on the page of its first citation or the next
  (Figs. 2 and 3 stood two and three pages after the text they belong to);
- no text, the figures' included, prints under 8 pt (the figures' subscripts of q_d, tau_s
  and tau_f, mathtext's, printed at 5.6 pt);
- no page ends with a heading, and the last page is not near-empty;
- the text layer reads q̈ and q̇ with their subscript d as one word, once ("q̈d", not
  "q̈q̈" nor "q̈ d"), and the subscripts s and i as letters, not Unicode's small ones.
"""

import re

import pytest
from pdf_checks import figure_pages, last_page_fill, page_lines, printed_sizes
from pdf_checks import text as pdf_text

from gd_analyze.report.typeset import MARGINS, MIN_PRINTED_PT, NEAR_EMPTY

#: Over 5 s on an idle machine (the shared PUMA 560 runs): run on one interpreter in CI.
pytestmark = pytest.mark.slow


@pytest.fixture(scope="module")
def pdf(shared_puma):
    folder, stem = shared_puma["control"]
    return folder / f"{stem}.pdf"


def _page_lines(path):
    """Per page: its lines of text above the footer, in reading order."""
    return page_lines(path, MARGINS[2])


def test_every_figure_on_the_page_of_its_first_citation_or_the_next(pdf):
    cited, placed = figure_pages(_page_lines(pdf))
    assert sorted(placed) == [1, 2, 3], placed
    assert set(cited) == set(placed), (cited, placed)
    for n, page in placed.items():
        assert cited[n] <= page <= cited[n] + 1, (n, cited[n], page)


def test_no_text_prints_under_8_pt(pdf):
    small = [s for s in printed_sizes(pdf) if s[1] < MIN_PRINTED_PT - 1e-6]
    assert not small, small[:5]


def test_last_page_is_not_near_empty(pdf):
    """The report ends on a page at least a third full (it ended on one holding the
    provenance table alone, 29 % full)."""
    assert last_page_fill(pdf, MARGINS) >= NEAR_EMPTY


def test_no_page_ends_with_a_heading(pdf):
    pages = _page_lines(pdf)
    for k, lines in enumerate(pages[:-1], 1):
        assert not re.fullmatch(r"\d+\. [A-Z].*", lines[-1]), (k, lines[-1])


def test_text_layer_reads_dotted_q_with_its_subscript_as_one_word(pdf):
    text = pdf_text(pdf)
    assert "v = q\u0308d + Kv (q\u0307d \u2212 q\u0307)" in text
    assert "(q, q\u0307, q\u0308)" in text
    assert not re.search("(q[\u0307\u0308])\\1", text)
    assert not re.search("q[\u0307\u0308] d", text)
    # tau_s and s_i set as letters with a subscript, not as Unicode's small letters
    assert "\u03c4s \u2212 \u03c4f" in text
    assert "\u209b" not in text and "\u1d62" not in text
