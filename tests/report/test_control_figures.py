"""The control report's figures for print (gd_analyze.report.control): the
three controllers told apart in black and white, log-axis exponents in 7-pt type, no key
entry for a band too thin to see, joints named as in the main report."""

import matplotlib
import numpy as np
import pytest
from conftest import two_link_control

from gd_analyze.report.control import FIGURE_RC, control_figures


@pytest.fixture(scope="module")
def control(tmp_path_factory):
    folder = tmp_path_factory.mktemp("control")
    return folder, two_link_control(folder, 40)


def _key(fig):
    legend = fig.legends[0]
    return {text.get_text(): handle for text, handle in
            zip(legend.get_texts(), legend.legend_handles)}


def test_three_controllers_differ_in_line_style_and_marker(control):
    """Applied torques (Fig. 3), whose three curves lie on one another: each controller has
    its own dash pattern, width and marker, in the key too (never indistinguishable)."""
    _, ds = control
    figs = control_figures(ds)
    key = _key(figs["tau"])
    assert len(key) == 3
    styles = {(str(h.get_linestyle()), h.get_linewidth()) for h in key.values()}
    markers = {h.get_marker() for h in key.values()}
    assert len(styles) == 3 and len(markers) == 3
    for ax in figs["tau"].axes:
        if not ax.get_visible():
            continue
        marked = {line.get_marker() for line in ax.lines if line.get_linestyle() == "None"}
        assert marked == markers


def test_log_axis_exponents_in_7_pt_type(control):
    """The tracking error's log axes write their decades as 10⁻⁶ in the tick labels' own type
    (7 pt), not mathtext, whose exponents print at 70 % (4.9 pt)."""
    _, ds = control
    with matplotlib.rc_context(FIGURE_RC):
        fig = control_figures(ds)["error"]
        shown = 0
        for ax in fig.axes:
            if not ax.get_visible() or ax.get_yscale() != "log":
                continue
            fmt = ax.yaxis.get_major_formatter()
            for v in ax.get_yticks():
                text = fmt(v)
                assert "$" not in text and "^" not in text, text
                shown += bool(text)
            assert all(t.label1.get_fontsize() >= 7.0 for t in ax.yaxis.get_major_ticks())
    assert shown > 0


def test_no_key_entry_for_a_band_too_thin_to_see(control):
    """A torque difference a thousand times its noise floor: the ±floor band is 0.1 % of the
    panel's height, invisible at print size, so the key has no entry for it; at 5 times the
    floor it shows and is in the key."""
    _, ds = control
    floor = np.asarray(ds["tau_difference_floor"].values, float)
    t = np.asarray(ds["time"].values, float)
    wave = np.sin(2 * np.pi * t / max(t[-1], 1e-9))[:, None]
    for times, keyed in ((1000.0, False), (5.0, True)):
        big = ds.copy()
        big["tau_difference"] = (ds["tau_difference"].dims, times * floor[None, :] * wave)
        key = _key(control_figures(big)["tau_difference"])
        assert any("noise floor" in k for k in key) is keyed, (times, list(key))


def test_joints_named_as_in_the_main_report(control):
    """Table headers say "joint 1", as the main report does, not "J1"."""
    folder, _ = control
    html = (folder / "control" / "control_report.html").read_text(encoding="utf-8")
    assert "joint 1 [" in html and "J1 [" not in html and ">J1<" not in html
