"""Tests of the HTML and PDF report (gd_analyze.report.main)."""

import ast
import json
import re
from html import unescape
from html.parser import HTMLParser
from pathlib import Path

import numpy as np
import pytest
from conftest import SHIPPED, built_once
from pdf_checks import page_texts

import gd_analyze
from gd_analyze.errors import InputError
from gd_analyze.jobs.analyze import analyze
from gd_analyze.jobs.options import AnalysisOptions
from gd_analyze.report import main as report
from gd_analyze.report.main_context import zero_mask
from gd_analyze.report.markup import html as markup_html
from gd_analyze.report.markup import label as math_label
from gd_analyze.report.markup import marked
from gd_analyze.store.schema import open_results, write_dataset
from gd_analyze.trajectory.planning import plan_quintic
from gd_analyze.trajectory.trajectory import read_trajectory

#: Over 5 s on an idle machine (the module's fixtures): run on one interpreter in CI.
pytestmark = pytest.mark.slow

PAGE = re.compile(rb"/Type\s*/Page(?![a-zA-Z])")


# ------------------------------------------------------------------------------------------
# Helpers
# ------------------------------------------------------------------------------------------

class _Tables(HTMLParser):
    """Collect every <table> of an HTML document as a list of rows of cell texts."""

    def __init__(self):
        super().__init__()
        self.tables, self._row, self._cell, self._depth = [], None, None, 0

    def handle_starttag(self, tag, attrs):
        if tag == "table":
            self.tables.append([])
        elif tag == "tr":
            self._row = []
        elif tag in ("td", "th"):
            self._cell = []

    def handle_endtag(self, tag):
        if tag in ("td", "th") and self._cell is not None:
            self._row.append("".join(self._cell).strip())
            self._cell = None
        elif tag == "tr" and self._row is not None:
            self.tables[-1].append(self._row)
            self._row = None

    def handle_data(self, data):
        if self._cell is not None:
            self._cell.append(data)


def tables_of(html):
    parser = _Tables()
    parser.feed(html)
    return parser.tables


def table_with_header(html, first_cells):
    for table in tables_of(html):
        if table and table[0][:len(first_cells)] == list(first_cells):
            return table
    return None


def strings(values):
    return [str(v) for v in np.asarray(values).ravel()]


def make_results(robot, trajectory, folder, check=True):
    folder.mkdir(parents=True, exist_ok=True)
    analysis = analyze(robot, trajectory, AnalysisOptions(verify=check, formulations=False))
    path = folder / "results.h5"
    write_dataset(analysis.dataset, path)
    return path


# ------------------------------------------------------------------------------------------
# Fixtures: one dataset and one report per robot, shared by the module's tests
# ------------------------------------------------------------------------------------------

def _shared_report(name, robot, trajectory):
    """The robot's dataset (:func:`make_results`) and its report, built once a session
    (conftest's built_once: a folder shared by the xdist workers, read only)."""
    def build(folder):
        written = report.write_report(make_results(robot, trajectory, folder), folder / "out")
        (folder / "written.json").write_text(
            json.dumps([str(p.relative_to(folder)) for p in written]), encoding="utf-8")
    folder = built_once(f"test-main-{name}", build)
    results = folder / "results.h5"
    return {"results": results, "out": folder / "out",
            "written": [folder / p for p in json.loads((folder / "written.json").read_text(
                encoding="utf-8"))],
            "ds": open_results(results)}


@pytest.fixture(scope="module")
def puma_report(puma):
    return _shared_report("puma", puma, read_trajectory(SHIPPED, puma.n))


@pytest.fixture(scope="module")
def two_link_report(two_link):
    trajectory = plan_quintic(two_link, [0.0, 0.0], [np.pi / 2, np.pi / 3], n_setpoints=21)
    return _shared_report("two", two_link, trajectory)


@pytest.fixture(params=["puma", "two"])
def any_report(request, puma_report, two_link_report):
    return puma_report if request.param == "puma" else two_link_report


# ------------------------------------------------------------------------------------------
# Files
# ------------------------------------------------------------------------------------------

FIGURES = ("fig_joints_q_qd_qdd", "fig_3_10_D", "fig_3_11_h", "fig_torque_contributions",
           "fig_torque_full_vs_simplified", "fig_error_budget", "fig_cost_ladder")


def test_both_files_written_and_returned(any_report):
    """Page-width figures only: the column-width ones are written on request
    (``column_figures``)."""
    out = any_report["out"]
    figures = [out / "figures" / f"{name}.{ext}" for name in FIGURES for ext in ("pdf", "svg")]
    tables = sorted((out / "tables").glob("table_*.csv"),
                    key=lambda p: tuple(int(k) for k in p.stem.split("_")[1:]))
    assert tables                              # every table of the report as CSV
    assert any_report["written"] == [out / "report.html", out / "report.pdf"] + figures + tables
    for path in any_report["written"]:
        assert path.is_file() and path.stat().st_size > (1000 if path.suffix != ".csv" else 10)
    # written atomically: no temporary file is left behind
    assert sorted(p.name for p in out.iterdir()) == ["figures", "report.html", "report.pdf",
                                                     "tables"]
    assert sorted(p.name for p in (out / "figures").iterdir()) == sorted(p.name for p in figures)
    assert sorted(p.name for p in (out / "tables").iterdir()) == sorted(p.name for p in tables)


