"""The main report's figures at print size: no two labels collide, at most
about 12 markers per line, round-off never drawn, seven joints told apart in greyscale.

Collisions are measured on the drawn figure: every text's extent from the renderer
(``Text.get_window_extent``) against every other text's, and against the plotting area of every
other panel, at page width (7.2 in) and at column width (3.5 in), for the PUMA 560, the
Stanford arm (a prismatic joint 3) and the UR5.
"""

import matplotlib
import numpy as np
import pytest
from conftest import ROOT, column_run
from figure_checks import (
    code_names,
    column_twins,
    crowded_axis_labels,
    draw,
    smallest_type,
    texts,
    tick_texts,
)
from figure_checks import collisions as _collisions

from gd_analyze import load_robot
from gd_analyze.ranking.ranking import ROUND_OFF, is_round_off
from gd_analyze.report import main as report
from gd_analyze.report.figure_style import JOINT_STYLES, MAX_MARKERS, joint_style
from gd_analyze.report.main_figures import plot_data
from gd_analyze.trajectory.trajectory import read_trajectory

#: Over 5 s on an idle machine (the module's fixtures): run on one interpreter in CI.
pytestmark = pytest.mark.slow

ROBOTS = ("puma560", "stanford", "ur5")


@pytest.fixture(scope="module", params=ROBOTS)
def figures(request, shipped_dataset):
    name = request.param
    ds = shipped_dataset(name)
    figs = report.make_figures(ds, plot_data(ds), column=True)
    with matplotlib.rc_context(report.FIG_RC):      # as write_report draws them
        for fig in figs.values():
            draw(fig)
    return name, ds, figs


def _texts(fig):
    return texts(fig)


def _draw(fig):
    """Draw the figure as the report does (fixed layout) and give its renderer."""
    return draw(fig, report.FIG_RC)


def collisions(fig):
    return _collisions(fig, report.FIG_RC)


def test_no_label_collides_at_page_or_column_width(figures):
    name, _, figs = figures
    bad = {key: collisions(fig) for key, fig in figs.items()}
    bad = {k: v[:4] for k, v in bad.items() if v}
    assert not bad, f"{name}: {bad}"


def test_axis_labels_stand_clear_of_their_tick_labels(figures):
    """A panel's units ("[kg]", "[10⁻⁴ kg m²]") at least 1 pt from its tick labels: the
    Stanford Fig. 2 read "[kg]5.0" and "[kg m²]2" at 0.5 pt, at page and column width."""
    name, _, figs = figures
    bad = {key: crowded_axis_labels(fig, report.FIG_RC) for key, fig in figs.items()}
    bad = {k: v[:3] for k, v in bad.items() if v}
    assert not bad, f"{name}: {bad}"


def test_fig_2_key_in_mathematics(figures):
    """The key of Fig. 2 states the round-off threshold as 10⁻¹² (not 1e-12); every panel's
    y axis gives its units with its power of ten ("[10⁻³ kg m²]": one label style in Figs. 2
    and 3, never a bare "×10⁻³"), kg m² for an all-revolute arm."""
    name, _, figs = figures
    for key in ("D", "D_column"):
        words = " ".join(t.get_text().replace("\n", " ") for t in figs[key].texts)
        assert "10\u207b\u00b9\u00b2 of its scale" in words and "1e-12" not in words, words
        assert "] [" not in words, (name, key, words)
        assert "D(i,j) against time t [s]" in words, words
        for ax in figs[key].axes:
            label = ax.get_ylabel()
            assert label.startswith("[") and label.endswith("]") and "kg" in label, label
            assert "\u00d7" not in label
            if name != "stanford":                  # one unit for all elements
                assert label.endswith("kg m\u00b2]"), label


def test_column_versions_are_a_column_wide_with_7_pt_type(figures):
    _, _, figs = figures
    assert {"joints_column", "D_column", "h_column", "torque_column"} <= set(figs)
    for key in (k for k in report.COLUMN_FIGURES if f"{k}_column" in figs):
        fig = figs[f"{key}_column"]
        assert fig.get_size_inches()[0] == pytest.approx(3.5)
        _draw(fig)
        sizes = [t.get_fontsize() for _, t in _texts(fig)]
        assert min(sizes) >= 7.0


#: Text height of a letter page with 1-in margins [in] (A4's is taller): a figure must fit it.
PAGE_TEXT_HEIGHT = 9.0


