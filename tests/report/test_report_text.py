"""The reports' text and tables.

- every table has a numbered caption ("Table 5.2: ..."), numbered within its section, unique,
  and the PDF carries the same captions in the same order;
- no code name stands in for mathematics (share_tran, EPS, scale_i, tau_s, D_ij ...), in the
  HTML or the PDF text;
- no word of a PDF table or paragraph runs past the page's margins (Typst sets the columns);
- a URDF robot gets its joint placements (xyz, rpy) and axes, no DH table and no "n/a"; the
  printed placements rebuild the model's rotations with Pinocchio's rpyToMatrix (oracle);
- every report.pdf and every figure file ``figures/*.pdf`` is typeset by Typst (pdfinfo names
  it) and holds no Type 3 font (pdffonts): the figures are typeset from their SVG;
- no page of the PUMA 560 report but the last ends above 60 % of its height, unless the next
  page starts with a figure taller than the room left;
- one section list per report: the HTML headings and the PDF bookmarks are the same, in order,
  for the main, sweep and control reports.
"""

import re
from html import unescape

import numpy as np
import pdf_checks
import pytest
from html_checks import html_text, table_rows, without_figures
from pypdf import PdfReader

from gd_analyze import load_robot
from gd_analyze.report.typeset import MARGINS, write_pdf

#: Over 5 s on an idle machine (the module's fixtures): run on one interpreter in CI.
pytestmark = pytest.mark.slow

#: Code names that must not stand in for mathematics in a report's text.
CODE_NAMES = re.compile(r"\b(share_tran|peak_tran|peak_rot|peak_total|tau_s|tau_f|tau_i|"
                        r"tau_simplified|tau_full|scale_i|EPS|D_ij|D_ii|D_jj|h_i|D_tran|D_rot|"
                        r"h_tran|h_rot|qdd_d|Kp_pd|Kv_pd)\b")


def _text(html):
    return html_text(html, nbsp=True)


#: Subscript digits back to digits (tables letter D45 as D₄₅).
_PLAIN_DIGITS = str.maketrans("\u2080\u2081\u2082\u2083\u2084\u2085\u2086\u2087\u2088\u2089", "0123456789")


@pytest.fixture(scope="module")
def reports(shared_reports, shared_puma):
    """The main job on the PUMA 560 and the UR5, the sweep and the control report on the
    PUMA (all shared)."""
    return {"puma": shared_puma["puma"], "ur5": shared_reports["ur5"],
            "sweep": shared_reports["sweep"], "control": shared_puma["control"]}


def _files(reports, which):
    folder, stem = reports[which]
    return (folder / f"{stem}.html").read_text(encoding="utf-8"), folder / f"{stem}.pdf"


def _pdf_text(path):
    return "\n".join(pdf_checks.page_texts(path))


def _tables(html):
    """(caption, header cells, rows of cells) of every table."""
    out = []
    for cap, t in re.findall(r"<figure class=\"table\">\s*(?:<figcaption>(.*?)</figcaption>)?"
                             r"\s*<table[^>]*>(.*?)</table>", html, flags=re.S):
        rows = table_rows(t, nbsp=True)
        out.append((unescape(re.sub(r"<[^>]+>", "", cap)).strip() if cap else None,
                    rows[0], rows[1:]))
    return out


ALL = ("puma", "ur5", "sweep", "control")


@pytest.mark.parametrize("which", ALL)
def test_every_table_has_a_numbered_caption_in_html_and_pdf(reports, which):
    html, pdf = _files(reports, which)
    captions = [c for c, _, _ in _tables(html)]
    assert captions and None not in captions
    numbers = [re.match(r"Table (\d+)\.(\d+): \S", c) for c in captions]
    assert all(numbers), captions
    keys = [(int(m.group(1)), int(m.group(2))) for m in numbers]
    assert len(set(keys)) == len(keys)                          # unique
    # numbered within the section they sit in, from 1, in order
    body = without_figures(html)
    for m, (sec, k) in zip(re.finditer(r"<figcaption>Table (\d+)\.(\d+):", body), keys):
        heading = re.findall(r"<h2[^>]*>(\d+)\.", body[:m.start()])[-1]
        assert int(heading) == sec
        assert k == 1 or (sec, k - 1) in keys
    # the PDF: the same captions, in the same order
    text = _pdf_text(pdf)
    found = re.findall(r"Table (\d+)\.(\d+):", text)
    assert [(int(a), int(b)) for a, b in found] == keys


