"""Drawing the reports' figures: the ticks of a draw reused by its measure, the figures' PDFs
typeset on a worker thread, and a report's PDF typeset while its other files are written."""

from __future__ import annotations

import io
import threading

import matplotlib.axis
import pytest
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
from pdf_checks import info

from gd_analyze.report import drawing
from gd_analyze.report.drawing import (
    draw_each,
    draw_figures,
    figure_svg,
    kept_in_the_draw,
    svg_size,
)
from gd_analyze.report.figure_style import BASE_RC
from gd_analyze.report.sections import Outline

CREATED = "2026-11-27T12:00:00Z"
#: The same ids in every drawing of a figure.
RC = {**BASE_RC, "svg.hashsalt": "test"}


def _figure(sticking_out=False):
    """Two panels sharing x; with ``sticking_out`` the lower panel's tick labels and x label
    hang below the figure's edge."""
    fig = Figure(figsize=(4.0, 3.0))
    bottom = 0.02 if sticking_out else 0.2
    top = fig.add_axes((0.15, 0.6, 0.8, 0.35))
    low = fig.add_axes((0.15, bottom, 0.8, 0.35), sharex=top)
    for ax, k in ((top, 1.0), (low, -3.0)):
        ax.plot([0.0, 1.0, 2.0, 3.0], [0.0, k, 2 * k, 0.5 * k], marker="o")
        ax.set_ylabel("torque [N m]", fontsize=10)
        ax.tick_params(labelsize=10)
    low.set_xlabel("time [s]", fontsize=10)
    return fig


def _counted(monkeypatch):
    """Count every time an axis works its ticks out (matplotlib's own method, wrapped)."""
    calls = []
    work_out = matplotlib.axis.Axis._update_ticks

    def counted(self):
        calls.append(self)
        return work_out(self)

    monkeypatch.setattr(matplotlib.axis.Axis, "_update_ticks", counted)
    return calls


def test_a_name_in_a_script_the_font_lacks_is_drawn_without_a_warning():
    """A joint named in Japanese (a panel title of the identify report) gave matplotlib's
    "Glyph ... missing from font(s) DejaVu Sans" once per character and drawing: 21 lines on
    stderr under -q. The SVG keeps text as text, so the name is there as written (oracle:
    the title's own characters in the SVG)."""
    import warnings

    fig = _figure()
    fig.axes[0].set_title("joint 1: \u30b8\u30e7\u30a4\u30f3\u30c8")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        svg = figure_svg(fig, RC)
    assert "\u30b8\u30e7\u30a4\u30f3\u30c8" in svg


def test_each_axis_works_its_ticks_out_once_a_drawing(monkeypatch):
    """figure_svg draws, measures and (where its text sticks out) draws again a figure with
    each axis's ticks worked out once; a plain SVG draw works them out more often (the labels
    placed clear of the shared axes' tick labels)."""
    import io

    calls = _counted(monkeypatch)
    plain = _figure()
    with matplotlib.rc_context(BASE_RC):
        plain.savefig(io.BytesIO(), format="svg")
    assert len(calls) > 4
    for sticking_out in (False, True):
        calls.clear()
        figure_svg(_figure(sticking_out), BASE_RC)
        assert len(calls) == 4                  # two panels' x and y axes, once each


def test_the_drawing_is_the_one_of_ticks_worked_out_whenever_asked():
    """The SVG is the one matplotlib draws with no tick kept: drawn, measured on that
    drawing's renderer and, where text sticks out, drawn again as tall as its text."""
    import io

    from gd_analyze.report.figure_style import text_extent

    meta = {"Date": None, "Creator": None, "Format": None, "Type": None}
    for sticking_out in (False, True):
        fig, extent = _figure(sticking_out), []
        with matplotlib.rc_context(RC):
            buf = io.BytesIO()
            cid = fig.canvas.mpl_connect("draw_event",
                                         lambda e: extent.append(text_extent(fig, e.renderer)))
            fig.savefig(buf, format="svg", metadata=meta)
            fig.canvas.mpl_disconnect(cid)
            if sticking_out:
                assert extent[0].height > fig.bbox_inches.height
                buf = io.BytesIO()
                fig.savefig(buf, format="svg", bbox_inches=extent[0], metadata=meta)
        text = buf.getvalue().decode()
        assert figure_svg(_figure(sticking_out), RC) == text[text.index("<svg"):]