def test_standalone_figures_are_the_report_figures(puma_report):
    """Each figure file is a one-page PDF of the figure's own size, and its SVG is inlined."""
    from pypdf import PdfReader

    out = puma_report["out"]
    html = (out / "report.html").read_text(encoding="utf-8")
    for name in FIGURES:
        reader = PdfReader(out / "figures" / f"{name}.pdf")
        assert len(reader.pages) == 1
        w, h = (float(v) / 72 for v in reader.pages[0].mediabox[2:])
        width = 3.5 if name.endswith("_column") else 7.2    # a column's, or a page's text
        assert w == pytest.approx(width, abs=0.01) and h < 11.0
        if name.endswith("_column"):                # not in the report: a file of its own
            continue
        svg = (out / "figures" / f"{name}.svg").read_text(encoding="utf-8")
        assert svg.startswith("<svg")
        # the same drawing: its text content appears in the HTML (ids prefixed there)
        texts = re.findall(r">([^<>]{3,})</text>", svg)
        assert texts and all(t in html for t in texts[:20])


def test_only_requested_format(tmp_path, puma_report):
    written = report.write_report(puma_report["results"], tmp_path / "new", formats=("html",))
    assert written[0] == tmp_path / "new" / "report.html"
    assert all(p.parent.name in ("figures", "tables") for p in written[1:])
    assert not (tmp_path / "new" / "report.pdf").exists()
    assert not list((tmp_path / "new" / "tables").glob("*.tex"))      # LaTeX on request only
    assert not (tmp_path / "new" / "report.pdf").exists()


def test_bad_format_and_bad_input(tmp_path, puma_report):
    with pytest.raises(ValueError):
        report.write_report(puma_report["results"], tmp_path, formats=("docx",))
    with pytest.raises(ValueError):
        report.write_report(puma_report["results"], tmp_path, formats=())
    with pytest.raises(InputError):
        report.write_report(tmp_path / "missing.h5", tmp_path)
    # a netCDF file that is not a gd-analyze dataset
    other = tmp_path / "other.h5"
    write_dataset(puma_report["ds"][["t", "q"]], other)
    with pytest.raises(InputError, match="missing variable"):
        report.write_report(other, tmp_path / "o")
    assert not (tmp_path / "o" / "report.html").exists()


# ------------------------------------------------------------------------------------------
# HTML
# ------------------------------------------------------------------------------------------

def test_html_is_self_contained(any_report):
    html = (any_report["out"] / "report.html").read_text(encoding="utf-8")
    assert html.lstrip().lower().startswith("<!doctype html>")
    lower = html.lower()
    assert 'src="http' not in lower and "src='http" not in lower
    assert "<link " not in lower
    assert "<script" not in lower
    assert "<img" not in lower
    assert "@import" not in lower
    for ref in re.findall(r"url\(\s*['\"]?([^)'\"]*)", html):    # clip paths only
        assert ref.startswith("#"), ref
    assert "<!doctype svg" not in lower and "<?xml" not in lower
    # every reference is internal (SVG markers, clip paths, table of contents)
    for ref in re.findall(r'(?:xlink:)?href="([^"]*)"', html):
        assert ref.startswith("#"), ref
    assert lower.count("<svg") >= 4
    ids = re.findall(r'\sid="([^"]*)"', html)
    assert len(ids) == len(set(ids)), "duplicate ids in the HTML"
    for ref in re.findall(r'href="#([^"]*)"', html) + re.findall(r"url\(#([^)]*)\)", html):
        assert ref in ids, ref


