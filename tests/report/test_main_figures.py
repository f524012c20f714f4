"""Figs. 2 and 3 for print (gd_analyze.report.main_figures): panels at least 1.1 in
wide at page width, no panel of an element that is zero in every part, the drives' armature
drawn above the combined curve, and column-width figures only on request."""

import numpy as np
import pytest
from conftest import SHIPPED, column_run

from gd_analyze.report import main as report
from gd_analyze.report.main_context import zero_mask
from gd_analyze.report.main_figures import PART_STYLE, plot_data
from gd_analyze.report.markup import label as shown


def _panel_sizes(fig):
    """Width and height [in] of every plotting area, from the axes' positions."""
    W, H = fig.get_size_inches()
    return [(ax.get_position().width * W, ax.get_position().height * H) for ax in fig.axes]


@pytest.mark.parametrize("name", ["puma560", "stanford", "panda"])
def test_panels_at_least_1_1_in_wide_at_page_width(name, shipped_dataset):
    """Every panel of Figs. 2 and 3 (all their parts) is at least 1.1 in wide on a 7.2-in
    figure (the PUMA's were 0.57 in, the Panda's 0.45 in), and every figure part fits a
    page."""
    ds = shipped_dataset(name)
    figs = report.make_figures(ds, plot_data(ds), keys=("D", "h", *report.FIGURE_PARTS))
    keys = [k for k in figs if k == "h" or k == "D" or k.startswith("D_")]
    assert {"D", "h"} <= set(keys)
    for key in keys:
        fig = figs[key]
        assert fig.get_size_inches()[0] == pytest.approx(7.2)
        assert fig.get_size_inches()[1] <= 9.0, (name, key)
        widths = [w for w, _ in _panel_sizes(fig)]
        assert widths and min(widths) >= 1.1, (name, key, min(widths))


def test_no_panel_of_an_element_zero_in_every_part(shipped_dataset):
    """D45 and D56 of the PUMA 560 are ≡ 0: no panel of theirs (no empty lower-left triangle
    either: only panels with data are laid out), a note names them; every panel draws its
    element."""
    ds = shipped_dataset("puma560")
    labels, zero = zero_mask(ds)
    zeros = [lab for lab, z in zip(labels, zero) if z]
    assert {"D45", "D56"} <= set(zeros)
    figs = report.make_figures(ds, plot_data(ds), keys=("D", "h"))
    for key in ("D", "h"):
        fig = figs[key]
        for ax in fig.axes:
            assert "\u2261" not in ax.get_title()
            assert len(ax.lines) >= 3 and ax.get_title(), ax.get_title()
        drawn = {ax.get_title().split(":")[0] for ax in fig.axes}
        mine = [lab for lab in labels if lab.startswith(key)]
        assert drawn == {shown(lab) for lab in mine if lab not in zeros}
        note = " ".join(t.get_text().replace("\n", " ") for t in fig.texts)
        for lab in (z for z in zeros if z.startswith(key)):
            assert shown(lab) in note.split("not drawn:")[1]
    assert len(figs["D"].axes) == 21 - len([z for z in zeros if z.startswith("D")])


@pytest.fixture(scope="module")
def drives(shared_main):
    """The PUMA 560 with drives' default run on its shipped trajectory (shared, read only:
    tests/conftest.py): its results.h5 and the dataset, loaded."""
    from gd_analyze.store.schema import open_results

    path = shared_main("puma560-drives", SHIPPED) / "results.h5"
    with open_results(path, lazy=True) as ds:
        return path, ds.load()


