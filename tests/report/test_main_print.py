"""The main report of the PUMA 560 (its shipped trajectory, all defaults) and its sweep report
(the shared sweep of tests/conftest.py) as printed, read from their PDFs as a reader's tools see
them (poppler's pdftotext, pypdf for the type sizes):

- no text, the figures' included, prints under 8 pt;
- the text layer holds no Unicode subscript character (τₛ, sᵢ, D₁₂: small glyphs that print
  well under 8 pt in a 9 pt text): the text and tables set subscripts as such (τs in the text
  layer), the figures write their elements D(1,2), h(3) and the torque error Δτ.
"""

import re

import pytest
from pdf_checks import printed_sizes, text

from gd_analyze.report.typeset import MIN_PRINTED_PT

#: Over 5 s on an idle machine (the shared PUMA 560 run): run on one interpreter in CI.
pytestmark = pytest.mark.slow

#: Unicode's subscript characters: digits, signs and letters (U+2080-U+209C, U+1D62-U+1D6A,
#: U+2C7C).
_SUBSCRIPTS = re.compile("[\u2080-\u209c\u1d62-\u1d6a\u2c7c]")


@pytest.fixture(scope="module")
def pdf(shared_puma):
    folder, stem = shared_puma["puma"]
    return folder / f"{stem}.pdf"


def test_no_text_prints_under_8_pt(pdf):
    small = [s for s in printed_sizes(pdf) if s[1] < MIN_PRINTED_PT - 1e-6]
    assert not small, small[:5]


def _subscripts(path):
    layer = text(path)
    return layer, [layer[max(0, m.start() - 20):m.end() + 5]
                   for m in _SUBSCRIPTS.finditer(layer)]


def test_text_layer_has_no_unicode_subscripts(pdf):
    layer, found = _subscripts(pdf)
    assert not found, found[:8]
    # the subscripts as letters: tau_s in the text, the elements in the tables and figures
    assert "\u03c4s \u2212 \u03c4" in layer
    assert "D(1,1)" in layer and "h(1)" in layer


def test_sweep_report_prints_no_unicode_subscripts(shared_reports):
    folder, stem = shared_reports["sweep"]
    path = folder / f"{stem}.pdf"
    layer, found = _subscripts(path)
    assert not found, found[:8]
    assert "D(1,1)" in layer and "\u0394\u03c4" in layer
    small = [s for s in printed_sizes(path) if s[1] < MIN_PRINTED_PT - 1e-6]
    assert not small, small[:5]