def test_html_labels_classes_and_ranking_table(any_report):
    ds = any_report["ds"]
    html = (any_report["out"] / "report.html").read_text(encoding="utf-8")
    labels = strings(ds["element"].values)
    n = ds.sizes["joint"]
    assert labels == [f"D{i + 1}{j + 1}" for i in range(n) for j in range(i, n)] + \
        [f"h{i + 1}" for i in range(n)]
    for lab in labels:
        assert math_label(lab) in html           # lettered as the figures letter it: D(1,2)
        assert str(markup_html(marked(lab))) in html     # and the tables: D<sub>12</sub>
    ranking = table_with_header(html, ["element", "translational share", "class", "peak |Xtran|",
                                       "peak |Xrot|", "peak |X|", "units"])
    assert ranking is not None
    rows = ranking[1:]
    assert [r[0] for r in rows] == labels     # D<sub>12</sub> read without its tags
    assert [r[2] for r in rows] == strings(ds["dominance"].values)
    zero = set(zero_mask(ds)[0][k] for k in np.flatnonzero(zero_mask(ds)[1]))
    for row, share in zip(rows, ds["share_tran"].values):
        if row[0] in zero:
            assert row[1] == "\u2261 0"             # rounding noise is not printed as a share
        elif row[1][0] in "<>":                     # "> 0.9999": a share within 1e-4 of 1
            assert (share > float(row[1][1:])) == (row[1][0] == ">")
        else:
            assert float(row[1]) == pytest.approx(share, abs=1e-3)
    assert all(r[6] in ("kg m²", "N m") for r in rows)
    if ds.attrs.get("simplified_form", "explicit") == "explicit":
        choices = table_with_header(html, ["element", "class", "kept part"])
        assert [r[2] for r in choices[1:]] == strings(ds["choice"].values)
    else:                     # the recursive form: a row per base parameter, a column per part
        table = table_with_header(html, ["base parameter", "value", "units", "inertial",
                                         "velocity", "gravity"])
        value = ds["base_parameter_value"].values
        shown = [k for k in range(value.size) if value[k] != 0]     # zeros named in the text
        names = strings(ds["base_parameter"].values)
        assert [r[0] for r in table[1:]] == [names[k] for k in shown]
        dropped = ds["base_parameter_dropped"].values
        rel = ds["base_parameter_relative_peak"].values
        for k, row in zip(shown, table[1:]):
            for p in range(3):
                want = "\u2261 0" if rel[k, p] < 1e-12 else ("dropped" if dropped[k, p]
                                                            else "kept")
                assert row[3 + p] == want, (row, p)


def test_html_torque_error_table(any_report):
    ds = any_report["ds"]
    html = (any_report["out"] / "report.html").read_text(encoding="utf-8")
    table = next(t for t in tables_of(html) if t and t[0][0] == "joint"
                 and t[0][1].startswith("peak |"))
    rows = table[1:]
    assert len(rows) == ds.sizes["joint"]
    for k, row in enumerate(rows):
        peak, top = ds["tau_error_peak"].values[k], ds["tau_peak"].values[k]
        assert float(row[3]) == pytest.approx(top, rel=1e-3)
        if peak <= 1e-12 * top:              # round-off of the joint's scale: not tabulated
            assert row[1].startswith("\u2261 0") and row[4] == "\u2261 0", row
            continue
        assert float(row[1]) == pytest.approx(peak, rel=1e-3, abs=1e-12)
        assert float(row[2]) == pytest.approx(ds["tau_error_rms"].values[k], rel=1e-3, abs=1e-12)
        assert row[4].endswith("%")


def test_summary_names_a_largest_error_only_where_one_is_not_round_off(any_report):
    """The two-link arm's model is exact (every joint's stored torque error is round-off):
    its summary says so instead of naming a joint's "≡ 0" as the largest error; the PUMA
    560's drops terms and names its largest. Oracle: the stored round-off marks."""
    noise = any_report["ds"]["tau_error_round_off"].values.astype(bool)
    html = (any_report["out"] / "report.html").read_text(encoding="utf-8")
    text = re.sub(r"\s+", " ", unescape(re.sub(r"<[^>]+>", "", html)))
    assert ("at every joint (round-off only)" in text) == bool(noise.all())
    assert ("largest open-loop torque error" in text) == (not noise.all())


def test_html_robot_trajectory_and_provenance(puma_report):
    ds = puma_report["ds"]
    html = (puma_report["out"] / "report.html").read_text(encoding="utf-8")
    for key in ("robot_sha256", "input_sha256", "robot_description", "input_file"):
        assert str(ds.attrs[key]) in html
    dh = table_with_header(html, ["joint", "d [m]", "a [m]"])
    assert len(dh) == 1 + ds.sizes["joint"]
    alpha = [float(r[3]) for r in dh[1:]]
    np.testing.assert_allclose(alpha, np.degrees(ds["dh_alpha"].values), atol=1e-3)
    trajectory = table_with_header(html, ["item", "value"])
    assert trajectory is not None
    assert "set points N" in html and ">31<" in html
    provenance = [t for t in tables_of(html) if t and t[0] == ["item", "value"]][-1]
    prov = dict(r for r in provenance[1:] if len(r) == 2)
    assert prov["dominance threshold s, negligibility threshold e"] == "0.9, 0.01"
    assert prov["verification against Pinocchio"].startswith("passed on 31 of 31 set points")
    assert "Dtran" in prov["verification against Pinocchio"]       # one row, every term named
    assert prov["software"] == f"gd-analyze {ds.attrs['gd_analyze_version']}"
    # each setting once, in words: no attribute name, no value twice
    assert len(prov) == len(provenance) - 1
    assert not [k for k in prov if "_" in k]
    values = [v for v in prov.values()]
    assert len(set(values)) == len(values), values
    version = f"gd-analyze {ds.attrs['gd_analyze_version']}"
    assert sum(version in v for v in values) == 1, values     # the version once
    assert "mounting_base_rpy_deg" not in ds.attrs or prov["mounting"].startswith(
        "base not turned")
    assert "CF conventions, version" in prov["file format"]
    assert not [k for k in prov if k.startswith(("mounting ", "conventions"))]