def test_armature_curve_drawn_above_the_combined_one(drives):
    """puma560-drives: on every diagonal panel D_ii with armature, the armature is a curve
    of its own (the stored D_arm_i), drawn above every other curve of the panel, the combined
    one included (which holds it, and hid it), with a marker at every set point."""
    _, ds = drives
    arm = ds["D_arm"].values
    assert (arm > 0).any()
    fig = report.make_figures(ds, plot_data(ds), keys=("D",))["D"]
    by_title = {ax.get_title().split(":")[0]: ax for ax in fig.axes}
    N = ds.sizes["t"]
    found = 0
    for i in np.flatnonzero(arm > 0):
        ax = by_title[shown(f"D{i + 1}{i + 1}")]
        lines = {line.get_label(): line for line in ax.lines}
        armature, combined = lines[PART_STYLE["arm"]["label"]], lines[PART_STYLE["total"]["label"]]
        np.testing.assert_allclose(armature.get_ydata(), arm[i])
        assert armature.get_zorder() > max(line.get_zorder() for line in ax.lines
                                           if line is not armature)
        assert armature.get_zorder() > combined.get_zorder()
        assert armature.get_marker() not in (None, "None", "") and armature.get_markevery() == 1
        assert len(armature.get_xdata()) == N
        found += 1
    assert found == int((arm > 0).sum())
    n = ds.sizes["joint"]
    for lab in (f"D{i + 1}{j + 1}" for i in range(n) for j in range(i + 1, n)):
        if shown(lab) in by_title:          # off the diagonal: no armature
            labels = {ln.get_label() for ln in by_title[shown(lab)].lines}
            assert PART_STYLE["arm"]["label"] not in labels


def test_column_figures_only_on_request(drives, shared_main):
    """write_report writes no <name>_column file by default (latency); with
    column_figures=True every page-width figure has its 3.5-in twin; the main job's
    --column-figures asks for them. The reports are shared runs' own (the main job's
    write_report without column_figures, and with them: test_figure_print's run), not
    written a second time here."""
    import inspect

    from gd_analyze.cli.parsing import analyze_parser

    path, _ = drives
    assert inspect.signature(report.write_report).parameters["column_figures"].default is False
    names = [p.name for p in path.parent.rglob("*")]
    assert "fig_3_10_D.pdf" in names and not any("_column" in n for n in names)
    stems = {p.stem for p in (column_run(shared_main) / "figures").iterdir()}
    page = {s for s in stems if not s.endswith("_column")}
    assert page and {f"{s}_column" for s in page} <= stems
    assert analyze_parser().parse_args(["puma560", "x.csv"]).column_figures is False
    assert analyze_parser().parse_args(["puma560", "x.csv", "--column-figures"]).column_figures


def test_make_figures_leaves_the_ticks_to_be_restyled(shipped_dataset):
    """Figures of the public make_figures keep matplotlib's own ticks (ticks_once is applied
    only inside write_report): a caller can still restyle them, e.g. relabel an axis."""
    ds = shipped_dataset("puma560")
    fig = report.make_figures(ds, plot_data(ds), keys=("torque",))["torque"]
    from matplotlib.ticker import NullLocator

    for ax in fig.axes:
        assert not isinstance(ax.yaxis.get_major_locator(), NullLocator)
        ticks = ax.yaxis.get_major_ticks()
        assert ticks
        ax.tick_params(labelsize=9)             # restyled: the Tick objects take it
        assert all(t.label1.get_fontsize() == 9 for t in ax.yaxis.get_major_ticks())


def test_an_arm_without_elements_gets_no_panel():
    """Every element of D and h identically zero: the D figure has no panel (the report of a
    massless arm stopped with exit 4; such an arm is now refused as input, jobs/analyze)."""
    from gd_analyze.report.main_figures import element_parts

    assert element_parts([]) == [[]]