@pytest.mark.parametrize("which", ALL)
def test_html_breaks_prose_only_between_words(reports, which):
    """The provenance cell read "every diff / erence" in Chromium: ``word-break: break-all``
    breaks any word anywhere. ``overflow-wrap: anywhere`` breaks inside a word only when the
    word alone is wider than its cell (a SHA-256)."""
    html, _ = _files(reports, which)
    style = " ".join(re.findall(r"<style[^>]*>(.*?)</style>", html, flags=re.S))
    assert "break-all" not in style
    assert "overflow-wrap: anywhere" in style


def test_operation_count_axes_write_powers_of_ten(reports):
    """Fig. 5 labelled its logarithmic axes "1e2 ... 1e6", code for 10², ..., 10⁶. Oracle:
    each label, read as a power of ten, gives back its tick."""
    from figure_checks import draw, tick_texts

    from gd_analyze.report import main as report
    from gd_analyze.store.schema import open_results

    digits = "\u2070\u00b9\u00b2\u00b3\u2074\u2075\u2076\u2077\u2078\u2079"
    folder, _ = reports["puma"]
    with open_results(folder / "results.h5", lazy=True) as ds:
        figs = report.make_figures(ds.load(), keys=("formulations", "formulations_column"))
    assert set(figs) == {"formulations", "formulations_column"}
    for key, fig in figs.items():
        draw(fig, report.FIG_RC)                            # its ticks as the report draws them
        labels = [(v, t.get_text()) for ax in fig.axes for v, t in tick_texts(ax, "y")
                  if t.get_text()]
        assert len(labels) >= 4, key
        for value, text in labels:
            m = re.fullmatch(f"10(\u207b?)([{digits}]+)", text)
            assert m, (key, text)
            k = int("".join(str(digits.index(c)) for c in m.group(2)))
            assert value == pytest.approx(10.0 ** (-k if m.group(1) else k)), (key, text)


def _typeset_text(reports, which, tmp_path):
    """The text of the PDF typeset without its figures (the figures' lettering is the figures'
    business): the report's outline written again with no figure."""
    import xarray as xr

    from gd_analyze.report import control, sweep
    from gd_analyze.report.main import main_outline
    from gd_analyze.report.main_context import report_context

    folder, _ = reports[which]
    if which in ("puma", "ur5"):
        with xr.open_dataset(folder / "results.h5") as ds:
            outline = main_outline(report_context(ds.load()), {})
    else:
        module, name = (sweep, "sweep.h5") if which == "sweep" else (control, "control.h5")
        with xr.open_dataset(folder / name) as ds:
            ds = ds.load()
            ctx = (control.control_context(ds) if which == "control"
                   else sweep.sweep_context(ds, None))
        outline = module._outline(ctx, {})
    write_pdf(outline, {}, tmp_path / "text.pdf")
    return pdf_checks.text(tmp_path / "text.pdf")


@pytest.mark.parametrize("which", ALL)
def test_no_code_names_in_the_text(reports, which, tmp_path):
    html, _ = _files(reports, which)
    text = _text(html)
    assert not CODE_NAMES.findall(text), sorted(set(CODE_NAMES.findall(text)))
    text = _typeset_text(reports, which, tmp_path)
    assert not CODE_NAMES.findall(text), sorted(set(CODE_NAMES.findall(text)))


