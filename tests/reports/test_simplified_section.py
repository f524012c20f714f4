"""The torque-error figure of the simplified model (gd_analyze.reports.simplified_section)."""

import numpy as np
import xarray as xr

from gd_analyze.reports.simplified_section import ROUND_OFF, error_figure


def _ds(diff, bound, scale):
    N, n = diff.shape
    t = np.linspace(0.0, 2.0, N)
    tau = np.sin(t)[:, None] * scale[None, :]
    return xr.Dataset({"t": ("t", t), "tau": (("t", "joint"), tau),
                       "tau_simplified": (("t", "joint"), tau + diff),
                       "simplified_bound": ("joint", bound),
                       "simplified_scale": ("joint", scale)})


def _texts(ax):
    return " ".join(t.get_text() for t in ax.texts)


def test_round_off_reads_equal_and_a_real_error_is_drawn():
    N = 31
    rng = np.random.default_rng(1)
    scale = np.array([10.0, 2.0, 1.2e-4, 1.0])
    noise = rng.standard_normal(N) * 1e-17
    diff = np.column_stack([
        0.01 * np.sin(np.linspace(0, 3, N)),        # a kept error within its bound
        noise,                                      # nothing dropped, round-off
        noise,                                      # round-off of a tiny joint: still noise
        1e-6 * np.ones(N),                          # bound 0 but a real difference: drawn
    ])
    fig = error_figure(_ds(diff, np.array([0.02, 0.0, 0.0, 0.0]), scale))
    axes = fig.axes
    assert len(axes[0].lines) >= 3 and "nothing dropped" not in _texts(axes[0])
    for ax in axes[1:3]:
        assert "nothing dropped" in _texts(ax) and "round-off" in _texts(ax)
        assert not any(len(line.get_xdata()) == N for line in ax.lines)   # no noise drawn
        assert list(ax.get_yticks()) == []
    assert "nothing dropped" not in _texts(axes[3])
    assert any(np.allclose(line.get_ydata(), 1e-6) for line in axes[3].lines)


def test_the_threshold_is_relative_to_the_joint_scale():
    N = 5
    scale = np.array([1.0, 1.0])
    at = ROUND_OFF * np.ones(N)
    above = 2 * ROUND_OFF * np.ones(N)
    fig = error_figure(_ds(np.column_stack([at, above]), np.zeros(2), scale))
    assert "nothing dropped" in _texts(fig.axes[0])
    assert "nothing dropped" not in _texts(fig.axes[1])


def test_nan_is_never_round_off():
    N = 5
    diff = np.full((N, 1), np.nan)
    fig = error_figure(_ds(diff, np.zeros(1), np.ones(1)))
    assert "nothing dropped" not in _texts(fig.axes[0])


def test_the_inertia_check_sentence_is_the_stored_check():
    """Issue 30 item 3: the report says what the stored check found, for each outcome."""
    from gd_analyze.reports.markup import plain
    from gd_analyze.reports.simplified_section import inertia_check_text
    from gd_analyze.workflows.simplified_dataset import inertia_check_attrs

    base = {"where": "region", "samples": 200, "gershgorin_proved": 150,
            "min_relative_eigenvalue": 0.0123, "restored": []}
    ok = plain(inertia_check_text(inertia_check_attrs({**base, "positive_definite": True})))
    assert "is positive definite at 200 positions sampled uniformly over the joint-limit" in ok
    assert "0.0123" in ok and "at 150)" in ok and "not proved between" in ok
    bad = plain(inertia_check_text(inertia_check_attrs(
        {**base, "where": "trajectory", "samples": 31, "positive_definite": False})))
    assert "is not positive definite at the 31 positions of the trajectory" in bad
    kept = plain(inertia_check_text(inertia_check_attrs(
        {**base, "positive_definite": True, "restored": ["XX2", "ZZ3"]})))
    assert kept.endswith("kept with all parts: XX2, ZZ3.")
    assert inertia_check_text({}) == ""