@pytest.mark.parametrize("paper", ["a4", "letter"])
@pytest.mark.parametrize("n", [6, 13, 15])
def test_a_part_of_fig_2_fits_under_its_heading_and_lead(n, paper, tmp_path):
    """The first part of Fig. 2 stands on the page of its section's heading and lead paragraph
    (as long as the report's: 472 characters): a part of six rows of a 15-joint arm (8.68 in)
    went to the next page, leaving the heading and lead alone on a page 89 % empty."""
    import matplotlib
    from pdf_checks import text

    from gd_analyze.ranking.ranking import element_label
    from gd_analyze.report.drawing import figure_svg
    from gd_analyze.report.main_figures import RC, PlotData, fig_D
    from gd_analyze.report.sections import Outline
    from gd_analyze.report.typeset import write_pdf

    rng = np.random.default_rng(n)
    D = rng.standard_normal((21, n, n))
    data = PlotData(x=np.linspace(0.0, 2.0, 21), enveloped=False, N=21,
                    series={"D_tran": D, "D_rot": 0.5 * D, "D": 1.5 * D})
    labels = [element_label("D", i, j) for i in range(n) for j in range(i, n)]
    with matplotlib.rc_context(RC):
        fig = fig_D(data, {lab: "both" for lab in labels}, {}, 0.9, 0.01)
        size, svg = tuple(fig.get_size_inches()), figure_svg(fig)
    o = Outline("Report", figures={"D"})
    o.section("1", "Acceleration-related elements of D")
    o.paragraph("One panel per element of the inertia matrix, in reading order. " * 7, "note")
    o.figure("D", "Elements of D against time, split into their parts. " * 5)
    write_pdf(o, {"D": (svg, size)}, tmp_path / "doc.pdf", paper)
    first = " ".join(text(tmp_path / "doc.pdf").split("\f")[0].split())
    assert "One panel per element" in first and "Figure 1. Elements of D" in first, size


def _touching_other_panels(fig, gap_pt):
    """Texts of a drawn figure closer than ``gap_pt`` [pt] to the frame of a panel they do
    not belong to: (text, panel index, gap [pt]); measured with the renderer's extents."""
    from figure_checks import texts

    renderer = fig.canvas.get_renderer()
    pt = fig.dpi / 72.0
    frames = [(k, ax, ax.get_window_extent(renderer)) for k, ax in enumerate(fig.axes)
              if ax.get_visible()]
    found = []
    for owner, t in texts(fig):
        a = t.get_window_extent(renderer)
        for k, ax, b in frames:
            if ax is owner:
                continue
            dx = max(b.x0 - a.x1, a.x0 - b.x1, 0.0)
            dy = max(b.y0 - a.y1, a.y0 - b.y1, 0.0)
            if max(dx, dy) < gap_pt * pt:
                found.append((t.get_text(), k, round(max(dx, dy) / pt, 2)))
    return found


@pytest.mark.parametrize("width", ["page", "column"])
@pytest.mark.parametrize("n, prismatic", [(2, ()), (7, ()), (10, ()), (10, (2, 5)), (15, ())])
def test_joint_motion_labels_stand_clear_of_the_next_panel(n, prismatic, width):
    """Fig. 1 drawn as the report draws it (its text raised to the printed minimum): every
    text at least 1 pt from the frame of every panel it does not belong to. A 10-joint arm's
    accelerations of about 3,400 deg/s² ("−2000" tick labels, Unitree G1's right arm) set
    the q̈ panel's label against the q̇ panel's frame."""
    import matplotlib
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    from gd_analyze.report.drawing import figure_svg
    from gd_analyze.report.main_figures import COLUMN_WIDTH, PAGE_WIDTH, RC, PlotData, fig_joints

    t = np.linspace(0.0, 0.5, 31)
    k = np.arange(1, n + 1)
    w = 2 * np.pi / 0.5
    q = 1.5 * np.sin(w * t[:, None] / k + k)            # [rad]: about +-86 deg
    data = PlotData(x=t, enveloped=False, N=t.size,
                    series={"q": q, "qd": 0.4 * w * np.cos(w * t[:, None] + k),
                            "qdd": -0.4 * w**2 * np.sin(w * t[:, None] + k)})
    kinds = np.isin(np.arange(n), prismatic)
    with matplotlib.rc_context(RC):
        fig = fig_joints(data, kinds, PAGE_WIDTH if width == "page" else COLUMN_WIDTH)
        figure_svg(fig)
        FigureCanvasAgg(fig).draw()
    peak = float(np.degrees(np.abs(data.series["qdd"]).max()))
    assert peak > 3000.0
    bad = _touching_other_panels(fig, 1.0)
    assert not bad, bad