def test_a_figure_whose_text_sticks_out_is_drawn_as_tall_as_its_text():
    """The SVG is as tall as the figure's box grown to hold its text, measured by matplotlib
    on a figure of its own drawn by the Agg backend (the ticks worked out afresh there)."""
    for sticking_out in (False, True):
        oracle = _figure(sticking_out)
        with matplotlib.rc_context(BASE_RC):
            canvas = FigureCanvasAgg(oracle)
            canvas.draw()
            tight = oracle.get_tightbbox(canvas.get_renderer())
        height = max(3.0, tight.y1) - min(0.0, tight.y0)
        w, h = svg_size(figure_svg(_figure(sticking_out), BASE_RC))
        assert w == pytest.approx(4.0)
        assert h == pytest.approx(height, abs=0.02)          # the SVG's sizes: to 0.01 pt
        assert (h > 3.05) == sticking_out


def test_ticks_of_the_draw_are_worked_out_again_once_the_block_is_left(monkeypatch):
    calls = _counted(monkeypatch)
    fig = _figure()
    with kept_in_the_draw(fig) as (ticks, _):
        FigureCanvasAgg(fig).draw()
        n = len(calls)
        assert n == len(ticks) == 4                         # two panels' x and y axes
        fig.get_tightbbox(fig.canvas.get_renderer())
        assert len(calls) == n                              # handed back, none worked out
    fig.get_tightbbox(fig.canvas.get_renderer())
    assert len(calls) > n                                   # the class's own method again
    assert all("_update_ticks" not in vars(a) for ax in fig.axes for a in (ax.xaxis, ax.yaxis))


def test_layouts_of_the_draw_are_those_matplotlib_works_out():
    """Texts of one string in different settings (size, font weight, rotation, alignments,
    line spacing, two lines), each laid out on an Agg and an SVG renderer: within the block
    every layout is the one matplotlib's own method works out for that text, however often
    asked; one is worked out per setting and renderer; on leaving, the class's own method."""
    from matplotlib.backends.backend_svg import RendererSVG
    from matplotlib.text import Text

    fig = Figure(figsize=(4.0, 3.0))
    settings = [{}, {"fontsize": 12}, {"fontweight": "bold"}, {"rotation": 90},
                {"rotation": 30, "rotation_mode": "anchor"}, {"ha": "right"}, {"va": "top"},
                {"linespacing": 2.0}, {"text": "0.5\n10"}, {"text": "0.5\n10", "ma": "right"}]
    texts = [fig.text(0.1, 0.05 * k, **{"s": s.pop("text", "0.5"), **s})
             for k, s in enumerate(settings)]
    texts.append(fig.text(0.5, 0.5, "0.5"))                 # the first one's setting again
    renderers = [FigureCanvasAgg(fig).get_renderer(), RendererSVG(4.0 * 72, 3.0 * 72, io.StringIO())]
    own = Text._get_layout

    def laid_out(layout):
        return [(box.bounds, lines, corner) for box, lines, corner in layout]

    expected = laid_out(own(t, r) for r in renderers for t in texts)
    with kept_in_the_draw(fig) as (_, kept):
        for _ in range(2):
            assert laid_out(Text._get_layout(t, r) for r in renderers for t in texts) == expected
        assert len(kept) == 2 * len(settings)
    assert Text._get_layout is own


