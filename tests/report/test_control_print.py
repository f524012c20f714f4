"""The control report of the PUMA 560 (its shipped trajectory, all defaults) as printed, read
from its PDF as a reader's tools see it (poppler's pdftotext, pypdf for the type sizes):

- the text layer reads q̈ and q̇ with their subscript d as one word, once ("q̈d", not
  "q̈q̈" nor "q̈ d").
"""

import re

import pytest

#: Over 5 s on an idle machine (the shared PUMA 560 runs): run on one interpreter in CI.
pytestmark = pytest.mark.slow


@pytest.fixture(scope="module")
def pdf(shared_puma):
    folder, stem = shared_puma["control"]
    return folder / f"{stem}.pdf"


def test_text_layer_reads_dotted_q_with_its_subscript_as_one_word(pdf):
    import subprocess

    text = subprocess.run(["pdftotext", str(pdf), "-"], check=True, capture_output=True,
                          text=True).stdout
    assert "v = q\u0308d + Kv (q\u0307d \u2212 q\u0307)" in text
    assert "(q, q\u0307, q\u0308)" in text
    assert not re.search("(q[\u0307\u0308])\\1", text)
    assert not re.search("q[\u0307\u0308] d", text)