@pytest.fixture(scope="module")
def d_parts():
    """The parts of Fig. 2 :func:`test_the_first_part_of_fig_2_fills_the_foot_of_its_page`
    draws, by (n, first_rows, rows): each drawn once a module (the cases of the same n draw
    the same parts before they are fitted to their paper), as SVG text and size. Shared:
    read only."""
    return {}


@pytest.mark.parametrize("n, paper, filler", [(10, "a4", 7), (10, "letter", 5), (15, "a4", 9)])
def test_the_first_part_of_fig_2_fills_the_foot_of_its_page(n, paper, filler, tmp_path,
                                                           d_parts):
    """A D figure in parts whose first part does not fit under the text citing it: drawn
    again as the room reported by Typst and part_rows say, that part stands on the page of
    its lead, filling its foot to within a row, and every later part's page but the last is
    at least three quarters full (Unitree G1's right arm: the page of Sec. 2's heading and
    lead stood 40 % empty, the whole first part moved on)."""
    import matplotlib
    from pdf_checks import words

    from gd_analyze.ranking.ranking import element_label
    from gd_analyze.report.drawing import figure_svg
    from gd_analyze.report.main_figures import (
        RC,
        PlotData,
        element_parts,
        element_row,
        fig_D,
        part_rows,
    )
    from gd_analyze.report.sections import Outline
    from gd_analyze.report.typeset import (
        MARGINS,
        body_height,
        figure_rooms,
        printed_width,
        write_pdf,
    )

    rng = np.random.default_rng(n)
    D = rng.standard_normal((21, n, n))
    data = PlotData(x=np.linspace(0.0, 2.0, 21), enveloped=False, N=21,
                    series={"D_tran": D, "D_rot": 0.5 * D, "D": 1.5 * D})
    labels = [element_label("D", i, j) for i in range(n) for j in range(i, n)]
    classes = {lab: "both" for lab in labels}

    def drawn(first=None, rows=None):
        if (n, first, rows) in d_parts:
            return d_parts[n, first, rows]
        out = {}
        with matplotlib.rc_context(RC):
            for k in range(len(element_parts(labels, first_rows=first, rows=rows))):
                fig = fig_D(data, classes, {}, 0.9, 0.01, part=k, first_rows=first, rows=rows)
                out["D" if k == 0 else f"D_{k + 1}"] = (figure_svg(fig),
                                                        tuple(fig.get_size_inches()))
        d_parts[n, first, rows] = out
        return out

    def outline(figures):
        o = Outline("Report", figures=set(figures))
        o.section("1", "Robot")
        for k in range(filler):
            o.paragraph(" ".join(["word"] * 42) + f" filler{k}.")
        o.section("2", "Acceleration-related elements of D")
        o.paragraph("One panel per element of the inertia matrix, in reading order. " * 6)
        for key in figures:
            o.figure(key, "Elements of D against time, split into their parts. " * 4)
        o.section("3", "What follows", flush=True)
        o.paragraph("The text after the figure.")
        return o

    first = drawn()
    assert len(first) > 1
    room, need = figure_rooms(outline(first), first, paper)["D"]
    size = first["D"][1]
    scale = printed_width(size, paper) / size[0]
    rows = part_rows(len(labels), room, need, scale, body_height(paper))
    assert rows is not None, (room, need)
    parts = drawn(*rows)
    path = tmp_path / "doc.pdf"
    write_pdf(outline(parts), parts, path, paper)
    pages = words(path)
    lead = next(k for k, (_, _, ws) in enumerate(pages) if any(w[0] == "One" for w in ws))
    row = element_row(len(labels)) * scale * 72                        # [pt]
    body = 72 * body_height(paper)
    for k, (_, height, ws) in enumerate(pages[lead:-1], lead):
        foot = height - 72 * MARGINS[2]
        lowest = max(w[4] for w in ws if w[4] < foot)
        assert any(w[0] == "Figure" for w in ws), f"page {k + 1} holds no part"
        # the lead's page filled to within a row, each later one to within a quarter
        assert foot - lowest < (row if k == lead else body / 4), (k + 1, foot - lowest, row)


