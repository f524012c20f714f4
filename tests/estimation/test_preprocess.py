"""Preprocessing: derivatives of a known signal, the data's cutoff, gaps, the same filter, the
most samples it gives."""

from pathlib import Path

import numpy as np
import pytest
from identify_recordings import fourier, irregular_clock, truth_for
from scipy import signal

from gd_analyze import load_robot
from gd_analyze.estimation.preprocess import (
    CLIP_COARSE,
    CLIP_REACH,
    clipped_samples,
    coarse_columns,
    confirmed_clips,
    default_cutoff,
    despiked,
    extreme_samples,
    model_clipped,
    most_samples,
    preprocess,
    still_joints,
)


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


def test_default_cutoff_leaves_out_a_joint_held_still():
    """A joint held at 0.3 rad whose encoder reads white noise of 1e-5 rad: its power spreads
    to the Nyquist frequency, and counted, it set the cutoff to 0.4 x Nyquist (no filtering:
    the moving joints' differentiated noise then spoilt the fit). Left out, the cutoff is the
    moving joint's alone."""
    t = np.arange(0, 60, 0.002)
    moving = _signal(t, 0.2)[0]
    held = 0.3 + 1e-5 * np.random.default_rng(3).normal(size=(t.size, 1))
    alone = default_cutoff(t, moving)
    assert default_cutoff(t, np.hstack([moving, held]), np.array([False, False])) == alone
    assert default_cutoff(t, np.hstack([held, moving])) == alone


def test_without_filter_the_given_derivatives_are_kept():
    t = np.sort(np.random.default_rng(2).uniform(0, 5, 300))
    q, qd, qdd = _signal(t)
    pre = preprocess(t, q, q, qd, qdd, cutoff=None)
    assert np.array_equal(pre.t, t) and np.array_equal(pre.qdd, qdd) and pre.keep.all()


def test_a_cutoff_beyond_nyquist_is_refused():
    t = np.arange(0, 5, 0.01)
    with pytest.raises(ValueError, match="Nyquist"):
        preprocess(t, _signal(t)[0], _signal(t)[0], cutoff=60.0)


def test_a_joint_held_still_has_zero_speed_and_acceleration():
    """Joint 2 held at 0.3 rad, read through a 17-bit encoder with noise: its differences are
    noise, which sign(qd) would take for motion. Given the joints' kinds, it is found held and
    its qd and qdd are exactly 0; the moving joint keeps its differentiated speed (the analytic
    derivative, to the filter's accuracy). A prismatic joint moving 5 mm is not held, a
    revolute one moving 0.005 rad is."""
    t = np.arange(4000) * 2e-3
    rng = np.random.default_rng(1)
    res = 2 * np.pi / 2 ** 17
    q = np.column_stack([0.8 * np.sin(0.5 * t),
                         np.round((0.3 + 2e-5 * rng.normal(size=t.size)) / res) * res])
    tau = rng.normal(size=q.shape)
    plain = preprocess(t, q, tau)
    assert plain.held is None and np.abs(plain.qd[plain.keep, 1]).max() > 0
    pre = preprocess(t, q, tau, prismatic=np.array([False, False]))
    assert pre.held.tolist() == [False, True]
    assert not pre.qd[:, 1].any() and not pre.qdd[:, 1].any()
    np.testing.assert_allclose(pre.qd[pre.keep, 0], 0.4 * np.cos(0.5 * pre.t[pre.keep]),
                               rtol=0, atol=1e-4)
    assert any("joint(s) 2 held still" in note for note in pre.notes)
    small = np.column_stack([0.0025 * np.sin(0.5 * t), 0.0025 * np.sin(0.5 * t)])
    assert still_joints(small, np.array([True, False])).tolist() == [False, True]