def test_html_chapter_comparison_puma(puma_report):
    ds = puma_report["ds"]
    html = (puma_report["out"] / "report.html").read_text(encoding="utf-8")
    table = table_with_header(html, ["element", "our class", "chapter's class", "agree"])
    assert table is not None
    ours, theirs = strings(ds["dominance"].values), strings(ds["chapter_dominance"].values)
    expected = sum(a == b for a, b in zip(ours, theirs) if b)
    compared = sum(bool(b) for b in theirs)
    assert [r[3] for r in table[1:]] == ["yes" if a == b else "no" for a, b in zip(ours, theirs)]
    assert f"Agreement: {expected} of {compared} elements." in html


def test_html_chapter_comparison_not_for_two_link(two_link_report):
    html = (two_link_report["out"] / "report.html").read_text(encoding="utf-8")
    assert table_with_header(html, ["element", "our class", "chapter's class"]) is None
    assert "Comparison with the chapter" not in html      # the section only for the PUMA 560
    assert "not compared" not in html and "not meaningful" not in html
    numbers = [int(m) for m in re.findall(r"<h2[^>]*>\s*(\d+)[ .]", html)]
    assert numbers == list(range(1, len(numbers) + 1)), numbers   # no gap where it was


def test_html_escapes_dataset_text(tmp_path, puma_report):
    ds = puma_report["ds"].copy()
    ds.attrs["robot_description"] = "arm <script>alert(1)</script> & co"
    path = tmp_path / "results.h5"
    write_dataset(ds, path)
    report.write_report(path, tmp_path, formats=("html",))
    html = (tmp_path / "report.html").read_text(encoding="utf-8")
    assert "<script>" not in html
    assert "arm &lt;script&gt;alert(1)&lt;/script&gt; &amp; co" in html


# ------------------------------------------------------------------------------------------
# PDF
# ------------------------------------------------------------------------------------------

@pytest.mark.parametrize("which", ["puma", "two"])
def test_pdf_is_a_document(which, puma_report, two_link_report):
    from pypdf import PdfReader

    rep = puma_report if which == "puma" else two_link_report
    reader = PdfReader(rep["out"] / "report.pdf")
    info = reader.metadata
    assert info["/Author"] == f"gd-analyze {gd_analyze.__version__}"
    assert info["/Creator"].startswith("Typst ")                # typeset by Typst
    assert info["/Title"].startswith("G-D dominance analysis")
    assert str(rep["ds"].attrs["robot_sha256"]) in info["/Keywords"]
    # one page size: A4
    sizes = {tuple(round(float(v), 1) for v in page.mediabox[2:]) for page in reader.pages}
    assert sizes == {(595.3, 841.9)}                 # ISO A4: 210 x 297 mm
    K = len(reader.pages)
    texts = list(page_texts(rep["out"] / "report.pdf"))
    for k, text in enumerate(texts):
        assert f"page {k + 1} of {K}" in text
    # every section of the HTML, as a bookmark, in order
    html = (rep["out"] / "report.html").read_text(encoding="utf-8")
    sections = [re.sub(r"<[^>]+>", "", h).replace("&#39;", "'")
                for h in re.findall(r"<h2[^>]*>(.*?)</h2>", html)]
    top = [item["/Title"] for item in reader.outline if not isinstance(item, list)]
    assert top == sections
    # numbered figures with captions, the same numbers as the HTML
    whole = "\n".join(texts)
    for k in range(1, 5):
        assert f"Figure {k}." in whole and f"Figure {k}." in html
    # the same numbers as the HTML: the ranking table's shares and the torque errors
    ranking = table_with_header(html, ["element", "translational share", "class"])
    for row in ranking[1:]:
        assert row[1] in whole
    flat = re.sub(r"\s+", " ", whole)
    assert rep["ds"].attrs["robot"] in flat


def test_pdf_letter(tmp_path, two_link_report):
    from pypdf import PdfReader

    report.write_report(two_link_report["results"], tmp_path, formats=("pdf",), paper="letter")
    reader = PdfReader(tmp_path / "report.pdf")
    assert {tuple(round(float(v)) for v in p.mediabox[2:]) for p in reader.pages} == {(612, 792)}
    with pytest.raises(ValueError):
        report.write_report(two_link_report["results"], tmp_path, paper="a5")