def test_every_figure_fits_a_page(figures):
    """A column figure taller than a page cannot be printed on one (the Stanford arm's D figure
    was 13.3 in tall: its per-panel units put it two panels a row)."""
    name, _, figs = figures
    tall = {k: round(fig.get_size_inches()[1], 2) for k, fig in figs.items()
            if fig.get_size_inches()[1] > PAGE_TEXT_HEIGHT}
    assert not tall, f"{name}: {tall}"


def test_minus_signs_survive(figures):
    """A negative tick is written with its minus sign (U+2212) and no tick label is cut by
    a neighbouring panel (checked above); here: every negative tick's label starts with it."""
    _, _, figs = figures
    negative = 0
    for fig in figs.values():
        for ax in fig.axes:
            for loc, lab in tick_texts(ax, "y") + tick_texts(ax, "x"):
                if loc < 0 and lab.get_text():
                    assert lab.get_text().startswith("\u2212"), lab.get_text()
                    negative += 1
    assert negative > 0                     # every arm has D_ij and tau_i below zero


def _markers_shown(line):
    """Markers a Line2D draws: its points picked by its markevery."""
    if line.get_marker() in (None, "None", "", " "):
        return 0
    n = len(line.get_xdata())
    every = line.get_markevery()
    if every is None:
        return n
    if isinstance(every, int):
        return len(range(0, n, every))
    if isinstance(every, tuple) and len(every) == 2 and all(isinstance(v, int) for v in every):
        return len(range(every[0], n, every[1]))
    return len(np.arange(n)[every])


def test_a_marker_at_every_set_point_of_figs_2_and_3(figures):
    """Up to 50 set points (the shipped trajectories have 31), every line of Figs. 2 and 3
    has a marker at every set point, as the chapter's Figs. 3.10 and 3.11 do (the
    curves could not be told apart in black and white with a marker at every 8th)."""
    name, ds, figs = figures
    N = ds.sizes["t"]
    assert N <= 50
    for key in ("D", "h", "D_column", "h_column"):
        for ax in figs[key].axes:
            shown = [_markers_shown(line) for line in ax.lines if len(line.get_xdata()) == N]
            assert shown and all(k == N for k in shown), (name, key, ax.get_title(), shown)


def test_at_most_about_12_markers_per_panel(figures):
    """All lines of a panel of Fig. 1 together: at most MAX_MARKERS ("at most
    about 12 per panel"); every line with a marker keeps at least two, to show which it is."""
    name, _, figs = figures
    for key in ("joints", "joints_column"):
        for ax in figs[key].axes:
            shown = [_markers_shown(line) for line in ax.lines]
            assert sum(shown) <= MAX_MARKERS, (name, key, ax.get_title(), shown)
            assert all(k >= 2 for k in shown if k), (name, key, ax.get_title(), shown)


def test_the_combined_curve_is_drawn_first_and_thinner(figures):
    _, _, figs = figures
    for ax in figs["D"].axes:
        lines = {ln.get_label(): ln for ln in ax.lines}
        if "combined" not in lines:
            continue
        total, tran, rot = lines["combined"], lines["translational"], lines["rotational"]
        assert total.get_zorder() < min(tran.get_zorder(), rot.get_zorder())
        assert total.get_linewidth() < min(tran.get_linewidth(), rot.get_linewidth())


def test_one_tick_notation_per_figure(figures):
    _, _, figs = figures
    for key in ("D", "h", "D_column", "h_column", "torque", "torque_column", "joints"):
        if key.startswith("torque") and not figs[key].axes:   # an exact model: a note only
            assert any("Nothing dropped" in t.get_text() for t in figs[key].texts), key
            continue
        assert any(tick_texts(ax, "y") for ax in figs[key].axes), key
        for ax in figs[key].axes:
            for value, lab in tick_texts(ax, "y") + tick_texts(ax, "x"):
                assert "e" not in lab.get_text(), (key, lab.get_text())   # fixed notation


def _power(label):
    """k of a "10ᵏ" in an axis label, 0 if none."""
    import re

    digits = "\u2070\u00b9\u00b2\u00b3\u2074\u2075\u2076\u2077\u2078\u2079"
    m = re.search(f"10(\u207b?)([{digits}]+)", label)
    if not m:
        return 0
    value = int("".join(str(digits.index(c)) for c in m.group(2)))
    return -value if m.group(1) else value


