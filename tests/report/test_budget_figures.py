"""The figures of what the error budget acts on (gd_analyze.report.simplified_section): the torque
contributions against Pinocchio, the budget against the stored bound, the costs as stored."""

import dataclasses

import matplotlib
import numpy as np
import pinocchio as pin
import pytest
from pdf_checks import text

from gd_analyze import load_robot
from gd_analyze.dynamics.pinocchio import pinocchio_model
from gd_analyze.report.common import strings
from gd_analyze.report.drawing import figure_svg
from gd_analyze.report.main import FIG_RC
from gd_analyze.report.main_figures import plot_data
from gd_analyze.report.sections import Outline
from gd_analyze.report.simplified_section import (
    CONTRIBUTIONS,
    budget_parts,
    contribution_series,
    cost_points,
    fig_cost_ladder,
    fig_error_budget,
    fig_torque_contributions,
)
from gd_analyze.report.typeset import write_pdf


@pytest.mark.parametrize("name", ["puma560", "stanford"])
def test_the_five_contributions_sum_to_pinocchios_rnea(name, shipped_dataset):
    """Oracle: D^tran qdd + D^rot qdd + h^tran + h^rot + c = tau = Pinocchio's rnea(q, qd, qdd)
    (Eq. (3.4-25)), per set point and joint, within 1e-9 of the joint's peak |tau|; the figure
    draws exactly these series (and tau_s), one panel per joint."""
    ds = shipped_dataset(name)
    data = plot_data(ds)
    series = contribution_series(data)
    total = sum(series[key] for key, *_ in CONTRIBUTIONS)
    model = pinocchio_model(load_robot(name))
    pdata = model.createData()
    q, qd, qdd = (ds[k].values for k in ("q", "qd", "qdd"))
    tau = np.array([pin.rnea(model, pdata, a, b, c) for a, b, c in zip(q, qd, qdd)])
    scale = np.abs(tau).max(axis=0)
    assert np.all(np.abs(total - tau) <= 1e-9 * scale), np.abs(total - tau).max(axis=0) / scale
    # no part is the whole torque: the split carries information on every arm
    assert all(np.abs(series[key]).max() > 1e-6 * scale.max() for key in ("D_tran_qdd", "c"))
    with matplotlib.rc_context(FIG_RC):
        fig = fig_torque_contributions(data, ["N m"] * ds.sizes["joint"])
    assert [ax.get_title() for ax in fig.axes] == [f"joint {i + 1}"
                                                   for i in range(ds.sizes["joint"])]
    for i, ax in enumerate(fig.axes):
        drawn = {line.get_label(): line.get_ydata() for line in ax.lines}
        for key, label, *_ in CONTRIBUTIONS:
            np.testing.assert_array_equal(drawn[label], series[key][:, i])
        assert any(np.array_equal(y, ds["tau_simplified"].values[:, i]) for y in drawn.values())


def test_the_drives_contribution_closes_the_sum(tmp_path):
    """puma560-drives: tau also holds the armature's and friction's torque; the figure draws
    it as a sixth curve, tau - (the five), which is not zero."""
    from conftest import ROOT

    from gd_analyze.jobs.analyze import analyze_to_file
    from gd_analyze.jobs.options import AnalysisOptions
    from gd_analyze.store.schema import open_results
    from gd_analyze.trajectory.trajectory import read_trajectory

    robot = load_robot("puma560-drives")
    traj = read_trajectory(ROOT / "data" / "puma560_trajectory.csv", robot.n)
    path = tmp_path / "results.h5"
    analyze_to_file(robot, traj, path, AnalysisOptions(formulations=False, verify=False))
    with open_results(path, lazy=True) as ds:
        ds = ds.load()
    series = contribution_series(plot_data(ds), drives=True)
    drives = series["drives"]
    np.testing.assert_allclose(sum(series[k] for k, *_ in CONTRIBUTIONS) + drives,
                               ds["tau"].values, rtol=0, atol=1e-12 * np.abs(ds["tau"]).max())
    assert np.abs(drives).max() > 1e-3 * np.abs(ds["tau"].values).max()