@pytest.mark.parametrize("cutoff", [5.0, 1.5, None])
@pytest.mark.parametrize("rows", [1, 7, 64, 10**6])
def test_blocks_are_the_whole_segments_filtered(cutoff, rows):
    """filtered_blocks against scipy's sosfiltfilt on each whole segment: the same numbers,
    every sample once, each sample made at most twice, never more than a block at a time."""
    t = np.concatenate([np.arange(0, 6, 0.01), np.arange(10, 15, 0.01)])    # a gap: 2 segments
    q = _signal(t)[0]
    pre = preprocess(t, q, q, cutoff=cutoff)
    assert len(pre.segments) == 2
    x = np.random.default_rng(3).normal(size=(pre.t.size, 2, 3))
    if cutoff is None:
        whole = x
    else:
        sos = signal.butter(4, cutoff, fs=1 / pre.step, output="sos")
        whole = np.concatenate([signal.sosfiltfilt(sos, x[a:b], axis=0)
                                for a, b in pre.segments])
    made = np.zeros(pre.t.size, int)

    def make(a, b):
        assert b - a <= max(rows, 3 * (2 * 2 + 1) + 1)     # a block, or an end's extension
        made[a:b] += 1
        return x[a:b].copy()
    out = np.full(x.shape, np.nan)
    for a, b, y in pre.filtered_blocks(make, rows):
        assert np.isnan(out[a:b]).all()                     # each sample yielded once
        out[a:b] = y
    assert np.array_equal(out, whole)
    assert made.max() <= 3 and np.median(made) <= (1 if cutoff is None else 2)
    for a, b, y in pre.filtered_blocks(lambda a, b: x[a:b, 0, 0], rows):  # a 1-D signal
        np.testing.assert_array_equal(y, whole[a:b, 0, 0])
    with pytest.raises(ValueError, match="rows"):
        next(pre.filtered_blocks(make, 0))


@pytest.mark.parametrize("clock", ["irregular", "skewed", "gap", "regular"])
@pytest.mark.parametrize("cutoff", [None, 5.0])
def test_most_samples_bounds_the_samples_preprocessing_gives(clock, cutoff):
    """The bound the output folder's estimate uses: never below the samples preprocess gives
    (resampled onto the median step, or kept as they are), and within 2x of them."""
    rng = np.random.default_rng(3)
    steps = {"irregular": rng.uniform(0.7e-3, 8.8e-3, 3000),
             "skewed": np.where(rng.random(3000) < 0.8, 1e-3, 1.5e-2),
             "gap": np.concatenate([np.full(1500, 2e-3), [5.0], np.full(1500, 2e-3)]),
             "regular": np.full(3000, 2e-3)}[clock]
    t = np.concatenate([[0.0], np.cumsum(steps)])
    q = _signal(t)[0]
    given = {} if cutoff is not None else dict(qd=q, qdd=q)
    pre = preprocess(t, q, q, cutoff=cutoff, **given)
    most = most_samples(t, resampled=cutoff is not None)
    assert pre.t.size <= most <= 2 * pre.t.size


def test_clipped_torque_is_found_not_a_quantised_peak_a_dither_or_a_hold():
    """A torque clipped at +-0.8 of its peak (a drive's limit): exactly the samples at +-0.8,
    and the rows the filter's reach spreads them to (CLIP_REACH periods of the cutoff) marked on
    the preprocessed clock. Not clipping: the same torque quantised to 1e-3 (its peaks hold
    their top level over several samples; clipped, it is found), a joint held still dithering
    over 3 levels, the arm at rest at its peak torque."""
    rng = np.random.default_rng(1)
    t = np.cumsum(rng.uniform(0.5e-3, 1.5e-3, 20000))
    q = np.column_stack([np.sin(0.7 * t), np.cos(0.3 * t)])
    tau = np.column_stack([5 * np.sin(0.7 * t) + 3 * np.sin(2.1 * t), np.cos(0.3 * t)])
    clipped, limit = tau.copy(), 0.8 * np.abs(tau[:, 0]).max()
    clipped[:, 0] = np.clip(tau[:, 0], -limit, limit)
    mask = clipped_samples(q, clipped)
    assert np.array_equal(mask[:, 0], np.abs(clipped[:, 0]) == limit) and mask[:, 0].mean() > 0.05
    assert not mask[:, 1].any()
    pre = preprocess(t, q, clipped, cutoff=2.0, clipped=mask)
    reach = int(np.ceil(CLIP_REACH / (2.0 * pre.step)))
    inside = np.interp(pre.t, t, mask[:, 0].astype(float)) > 0
    assert np.array_equal(pre.clipped[:, 0], np.convolve(inside, np.ones(2 * reach + 1),
                                                         "same") > 0)
    assert not pre.clipped[:, 1].any()
    quantised = np.round(tau / 1e-3) * 1e-3
    assert not clipped_samples(q, quantised).any()
    assert clipped_samples(q, np.clip(quantised, -limit, limit))[:, 0].any()
    dither = np.column_stack([quantised[:, 0], 1.0 + 1e-3 * rng.integers(-1, 2, t.size)])
    assert not clipped_samples(q, dither).any()
    rest = np.argmax(tau[:, 0])                 # the arm stops at its peak torque for 0.5 s
    hold = np.r_[:rest, [rest] * 500, rest:t.size]
    assert not clipped_samples(q[hold], tau[hold]).any()