def test_mathematics_is_typeset(reports):
    html, pdf = _files(reports, "puma")
    assert "D<sub>ij</sub><sup>tran</sup>" in html and "D<sub>ij</sub><sup>rot</sup>" in html
    assert "\u03c4<sub>s</sub> \u2212 \u03c4" in html
    text = pdf_checks.text(pdf)
    # sub- and superscripts set as such (tests/report/test_typeset.py): no markup, no "^"
    assert "Dijtran" in re.sub(r"\s+", "", text) and "^" not in text
    assert "\u03b5\u00b7s" in text or "\u03b5\u00b7s" in _text(html)


@pytest.mark.parametrize("which", ALL)
def test_no_word_runs_past_the_margins(reports, which):
    """Typst sets the tables' columns: every word of every page lies within the page's
    margins (a table too wide for the page would run past the right one), but for the
    punctuation Typst hangs into the right margin of justified lines (about 2 pt)."""
    for w, h, ws in pdf_checks.words(_files(reports, which)[1]):
        for word, x0, y0, x1, y1 in ws:
            assert x0 >= 72 * MARGINS[0] - 1 and x1 <= w - 72 * MARGINS[0] + 3, (word, x1)


def test_urdf_robot_shows_its_joint_placements(reports):
    import pinocchio as pin

    html, pdf = _files(reports, "ur5")
    tables = _tables(html)
    assert not [h for _, h, _ in tables if h[:3] == ["joint", "d [m]", "a [m]"]]   # no DH
    for caption, header, rows in tables:
        assert "n/a" not in [c for row in rows for c in row], caption
    (caption, header, rows), = [t for t in tables if t[1][:3] == ["joint", "type", "x [m]"]]
    assert header == ["joint", "type", "x [m]", "y [m]", "z [m]", "roll [deg]", "pitch [deg]",
                      "yaw [deg]", "axis in frame i\u22121"]
    robot = load_robot("ur5")
    assert len(rows) == robot.n
    for k, row in enumerate(rows):
        assert row[1] == robot.joint_types[k]
        np.testing.assert_allclose([float(v) for v in row[2:5]], robot.translation[k],
                                   atol=1e-4)
        R = pin.rpy.rpyToMatrix(*np.radians([float(v) for v in row[5:8]]))
        np.testing.assert_allclose(R, robot.rotation[k], atol=1e-3)
        axis = [float(v) for v in row[8].strip("()").split(",")]
        np.testing.assert_allclose(axis, robot.rotation[k][:, 2], atol=1e-3)
    assert "Joint placements" in _pdf_text(pdf) and "n/a" not in _pdf_text(pdf)


def test_dh_robot_keeps_its_dh_table(reports):
    html, _ = _files(reports, "puma")
    headers = [h for _, h, _ in _tables(html)]
    assert ["joint", "d [m]", "a [m]", "\u03b1 [deg]", "\u03b8 [deg]"] in headers
    assert not [h for h in headers if h[:3] == ["joint", "type", "x [m]"]]


@pytest.mark.parametrize("which", ALL)
def test_typst_typesets_every_report_without_type3_fonts(reports, which):
    """Typst typesets the main, sweep and control reports and every figure file
    of each (``figures/*.pdf``, typeset from the figure's SVG); no Type 3 font in any."""
    pdf = _files(reports, which)[1]
    figures = sorted((reports[which][0] / "figures").glob("*.pdf"))
    assert len(figures) >= 3
    for one in [pdf, *figures]:
        assert pdf_checks.info(one)["Creator"].startswith("Typst "), one
        fonts = pdf_checks.font_types(one)
        assert fonts and "Type 3" not in fonts.values(), (one, fonts)


@pytest.mark.parametrize("which", ALL)
def test_pdf_keeps_the_provenance(reports, which):
    """The PDF's document information names the version and the robot file's SHA-256 (the
    sweep's also the SHA-256 of all its inputs), as the dataset stores them."""
    import xarray as xr

    import gd_analyze

    folder, _ = reports[which]
    name = {"sweep": "sweep.h5", "control": "control.h5"}.get(which, "results.h5")
    with xr.open_dataset(folder / name) as ds:
        shas = [str(ds.attrs[k]) for k in ("robot_sha256", "inputs_sha256") if k in ds.attrs]
    meta = pdf_checks.info(_files(reports, which)[1])
    assert shas and all(sha in meta["Keywords"] for sha in shas), meta
    assert meta["Author"] == f"gd-analyze {gd_analyze.__version__}"


