"""The per-joint line figure the identify report and the main report's fallback torque figure
share: what each panel draws and says, against the arrays given."""

import numpy as np

from gd_analyze.report.figure_style import joint_lines

MEASURED = ("#000000", "-", 1.3, "measured")
MODEL = ("#0072B2", "--", 1.0, "model")


def test_each_panel_draws_its_joints_column_every_step_th_sample():
    t = np.linspace(0.0, 2.0, 11)
    a = np.column_stack([np.sin(t), np.cos(t), t ** 2, -t])
    b = 2.0 * a
    titles = ["joint 1: a", "joint 2: b", "joint 3: $c$", "joint 4: d"]
    fig = joint_lines(t, [(MEASURED, a), (MODEL, b)], titles,
                      ["\u03c4 [N m]", "\u03c4 [N m]", "\u03c4 [N]", "\u03c4 [N m]"], 7.2,
                      cols=2, step=3)
    axes = [ax for ax in fig.axes if ax.get_visible()]
    assert len(axes) == 4
    for j, ax in enumerate(axes):
        first, second = ax.get_lines()
        np.testing.assert_array_equal(first.get_xdata(), t[::3])
        np.testing.assert_array_equal(first.get_ydata(), a[::3, j])
        np.testing.assert_array_equal(second.get_ydata(), b[::3, j])
        assert (first.get_color(), second.get_linestyle()) == ("#000000", "--")
    # titles on the left, as given
    assert [ax.get_title(loc="left") for ax in axes] == titles
    # each panel's own y label
    assert [ax.get_ylabel() for ax in axes] == ["\u03c4 [N m]", "\u03c4 [N m]", "\u03c4 [N]",
                                                "\u03c4 [N m]"]
    legend, = fig.legends
    assert [text.get_text() for text in legend.get_texts()] == ["measured", "model"]
    assert fig.get_size_inches()[0] == 7.2
