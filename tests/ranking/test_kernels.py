"""The chunk updates of the ranking and the part peaks (the compiled kernels) against their
numpy formulation (the code the kernels replaced, kept here as the oracle): the same values bit
for bit, on the G-D terms of arms with and without drives, and on made-up chunks with -0.0, inf
and NaN.
"""

import numpy as np
import pytest
from conftest import random_states
from numpy_engines import element_series

from gd_analyze import gd_terms, load_robot
from gd_analyze.ranking.ranking import RankingAccumulator
from gd_analyze.ranking.statistics import ROWS
from gd_analyze.simplify.budget import PartPeaks, part_index


class NumpyRanking:
    """RankingAccumulator's sums and peaks as numpy arrays (the formulation before the kernel),
    by name; the statistics the kernel added since, by (series, statistic) in ``more``."""

    def __init__(self, n):
        m = n * (n + 1) // 2 + n
        self.n = n
        self.sum_tran, self.sum_rot = np.zeros(m), np.zeros(m)
        self.peak_tran, self.peak_rot, self.peak_total = np.zeros(m), np.zeros(m), np.zeros(m)
        self.more = {key: np.zeros(m) for key in (
            ("tran", "sum_sq"), ("rot_arm", "sum_sq"), ("total", "sum_abs"),
            ("total", "sum_sq"), ("rot_arm", "peak_abs"))}
        self.sum_arm, self.arm = np.zeros(m), np.zeros(m)
        self.scale_D = np.zeros(n * (n + 1) // 2)
        self.peak_tau = np.zeros(n)

    def update(self, D_tran, D_rot, h_tran, h_rot, tau, armature=None):
        n, N = self.n, h_tran.shape[0]
        tran, rot = element_series(D_tran, D_rot, h_tran, h_rot)
        at, ar = np.abs(tran), np.abs(rot)
        arm_d = np.zeros(n) if armature is None else np.asarray(armature, float)
        if arm_d.any():
            iu = np.triu_indices(n)
            self.arm[:iu[0].size] = np.where(iu[0] == iu[1], arm_d[iu[0]], 0.0)
            self.sum_arm += N * self.arm
            ar = np.abs(rot + self.arm)
        self.sum_tran += at.sum(axis=0)
        self.sum_rot += ar.sum(axis=0)
        np.maximum(self.peak_tran, at.max(axis=0), out=self.peak_tran)
        np.maximum(self.peak_rot, np.abs(rot).max(axis=0), out=self.peak_rot)
        np.maximum(self.peak_total, np.abs(tran + rot + self.arm).max(axis=0),
                   out=self.peak_total)
        rot_arm, total = rot + self.arm, tran + rot + self.arm
        self.more["tran", "sum_sq"] += (tran * tran).sum(axis=0)
        self.more["rot_arm", "sum_sq"] += (rot_arm * rot_arm).sum(axis=0)
        self.more["total", "sum_abs"] += np.abs(total).sum(axis=0)
        self.more["total", "sum_sq"] += (total * total).sum(axis=0)
        np.maximum(self.more["rot_arm", "peak_abs"], np.abs(rot_arm).max(axis=0),
                   out=self.more["rot_arm", "peak_abs"])
        diag = np.clip(np.diagonal(D_tran + D_rot, axis1=1, axis2=2) + arm_d, 0.0, None)
        iu = np.triu_indices(n)
        with np.errstate(invalid="ignore"):         # 0 x inf
            np.maximum(self.scale_D, np.sqrt(diag[:, iu[0]] * diag[:, iu[1]]).max(axis=0),
                       out=self.scale_D)
        np.maximum(self.peak_tau, np.abs(tau).max(axis=0), out=self.peak_tau)


def numpy_part_peaks(peaks, tau_peak, n, D_tran, D_rot, h_tran, h_rot, qdd, tau):
    """PartPeaks.update as numpy code (the formulation before the kernel), in place."""
    parts = {"tran": (D_tran, h_tran), "rot": (D_rot, h_rot)}
    for r, (_, p, kind, i, j) in enumerate(part_index(n)):
        D, h = parts[p]
        if kind == "D":
            peaks[r, i] = max(peaks[r, i], np.abs(D[:, i, j] * qdd[:, j]).max())
            if i != j:
                peaks[r, j] = max(peaks[r, j], np.abs(D[:, i, j] * qdd[:, i]).max())
        else:
            peaks[r, i] = max(peaks[r, i], np.abs(h[:, i]).max())
    np.maximum(tau_peak, np.abs(tau).max(axis=0), out=tau_peak)


#: The accumulator's attributes the oracle holds under the same name.
RANKED = ("sum_arm", "arm", "scale_D", "peak_tau")
#: The oracle's sums and peaks by name, and the statistic of the accumulator each is.
STATISTICS = {"sum_tran": ("tran", "sum_abs"), "sum_rot": ("rot_arm", "sum_abs"),
              "peak_tran": ("tran", "peak_abs"), "peak_rot": ("rot", "peak_abs"),
              "peak_total": ("total", "peak_abs")}


def _same(a, b):
    """Equal bit for bit up to NaN payloads (NaN where the other has NaN)."""
    a, b = np.asarray(a), np.asarray(b)
    return a.shape == b.shape and bool(np.all((a == b) & (np.signbit(a) == np.signbit(b))
                                              | (np.isnan(a) & np.isnan(b))))


def _feed(chunks, armature=None):
    """Feed the chunks to the kernels and to the oracle; every value the same bit for bit."""
    n = chunks[0][2].shape[1]
    ref = NumpyRanking(n)
    acc, parts = RankingAccumulator(n), PartPeaks(n)
    peaks, tau_peak = np.zeros((len(part_index(n)), n)), np.zeros(n)
    for D_tran, D_rot, h_tran, h_rot, qdd, tau in chunks:
        ref.update(D_tran, D_rot, h_tran, h_rot, tau, armature=armature)
        numpy_part_peaks(peaks, tau_peak, n, D_tran, D_rot, h_tran, h_rot, qdd, tau)
        acc.update(D_tran, D_rot, h_tran, h_rot, tau, armature=armature)
        parts.update(D_tran, D_rot, h_tran, h_rot, qdd, tau)
    for name in RANKED:
        assert _same(getattr(acc, name), getattr(ref, name)), name
    expected = {**{key: getattr(ref, name) for name, key in STATISTICS.items()}, **ref.more}
    assert sorted(expected) == sorted(ROWS)                 # every statistic is checked
    for key, value in expected.items():
        assert _same(acc.statistic(*key), value), key
    assert _same(parts.peaks, peaks) and _same(parts.tau_peak, tau_peak)
    return acc


@pytest.mark.parametrize("name, drives", [("puma560", False), ("puma560-drives", True),
                                          ("two-link", False), ("stanford", False)])
def test_the_kernels_give_the_numpy_values_on_gd_terms(name, drives):
    robot = load_robot(name)
    q, qd, qdd = random_states(robot, 700, 5)
    terms = gd_terms(robot, q, qd)
    tau = terms.tau(qdd)
    cuts = [0, 1, 2, 300, 699, 700]                 # uneven chunks, one of a single row
    chunks = [(terms.D_tran[a:b], terms.D_rot[a:b], terms.h_tran[a:b], terms.h_rot[a:b],
               qdd[a:b], tau[a:b]) for a, b in zip(cuts, cuts[1:])]
    acc = _feed(chunks, armature=terms.armature)
    assert acc.count == 700
    assert bool(np.any(acc.arm)) == drives


def _made_up(rng, N, n, scale):
    def a(*shape):
        return rng.standard_normal(shape) * 10.0 ** rng.integers(-scale, scale + 1, shape)
    return a(N, n, n), a(N, n, n), a(N, n), a(N, n), a(N, n), a(N, n)


@pytest.mark.parametrize("n", [1, 2, 3, 6, 7])
def test_the_kernels_give_the_numpy_values_where_summation_order_shows(n):
    """Magnitudes over 24 decades: any other order of the sums would show in the last bits."""
    rng = np.random.default_rng(n)
    chunks = [_made_up(rng, N, n, 12) for N in (1, 5, 2000, 333)]
    at = np.abs(element_series(*chunks[2][:4])[0])
    assert not np.array_equal(at.sum(axis=0), at[::-1].sum(axis=0))    # the order shows
    _feed(chunks)
    _feed(chunks, armature=np.abs(rng.standard_normal(n)))


def test_the_kernels_keep_the_numpy_handling_of_signed_zeros_inf_and_nan():
    rng = np.random.default_rng(7)
    n = 3
    chunks = []
    for special in (-0.0, np.inf, -np.inf, np.nan):
        c = [x.copy() for x in _made_up(rng, 40, n, 3)]
        for x in c:                                 # sprinkle the special value
            flat = x.reshape(-1)
            flat[rng.integers(0, flat.size, 6)] = special
        chunks.append(c)
    zeros = [np.zeros_like(x) for x in chunks[0]]
    negative_zeros = [-z for z in zeros]
    for order in ([zeros, negative_zeros], [negative_zeros], chunks, chunks[::-1],
                  [chunks[0], chunks[3], chunks[1]]):
        _feed(order)
        _feed(order, armature=np.array([0.5, 0.0, 2.0]))


def test_a_chunk_whose_peak_is_nan_is_not_kept():
    """A NaN in a chunk makes that chunk's peak of the part NaN, and a NaN chunk peak is not
    kept, even where the chunk's finite values are larger (the numpy formulation's built-in
    max); a NaN |tau| is kept (np.maximum)."""
    rng = np.random.default_rng(3)
    n = 3
    small = [0.01 * x for x in _made_up(rng, 10, n, 0)]
    large = [100.0 * np.abs(x) + 100.0 for x in _made_up(rng, 10, n, 0)]
    large[0][4, 0, 1] = np.nan                      # D_tran[0, 1]: part "D12", "tran"
    large[5][7, 2] = np.nan                         # tau_3
    parts = PartPeaks(n)
    for chunk in (small, large):
        parts.update(*chunk)
    r = [k for k, (label, p, *_) in enumerate(part_index(n)) if (label, p) == ("D12", "tran")]
    assert parts.peaks[r[0], 0] < 1.0 and parts.peaks[r[0], 1] < 1.0
    assert parts.peaks[r[0] + 1, 0] > 100.0             # the rot part took the large chunk
    assert np.isnan(parts.tau_peak[2]) and not np.isnan(parts.tau_peak[:2]).any()
    _feed([small, large])