def _pinocchio_torque(name, friction=1.0):
    """A Fourier trajectory of a true arm (Pinocchio's rnea, friction, offsets), 25 s on an
    irregular clock: q and the torque, shape (N, n) each."""
    robot = load_robot(name)
    truth = truth_for(robot, seed=4)
    truth.coulomb = truth.coulomb * friction
    t = irregular_clock(25, 2)
    q, qd, qdd = fourier(robot.n, t, seed=2)
    return q, truth.torque(q, qd, qdd)


@pytest.mark.parametrize("name", ["puma560", "two-link"])
def test_a_noisy_clipped_torque_is_found_not_an_honest_one(name):
    """Pinocchio's torque clipped at 85 % of each joint's peak with sensor noise (0.2 % of its
    standard deviation) added after the clip: at least 90 % of the clipped samples are found,
    and every sample marked is within 6 noise deviations of the limit. (With 1 % noise some of
    the PUMA 560's clips, whose torque barely passes the limit, approach their level as slowly
    as an honest peak of order 8 would: not told apart. Quantised to 15 levels, a clip one step
    deep is left to the check against the fitted model.) Not clipping: the same torque
    unclipped, with noise, quantised to 1e-3 or to 15 levels."""
    q, tau = _pinocchio_torque(name)
    sigma = 0.002 * tau.std(axis=0)
    noise = sigma * np.random.default_rng(3).normal(size=tau.shape)
    limit = 0.85 * np.abs(tau).max(axis=0)
    mask = clipped_samples(q, np.clip(tau, -limit, limit) + noise)
    for j in range(tau.shape[1]):
        beyond = np.abs(tau[:, j]) >= limit[j]
        assert np.mean(mask[beyond, j]) > 0.9, (j, np.mean(mask[beyond, j]))
        assert (np.abs(tau[mask[:, j], j]) > limit[j] - 6 * sigma[j]).all(), j
    for honest in (tau + 5 * noise, np.round(tau / 1e-3) * 1e-3,
                   np.round(tau / (2 * np.abs(tau).max(axis=0) / 14)) * (
                       2 * np.abs(tau).max(axis=0) / 14)):
        assert not clipped_samples(q, honest).any()


def test_a_real_recording_and_a_friction_square_wave_are_not_clipped():
    """Torques flat over long stretches that are no limit: the TIAGo recording shipped in
    data/tiago (its torso's effort a square wave of the lift's direction, 1e-3 steps and noise;
    three wrist joints at exactly 0 most of the time), and a Pinocchio PUMA 560 whose Coulomb
    friction is 100 times the true arm's, with noise (its wrist's torques square waves of the
    joints' directions): nothing is clipped."""
    from gd_analyze.trajectory.trajectory import read_recording

    tiago = Path(__file__).resolve().parents[2] / "data" / "tiago"
    for path in sorted(tiago.glob("*.csv")):
        rec = read_recording(path)
        assert not clipped_samples(rec.q, rec.tau).any(), path
    q, tau = _pinocchio_torque("puma560", friction=100.0)
    noisy = tau + 0.01 * tau.std(axis=0) * np.random.default_rng(5).normal(size=tau.shape)
    assert not clipped_samples(q, noisy).any()