# ------------------------------------------------------------------------------------------
# Figures and the envelope
# ------------------------------------------------------------------------------------------

def test_make_figures_panels(any_report):
    ds = any_report["ds"]
    n = ds.sizes["joint"]
    dom = dict(zip(strings(ds["element"].values), strings(ds["dominance"].values)))
    from gd_analyze.report.main_figures import SHORT_CLASS
    from gd_analyze.report.markup import label as shown

    figs = report.make_figures(ds)
    assert set(figs) == {"joints", "D", "h", "torque", "contributions", "budget", "cost_ladder"}
    assert set(report.make_figures(ds, column=True)) == set(figs) | {
        f"{k}_column" for k in figs}
    figs = {k: figs[k] for k in ("joints", "D", "h", "torque")}
    labels, zero = zero_mask(ds)
    zero = dict(zip(labels, zero))
    titles = {ax.get_title(): ax for ax in figs["D"].axes if ax.get_title()}
    assert len(titles) == n * (n + 1) // 2 - sum(zero[k] for k in zero if k[0] == "D")
    note = " ".join(t.get_text() for t in figs["D"].texts)
    t = ds["t"].values
    for i in range(n):
        for j in range(i, n):
            label = f"D{i + 1}{j + 1}"
            if zero[label]:                 # noise is not drawn as data: named in the note
                assert not any(k.startswith(shown(label) + ":") for k in titles)
                assert shown(label) in note.split("not drawn:")[1]
                assert np.abs(ds["D"].values[:, i, j]).max() < 1e-12
                continue
            ax = titles[f"{shown(label)}: {SHORT_CLASS[dom[label]]}"]
            by_label = {ln.get_label(): ln for ln in ax.get_lines()}
            lines = [by_label[k] for k in ("translational", "rotational", "combined")]
            assert [ln.get_marker() for ln in lines] == ["o", "x", "^"]
            np.testing.assert_allclose(lines[0].get_xdata(), t)      # time [s] on x
            np.testing.assert_allclose(lines[0].get_ydata(), ds["D_tran"].values[:, i, j])
            np.testing.assert_allclose(lines[1].get_ydata(), ds["D_rot"].values[:, i, j])
            np.testing.assert_allclose(lines[2].get_ydata(), ds["D"].values[:, i, j])
            lo, hi = ax.get_ylim()                         # nothing clipped by the frame
            for ln in lines[:3]:
                y = ln.get_ydata()
                assert lo < y.min() and y.max() < hi
    h_titles = [ax.get_title() for ax in figs["h"].axes if ax.get_visible() and ax.get_title()]
    assert h_titles == [shown(f"h{i + 1}") + ": " + SHORT_CLASS[dom[f"h{i + 1}"]]
                        for i in range(n) if not zero[f"h{i + 1}"]]
    # one panel size for D and h, and type of at least 7 pt at the printed size (7.2 in)
    size = {tuple(np.round(ax.get_position().size * figs[k].get_size_inches(), 3))
            for k in ("D", "h") for ax in figs[k].axes}
    assert len(size) == 1
    for fig in figs.values():
        assert fig.get_size_inches()[0] == pytest.approx(7.2)
        for text in fig.findobj(lambda a: hasattr(a, "get_fontsize") and
                                hasattr(a, "get_text") and a.get_text()):
            assert text.get_fontsize() >= 7.0
    # joint plots in degrees, with units on the axes
    q_ax = figs["joints"].axes[0]
    assert "[deg]" in q_ax.get_ylabel()
    np.testing.assert_allclose(q_ax.get_lines()[0].get_ydata(), np.degrees(ds["q"].values[:, 0]))
    power = re.compile("(?<=\\[)10\u207b?[\u2070\u00b9\u00b2\u00b3\u2074-\u2079]+ ")
    assert all("[N m]" in power.sub("", ax.get_ylabel())        # [10⁻³ N m] is N m too
               for ax in figs["torque"].axes if ax.get_visible())


def test_zero_velocity_has_no_nan_share(tmp_path, puma):
    """With q̇ = 0 the h elements are ≡ 0: no 'nan' share anywhere in the report."""
    from gd_analyze.trajectory.trajectory import Trajectory

    N = 11
    q = np.tile(np.radians([10.0, 20.0, -30.0, 40.0, 50.0, 60.0]), (N, 1))
    traj = Trajectory(t=np.linspace(0, 1, N), q=q, qd=np.zeros_like(q), qdd=np.zeros_like(q),
                      source="static", derivatives="file")
    results = make_results(puma, traj, tmp_path, check=False)
    report.write_report(results, tmp_path / "out", formats=("html",))   # read: the HTML
    html = (tmp_path / "out" / "report.html").read_text(encoding="utf-8")
    assert not re.search(r"\bnan\b", html, re.IGNORECASE)
    h = table_with_header(html, ["element", "translational share", "class"])
    assert [r[1] for r in h[1:] if r[0].startswith("h")] == ["\u2261 0"] * 6


