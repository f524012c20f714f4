"""Hostile robot names and descriptions in the HTML and PDF reports.

The HTML shows them as text only (autoescape: no element or attribute comes from them); the
PDF shows them as literal text (no mathtext, no Typst markup: the name reaches the template as
data), whole in its text and metadata, and a long one cannot push the footer over the page
number.
"""

import dataclasses
import json
import re
import types
import unicodedata
from html.parser import HTMLParser
from importlib import resources

import numpy as np
import pytest
from pdf_checks import info, page_texts, words

from gd_analyze import load_robot
from gd_analyze.jobs.analyze import analyze
from gd_analyze.jobs.options import AnalysisOptions
from gd_analyze.report import main as report
from gd_analyze.report.sections import Outline
from gd_analyze.report.typeset import write_pdf
from gd_analyze.store.schema import write_dataset
from gd_analyze.trajectory.planning import plan_quintic

#: A name that would open a script element, end an attribute, run mathtext, escape a PDF
#: string, end a C comment and run Typst (a panic, strong text, mathematics, a closing
#: bracket), long enough that the footer cannot hold it.
NAME = ('<script>alert(1)</script><gdinjected onload="x"> \' " */ $\\frac{1}{0}$ ( ) \\ '
        '&amp; ??/ #panic("x") *bold* $x$ ] ' + "W" * 80)
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


def _pdf_text(path):
    """The PDF's text as pypdf extracts it: a hyphen that ends a line is kept (pdftotext
    joins the line to the next without it)."""
    return "".join(page_texts(path))


def _footers(path):
    """Per page: the words of the footer's visible line and the x where "page k of K" starts
    [pt], from the words' boxes (pdftotext -bbox)."""
    pages = []
    for w, h, ws in words(path):
        number = [(x0, y0) for k, (word, x0, y0, _, _) in enumerate(ws)
                  if word == "page" and y0 > h - 72 and re.fullmatch(r"\d+", ws[k + 1][0])][-1]
        foot = sorted((x0, word, x1) for word, x0, y0, x1, _ in ws
                      if abs(y0 - number[1]) < 0.5 and x0 < number[0])
        pages.append((foot, number[0]))
    return pages


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
    meta = info(hostile_report / "report.pdf")
    assert NAME in meta["Title"] and NAME in meta["Keywords"]
    assert meta["Creator"].startswith("Typst ")
    whole = re.sub(r"\s+", "", _pdf_text(hostile_report / "report.pdf"))
    assert re.sub(r"\s+", "", NAME) in whole             # wrapped in the text, but whole
    for foot, number in _footers(hostile_report / "report.pdf"):
        assert [word for _, word, _ in foot[:2]] == ["gd-analyze", "0.1.0:"] or \
            foot[0][1] == "gd-analyze"
        assert max(x1 for _, _, x1 in foot) < number    # stops before "page k of K"


def test_long_footer_stops_before_the_page_number(tmp_path):
    footer = "gd-analyze: " + NAME + " " + "M" * 200
    o = Outline("A title")
    o.section("1", "Section")
    for _ in range(8):
        o.paragraph("word " * 300)
    K = write_pdf(o, {}, tmp_path / "doc.pdf", footer=footer)
    footers = _footers(tmp_path / "doc.pdf")
    assert len(footers) == K > 1
    for foot, number in footers:
        assert foot[0][1] == "gd-analyze:" and "<script>alert(1)</script><gdinjected" in \
            "".join(word for _, word, _ in foot)
        assert max(x1 for _, _, x1 in foot) < number


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
    out, command = hostile_control
    assert "<script>" in command and "$" in command
    html = (out / "control_report.html").read_text(encoding="utf-8")
    parser = _Collect()
    parser.feed(html)
    tags = {t for t, _ in parser.tags}
    assert "script" not in tags and "gdinjected3" not in tags
    assert not any(name.startswith("on") for _, attrs in parser.tags for name, _ in attrs)
    assert command in "".join(parser.text)               # whole, as text, after unescaping
    whole = re.sub(r"\s+", "", _pdf_text(out / "control_report.pdf"))
    assert re.sub(r"\s+", "", command) in whole          # literal (no mathtext), wrapped


#: Joint names with format characters (Unicode Cf): U+202E RIGHT-TO-LEFT OVERRIDE, which
#: would show "1j" reversed and everything after it, and U+200B ZERO WIDTH SPACE, unseen.
BIDI_JOINTS = ("j\u202e1", "j\u200b2")


@pytest.fixture(scope="module")
def bidi_report(tmp_path_factory):
    folder = tmp_path_factory.mktemp("bidi")
    robot = load_robot("two-link")
    # as a URDF chain's description lists its joints (gd_analyze.model.urdf)
    robot = dataclasses.replace(robot, description=f"2 joints ({', '.join(BIDI_JOINTS)}), "
                                "mounted \u2066upside\u2069 down",
                                metadata=types.MappingProxyType(
                                    {**robot.metadata, "urdf_joints": list(BIDI_JOINTS)}))
    trajectory = plan_quintic(robot, [0.0, 0.0], [np.pi / 2, np.pi / 3], n_setpoints=21)
    write_dataset(analyze(robot, trajectory, AnalysisOptions(formulations=False)).dataset,
                  folder / "results.h5")
    report.write_report(folder / "results.h5", folder / "out")
    return folder / "out"


def _format_characters(text):
    return sorted({f"U+{ord(c):04X}" for c in text if unicodedata.category(c) == "Cf"})


def test_format_characters_are_shown_not_obeyed(bidi_report):
    """No bidi control or zero-width character reaches report.html, the PDF's text or its
    metadata raw: each is shown as [U+XXXX] where the name or description stands."""
    html = (bidi_report / "report.html").read_text(encoding="utf-8")
    assert _format_characters(html) == []
    for shown in ("j[U+202E]1", "j[U+200B]2", "mounted [U+2066]upside[U+2069] down"):
        assert shown in html, shown
    pdf = _pdf_text(bidi_report / "report.pdf")
    assert _format_characters(pdf) == []
    assert "j[U+202E]1" in re.sub(r"\s+", "", pdf)
    assert _format_characters("".join(str(v) for v in info(bidi_report / "report.pdf").values())) \
        == []