def _flat_peaks(seeds, n=151, sigma=1e-3):
    """Honest flat-topped peaks, 1 - |t|^p over t in [-1, 1] for p = 2, 4, 8, with N(0, sigma)
    noise: (p, seed, t, tau) per case, t and tau of shape (n, 1)."""
    t = np.linspace(-1.0, 1.0, n)[:, None]
    for p in (2, 4, 8):
        for seed in seeds:
            yield p, seed, t, 1.0 - np.abs(t) ** p + np.random.default_rng(seed).normal(
                0.0, sigma, t.shape)


def test_an_honest_flat_topped_peak_of_any_order_is_not_clipped():
    """1 - |t|^p for p = 2, 4, 8 with N(0, 1e-3) noise over 151 samples (the code before took
    p = 4 for clipped in 67 of 100 seeds, p = 8 in all), over 1001 samples and with 10 times the
    noise, noise-free and quantised to 1e-3 or 1e-2 (a smooth peak's depth grows as |t|^p, so
    that its time near the top against the time just below is bounded whatever its width): in
    no seed is a sample taken for clipped. The same peaks clipped at 95 % of their height are
    (the rule is not blind)."""
    cases = [*_flat_peaks(range(100)), *_flat_peaks(range(30), n=1001),
             *_flat_peaks(range(30), sigma=1e-2)]
    flagged = [(p, seed) for p, seed, t, tau in cases if clipped_samples(t, tau).any()]
    assert not flagged, flagged
    for p, _, t, tau in _flat_peaks([0], sigma=0.0):
        for honest in (tau, np.round(tau / 1e-3) * 1e-3, np.round(tau / 1e-2) * 1e-2):
            assert not clipped_samples(t, honest).any(), p
        assert clipped_samples(t, np.minimum(tau, 0.95)).any(), p


def _clipped(x, frac, where, noise):
    """x, shape (N, n), clipped at ``frac`` of each column's peak |x|, with ``noise`` added
    before or after the clip (``where``: "none", "before", "after"); and the limits, shape (n,)."""
    limit = frac * np.abs(x).max(axis=0)
    before, after = (noise if where == w else 0.0 for w in ("before", "after"))
    return np.clip(x + before, -limit, limit) + after, limit


@pytest.fixture(scope="module")
def clip_signals():
    """(t or q, x) of :func:`test_a_clipped_sinusoid_or_excitation_torque_is_found_in_every_seed`:
    30 seeds' sinusoid and random excitation, then the two-link arm's torque along 5 seeds'
    Fourier excitations (Pinocchio's rnea, once a module for the three cases); read only."""
    t, t_x = np.linspace(0.0, 1.0, 2000), np.linspace(0.0, 10.0, 3000)
    robot = load_robot("two-link")
    truth, clock = truth_for(robot, seed=4), irregular_clock(25, 2)
    signals = []
    for seed in range(30):
        rng = np.random.default_rng(seed)
        w, phase = 2 * np.pi * rng.uniform(2, 5), rng.uniform(0, 2 * np.pi)
        signals.append((t[:, None], np.sin(w * t + phase)[:, None]))
        x = sum(rng.normal() / h * np.sin(0.4 * np.pi * h * t_x + rng.uniform(0, 2 * np.pi))
                for h in range(1, 6))
        signals.append((t_x[:, None], x[:, None]))
    for seed in range(5):
        q, qd, qdd = fourier(robot.n, clock, seed=seed)
        signals.append((q, truth.torque(q, qd, qdd)))
    for pair in signals:
        for a in pair:
            a.setflags(write=False)
    return tuple(signals)