def test_the_parts_of_fig_2_are_drawn_once_when_the_first_is_fitted(tmp_path, monkeypatch):
    """A 10-joint arm whose first part of Fig. 2 does not fit under the text citing it: the
    report draws each part once, with the rows that fit (the room measured before D is
    drawn); every part was drawn twice, as planned and then fitted."""
    from model.test_chain import random_chain_spec

    from gd_analyze.jobs.analyze import analyze
    from gd_analyze.jobs.options import AnalysisOptions
    from gd_analyze.model.robot_spec import robot_from_chain
    from gd_analyze.report.drawing import svg_size
    from gd_analyze.store.results_view import Results
    from gd_analyze.trajectory.planning import plan_quintic

    robot = robot_from_chain("chain10", random_chain_spec(10, 1), [0.0, 0.0, -9.81],
                             source="<test>")
    trajectory = plan_quintic(robot, np.zeros(10), np.full(10, 0.5), n_setpoints=21)
    results = analyze(robot, trajectory, AnalysisOptions(verify=False, formulations=False,
                                                         simplify=None))
    made, fig_D = [], report.fig_D

    def counted(*args, **kwargs):
        fig = fig_D(*args, **kwargs)
        made.append((kwargs.get("part", 0), kwargs.get("first_rows"), kwargs.get("rows"),
                     tuple(fig.get_size_inches())))
        return fig
    monkeypatch.setattr(report, "fig_D", counted)
    written = report.write_report(Results.of(results.dataset), tmp_path, ("pdf",))
    svgs = [p for p in written if p.name.startswith("fig_3_10_D") and p.suffix == ".svg"]
    assert len(svgs) > 1 and all(first is not None for _, first, _, _ in made), made
    assert [part for part, *_ in made] == list(range(len(svgs)))
    assert [svg_size(p.read_text(encoding="utf-8")) == pytest.approx(size)
            for p, (*_, size) in zip(svgs, made)] == [True] * len(svgs)


@pytest.mark.parametrize("first_rows, rows", [(None, None), (1, (6, 6, 1)), (2, (5,))])
@pytest.mark.parametrize("width", ["page", "column"])
def test_the_planned_size_of_a_part_of_fig_2_is_the_made_figure_s(width, first_rows, rows):
    """d_size gives the size of the figure fig_D makes, part by part, elements ≡ 0 and the
    drives' armature (its legend entry) included."""
    import matplotlib

    from gd_analyze.ranking.ranking import element_label
    from gd_analyze.report.main_figures import (
        COLUMN_WIDTH,
        PAGE_WIDTH,
        RC,
        PlotData,
        d_size,
        element_parts,
        fig_D,
    )

    n, W = 12, PAGE_WIDTH if width == "page" else COLUMN_WIDTH
    D = np.random.default_rng(n).standard_normal((21, n, n))
    data = PlotData(x=np.linspace(0.0, 2.0, 21), enveloped=False, N=21,
                    series={"D_tran": D, "D_rot": 0.5 * D, "D": 1.5 * D})
    labels = [element_label("D", i, j) for i in range(n) for j in range(i, n)]
    zero = {lab: k % 5 == 1 for k, lab in enumerate(labels)}
    args = (data, {}, zero, 0.9, 0.01)
    kw = {"width": W, "armature": np.linspace(0.0, 0.1, n), "first_rows": first_rows,
          "rows": rows}
    parts = element_parts([lab for lab in labels if not zero[lab]], W, first_rows, rows)
    assert len(parts) > 1
    for k in range(len(parts)):
        with matplotlib.rc_context(RC):
            made = tuple(fig_D(*args, part=k, **kw).get_size_inches())
        assert d_size(*args, part=k, **kw) == made