def test_draw_each_gives_what_draw_figures_gives_and_typesets_off_the_main_thread(monkeypatch):
    """The same SVG, PDF and size of every figure, in the makers' order; the PDFs are typeset
    on another thread than the one drawing."""
    makers = {"b": lambda: _figure(True), "a": _figure}
    expected = draw_figures({k: m() for k, m in makers.items()}, RC, created=CREATED)
    threads = []
    typeset = drawing.figure_pdfs

    def recorded(figures, created=None):
        threads.append(threading.current_thread())
        return typeset(figures, created)

    monkeypatch.setattr(drawing, "figure_pdfs", recorded)
    got = draw_each(makers, RC, CREATED)
    assert list(got) == ["b", "a"]
    for k in makers:
        svg, pdf, size = got[k]
        assert svg == expected[k][0] and size == expected[k][2]
        assert pdf is not None and pdf.startswith(b"%PDF")
        assert pdf == expected[k][1]
    assert len(threads) == 2 and threading.main_thread() not in threads


def _write(tmp_path, paper):
    drawn = draw_figures({"a": _figure()}, BASE_RC, created=CREATED)

    def outline(shown):
        o = Outline("A report", figures=set(shown))
        o.section("1", "Figures")
        o.paragraph("One figure.")
        o.figure("a", "a figure")
        return o

    return drawing.write_documents(
        tmp_path, drawn, {"a": "fig_a"}, outline, lambda o, d: "<html></html>",
        {"metadata": {}, "footer": "test", "created": CREATED}, paper=paper)


def test_write_documents_waits_for_the_pdf_and_writes_every_file(tmp_path):
    files = _write(tmp_path, "a4")
    names = [p.relative_to(tmp_path).as_posix() for p in files]
    assert names[:4] == ["report.html", "report.pdf", "figures/fig_a.pdf", "figures/fig_a.svg"]
    assert all(p.is_file() and p.stat().st_size > 0 for p in files)
    assert (tmp_path / "report.pdf").read_bytes().startswith(b"%PDF")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["figures", "report.html",
                                                          "report.pdf", "tables"]


def test_write_documents_makes_its_folder(tmp_path):
    # the control and sweep reports write into a folder not made yet: the documents were
    # staged there before the figures' folder (which makes it) existed
    files = _write(tmp_path / "new" / "out", "a4")
    assert all(p.is_file() for p in files) and (tmp_path / "new" / "out" / "report.pdf").is_file()


def test_a_pdf_that_fails_on_the_worker_thread_leaves_no_file(tmp_path):
    """The PDF's error reaches the caller, and no file of the report is left behind."""
    with pytest.raises(ValueError, match="paper"):
        _write(tmp_path, "a5")
    assert [p for p in tmp_path.rglob("*") if p.is_file()] == []


def test_write_report_files_renders_the_template_and_the_pdf_information(tmp_path):
    """The HTML is the template rendered from the context and the outline; the PDF carries
    the context's version, the subject and the keywords given (or the context's own)."""
    drawn = draw_figures({"a": _figure()}, BASE_RC, created=CREATED)
    ctx = {"version": "9.8.7", "title": "A <b>report</b>", "keywords": "from the context"}

    def outline(context, shown):
        o = Outline(context["title"], figures=set(shown))
        o.section("1", "Figures")
        o.figure("a", "a figure")
        return o

    for keywords, expected in ((None, "from the context"), ("given", "given")):
        folder = tmp_path / str(keywords)
        files = drawing.write_report_files(folder, ctx, drawn, {"a": "fig_a"}, outline,
                                           "control_report.html.j2", "the subject", "foot",
                                           keywords, stem="rep", latex=False)
        assert [p.name for p in files[:4]] == ["rep.html", "rep.pdf", "fig_a.pdf", "fig_a.svg"]
        html = (folder / "rep.html").read_text(encoding="utf-8")
        assert "<title>A &lt;b&gt;report&lt;/b&gt;</title>" in html    # escaped, from ctx
        assert 'content="gd-analyze 9.8.7"' in html and "<svg" in html
        meta = info(folder / "rep.pdf")
        assert meta["Subject"] == "the subject" and meta["Keywords"] == expected
        assert meta["Author"] == "gd-analyze 9.8.7"