@pytest.mark.parametrize("where", ["none", "before", "after"])
def test_a_clipped_sinusoid_or_excitation_torque_is_found_in_every_seed(where, clip_signals):
    """Clipped at 80, 85, 90 and 95 % of its peak, without noise or with noise of 1e-3 of the
    peak before or after the clip: in each of 30 seeds a sinusoid (random frequency and phase,
    2,000 samples over 2 to 5 periods) and a random excitation (5 harmonics of 0.2 Hz, random
    weights and phases, 3,000 samples over 10 s), and the two-link arm's torque on each joint (Pinocchio's rnea, friction,
    offsets; 25 s Fourier excitations of 5 seeds) are found clipped, every sample marked within
    6 noise deviations (or 1e-9 of the peak) of the limit. The same torques unclipped, with the
    noise: nothing. (The arm's 95 % clips with noise after them are left out: in seed 0 the
    stretch longest at joint 2's limit passes it by 0.5 % of the peak, 5 noise deviations, and
    approaches it as slowly as an honest peak of order 8 would.)"""
    for k, (q, tau) in enumerate(clip_signals):
        sigma = 1e-3 * np.abs(tau).max(axis=0)
        noise = sigma * np.random.default_rng(100 + k).normal(size=tau.shape)
        assert not clipped_samples(q, tau + noise).any(), k
        for frac in (0.8, 0.85, 0.9) + ((0.95,) if k < 60 or where != "after" else ()):
            x, limit = _clipped(tau, frac, where, noise if where != "none" else 0.0)
            mask = clipped_samples(q, x)
            assert mask.any(axis=0).all(), (k, frac, mask.any(axis=0))
            slack = 6 * sigma if where != "none" else 1e-9 * np.abs(tau).max(axis=0)
            assert (np.abs(np.abs(x) - limit)[mask] <= np.broadcast_to(slack, x.shape)[mask]).all()


def _adc(x, levels, top=None):
    """x, shape (N, n), rounded to ``levels`` values per column from its minimum to ``top``
    (default its maximum): an ADC over the recorded range."""
    lo = x.min(axis=0)
    step = ((x.max(axis=0) if top is None else top) - lo) / (levels - 1)
    return lo + np.clip(np.round((x - lo) / step), 0, levels - 1) * step


@pytest.mark.parametrize("levels", [10, 12, 14, 17])
def test_a_coarse_clip_is_found_against_the_model_not_an_honest_peak(levels):
    """Two-link (Pinocchio): joint 1's torque clipped at 85 % of its peak, then every joint
    quantised to 10 to 17 levels over its recorded range, which clipped_samples misses. Against
    the exact model (Pinocchio's unclipped torque, residual spread 0) at least 90 % of the
    clipped samples are found, nothing on joint 2. Honest torques, quantised alike: unclipped,
    with their peaks 0.45 step above the top level (an ADC's range wider than the torque), and
    with 100 x the Coulomb friction: nothing (rounding keeps them within half a step)."""
    q, tau = _pinocchio_torque("two-link")
    limit = 0.85 * np.abs(tau[:, 0]).max()
    clipped = tau.copy()
    clipped[:, 0] = np.clip(tau[:, 0], -limit, limit)
    coarse = _adc(clipped, levels)
    beyond = np.abs(tau[:, 0]) >= limit
    assert not clipped_samples(q, coarse)[beyond, 0].mean() > 0.9     # what the model adds
    found = model_clipped(q, coarse, tau, np.zeros(2))
    assert found[beyond, 0].mean() >= 0.9 and not found[:, 1].any(), found[beyond, 0].mean()
    assert (extreme_samples(coarse) >= found).all()
    wide = tau.min(axis=0) + (levels - 1) * (np.ptp(tau, axis=0) / (levels - 1 + 0.45))
    q_f, tau_f = _pinocchio_torque("two-link", friction=100.0)
    for x, honest in ((q, _adc(tau, levels)), (q, _adc(tau, levels, wide)),
                      (q_f, _adc(tau_f, levels))):
        assert not model_clipped(x, honest, tau_f if x is q_f else tau, np.zeros(2)).any()