def test_plot_data_reads_long_series_in_chunks():
    """The chunked envelope holds each column's extremes of the full series (oracle: numpy on
    the whole array), whatever the chunk size."""
    import xarray as xr

    from gd_analyze.report.main_figures import plot_data

    rng = np.random.default_rng(3)
    N, columns = 50_000, 100
    t = np.linspace(0.0, 5.0, N)
    y = np.sin(t)[:, None] + 0.1 * rng.standard_normal((N, 2))
    y[123, 1] = 9.0
    ds = xr.Dataset({"t": ("t", t), "q": (("t", "joint"), y)})
    col = np.minimum((t / 5.0 * columns).astype(int), columns - 1)
    for chunk in (997, 50_000):
        data = plot_data(ds, names=("q",), columns=columns, chunk=chunk)
        assert data.enveloped and data.series["q"].shape == (2 * columns, 2)
        lo, hi = data.series["q"][0::2], data.series["q"][1::2]
        for c in (0, 37, columns - 1):
            np.testing.assert_array_equal(lo[c], y[col == c].min(axis=0))
            np.testing.assert_array_equal(hi[c], y[col == c].max(axis=0))
        assert data.series["q"].max() == 9.0
        assert np.all(np.diff(data.x) >= 0) and data.x[0] >= 0 and data.x[-1] <= 5.0
    short = plot_data(ds.isel(t=slice(0, 31)), names=("q",))
    assert not short.enveloped and short.series["q"].shape == (31, 2)


def test_plot_data_envelope_of_the_torque_error():
    """tau_error is the envelope of tau_s - tau taken per set point (oracle: numpy on the whole
    difference), not the difference of the two envelopes."""
    import xarray as xr

    from gd_analyze.report.main_figures import plot_data

    rng = np.random.default_rng(5)
    N, columns = 20_000, 50
    t = np.linspace(0.0, 2.0, N)
    tau = np.cos(3 * t)[:, None] * np.ones((1, 2)) + 0.01 * rng.standard_normal((N, 2))
    tau_s = tau + 1e-3 * rng.standard_normal((N, 2))
    ds = xr.Dataset({"t": ("t", t), "tau": (("t", "joint"), tau),
                     "tau_simplified": (("t", "joint"), tau_s)})
    col = np.minimum((t / 2.0 * columns).astype(int), columns - 1)
    diff = tau_s - tau
    for chunk in (777, N):
        data = plot_data(ds, names=("tau_error",), columns=columns, chunk=chunk)
        lo, hi = data.series["tau_error"][0::2], data.series["tau_error"][1::2]
        for c in range(columns):
            np.testing.assert_array_equal(lo[c], diff[col == c].min(axis=0))
            np.testing.assert_array_equal(hi[c], diff[col == c].max(axis=0))
    short = plot_data(ds.isel(t=slice(0, 40)), names=("tau_error",))
    np.testing.assert_array_equal(short.series["tau_error"], diff[:40])


def test_long_trajectory_html_under_5mb(tmp_path, puma):
    start = np.radians([-60.0, 20.0, -150.0, -80.0, -60.0, -120.0])
    goal = np.radians([60.0, 110.0, -60.0, 80.0, 60.0, 120.0])
    trajectory = plan_quintic(puma, start, goal, n_setpoints=100_000)
    results = make_results(puma, trajectory, tmp_path, check=False)
    html_path = report.write_report(results, tmp_path, formats=("html",))[0]
    size = html_path.stat().st_size
    assert size < 5_000_000, f"report.html is {size / 1e6:.2f} MB"
    html = html_path.read_text(encoding="utf-8")
    assert "min/max envelope" in html and ">100,000<" in html
    assert "not run" in html                        # no verification without check
    for lab in ("D11", "D66", "h6"):
        assert math_label(lab) in html


# ------------------------------------------------------------------------------------------
# The report reads, it does not recompute
# ------------------------------------------------------------------------------------------

def test_report_does_not_recompute_dynamics(tmp_path, monkeypatch, puma_report):
    def boom(*args, **kwargs):
        raise AssertionError("the report must not recompute the dynamics")

    import gd_analyze.dynamics.dalembert
    import gd_analyze.dynamics.pinocchio
    import gd_analyze.jobs.analyze
    import gd_analyze.simplify.simplified

    monkeypatch.setattr(gd_analyze.dynamics.dalembert, "gd_terms", boom)
    monkeypatch.setattr(gd_analyze, "gd_terms", boom)
    monkeypatch.setattr(gd_analyze.jobs.analyze, "gd_terms", boom)
    # core.simplified evaluates the explicit model only (no masked G-D fallback since the
    # explicit model covers prismatic joints), so it has no gd_terms to patch
    assert not hasattr(gd_analyze.simplify.simplified, "gd_terms")
    monkeypatch.setattr(gd_analyze.dynamics.pinocchio, "reference_terms", boom)
    monkeypatch.setattr(gd_analyze.jobs.analyze, "analyze", boom)
    written = report.write_report(puma_report["results"], tmp_path)
    assert [p.name for p in written[:2]] == ["report.html", "report.pdf"]