def test_every_tick_label_reads_back_its_tick(figures):
    """Oracle: the tick's own position. Each label, times the power of ten its axis label
    states (units of 10ᵏ), gives back the tick within 1e-9 of the axis' largest tick."""
    name, _, figs = figures
    scaled = 0
    for key, fig in figs.items():
        for ax in fig.axes:
            k = _power(ax.get_ylabel())
            scaled += k != 0
            ticks = tick_texts(ax, "y")
            big = max((abs(v) for v, _ in ticks), default=0.0)
            for value, lab in ticks:
                shown = float(lab.get_text().replace("\u2212", "-")) * 10.0 ** k
                assert abs(shown - value) <= 1e-9 * big, (key, lab.get_text(), k, value)
    if name == "puma560":                   # D and h of the wrist are below 1e-3
        assert scaled > 0


def test_round_off_is_never_drawn_as_data(figures):
    """An element whose parts are round-off (D45, D56 of the PUMA) reads "≡ 0" with no
    curve; a joint whose torque error and bound are round-off reads "Δτ = 0" with no curve."""
    name, ds, figs = figures
    labels = [str(v) for v in ds["element"].values]
    peak = np.fmax(np.fmax(ds["peak_tran"].values, ds["peak_rot"].values),
                   ds["peak_total"].values)
    zero = is_round_off(peak, ds["element_scale"].values)
    if name == "puma560":
        assert {lab for lab, z in zip(labels, zero) if z} == {"D45", "D56"}
    for key in ("D", "D_column"):
        for ax in figs[key].axes:
            element = ax.get_title().split(":")[0]
            if element in labels and zero[labels.index(element)]:
                assert not ax.lines, (key, element)
    diff = ds["tau_simplified"].values - ds["tau"].values
    bound = ds["simplified_bound"].values
    for key in ("torque", "torque_column"):
        axes = [ax for ax in figs[key].axes if ax.get_title().startswith("joint")]
        for i, ax in enumerate(axes):
            texts = " ".join(t.get_text() for t in ax.texts)
            if bound[i] == 0:           # nothing dropped: the difference is round-off
                assert "round-off" in texts and not ax.lines, (name, key, i + 1)
            else:
                assert ax.lines and "round-off" not in texts
    assert np.abs(diff).max() > 0       # the data hold a difference to hide or to draw


def test_the_round_off_rule_is_relative_to_the_scale():
    """Physical reading: 1e-19 kg m^2 on an element of scale 1 kg m^2 is round-off; the same
    1e-19 on a scale of 1e-9 is 1e-10 of it, data; NaN is never round-off."""
    assert is_round_off(1e-19, 1.0)
    assert not is_round_off(1e-19, 1e-9)
    assert is_round_off(ROUND_OFF, 1.0) and not is_round_off(2 * ROUND_OFF, 1.0)
    assert not is_round_off(np.nan, 1.0) and not is_round_off(np.inf, np.inf)


def test_seven_joints_differ_in_line_style_and_marker():
    styles = [joint_style(j, 31) for j in range(7)]
    dashes = [str(s["linestyle"]) for s in styles]
    markers = [s["marker"] for s in styles]
    assert len(set(dashes)) == 7 and len(set(markers)) == 7
    assert len(JOINT_STYLES) >= 7


# --------------------------------------------------------------------------------------------
# Mathematics in the lettering; the payload figure; a column twin of every figure file
# --------------------------------------------------------------------------------------------

def test_figures_letter_mathematics_not_code_names(figures):
    """Titles, axis labels, legends and keys write D(1,2), h(i), Δτ: no D12, D_ij, share_tran,
    tau_s (mathtext spans count as mathematics)."""
    name, _, figs = figures
    bad = {key: code_names(fig) for key, fig in figs.items()}
    bad = {k: v[:4] for k, v in bad.items() if v}
    assert not bad, f"{name}: {bad}"


@pytest.fixture(scope="module", params=ROBOTS)
def payload_figures(request):
    from gd_analyze.jobs.payload import payload_sweep
    from gd_analyze.report.main_figures import COLUMN_WIDTH, payload_figure

    name = request.param
    robot = load_robot(name)
    traj = read_trajectory(ROOT / "data" / f"{name}_trajectory.csv", robot.n)
    ds = payload_sweep(robot, traj, [0.0, 0.5, 1.0, 2.0])
    return name, {"payload": payload_figure(ds), "payload_column": payload_figure(ds, COLUMN_WIDTH),
                  "data": ds}