def test_budget_bars_are_the_stored_bound_and_the_dash_is_eps(shipped_dataset):
    """The stacked bars add up to the stored bound / s_i, the dash sits at EPS, the diamond
    at the stored peak error / s_i; a joint with nothing dropped says so."""
    ds = shipped_dataset("puma560")
    scale = ds["simplified_scale"].values
    parts = budget_parts(ds)
    np.testing.assert_allclose(sum(parts.values()), ds["simplified_bound"].values / scale,
                               rtol=1e-9, atol=1e-15)
    with matplotlib.rc_context(FIG_RC):
        fig = fig_error_budget(ds)
    ax = fig.axes[0]
    tops = np.zeros(scale.size)
    for bar in ax.patches:
        i = int(round(bar.get_x() + bar.get_width() / 2)) - 1
        tops[i] = max(tops[i], bar.get_y() + bar.get_height())
    np.testing.assert_allclose(tops, 100 * ds["simplified_bound"].values / scale, rtol=1e-9)
    eps = float(ds.attrs["simplified_tolerance"])
    dash = ax.collections[0].get_segments()
    assert all(np.isclose(seg[0][1], 100 * eps) for seg in dash)
    diamond = next(line for line in ax.lines if line.get_marker() == "D")
    np.testing.assert_allclose(diamond.get_ydata(),
                               100 * ds["tau_error_peak"].values / scale)
    nothing = sum(t.get_text() == "nothing\ndropped" for t in ax.texts)
    assert nothing == int((ds["simplified_bound"].values == 0).sum())


def test_cost_ladder_reads_the_stored_costs(shipped_dataset):
    """Every point's operations are a stored ``cost_total``; AKB's 305 (stated, 1 %) only for
    the PUMA 560; the model built at its measured worst error / s_i; the exact recursive model
    and Newton-Euler at 0."""
    for name, akb in (("puma560", True), ("stanford", False)):
        ds = shipped_dataset(name)
        stored = dict(zip(strings(ds["cost_model"].values), ds["cost_total"].values))
        points = cost_points(ds)
        by = {label: (ops, err, kind) for label, ops, err, kind in points}
        assert all(ops in stored.values() for _, ops, _, _ in points)
        assert ("AKB 1986 simplified (1 %)" in by) is akb
        if akb:
            assert by["AKB 1986 simplified (1 %)"][:2] == (305.0, 0.01)
        assert by["recursive N-E, exact"][1] == 0.0
        assert by["project N-E as implemented"][1] == 0.0
        model = next(p for p in points if p[3] == "model")
        worst = np.max(ds["tau_error_peak"].values / ds["simplified_scale"].values)
        assert model[2] == pytest.approx(worst)
        with matplotlib.rc_context(FIG_RC):
            fig = fig_cost_ladder(ds)
        xs = sorted(float(line.get_xdata()[0]) for line in fig.axes[0].lines
                    if len(line.get_xdata()) == 1)
        assert xs == sorted(ops for _, ops, _, _ in points)



@pytest.mark.parametrize("width", [7.2, 3.5])
def test_cost_ladders_operation_ticks_are_1_2_5_per_decade(shipped_dataset, width):
    """The operations axis is labelled at every 1, 2 and 5 times a power of ten within its
    limits, and only there, each written as the whole number with a thousands comma. Oracle:
    the products m 10^k listed from the axis' limits."""
    from figure_checks import tick_texts

    with matplotlib.rc_context(FIG_RC):
        ax = fig_cost_ladder(shipped_dataset("puma560"), width=width).axes[0]
    lo, hi = ax.get_xlim()
    want = [m * 10.0 ** k for k in range(-1, 8) for m in (1, 2, 5) if lo <= m * 10.0 ** k <= hi]
    got = tick_texts(ax, "x")
    assert len(want) >= 3
    assert [v for v, _ in got] == pytest.approx(want, rel=1e-12)
    assert [t.get_text() for _, t in got] == [f"{round(v):,}" for v in want]