def test_report_module_imports_no_dynamics():
    source = Path(report.__file__).read_text(encoding="utf-8")
    imported = set()
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.ImportFrom):
            imported.add((node.module or "").split(".")[-1])
            imported.update(a.name for a in node.names)
        elif isinstance(node, ast.Import):
            imported.update(a.name.split(".")[-1] for a in node.names)
    forbidden = {"dalembert", "gd_terms", "pipeline", "analyze", "reference", "kinematics",
                 "simplified", "lagrange_euler", "pinocchio"}
    assert not imported & forbidden


def test_formulations_section_from_the_stored_counts(shared_main):
    """The main job's dataset carries the formulations; the report shows them as stored."""
    # the main job's default run on the shipped trajectory and the report it wrote with
    # write_report (conftest's shared_main, read only): a report written again from its
    # results.h5 differs from it only in the time it was created
    out = shared_main("puma560", SHIPPED)
    results = out / "results.h5"
    html = (out / "report.html").read_text(encoding="utf-8")
    assert "Formulations: Lagrange-Euler, Newton-Euler, G-D" in html
    ds = open_results(results)
    costs = next(t for t in tables_of(html) if t and t[0][:2] == ["formulation", "multiplications"])
    by_name = {row[0]: row for row in costs[1:]}
    shown = {"lagrange-euler": "Lagrange-Euler", "newton-euler": "Newton-Euler",
             "gd": "G-D, compiled engine"}          # names in words, not dataset keys
    for name in ("lagrange-euler", "newton-euler", "gd"):
        stored = ds.op_multiplications.sel(dof=6, formulation=name).item()
        assert by_name[shown[name]][1] == f"{stored:,.0f}"
        assert by_name[shown[name]][3] == f"{ds.op_multiplications_table_3_5.sel(dof=6, formulation=name).item():,.0f}"
    # joints, D, h, contributions, torque, budget, cost ladder, formulations
    assert html.count("<svg") == 8


def test_report_without_formulations_says_so(puma_report):
    html = (puma_report["out"] / "report.html").read_text()   # analyze(): no formulations
    assert "holds no comparison of the formulations" in html


