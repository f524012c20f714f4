"""Hostile robot names and descriptions in the HTML and PDF reports (issue 16, item 1).

The HTML shows them as text only (autoescape: no element or attribute comes from them); the
PDF shows them as literal text (no mathtext), whole in its text and metadata, and a long one
cannot push the footer over the page number.
"""

import json
import re
from html.parser import HTMLParser
from importlib import resources

import numpy as np
import pytest

from gd_analyze import load_robot
from gd_analyze.io.planning import plan_quintic
from gd_analyze.io.schema import write_dataset
from gd_analyze.reports import main as report
from gd_analyze.reports.pages import Document
from gd_analyze.workflows.analyze import analyze
from gd_analyze.workflows.options import AnalysisOptions

#: A name that would open a script element, end an attribute, run mathtext, escape a PDF
#: string and end a C comment, long enough that the footer cannot hold it.
NAME = ('<script>alert(1)</script><gdinjected onload="x"> \' " */ $\\frac{1}{0}$ ( ) \\ '
        '&amp; ??/ ' + "W" * 110)
DESCRIPTION = "line 1\nline 2 <gdinjected2> </td></tr></table> $x^$ \u2028 \\) Tj"


class _Collect(HTMLParser):
    """Every start tag with its attributes, and the text of the document (unescaped)."""

    def __init__(self):
        super().__init__()
        self.tags, self.text = [], []

    def handle_starttag(self, tag, attrs):
        self.tags.append((tag, attrs))

    def handle_data(self, data):
        self.text.append(data)


def _footers(path):
    """Per page: (footer text, its x, the page number's x) [pt], from the PDF's text objects."""
    from pypdf import PdfReader

    pages = []
    for page in PdfReader(path).pages:
        runs = []
        page.extract_text(visitor_text=lambda text, cm, tm, font, size: runs.append(
            (text, cm[4] + tm[4], cm[5] + tm[5], size)) if text.strip() else None)
        number, bottom = [(x, y) for t, x, y, _ in runs
                          if re.fullmatch(r"page \d+ of \d+", t.strip())][-1]
        foot = sorted((x, t) for t, x, y, s in runs
                      if abs(y - bottom) < 0.5 and s == 7 and x < number)
        pages.append(("".join(t for _, t in foot), foot[0][0], number))
    return pages


def _width(text, size):
    """Drawn width [pt] of a line of DejaVu Sans (the text pages' font), from its glyphs."""
    import warnings

    from matplotlib.font_manager import FontProperties
    from matplotlib.textpath import text_to_path

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return text_to_path.get_text_width_height_descent(
            text, FontProperties(family="DejaVu Sans", size=size), ismath=False)[0]


@pytest.fixture(scope="module")
def hostile_report(tmp_path_factory):
    folder = tmp_path_factory.mktemp("hostile")
    src = resources.files("gd_analyze").joinpath("data/two-link.toml").read_text("utf-8")
    src = src.replace('name = "two-link"', f"name = {json.dumps(NAME)}", 1)
    src = re.sub(r'^description = .*$', lambda m: f"description = {json.dumps(DESCRIPTION)}",
                 src, count=1, flags=re.M)
    (folder / "robot.toml").write_text(src, encoding="utf-8")
    robot = load_robot(folder / "robot.toml")
    assert robot.name == NAME and robot.description == DESCRIPTION
    trajectory = plan_quintic(robot, [0.0, 0.0], [np.pi / 2, np.pi / 3], n_setpoints=21)
    write_dataset(analyze(robot, trajectory, AnalysisOptions(formulations=False)).dataset, folder / "results.h5")
    report.write_report(folder / "results.h5", folder / "out")
    return folder / "out"


def test_html_shows_hostile_text_as_text_only(hostile_report):
    html = (hostile_report / "report.html").read_text(encoding="utf-8")
    parser = _Collect()
    parser.feed(html)
    tags = {t for t, _ in parser.tags}
    assert "script" not in tags and not tags & {"gdinjected", "gdinjected2"}
    assert not any(name.startswith("on") for _, attrs in parser.tags for name, _ in attrs)
    text = "".join(parser.text)
    assert NAME in text                                  # whole, as text, after unescaping
    assert "<gdinjected2>" in re.sub(r"\s+", " ", text)