def test_a_flat_topped_honest_peak_of_a_coarse_torque_is_not_confirmed_a_clip_by_the_model():
    """PUMA 560 (Pinocchio): joint 5's torque has two maxima 0.12 N m apart near its peak, the
    dip between them within a step of an ADC over twice its range, centred, at 20 levels (9
    used): its top level, held over both maxima, outnumbers the level below about 3 times, so
    that a count of the samples took it for a clip (clipped_samples no longer does). Taken for
    clipped, the exact model (Pinocchio's unquantised torque) does not go beyond the level by
    half a step: confirmed_clips drops the samples. Joint 1's
    torque clipped at 70 % of its peak, then quantised alike (the limit 1.6 steps below the
    peak: visible after rounding, unlike a clip within half a step of the peak, which leaves the
    same levels as the honest torque): the samples the model goes beyond are kept. A finer
    torque's are kept as they are."""
    q, tau = _pinocchio_torque("puma560")
    mid, half = 0.5 * (tau.max(axis=0) + tau.min(axis=0)), np.ptp(tau, axis=0)

    def adc(x):
        step = 2 * half / 19
        return mid - half + np.round((x - mid + half) / step) * step
    honest = adc(tau)
    assert coarse_columns(honest).all()
    assert not clipped_samples(q, honest).any()     # its approach is not cut (the code before:
    marked = np.zeros(tau.shape, bool)              # 19.5 % of joint 5's samples, its top level)
    marked[:, 4] = honest[:, 4] == honest[:, 4].max()
    assert not confirmed_clips(q, honest, marked, tau).any()
    limit = 0.7 * np.abs(tau[:, 0]).max()
    clipped = tau.copy()
    clipped[:, 0] = np.clip(tau[:, 0], -limit, limit)
    coarse = adc(clipped)
    marked = extreme_samples(coarse) & (np.arange(tau.shape[1]) == 0)      # joint 1's levels
    kept = confirmed_clips(q, coarse, marked, tau)
    beyond = np.abs(tau[:, 0]) >= limit
    assert kept[beyond, 0].mean() == marked[beyond, 0].mean() > 0.5
    assert (kept <= marked).all()
    assert np.array_equal(confirmed_clips(q, tau, marked, np.zeros_like(tau)), marked)   # fine


def test_spikes_are_replaced_not_steps_slopes_or_noise():
    """Pinocchio's torque with noise and 12 spikes of 30 noise deviations: exactly the spikes
    are found and each is replaced within 3 noise deviations of the torque; nothing else
    changes. Noise-free (Coulomb friction jumps at every reversal), quantised to 1e-2 or
    noisy without spikes: nothing is found, the torque is returned as it is."""
    q, tau = _pinocchio_torque("puma560")
    rng = np.random.default_rng(4)
    sigma = 0.01 * tau.std(axis=0)
    noisy = tau + sigma * rng.normal(size=tau.shape)
    spiked = noisy.copy()
    rows = rng.choice(np.arange(5, tau.shape[0] - 5), 12, replace=False)
    cols = rng.integers(0, tau.shape[1], 12)
    spiked[rows, cols] += 30 * sigma[cols] * rng.choice([-1, 1], 12)
    clean, spikes = despiked(spiked)
    expected = np.zeros(tau.shape, bool)
    expected[rows, cols] = True
    assert np.array_equal(spikes, expected)
    assert (np.abs(clean - tau)[spikes] < 3 * sigma[cols]).all()
    assert np.array_equal(clean[~spikes], spiked[~spikes])
    for honest in (tau, np.round(tau / 1e-2) * 1e-2, noisy):
        clean, spikes = despiked(honest)
        assert not spikes.any() and np.array_equal(clean, honest)


@pytest.mark.parametrize("levels", [10, 19, 20, 200])
def test_only_a_torque_of_fewer_than_clip_coarse_levels_is_judged_against_the_model(levels):
    """A sinusoid quantised to ``levels`` values holds its extreme levels over runs either way;
    only below CLIP_COARSE levels are they the samples a fitted model judges (a finer torque
    is left to the model-free rule, and its own error would set what goes beyond a level)."""
    t = np.linspace(0.0, 4.0, 2000)
    step = 2.0 / (levels - 1)
    tau = (np.round((np.sin(3.0 * t) + 1.0) / step) * step - 1.0)[:, None]    # -1 ... 1
    assert len(np.unique(tau)) == levels
    found = extreme_samples(tau)[:, 0]
    assert found.any() == (levels < CLIP_COARSE)
    clip = np.clip(tau, -1.0 + 2 * step, 1.0 - 2 * step)              # two steps deep
    clipped = model_clipped(t[:, None], clip, np.sin(3.0 * t)[:, None], np.array([step / 4]))
    assert clipped.any() == (len(np.unique(clip)) < CLIP_COARSE)       # its own levels