def test_pages_are_full_unless_a_tall_figure_follows(reports):
    """No page of the PUMA 560 report but the last ends above 60 % of its height,
    unless the next page starts with a figure taller than the room left on it."""
    pages = pdf_checks.words(_files(reports, "puma")[1])
    assert len(pages) > 2
    for k, (w, h, ws) in enumerate(pages[:-1]):
        foot = h - 72 * MARGINS[2]
        bottom = max(y1 for _, _, _, _, y1 in ws if y1 < foot)
        if bottom >= 0.6 * h:
            continue
        _, _, nxt = pages[k + 1]
        seq = [(word, y0) for word, _, y0, _, y1 in nxt if y1 < foot]     # reading order
        caption = next(y for (word, y), (n, _) in zip(seq, seq[1:])
                       if word == "Figure" and re.fullmatch(r"\d+\.", n))
        assert caption - min(y for _, y in seq) > foot - bottom, (k + 1, bottom / h)


def _outline_titles(outline, level=1):
    out = []
    for item in outline:
        if isinstance(item, list):
            out += _outline_titles(item, level + 1)
        else:
            out.append(str(item["/Title"]))
    return out


@pytest.mark.parametrize("which", ALL)
def test_html_and_pdf_headings_are_one_list(reports, which):
    html, pdf = _files(reports, which)
    body = without_figures(html)
    headings = [unescape(re.sub(r"<[^>]+>", "", h)).strip()
                for h in re.findall(r"<h[23][^>]*>(.*?)</h[23]>", body, flags=re.S)]
    bookmarks = _outline_titles(PdfReader(pdf).outline)
    assert headings and headings == bookmarks
    assert len(headings) >= 6


def test_markup_escapes_and_renders():
    from gd_analyze.report import markup

    s = "<b>" + markup.element("D", "12", "tran") + " & " + markup.sub("d")
    assert str(markup.html(s)) == "&lt;b&gt;D<sub>12</sub><sup>tran</sup> &amp; <sub>d</sub>"
    # d has no Unicode subscript: the span stays marked (figures letter the Unicode ones)
    assert markup.unicode(s) == "<b>D\u2081\u2082\u1d57\u02b3\u1d43\u207f & " + markup.sub("d")
    assert markup.plain(s) == "<b>D12tran & d"


def test_marks_in_a_file_s_text_are_dropped():
    """A robot name holding the private-use marks reaches the report as plain text."""
    import xarray as xr

    from gd_analyze.report import markup
    from gd_analyze.report.common import attr_text

    ds = xr.Dataset(attrs={"robot": "arm" + markup.sub("<i>") + markup.sup("x")})
    assert attr_text(ds.attrs["robot"]) == "arm<i>x"
    assert str(markup.html(attr_text(ds.attrs["robot"]))) == "arm&lt;i&gt;x"


#: A number that is round-off of any quantity's scale the reports tabulate (1e-13 and below).
_TINY = re.compile(r"(?<![\w.])-?[0-9.]+e-(1[3-9]|[2-9][0-9])(?![\w])")