@pytest.mark.parametrize("extra", [0, 3, 8])
@pytest.mark.parametrize("width", [7.2, 3.5])
def test_the_cost_ladders_key_never_runs_into_the_axis_label(shipped_dataset, width, extra,
                                                            monkeypatch):
    """The numbered key below the axes, raised to the printed minimum and wrapped again as the
    report's drawing does (which made the PUMA 560's key four lines, the fourth in the axis
    label), stays below the x axis label and its tick labels, within the saved figure's box."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    from gd_analyze.report import simplified_section
    from gd_analyze.report.figure_style import raise_small_text, text_extent
    from gd_analyze.report.typeset import MIN_PRINTED_PT, printed_scale

    ds = shipped_dataset("puma560")
    points = cost_points(ds)
    more = [(f"explicit, budget EPS=0.0{k} (a model with a long name)", 400.0 + 40 * k,
             0.001 * k, "exact") for k in range(extra)]
    monkeypatch.setattr(simplified_section, "cost_points", lambda _: points + more)
    with matplotlib.rc_context(FIG_RC):
        fig = fig_cost_ladder(ds, width=width)
        renderer = FigureCanvasAgg(fig).get_renderer()
        raise_small_text(fig, MIN_PRINTED_PT / printed_scale(fig.get_size_inches()))
        fig.draw(renderer)
        key = next(t for t in fig.texts if t.get_text().startswith("1: "))
        box = key.get_window_extent(renderer)
        label = fig.axes[0].xaxis.label.get_window_extent(renderer)
        ticks = [t.get_window_extent(renderer) for t in fig.axes[0].get_xticklabels()
                 if t.get_text()]
        saved = text_extent(fig)
    assert key.get_text().count("\n") >= 2
    assert box.y1 < label.y0 and all(box.y1 < t.y0 for t in ticks)
    assert box.y0 >= saved.y0 * fig.dpi - 1 and box.x1 <= fig.bbox.x1


@pytest.mark.parametrize("eps_share", [0.2, 0.45, 0.8])
@pytest.mark.parametrize("width", [7.2, 3.5])
def test_nothing_dropped_never_crosses_the_budgets_dash(shipped_dataset, width, eps_share,
                                                        monkeypatch):
    """A joint's "nothing dropped", raised to the printed minimum as the report draws it,
    stays clear of the budget's dash and within the axes, wherever the dash sits (on the
    PUMA 560 at a quarter of the axis the dash struck through it)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    from gd_analyze.report import simplified_section
    from gd_analyze.report.figure_style import raise_small_text
    from gd_analyze.report.typeset import MIN_PRINTED_PT, printed_scale

    ds = shipped_dataset("puma560")
    eps = float(ds.attrs["simplified_tolerance"])
    parts = budget_parts(ds)
    # the tallest bar at eps / (eps_share * 1.25): the dash at eps_share of the axis height
    top = 100 * eps / eps_share / 1.25
    peak = max(float(np.nanmax(sum(parts.values()))) * 100, 1e-300)
    scaled = {k: v * top / peak for k, v in parts.items()}
    monkeypatch.setattr(simplified_section, "budget_parts", lambda _: scaled)
    with matplotlib.rc_context(FIG_RC):
        fig = fig_error_budget(ds, width=width)
        renderer = FigureCanvasAgg(fig).get_renderer()
        raise_small_text(fig, MIN_PRINTED_PT / printed_scale(fig.get_size_inches()))
        fig.draw(renderer)
        ax = fig.axes[0]
        labels = [t for t in ax.texts if "nothing" in t.get_text()]
        dash = ax.transData.transform((1, 100 * eps))[1]
        frame = ax.get_window_extent(renderer)
        boxes = [t.get_window_extent(renderer) for t in labels]
    assert labels
    for b in boxes:
        assert b.y0 > dash + 1 or b.y1 < dash - 1, (b, dash)
        assert frame.y0 <= b.y0 and b.y1 <= frame.y1, (b, frame)


def test_wide_tick_labels_leave_room_for_every_panels_axis_label(shipped_dataset):
    """A joint whose torques are a few hundredths of a N m gets tick labels like -0.050: the
    panels move right so that every axis label, drawn, lies inside the figure with a margin
    (with a fixed margin of 0.55 in it came within 0.02 in of the edge, and on the Panda's
    joint 7 was cut off)."""
    import dataclasses

    ds = shipped_dataset("puma560")
    data = plot_data(ds)
    peak = np.abs(np.asarray(data.series["tau"], float)).max(axis=0)          # (n,)
    small = {k: np.asarray(v, float) * (0.061 / peak) for k, v in data.series.items()}
    data = dataclasses.replace(data, series=small)
    with matplotlib.rc_context(FIG_RC):
        fig = fig_torque_contributions(data, ["N m"] * ds.sizes["joint"])
        from matplotlib.backends.backend_agg import FigureCanvasAgg

        canvas = FigureCanvasAgg(fig)
        canvas.draw()
        renderer = canvas.get_renderer()
        for ax in fig.axes:
            label = ax.yaxis.label.get_window_extent(renderer)
            ticks = ax.yaxis.get_tightbbox(renderer)
            margin = 0.05 * fig.dpi                     # 0.05 in clear of the figure's edge
            assert label.x0 >= margin and ticks.x0 >= margin, (ax.get_title(), label.x0)


def _tiled(ds, n):
    """The PUMA 560's per-joint record repeated to n joints: the variables of dimension
    ``joint`` alone, with the dataset's attributes (what the budget figure reads)."""
    names = [v for v in ds.data_vars if ds[v].dims == ("joint",)]
    out = ds[names].isel(joint=np.arange(n) % ds.sizes["joint"])
    out = out.assign_coords(joint=[f"j{k + 1}" for k in range(n)])
    out.attrs = dict(ds.attrs)
    return out