def test_pdf_shows_hostile_text_whole_and_the_footer_fits(hostile_report):
    from pypdf import PdfReader

    reader = PdfReader(hostile_report / "report.pdf")
    assert NAME in reader.metadata["/Title"] and NAME in reader.metadata["/Keywords"]
    whole = re.sub(r"\s+", "", "".join(p.extract_text() for p in reader.pages))
    assert re.sub(r"\s+", "", NAME) in whole             # wrapped in the text, but whole
    for text, x, number in _footers(hostile_report / "report.pdf"):
        assert text.startswith("gd-analyze") and "<script>" in text
        assert x + _width(text, 7) < number              # stops before "page k of K"


def test_long_footer_is_cut_before_the_page_number(tmp_path):
    from gd_analyze.reports.pages import _fit_line

    footer = "gd-analyze: " + NAME + " " + "M" * 200
    doc = Document("A title", footer=footer)
    doc.heading("1. Section")
    doc.paragraph("word " * 2000)
    K = doc.write(tmp_path / "doc.pdf")
    footers = _footers(tmp_path / "doc.pdf")
    assert len(footers) == K > 1
    # the line drawn is the footer cut and ended by an ellipsis (the extracted glyphs of the
    # embedded font subset differ between matplotlib versions, so the cut is checked on the
    # line itself and the extracted text only for its start and its extent)
    cut = _fit_line(footer, 7, 5.0)
    assert cut.endswith("\u2026") and footer.startswith(cut[:-1]) and len(cut) < len(footer)
    for text, x, number in footers:
        assert text.startswith("gd-analyze: <script>") and len(text) < len(footer)
        assert x + _width(text, 7) < number


#: Folders in a command line: quotes, a script element, mathtext, a PDF string's end.
HOSTILE_DIR = "x'\" <script>alert(2)</script><gdinjected3 onload=\"y\"> $\\frac{1}{0}$ ) Tj"


@pytest.fixture(scope="module")
def hostile_control(tmp_path_factory):
    """The control report of a run whose trajectory lies in a hostile folder: its command line
    (stored in control.h5 and shown in the provenance) and paths carry the hostile text."""
    import shlex

    from gd_analyze.cli import main

    tmp = tmp_path_factory.mktemp("control")
    folder = tmp / HOSTILE_DIR                   # "</script>" makes a sub-folder: the path
    folder.mkdir(parents=True)                   # still reads "<script>...</script>"
    csv = str(folder / "traj.csv")
    assert main(["plan", "two-link", "-o", csv, "--setpoints", "11"]) == 0
    assert main(["two-link", csv, "-o", str(tmp / "main"), "-q", "--no-report"]) == 0
    argv = ["control", str(tmp / "main" / "simplified_model.json"), csv,
            "-o", str(tmp / "control"), "-q"]
    assert main(list(argv)) == 0
    return tmp / "control", shlex.join(["gd-analyze", *argv])


def test_control_report_shows_a_hostile_command_line_as_text(hostile_control):
    from pypdf import PdfReader

    out, command = hostile_control
    assert "<script>" in command and "$" in command
    html = (out / "control_report.html").read_text(encoding="utf-8")
    parser = _Collect()
    parser.feed(html)
    tags = {t for t, _ in parser.tags}
    assert "script" not in tags and "gdinjected3" not in tags
    assert not any(name.startswith("on") for _, attrs in parser.tags for name, _ in attrs)
    assert command in "".join(parser.text)               # whole, as text, after unescaping
    reader = PdfReader(out / "control_report.pdf")
    whole = re.sub(r"\s+", "", "".join(p.extract_text() for p in reader.pages))
    assert re.sub(r"\s+", "", command) in whole          # literal (no mathtext), wrapped