def test_payload_figure_at_page_and_column_width(payload_figures):
    """The payload figure (main job with --payload-sweep, sweep report) has a 3.5-in version
    with type of at least 7 pt; neither collides, both letter elements as mathematics."""
    name, figs = payload_figures
    figs = {k: v for k, v in figs.items() if k != "data"}
    assert figs["payload"].get_size_inches()[0] == pytest.approx(7.2)
    assert figs["payload_column"].get_size_inches()[0] == pytest.approx(3.5)
    for key, fig in figs.items():
        assert not collisions(fig), (name, key, collisions(fig)[:4])
        assert smallest_type(fig, report.FIG_RC) >= 7.0, (name, key)
        assert not code_names(fig), (name, key, code_names(fig)[:4])
    heat = figs["payload_column"].axes[0]               # elements down, one row each
    assert [t.get_text() for t in heat.get_yticklabels()][:2] == ["D(1,1)", "D(1,2)"]


def test_every_figure_file_of_the_main_job_has_a_column_twin(shared_main):
    """The main job with a payload sweep writes each figure at page width and as
    <name>_column, 3.5 in wide (the PDF's MediaBox)."""
    folder = column_run(shared_main) / "figures"
    assert (folder / "fig_payload_dominance_column.pdf").is_file()
    assert not column_twins(folder), column_twins(folder)


def test_payload_figure_draws_no_share_of_round_off(payload_figures):
    """An element whose every part is round-off of its scale has a share of noise: the payload
    sweep flags it (``round_off``) and the heat map leaves its cells grey (masked), at page and
    at column width; every other cell keeps its share. D45 and D56 of the PUMA 560 are zero
    in every part (the wrist's axes 4, 5, 6 meet and the point load sits on axis 6, at the
    flange's origin), with any load."""
    name, figs = payload_figures
    from gd_analyze.ranking.ranking import element_labels

    ds = figs["data"]
    flag = ds["round_off"].values.astype(bool)                   # (payload, element)
    labels = element_labels(ds.sizes["joint"])
    if name == "puma560":
        assert {lab for lab, f in zip(labels, flag.all(axis=0)) if f} == {"D45", "D56"}
        assert not flag[:, [lab not in ("D45", "D56") for lab in labels]].any()
    for key in ("payload", "payload_column"):
        masked = np.ma.getmaskarray(figs[key].axes[0].images[0].get_array())
        per_payload = masked if key == "payload" else masked.T       # (payload, element)
        np.testing.assert_array_equal(per_payload, flag | ~np.isfinite(ds["share_tran"].values))


def test_payload_figure_gives_each_torque_axis_one_unit(payload_figures):
    """Peak |τ| against the payload: a joint's units from its type (N m revolute, N
    prismatic); a mixed arm (Stanford, joint 3 prismatic) gets a panel per unit, never N m and
    N on one axis."""
    name, figs = payload_figures
    prismatic = load_robot(name).prismatic
    for key in ("payload", "payload_column"):
        axes = [ax for ax in figs[key].axes if ax.get_ylabel().startswith("peak")]
        assert len(axes) == len(set(prismatic))
        drawn = []
        for ax in axes:
            joints = [int(ln.get_label().split()[1]) - 1 for ln in ax.lines]
            units = {"N" if prismatic[j] else "N m" for j in joints}
            assert len(units) == 1 and ax.get_ylabel() == f"peak |\u03c4| [{units.pop()}]"
            drawn += joints
        assert sorted(drawn) == list(range(len(prismatic)))


def test_one_tick_form_per_figure(figures):
    """One tick format per figure (ticks.label_axes' rule): when any panel of
    a figure is written in units of 10ᵏ, every panel whose ticks are all below 1 in magnitude
    is too; no panel reads "0.01" beside a panel reading "5" in units of 10⁻³ (PUMA Fig. 4,
    UR5 Fig. 2 D(1,6)). Oracle: the drawn labels and the ticks' own positions."""
    name, _, figs = figures
    for key, fig in figs.items():
        axes = []
        for ax in fig.axes:
            ticks = tick_texts(ax, "y")
            if not ticks:
                continue
            big = max(abs(v) for v, _ in ticks)
            axes.append((_power(ax.get_ylabel()), big, [lab.get_text() for _, lab in ticks]))
        if any(k for k, _, _ in axes):
            plain_small = [labs for k, big, labs in axes if k == 0 and 0 < big < 1]
            assert not plain_small, (name, key, plain_small)