@pytest.mark.parametrize(("n", "width"), [(6, 7.2), (12, 7.2), (15, 7.2), (6, 3.5), (15, 3.5)])
def test_joint_labels_and_nothing_dropped_never_touch(shipped_dataset, n, width, monkeypatch):
    """Across a page, 15 joints' "joint i" labels ran into each other ("joint 9joint
    10oint 11"), and so did their "nothing dropped": with its text raised to the printed
    minimum as the report draws it, the figure has no collision (tests/figure_checks.py);
    across a page 6 and 12 joints keep "joint i", 15 are numbered under an axis label
    "joint"; where a joint's room is too narrow even for the note on its side (15 joints in
    a column), the figure's note names the joints instead."""
    from figure_checks import collisions, draw

    from gd_analyze.report import simplified_section
    from gd_analyze.report.figure_style import raise_small_text
    from gd_analyze.report.typeset import MIN_PRINTED_PT, printed_scale

    ds = _tiled(shipped_dataset("puma560"), n)
    monkeypatch.setattr(simplified_section, "budget_parts",       # nothing dropped anywhere
                        lambda s: {k: 0 * v for k, v in budget_parts(s).items()})
    with matplotlib.rc_context(FIG_RC):
        fig = fig_error_budget(ds, width=width)
    raise_small_text(fig, MIN_PRINTED_PT / printed_scale(fig.get_size_inches()))
    assert not collisions(fig, FIG_RC), collisions(fig, FIG_RC)[:4]
    ax = fig.axes[0]
    notes = [t for t in ax.texts if "nothing" in t.get_text()]
    below = " ".join(t.get_text().replace("\n", " ") for t in fig.texts)
    listed = "Nothing dropped at joints " + ", ".join(map(str, range(1, n + 1))) + "."
    assert len(notes) == n or (not notes and listed in below), (n, width)
    assert (listed in below) == (not notes) and (notes or (n, width) == (15, 3.5))
    # neighbours' notes keep 2 pt apart: 12 joints across a page printed them touching, read
    # as "droppeddropped"
    renderer = draw(fig, FIG_RC)
    boxes = sorted((t.get_window_extent(renderer) for t in notes), key=lambda b: b.x0)
    gaps = [b.x0 - a.x1 for a, b in zip(boxes, boxes[1:])]
    assert min(gaps, default=np.inf) >= 2 * fig.dpi / 72, (n, width, min(gaps))
    labels = [t.get_text() for t in ax.get_xticklabels()]
    full = [f"joint {k}" for k in range(1, n + 1)]
    assert labels == full or labels == [str(k) for k in range(1, n + 1)]
    assert (ax.get_xlabel() == "joint") == (labels != full)
    assert (labels == full) == (width == 7.2 and n != 15)   # short where "joint i" won't fit


@pytest.fixture(scope="module")
def contributions_drawn(shipped_dataset):
    """The figure of the torque contributions of an arm of n joints (the PUMA 560's joints
    over again) as SVG text and size, by n: drawn once a module for both papers of
    :func:`test_the_contributions_of_many_joints_leave_their_page_room_for_the_error_table`
    (the figure does not depend on the paper). Shared: read only."""
    drawn = {}

    def get(n):
        if n not in drawn:
            data = plot_data(shipped_dataset("puma560"))
            cols = np.arange(n) % 6                       # the PUMA 560's joints over again
            data = dataclasses.replace(data, series={k: np.asarray(v)[:, cols] for k, v in
                                                     data.series.items() if np.ndim(v) == 2})
            with matplotlib.rc_context(FIG_RC):
                fig = fig_torque_contributions(data, ["N m"] * n)
                size = tuple(fig.get_size_inches())
                drawn[n] = figure_svg(fig), size
        return drawn[n]
    return get


@pytest.mark.parametrize("paper", ["a4", "letter"])
@pytest.mark.parametrize("n", [10, 12, 15])
def test_the_contributions_of_many_joints_leave_their_page_room_for_the_error_table(
        n, paper, contributions_drawn, tmp_path):
    """The figure of a 10- to 15-joint arm, set under its heading at a page's top, leaves room
    under it for the next section's table of the torque error per joint (n rows): that page is
    not left with its foot blank (the G1 right arm's figure of four rows of three panels, 8.07
    in tall, stood alone on its page, the table going to the next)."""
    svg, size = contributions_drawn(n)
    o = Outline("Report", figures={"c"})
    o.section("1", "Simplified model and torque error")
    o.figure("c", "What the error budget acts on.")
    o.section("1.1", "Torque error along the trajectory")
    o.table({"header": ["joint", "peak |\u03c4s \u2212 \u03c4| [N m]", "peak |\u03c4| [N m]",
                        "peak error / peak |\u03c4|"],
             "rows": [[str(i + 1), "1.234e-02", "30.386", "0.0123 %"] for i in range(n)],
             "align": ["left", "right", "right", "right"], "colour_cols": []},
            "Open-loop torque error per joint.")
    write_pdf(o, {"c": (svg, size)}, tmp_path / "doc.pdf", paper)
    first = " ".join(text(tmp_path / "doc.pdf").split("\f")[0].split())
    assert "What the error budget acts on" in first and "Open-loop torque error" in first, size