@pytest.mark.parametrize("n", [1, 2, 7, 10])
def test_fig_3_10_analogue_grows_to_n_by_n(n):
    """Any n: n(n+1)/2 panels D_ij, labels with a comma once an index has two digits."""
    import matplotlib

    from gd_analyze.ranking.ranking import element_label
    from gd_analyze.report.main_figures import RC, PlotData, element_parts, fig_D, fig_h
    from gd_analyze.report.markup import label as shown

    rng = np.random.default_rng(n)
    M = 21
    D = rng.standard_normal((M, n, n))
    h = rng.standard_normal((M, n))
    data = PlotData(x=np.linspace(0.0, 2.0, M), enveloped=False, N=M,
                    series={"D_tran": D, "D_rot": 0.5 * D, "D": 1.5 * D, "h_tran": h,
                            "h_rot": h, "h": 2 * h})
    labels = [element_label("D", i, j) for i in range(n) for j in range(i, n)]
    with matplotlib.rc_context(RC):             # in parts of at most five rows of four
        parts = [fig_D(data, {lab: "both" for lab in labels}, {}, 0.9, 0.01, part=k)
                 for k in range(len(element_parts(labels)))]
        figh = fig_h(data, {}, {})
    assert len(parts) == -(-len(labels) // 20)
    fig = parts[0]
    titles = [ax.get_title() for f in parts for ax in f.axes]
    assert len(titles) == n * (n + 1) // 2
    assert titles == [f"{shown(lab)}: both" for lab in labels]     # D12 -> D(1,2)
    assert ("D(1,2): both" in titles) == (n >= 2) and "D(1,1): both" in titles
    if n >= 10:                     # the comma of the label rule stays
        assert "D(1,10): both" in titles
        assert "D(10,10): both" in titles
    assert len(figh.axes) == n
    sizes = {tuple(np.round(ax.get_position().size * f.get_size_inches(), 3))
             for f in (*parts, figh) for ax in f.axes}
    assert len(sizes) == 1                          # one panel size for D and h
    assert fig.get_size_inches()[0] == pytest.approx(7.2)
    assert min(w for w, _ in sizes) >= 1.1          # at least 1.1 in wide at page width


def test_round_off_is_never_tabulated_as_data(puma_report):
    """A share of 4e-14, a part peak of 2e-18 or a torque error of 6e-16 is round-off
    of its quantity's scale and reads "≡ 0"; only the formulations' agreement, which measures
    round-off, keeps its digits."""
    import re

    html = (puma_report["out"] / "report.html").read_text(encoding="utf-8")
    tiny = re.compile(r"^-?[0-9.]+e-(1[3-9]|[2-9][0-9])( %)?$")
    for t in tables_of(html):
        if t and any("vs" in " ".join(r) for r in t[1:2]):
            continue                                    # the formulations' agreement
        for row in t[1:]:
            assert not any(tiny.match(cell.strip()) for cell in row), row


def test_chapter_model_dearer_than_full_is_explained(puma_report):
    """Table 5.4: the chapter rule's explicit model costs more than the full one;
    Sec. 5.3 says so and why, with the stored counts."""
    ds = puma_report["ds"]
    costs = dict(zip(strings(ds["cost_model"].values), ds["cost_total"].values))
    chapter, full = int(costs["explicit, chapter"]), int(costs["explicit, full"])
    html = unescape((puma_report["out"] / "report.html").read_text(encoding="utf-8"))
    if chapter <= full:
        assert "costs more than the full explicit model" not in html
        return
    assert (f"costs more than the full explicit model ({chapter:,} against {full:,} "
            "operations)") in html
    a = ds.attrs
    assert a["other_rule_harmonics"] <= a["full_harmonics"]        # it keeps fewer terms ...
    assert f"keeps {a['other_rule_harmonics']:,} of the full model's {a['full_harmonics']:,}" in html
    assert a["other_rule_coefficients"] > a["full_coefficients"]  # ... with less in common


def test_envelope_text_gives_the_drawn_column_count(tmp_path, two_link):
    """One fact in one place: on a 5,000-set-point run, the number of envelope
    columns the text and the captions give equals the columns of the drawn figure's curves
    (oracle: the distinct abscissae of the drawn lines); the context said "about 400" while
    it defined 1000 of its own."""
    from gd_analyze.report.main_context import report_context

    trajectory = plan_quintic(two_link, [0.0, 0.0], [np.pi / 2, np.pi / 3], n_setpoints=5000)
    with open_results(make_results(two_link, trajectory, tmp_path, check=False)) as ds:
        ds = ds.load()
    ctx = report_context(ds)
    fig = report.make_figures(ds, report.plot_data(ds), keys=("D",))["D"]
    drawn = {np.unique(line.get_xdata()).size for ax in fig.axes for line in ax.lines
             if len(line.get_xdata()) > 2}
    assert len(drawn) == 1
    texts = [ctx["envelope_note"], *ctx["captions"].values()]
    said = [int(m.replace(",", "")) for t in texts
            for m in re.findall(r"over (?:about )?([\d,]+) equal time columns", t)]
    assert len(said) >= 2 and set(said) == drawn, (said, drawn)
    assert report.ENVELOPE_COLUMNS == drawn.pop()


def test_torque_caption_describes_the_drawn_figure(puma_report):
    """Fig. 4's caption says what the figure drawn for the file shows (oracle: the drawn
    lines' colours and styles): with the simplified-model variables, τₛ − τ and its bound, no
    "green, dashed" τₛ; without them (results of analyze() without simplify), the fallback
    figure of τ (black, solid) and τₛ (green, dashed), as its caption says."""
    from gd_analyze.report.main_context import report_context

    ds = puma_report["ds"].load()
    bare = ds.drop_vars([v for v in ds.variables if str(v).startswith("simplified")])
    for data, simplified in ((ds, True), (bare, False)):
        caption = report_context(data)["captions"]["torque"]
        fig = report.make_figures(data, keys=["torque"])["torque"]
        drawn = {(line.get_color().lower(), line.get_linestyle()) for ax in fig.axes
                 for line in ax.lines if len(line.get_xdata()) > 2}
        green_dashed = ("#009e73", "--") in drawn
        assert green_dashed == ("green, dashed" in caption) == (not simplified), caption
        assert ("black, solid" in caption) == (("#000000", "-") in drawn)


def test_latex_tables_on_request(tmp_path, puma_report):
    """With ``latex`` every CSV table has its LaTeX twin, balanced braces, its number as label."""
    written = report.write_report(puma_report["results"], tmp_path / "tex", formats=("html",),
                                  latex=True)
    csvs = [p for p in written if p.suffix == ".csv"]
    texs = [p for p in written if p.suffix == ".tex"]
    assert csvs and [p.stem for p in texs] == [p.stem for p in csvs]
    for p in texs:
        tex = p.read_text(encoding="utf-8")
        number = ".".join(p.stem.split("_")[1:])
        assert f"\\label{{tab:gd-{number}}}" in tex
        unescaped = re.sub(r"\\[{}]", "", tex)
        assert unescaped.count("{") == unescaped.count("}"), p.name