@pytest.mark.parametrize("which", ("sweep", "control"))
def test_round_off_is_never_tabulated_in_the_sweep_and_control_reports(reports, which,
                                                                       tmp_path):
    """Round-off of a quantity's own scale reads "≡ 0" in every table of the sweep
    and control reports, in the HTML and in the PDF's text pages. The sweep's D45 and D56
    (zero for the PUMA 560 in every part: an axis intersection) have no share, D16 (rotational
    only) a share of exactly 0; the full-model controller's tracking error is the
    integrator's noise (its rtol of the range of motion)."""
    import xarray as xr

    from gd_analyze.ranking.ranking import is_round_off

    html, _ = _files(reports, which)
    for caption, header, rows in _tables(html):
        for row in rows:
            assert not any(_TINY.search(c) for c in row), (caption, row)
    text = _typeset_text(reports, which, tmp_path)
    assert not _TINY.findall(text), sorted(set(_TINY.findall(text)))
    folder, _ = reports[which]
    if which == "sweep":
        env = next(r for c, h, r in _tables(html) if h[-1] == "merged choice")
        by = {r[0]: r for r in env}
        by.update({k.translate(_PLAIN_DIGITS): r for k, r in by.items()})   # D₄₅ is D45
        for lab in ("D45", "D56"):
            assert by[lab][5:8] == ["\u2261 0"] * 3, by[lab]
        assert by["D16"][5:8] == ["0"] * 3, by["D16"]
        return
    with xr.open_dataset(folder / "control.h5") as ds:
        q_d = ds["q_d"].values
        scale = np.maximum(np.ptp(q_d, axis=0), np.abs(q_d).max(axis=0))
        noise = is_round_off(ds["error_peak_grid"].sel(controller="full").values, scale,
                             float(ds.attrs["rtol"]))
    assert noise.all()                      # the physics: the full model tracks exactly
    table = next(r for c, h, r in _tables(html) if h[0] == "controller" and "sampled at" in h)
    full = [r for r in table if r[0] == "full model"]
    assert len(full) == 4 and all(c == "\u2261 0" for r in full for c in r[3:]), full
    # nor in a sentence: the summary and the verdict say noise, not its digits
    with xr.open_dataset(folder / "control.h5") as ds:
        digits = f"{float(ds['error_peak_grid'].sel(controller='full').max()):.2e}"
    said = "full model: peak |e| \u2261 0 (integrator noise)"
    assert digits not in _text(html) and said in _text(html).replace("\n", " ")
    assert digits not in text
    assert re.search(r"full model: peak \|e\| +\u2261 0 \(integrator noise\)",
                     text.replace("\n", " ")), text[:400]


#: A code name: letters or digits joined by "_" (q_d, Y_b, share_tran, pd_gravity, tau_s).
_CODE = re.compile(r"[^\s(|]*[A-Za-z0-9]_[A-Za-z0-9][^\s,;)|]*")


def _is_code(token, names=""):
    """File and module names, the emitted functions (puma560_tau, velocity_terms) and the robot
    file's key tau_max are code written as code; names read from the robot's files (URDF
    links, packages) are names."""
    return ("." in token or "/" in token or token.startswith("PREFIX_")
            or token in ("tau_max", "velocity_terms") or token in names)


def _names(reports, which):
    """The robot's description and reference, as its files give them."""
    import xarray as xr

    folder, _ = reports[which]
    name = {"sweep": "sweep.h5", "control": "control.h5"}.get(which, "results.h5")
    with xr.open_dataset(folder / name) as ds:
        names = " ".join(str(ds.attrs.get(k, "")) for k in ("robot_description",
                                                           "robot_reference"))
        prefix = str(ds.attrs.get("c_prefix", ""))      # the emitted C functions' names
        return names + "".join(f" {prefix}{f}" for f in ("tau", "inertia", "velocity_terms",
                                                          "gravity", "regressor") if prefix)


@pytest.mark.parametrize("which", ALL)
def test_no_code_subscript_reaches_the_pdf_or_the_html(reports, which):
    """Mathematics, not code names, in the whole PDF as pdftotext extracts it
    (text and figures: q_d is q with a subscript d, never "q_d"; no "^") and in the HTML's
    text; file and module names excepted."""
    html, pdf = _files(reports, which)
    names = _names(reports, which)
    for where, text in (("pdf", pdf_checks.text(pdf)), ("html", _text(html))):
        bad = sorted({t for t in _CODE.findall(text) if not _is_code(t, names)})
        assert not bad, (where, bad)
        assert "^" not in text, where
