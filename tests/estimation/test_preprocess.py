"""Preprocessing: derivatives of a known signal, the data's cutoff, gaps, the same filter."""

import numpy as np
import pytest
from scipy import signal

from gd_analyze.estimation.preprocess import default_cutoff, preprocess


def _signal(t, f=0.4):
    w = 2 * np.pi * f
    return (np.sin(w * t)[:, None], (w * np.cos(w * t))[:, None],
            (-w * w * np.sin(w * t))[:, None])


def test_irregular_clock_filtered_and_differentiated_matches_the_analytic_derivatives():
    rng = np.random.default_rng(0)
    t = np.cumsum(rng.uniform(0.7e-3, 8.8e-3, 4000))
    q, qd, qdd = _signal(t)
    pre = preprocess(t, q, 3 * q, cutoff="auto")
    k = pre.keep
    assert 0.4 < pre.cutoff < 0.5 / pre.step
    _, qd_true, qdd_true = _signal(pre.t)
    assert np.abs(pre.qd[k] - qd_true[k]).max() < 2e-3 * np.abs(qd_true).max()
    assert np.abs(pre.qdd[k] - qdd_true[k]).max() < 2e-2 * np.abs(qdd_true).max()
    # the file's own time base, resampled on the median step
    assert pre.t[0] == t[0] and np.allclose(np.diff(pre.t), pre.step)
    assert any("irregular clock" in s for s in pre.notes)


def test_the_same_filter_on_another_signal():
    t = np.arange(0, 10, 0.01)
    q = _signal(t)[0]
    x = np.random.default_rng(1).normal(size=(t.size, 2, 3))
    pre = preprocess(t, q, q, cutoff=5.0)
    sos = signal.butter(4, 5.0, fs=100.0, output="sos")
    assert np.allclose(pre.filtered(x), signal.sosfiltfilt(sos, x, axis=0), atol=1e-12)


def test_a_gap_splits_the_recording():
    t = np.concatenate([np.arange(0, 10, 0.01), np.arange(20, 30, 0.01)])
    q = _signal(t)[0]
    pre = preprocess(t, q, q, cutoff=5.0)
    assert len(pre.segments) == 2
    assert not ((pre.t > 10) & (pre.t < 20)).any()
    assert any("gaps" in s for s in pre.notes)


def test_default_cutoff_follows_the_motion():
    t = np.arange(0, 60, 0.002)
    slow = default_cutoff(t, _signal(t, 0.2)[0])
    fast = default_cutoff(t, _signal(t, 2.0)[0])
    assert 0.2 < slow < 2.0 < fast < 0.2 / 0.002


def test_without_filter_the_given_derivatives_are_kept():
    t = np.sort(np.random.default_rng(2).uniform(0, 5, 300))
    q, qd, qdd = _signal(t)
    pre = preprocess(t, q, q, qd, qdd, cutoff=None)
    assert np.array_equal(pre.t, t) and np.array_equal(pre.qdd, qdd) and pre.keep.all()


def test_a_cutoff_beyond_nyquist_is_refused():
    t = np.arange(0, 5, 0.01)
    with pytest.raises(ValueError, match="Nyquist"):
        preprocess(t, _signal(t)[0], _signal(t)[0], cutoff=60.0)
