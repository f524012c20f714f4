"""Preprocessing of a recording: uniform clock, zero-phase low-pass filter, differentiation,
decimation.

Steps, each stated in :attr:`Preprocessed.notes`:

0. Outlier spikes of the torque, single samples far off their neighbours, are replaced by the
   mean of their neighbours (:func:`despiked`).
1. The clock is split at gaps longer than :data:`GAP_STEPS` median steps; each segment is
   handled alone (no data is invented across a gap).
2. With a filter, each segment is resampled onto a uniform clock (the median step, in the
   file's own time base) by linear interpolation: zero-phase filtering needs uniform samples.
3. q, tau (and qd, qdd where the file gives them) are low-pass filtered with a Butterworth
   filter of order :data:`ORDER` run forwards and backwards (``scipy.signal.sosfiltfilt``: zero
   phase, effective order 2 x ORDER). The same filter on the torque, as is standard
   (Gautier & Poignet, "Extended Kalman filtering and weighted least squares dynamic
   identification of robot", Control Engineering Practice 9, 2001; Swevers et al. 1997).
4. qd and qdd where absent: central differences of the filtered q and qd (on the uniform
   clock five-point ones, of fourth order; without a filter ``numpy.gradient``'s, second
   order, on the file's clock).
5. The first and last :func:`edge_samples` samples of each segment are dropped (the filter's
   and the differences' start-up).
6. Decimation: every k-th sample is kept (the low-pass is the anti-aliasing filter).
7. A joint held still (its kept positions span less than :data:`STILL_SPAN`) has q set to its
   mean and qd and qdd to 0: the differences of a held position are its noise and
   quantisation, which would otherwise enter sign(qd) and qd as motion, and the noise of q
   would make columns identifiable that a still joint cannot separate (:func:`still_joints`).
8. The kept samples' noise is correlated by the filter: :attr:`Preprocessed.correlation`
   of them hold as much information as one, which the fit's standard deviations take in.

The regressor built from the filtered states is filtered again by the same filter
(:meth:`Preprocessed.filtered`) before the rows are kept, as the torque was: the *parallel
filtering* of Gautier ("Dynamic identification of robots with power model", ICRA 1997), so that
a term the model holds but the filter smooths (Coulomb friction's step at a reversal) is smoothed
alike on both sides of tau = Y theta.

The default cutoff is chosen from the data (:func:`default_cutoff`). The rows of a clipped
torque (:func:`clipped_samples`; on a coarsely quantised torque, :func:`model_clipped`, against a
fitted model, which also confirms or rejects the runs :func:`clipped_samples` finds there,
:func:`confirmed_clips`) are marked on the output's clock, to be left out of the fit.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt

__all__ = ["Preprocessed", "preprocess", "most_samples", "default_cutoff", "edge_samples",
           "still_joints", "clipped_samples", "despiked", "CLIP_RUN", "CLIP_LEVELS", "CLIP_REACH",
           "CLIP_NOISE", "CLIP_ORDER", "CLIP_APPROACH", "CLIP_SHARE", "CLIP_SIGMAS", "CLIP_COARSE",
           "CLIP_FEW", "SPIKE_SIGMAS", "ORDER", "GAP_STEPS", "CUTOFF_FACTOR", "ENERGY", "SLOW_STEP",
           "EDGE_PERIODS", "STILL_SPAN", "MISMATCH", "FILTER_BLOCK", "extreme_samples",
           "model_clipped", "coarse_columns", "confirmed_clips", "not_velocities"]

#: Order of the Butterworth low-pass filter (run forwards and backwards).
ORDER = 4
#: A step longer than this many median steps splits the recording into segments.
GAP_STEPS = 20
#: The default cutoff is this multiple of the motion's bandwidth (:func:`default_cutoff`).
CUTOFF_FACTOR = 5.0
#: The motion's bandwidth holds this fraction of the power of the detrended positions.
ENERGY = 0.99
#: Periods of the cutoff dropped at each end of a segment (the filters' and the differences'
#: start-up: the second difference of the filtered positions settles last).
EDGE_PERIODS = 3.0
#: A joint whose kept positions span less than this is held still [rad for a revolute joint
#: (0.57 deg), m for a prismatic one].
STILL_SPAN = {"revolute": 1e-2, "prismatic": 1e-3}
#: A given qd whose distance from the differences of q exceeds this share of theirs, on a joint
#: that moves, is not that joint's velocity (a driver's zeros, a sign or a unit off): the
#: differences replace it.
MISMATCH = 0.5
#: A recording whose samples are this far apart or more (median) [s] is warned about: no arm's
#: torques are logged at 4 Hz or slower, but a clock in ms of a log at up to 4 kHz reads so in s.
SLOW_STEP = 0.25
#: The fewest samples in a row at a torque's extreme that are taken for clipping
#: (:func:`clipped_samples`).
CLIP_RUN = 3
#: Residual standard deviations of a fit by which the model's torque goes beyond a clipped level
#: (:func:`model_clipped`): the residual is mostly the recording's quantisation and noise, which
#: the half step already bounds, and the prediction's own error, from thousands of rows for a
#: few dozen parameters, is a small part of it; 3 would ask for a clip deeper than a step.
CLIP_SIGMAS = 1.0
#: A torque is judged against a fitted model (:func:`model_clipped`) only with fewer levels than
#: this: there a shallow clip and an honest peak hold the top level alike, so that
#: :func:`clipped_samples` is blind (analysis/clip_levels.py), while on a finer torque it finds
#: clips itself and the model's own error, not the step, would set what goes beyond a level.
CLIP_COARSE = 20
#: A torque of fewer values than this keeps the samples either clip check finds, its warning
#: line saying so (:func:`coarse_columns`): fitted without the extreme levels, which then hold
#: much of the samples, the model took a PUMA 560's honest integer currents of 4 to 8 values for
#: clipped on up to 45 % of a joint's samples.
CLIP_FEW = 10
#: The fewest steps between a torque's values in which clipping is looked for.
CLIP_LEVELS = 4
#: A torque's resolution for clipping is at least this many noise standard deviations.
CLIP_NOISE = 4.0
#: The flattest honest peak (:func:`clipped_samples`): a torque's depth below a smooth peak
#: grows as |t - t_0|^p with p at most this (2 for a peak with curvature; 4 or 8 for flatter
#: tops, as 1 - t^4 or a sum of harmonics in phase).
CLIP_ORDER = 8
#: The approach to a torque's extreme level is timed from depth b down to this many b below it
#: (b half its noise band, :func:`clipped_samples`).
CLIP_APPROACH = 5.0
#: The largest share of a joint's samples moving one way that a clipped extreme holds.
CLIP_SHARE = 0.7
#: A sample off the mean of its neighbours by more than this many noise standard deviations
#: (beyond their own difference) is a spike (:func:`despiked`).
SPIKE_SIGMAS = 10.0
#: The rows left out around a clipped sample: this many periods of the cutoff on each side
#: (the zero-phase filter spreads the clipping's error over its impulse response).
CLIP_REACH = 0.5
#: Samples per block of :meth:`Preprocessed.filtered_blocks` (a block of the regressor holds
#: this many x n x p numbers).
FILTER_BLOCK = 4096


@dataclass(frozen=True, eq=False)
class Preprocessed:
    """A recording after preprocessing.

    Attributes
    ----------
    t : ndarray, shape (N,)
        Time [s], the file's own time base.
    q, qd, qdd : ndarray, shape (N, n)
        [rad, rad/s, rad/s^2; m, m/s, m/s^2].
    tau : ndarray, shape (N, n)
        Filtered torque [N m or N].
    cutoff : float or None
        Filter cutoff [Hz]; None without a filter.
    step : float
        The median time step of the input [s].
    notes : tuple of str
        What was done, one sentence each.
    keep : ndarray of bool, shape (N,)
        The samples kept (not at a segment's ends, and every decimate-th): the arrays above
        hold every sample of the uniform clock, so that :meth:`filtered` runs on whole
        segments.
    segments : tuple of (int, int)
        Start and stop index of each segment in the arrays.
    sos : ndarray or None
        The filter's second-order sections.
    held : ndarray of bool, shape (n,), or None
        The joints held still (:func:`still_joints`), their q set to its mean and their qd and
        qdd to 0; None if the joints' kinds were not given.
    clipped : ndarray of bool, shape (N, n), or None
        The rows (sample, joint) a clipped torque reaches (:func:`clipped_samples`, widened by
        the filter's reach, half a period of the cutoff): left out of the fit; None if none
        were given.
    correlation : float
        Kept samples per independent one of a white noise through the filter, at least 1
        (1 without a filter): 1 / (decimate x mean |H|^4 over [0, Nyquist]), H the filter's
        response. The zero-phase filter keeps the noise's power below the cutoff, where the
        motion is, and divides its variance by 1 / mean |H|^4, so that the residual's
        variance understates the noise the fit sees by that factor (Ljung, *System
        Identification*, 2nd ed., 1999, Sec. 9.3).
    """

    t: np.ndarray
    q: np.ndarray
    qd: np.ndarray
    qdd: np.ndarray
    tau: np.ndarray
    cutoff: float | None
    step: float
    notes: tuple
    keep: np.ndarray | None = None
    segments: tuple = ()
    sos: np.ndarray | None = None
    held: np.ndarray | None = None
    clipped: np.ndarray | None = None
    correlation: float = 1.0

    def filtered(self, x: npt.NDArray[np.float64]) -> npt.NDArray[np.float64]:
        """The same zero-phase filter on another signal of the same samples, segment by segment.

        Parameters
        ----------
        x : ndarray, shape (N, ...)
            A signal on the arrays' samples (e.g. the regressor, shape (N, n, p)).

        Returns
        -------
        ndarray, shape (N, ...)
            x filtered along axis 0 (x itself without a filter).
        """
        if self.sos is None:
            return x
        from scipy import signal

        return np.concatenate([signal.sosfiltfilt(self.sos, x[a:b], axis=0)
                               for a, b in self.segments])

    def filtered_blocks(self, make: Callable[[int, int], npt.NDArray[np.float64]],
                        rows: int | None = None
                        ) -> Iterator[tuple[int, int, npt.NDArray[np.float64]]]:
        """:meth:`filtered` of a signal made block by block, in memory bounded by the block.

        Parameters
        ----------
        make : callable
            ``make(a, b)`` returns the signal's samples a to b - 1, an array of shape
            (b - a, ...) (e.g. the regressor of those samples, shape (b - a, n, p)); it is
            called twice per block with a filter (once without).
        rows : int, optional
            Samples per block (>= 1); default :data:`FILTER_BLOCK`.

        Yields
        ------
        a, b : int
            The block's samples, within one segment.
        y : ndarray, shape (b - a, ...)
            ``self.filtered(x)[a:b]`` for the whole signal x. The blocks of a segment come
            last to first with a filter, first to last without.

        Raises
        ------
        ValueError
            If ``rows`` < 1.

        Notes
        -----
        Per segment, the recurrences of ``scipy.signal.sosfiltfilt`` with its default odd
        extension of 3 (2 s + 1) samples (s sections; fewer where a section's b2 and a2 are
        both 0) at each end, and its initial states: forwards over the segment, keeping the
        filter's state at each block's start; then backwards, each block made again and
        filtered forwards from its kept state, then backwards from the state the later
        blocks left. The same operations in the same order as on the whole segment, so the
        same numbers, with a few blocks in memory instead of the whole signal.
        """
        rows = FILTER_BLOCK if rows is None else int(rows)
        if rows < 1:
            raise ValueError(f"rows must be >= 1, got {rows}")
        for s0, s1 in self.segments:
            if self.sos is None:
                for a in range(s0, s1, rows):
                    yield a, min(a + rows, s1), make(a, min(a + rows, s1))
            else:
                yield from _segment_blocks(self.sos, make, s0, s1, rows)


def _segment_blocks(sos, make, s0, s1, rows):
    """:meth:`Preprocessed.filtered_blocks` on one segment [s0, s1), with a filter."""
    from scipy import signal

    sections = sos.shape[0]
    edge = 3 * (2 * sections + 1 - min(int((sos[:, 2] == 0).sum()), int((sos[:, 5] == 0).sum())))
    head, tail = make(s0, s0 + edge + 1), make(s1 - edge - 1, s1)
    unit = signal.sosfilt_zi(sos).reshape((sections, 2) + (1,) * (head.ndim - 1))
    left = 2 * head[:1] - head[edge:0:-1]         # scipy.signal.odd_ext's two ends
    right = 2 * tail[-1:] - tail[-2::-1]
    _, z = signal.sosfilt(sos, left, axis=0, zi=unit * left[:1])
    starts = range(s0, s1, rows)
    states = []
    for a in starts:
        states.append(z)
        _, z = signal.sosfilt(sos, make(a, min(a + rows, s1)), axis=0, zi=z)
    y, z = signal.sosfilt(sos, right, axis=0, zi=z)
    _, z = signal.sosfilt(sos, y[::-1], axis=0, zi=unit * y[-1:])
    for k in reversed(range(len(starts))):
        a, b = starts[k], min(starts[k] + rows, s1)
        y, _ = signal.sosfilt(sos, make(a, b), axis=0, zi=states[k])
        y, z = signal.sosfilt(sos, y[::-1], axis=0, zi=z)
        yield a, b, y[::-1]


def _derivative(x, spacing):
    """d x / d t along axis 0: on a uniform clock (``spacing`` the step [s]) the five-point
    central difference, of fourth order, inside (the ends second order, ``numpy.gradient``);
    on the file's own clock (``spacing`` the time stamps) second-order differences. The
    three-point difference's gain sin(w h) / (w h) took 0.4 % off qd and 0.8 % off qdd at
    2.5 Hz sampled at 100 Hz, which biased the fit (a UR5's Coulomb friction by up to 28 %)."""
    d = np.gradient(x, spacing, axis=0)
    if np.ndim(spacing) == 0 and x.shape[0] > 4:
        d[2:-2] = (x[:-4] - 8 * x[1:-3] + 8 * x[3:-1] - x[4:]) / (12 * spacing)
    return d


def not_velocities(t: npt.NDArray[np.float64], q: npt.NDArray[np.float64],
                   qd: npt.NDArray[np.float64]) -> npt.NDArray[np.bool_]:
    """Which given velocity columns are not their joint's velocity.

    A driver may publish zeros, or a velocity of another sign or unit: fitted as it stands,
    such a column gives a wrong model (a two-link arm's joint 2 with its qd column zero: 72.8 %
    off on its own training data) or leaves no row to fit.

    Parameters
    ----------
    t : ndarray, shape (N,)
        Time [s], strictly increasing.
    q, qd : ndarray, shape (N, n)
        Positions [rad or m] and the velocities given [rad/s or m/s]; or velocities and the
        accelerations given [rad/s^2 or m/s^2], as :func:`preprocess` checks a given qdd.

    Returns
    -------
    ndarray of bool, shape (n,)
        True for a joint that moves (its positions span more than
        ``STILL_SPAN["prismatic"]``) whose given qd is farther from the differences of q
        (``numpy.gradient`` on the file's clock) than :data:`MISMATCH` times their norm.

    Examples
    --------
    >>> t = np.linspace(0.0, 1.0, 101)
    >>> q = np.column_stack([np.sin(t), np.sin(t)])
    >>> not_velocities(t, q, np.column_stack([np.cos(t), np.zeros_like(t)])).tolist()
    [False, True]
    """
    rate = np.gradient(q, t, axis=0)
    return (np.ptp(q, axis=0) > STILL_SPAN["prismatic"]) & (
        np.linalg.norm(qd - rate, axis=0) > MISMATCH * np.linalg.norm(rate, axis=0))


def _segments(t):
    """Index slices of the runs of t without a gap longer than GAP_STEPS median steps."""
    dt = np.diff(t)
    med = float(np.median(dt))
    bounds = np.concatenate([[0], np.flatnonzero(dt > GAP_STEPS * med) + 1, [t.size]])
    return [slice(int(a), int(b)) for a, b in zip(bounds[:-1], bounds[1:])], med


def most_samples(t: npt.ArrayLike, resampled: bool = True) -> int:
    """The most samples :func:`preprocess` can give a recording: its rows, or, resampled onto
    the median step (with a filter), each segment's span in median steps, plus one.

    Parameters
    ----------
    t : array_like, shape (N,)
        The recording's time stamps, increasing [s].
    resampled : bool, optional
        A filter is applied (a cutoff is given or chosen), so the segments are resampled.

    Returns
    -------
    int
        An upper bound of the samples kept (before the edges are dropped and the decimation).

    Examples
    --------
    >>> most_samples([0.0, 0.1, 0.2, 0.4, 0.5])   # the step of 0.2 s resampled as two
    6
    >>> most_samples([0.0, 0.1, 0.2, 0.4, 0.5], resampled=False)
    5
    """
    t = np.asarray(t, float)
    if t.size < 2 or not resampled:
        return int(t.size)
    segs, step = _segments(t)
    return max(int(t.size), sum(int((t[s][-1] - t[s][0]) / step) + 1 for s in segs))


def default_cutoff(t: npt.NDArray[np.float64], q: npt.NDArray[np.float64],
                   prismatic: npt.NDArray[np.bool_] | None = None) -> float:
    """The default low-pass cutoff, from the data: CUTOFF_FACTOR x the motion's bandwidth.

    Parameters
    ----------
    t : ndarray, shape (N,)
        Time [s], increasing.
    q : ndarray, shape (N, n)
        Joint positions [rad or m].
    prismatic : ndarray of bool, shape (n,), optional
        True for a prismatic joint (default: none), for :func:`still_joints`.

    Returns
    -------
    float
        The cutoff [Hz]: :data:`CUTOFF_FACTOR` times the highest, over the joints that move
        (not held still, :func:`still_joints`: a held joint's positions are encoder noise, whose
        power spreads to the Nyquist frequency),
        frequency below which :data:`ENERGY` of the power of the linearly detrended position
        lies (Welch's periodogram, ``scipy.signal.welch``, on the median-step clock), within
        [2 / duration, 0.4 x the Nyquist frequency].

    Examples
    --------
    >>> t = np.arange(0, 20, 0.001)
    >>> q = np.sin(2 * np.pi * 0.5 * t)[:, None]
    >>> 1.0 < default_cutoff(t, q) < 5.0
    True
    """
    from scipy import signal

    t, q = np.asarray(t, float), np.asarray(q, float)
    step = float(np.median(np.diff(t)))
    tu = np.arange(t[0], t[-1], step)
    qu = signal.detrend(np.column_stack([np.interp(tu, t, x) for x in q.T]), axis=0)
    nper = int(min(qu.shape[0], max(256, 2 ** int(np.log2(max(qu.shape[0] // 4, 1))))))
    f, P = signal.welch(qu, fs=1.0 / step, nperseg=nper, axis=0)
    band = 0.0
    for j in np.flatnonzero(~still_joints(q, prismatic)):
        total = P[:, j].sum()
        if not np.isfinite(total) or total <= 0:
            continue
        c = np.cumsum(P[:, j]) / total
        band = max(band, float(f[min(np.searchsorted(c, ENERGY), f.size - 1)]))
    return float(min(max(CUTOFF_FACTOR * band, 2.0 / (t[-1] - t[0])), 0.4 * 0.5 / step))


def edge_samples(step: float, cutoff: float | None) -> int:
    """Samples dropped at each end of a segment: EDGE_PERIODS periods of the cutoff, at least 2.

    Parameters
    ----------
    step : float
        Sample step [s].
    cutoff : float or None
        Filter cutoff [Hz]; None without a filter.

    Returns
    -------
    int
    """
    return 0 if cutoff is None else max(2, int(np.ceil(EDGE_PERIODS / (cutoff * step))))


def preprocess(t: npt.NDArray[np.float64], q: npt.NDArray[np.float64], tau: npt.NDArray[np.float64],
               qd: npt.NDArray[np.float64] | None = None,
               qdd: npt.NDArray[np.float64] | None = None, cutoff: float | str | None = "auto",
               decimate: int = 1, label: str = "recording",
               prismatic: npt.NDArray[np.bool_] | None = None,
               clipped: npt.NDArray[np.bool_] | None = None) -> Preprocessed:
    """Resample, filter, differentiate and decimate one recording (steps in the module docstring).

    Parameters
    ----------
    t : ndarray, shape (N,)
        Time [s], strictly increasing.
    q, tau : ndarray, shape (N, n)
        Positions [rad or m] and torques [N m or N].
    qd, qdd : ndarray, shape (N, n), optional
        Velocities and accelerations where measured.
    cutoff : float, "auto" or None, optional
        Low-pass cutoff [Hz]; ``"auto"`` chooses it from the data (:func:`default_cutoff`);
        None: no filter and no resampling (derivatives by differences on the file's clock).
    decimate : int, optional
        Keep every decimate-th sample (>= 1).
    label : str, optional
        The recording's name in the notes.
    prismatic : ndarray of bool, shape (n,), optional
        True for a prismatic joint: given, the joints held still are found
        (:func:`still_joints`), their q set to its mean and their qd and qdd to 0.
    clipped : ndarray of bool, shape (N, n), optional
        The rows (sample, joint) whose torque is clipped (:func:`clipped_samples`), to be left
        out of the fit: :attr:`Preprocessed.clipped` on the output's clock.

    Returns
    -------
    Preprocessed

    Raises
    ------
    ValueError
        If the cutoff is not below the Nyquist frequency, decimate < 1, or no segment is long
        enough for the filter.
    """
    from scipy import ndimage, signal

    t = np.asarray(t, float)
    segs, step = _segments(t)
    tau, spikes = despiked(tau)
    notes = [f"{label}: {spikes.sum()} outlier samples of the torque (spikes off their "
             f"neighbours) replaced by the mean of those"] if spikes.any() else []
    if len(segs) > 1:
        notes.append(f"{label}: {len(segs) - 1} gaps longer than {GAP_STEPS} median steps "
                     f"({step * 1e3:.3g} ms): processed as {len(segs)} separate segments")
    off = {"qd": np.zeros(q.shape[1], bool) if qd is None else not_velocities(t, q, qd)}
    rate = np.gradient(q, t, axis=0)    # qdd against the qd used: the given one where it is
    rate = rate if qd is None else np.where(off["qd"], rate, qd)
    off["qdd"] = np.zeros_like(off["qd"]) if qdd is None else not_velocities(t, rate, qdd)
    for k, x in (("qd", "q"), ("qdd", "qd")):
        if off[k].any():
            notes.append(f"{label}: the given {k} of joint(s) "
                         f"{', '.join(map(str, np.flatnonzero(off[k]) + 1))} is over "
                         f"{MISMATCH:.0%} off the differences of {x}: differentiated instead")
    dts = np.diff(t)
    if dts.min() < 0.9 * step or dts.max() > 1.1 * step:
        notes.append(f"{label}: irregular clock, steps {dts.min() * 1e3:.3g} to "
                     f"{dts.max() * 1e3:.3g} ms (median {step * 1e3:.3g} ms)")
    if isinstance(cutoff, str):
        cutoff = default_cutoff(t, q, prismatic)
        notes.append(f"{label}: cutoff {cutoff:.3g} Hz chosen from the data ({CUTOFF_FACTOR:g} x "
                     f"the bandwidth holding {ENERGY:.0%} of the positions' power)")
    if cutoff is not None and not 0 < cutoff < 0.5 / step:
        raise ValueError(f"cutoff {cutoff:g} Hz is not between 0 and the Nyquist frequency "
                         f"{0.5 / step:.4g} Hz of the median step")
    if int(decimate) < 1:
        raise ValueError(f"decimate must be >= 1, got {decimate}")
    trim = (1 if cutoff is None and (qd is None or qdd is None)   # one-sided differences
            else edge_samples(step, cutoff))
    out: dict[str, list[Any]] = {k: [] for k in ("t", "q", "qd", "qdd", "tau", "keep", "clipped")}
    given = {"q": q, "tau": tau, "qd": qd, "qdd": qdd}
    sos = None if cutoff is None else signal.butter(ORDER, cutoff, fs=1.0 / step, output="sos")
    dropped, need = 0, max(3 * (2 * ORDER + 1), 2 * trim + 3)
    for s in segs:
        ts = t[s]
        if ts.size < need:
            dropped += ts.size
            continue
        if sos is not None:
            tu = np.arange(ts[0], ts[-1] + 0.5 * step, step)
            tu = tu[tu <= ts[-1]]

            def resample(x, tu=tu, ts=ts):
                return np.column_stack([np.interp(tu, ts, x[:, j]) for j in range(x.shape[1])])
            d: dict[str, Any] = {k: None if v is None else signal.sosfiltfilt(
                sos, resample(v[s]), axis=0) for k, v in given.items()}
            # the samples next to a clipped one, and those within the filter's reach
            d["clipped"] = None if clipped is None else ndimage.maximum_filter1d(
                resample(clipped[s].astype(float)) > 0, axis=0,
                size=2 * int(np.ceil(CLIP_REACH / (cutoff * step))) + 1)
            d["t"], spacing = tu, step
        else:
            d = {k: None if v is None else v[s] for k, v in {**given, "clipped": clipped}.items()}
            d["t"], spacing = ts, ts
        for k, x in (("qd", "q"), ("qdd", "qd")):    # differences where not given (or qd off)
            diff = _derivative(d[x], spacing)
            d[k] = diff if d[k] is None else np.where(off[k], diff, d[k])
        d["keep"] = np.zeros(d["t"].size, bool)
        d["keep"][slice(trim, d["t"].size - trim, int(decimate))] = True
        for k in out:
            out[k].append(d[k])
    if not out["t"]:
        raise ValueError(f"{label}: no segment is long enough for the filter and the "
                         f"differences (the longest holds {max(s.stop - s.start for s in segs)} "
                         f"samples; {need} are needed with this filter)")
    if dropped:
        notes.append(f"{label}: {dropped} samples in segments too short for the filter dropped")
    notes.append(f"{label}: no filter, no resampling" if sos is None else
                 f"{label}: resampled onto a uniform {step * 1e3:.3g} ms clock by linear "
                 f"interpolation; q, tau{', qd' if qd is not None else ''}"
                 f"{', qdd' if qdd is not None else ''} low-pass filtered at {cutoff:.3g} Hz "
                 f"(Butterworth order {ORDER}, forwards and backwards: zero phase), and the "
                 f"regressor by the same filter as the torque (parallel filtering)")
    derived = [k for k in ("qd", "qdd") if given[k] is None]
    if derived:
        notes.append(f"{label}: {' and '.join(derived)} by central differences of the "
                     + ("filtered signals (five points, fourth order)" if sos is not None
                        else "signals"))
    notes.append(f"{label}: {trim} samples dropped at each end of each segment"
                 + (f"; every {int(decimate)}th sample kept" if int(decimate) > 1 else ""))
    cat = {k: np.concatenate(v) for k, v in out.items() if k != "clipped" or clipped is not None}
    held = None if prismatic is None else still_joints(cat["q"][cat["keep"]], prismatic)
    if held is not None and held.any():
        cat["qd"][:, held] = cat["qdd"][:, held] = 0.0
        cat["q"][:, held] = cat["q"][cat["keep"]][:, held].mean(axis=0)
        notes.append(f"{label}: joint(s) {', '.join(str(j + 1) for j in np.flatnonzero(held))}"
                     f" held still (position span below {STILL_SPAN['revolute']:g} rad or "
                     f"{STILL_SPAN['prismatic']:g} m): q set to its mean, qd and qdd to 0")
    stops = np.cumsum([v.size for v in out["t"]])
    segments = tuple((int(a), int(b)) for a, b in zip(np.concatenate([[0], stops[:-1]]), stops))
    return Preprocessed(t=cat["t"], q=cat["q"], qd=cat["qd"], qdd=cat["qdd"], tau=cat["tau"],
                        cutoff=cutoff, step=step, notes=tuple(notes), keep=cat["keep"],
                        segments=segments, sos=sos, held=held, clipped=cat.get("clipped"),
                        correlation=1.0 if sos is None else max(1.0, 1.0 / (int(decimate) * float(
                            np.mean(np.abs(signal.sosfreqz(sos, worN=4096)[1]) ** 4)))))


def still_joints(q: npt.NDArray[np.float64],
                 prismatic: npt.NDArray[np.bool_] | None) -> npt.NDArray[np.bool_]:
    """The joints held still in a recording: position span below :data:`STILL_SPAN`.

    A joint held still (braked, or left out of the excitation) has speeds that are the
    differentiated noise and quantisation of its position; taken as motion, they would enter
    the viscous and Coulomb columns (sign(qd) flipping with the noise) and have friction fitted
    to noise. With qd = qdd = 0 those columns are 0 wherever the joint is held.

    Parameters
    ----------
    q : ndarray, shape (N, n)
        Positions [rad, or m for a prismatic joint].
    prismatic : ndarray of bool, shape (n,), or None
        True for a prismatic joint (None: every joint revolute).

    Returns
    -------
    ndarray of bool, shape (n,)
        True where max q_i - min q_i < STILL_SPAN of the joint's kind.

    Examples
    --------
    >>> import numpy as np
    >>> q = np.column_stack([np.linspace(0.0, 1.0, 50), 0.3 + 1e-4 * np.sin(np.arange(50))])
    >>> still_joints(q, np.array([False, False])).tolist()
    [False, True]
    """
    q = np.asarray(q, float)
    span = q.max(axis=0) - q.min(axis=0)
    limit = np.where(np.asarray(prismatic, bool), STILL_SPAN["prismatic"],
                     STILL_SPAN["revolute"])
    return np.asarray(span < limit, bool)


def _resolution(x):
    """Per column of x, shape (N, n): the steps between its sorted values (inf where below 1e-9
    of their range, so that a value rounded to a multiple of the quantum counts as that
    multiple), and the scale of each sample's white noise from its second difference,
    |x[k+1] - 2 x[k] + x[k-1]| x 1.4826 / sqrt 6 (of which the median is the noise's standard
    deviation, robust to the signal's own curvature, its jumps and a few spikes; 0 for a
    noise-free or slowly quantised signal)."""
    steps = np.diff(np.sort(x, axis=0), axis=0)
    steps[steps <= 1e-9 * np.ptp(x, axis=0)] = np.inf
    return steps, np.abs(np.diff(x, 2, axis=0, prepend=x[:1], append=x[-1:])) * 1.4826 / 6 ** 0.5


def despiked(tau: npt.NDArray[np.float64]) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.bool_]]:
    """Outlier spikes replaced by the mean of their two neighbours.

    A sample is a spike when it stands off the mean m of its two neighbours by more than
    :data:`SPIKE_SIGMAS` x the signal's noise (or its quantum, if larger) plus the neighbours'
    own difference: a single bad sample, not a step (a Coulomb jump at a reversal, whose
    neighbours differ by the jump) nor a slope. Filtered, a spike would spread over the filter's
    impulse response (a Hampel-type filter, Pearson, "Outliers in process modeling and
    identification", IEEE Trans. Control Syst. Technol. 10(1), 2002).

    Parameters
    ----------
    tau : ndarray, shape (N, n)
        Recorded torques [N m or N] (or currents [A]), sorted by time.

    Returns
    -------
    tau : ndarray, shape (N, n)
        A copy, each spike replaced by m.
    spikes : ndarray of bool, shape (N, n)
        True at the spikes (never the first or last sample).

    Examples
    --------
    >>> x = np.sin(np.linspace(0, 6, 200))[:, None]
    >>> x[50] += 3.0
    >>> clean, spikes = despiked(x)
    >>> np.flatnonzero(spikes).tolist(), bool(abs(clean[50, 0] - np.sin(1.5075)) < 1e-3)
    ([50], True)
    """
    tau = np.array(tau, float)
    steps, noise = _resolution(tau)
    mid, spikes = 0.5 * (tau[2:] + tau[:-2]), np.zeros(tau.shape, bool)
    spikes[1:-1] = np.abs(tau[1:-1] - mid) > SPIKE_SIGMAS * np.maximum(
        np.median(noise, axis=0), steps.min(axis=0, initial=np.inf)) + np.abs(tau[2:] - tau[:-2])
    tau[1:-1][spikes[1:-1]] = mid[spikes[1:-1]]
    return tau, spikes


def clipped_samples(q: npt.NDArray[np.float64],
                    tau: npt.NDArray[np.float64]) -> npt.NDArray[np.bool_]:
    """The samples at which a joint's torque is clipped: held at its extreme while the joint moves.

    A drive's torque limit or a sensor's range holds the recorded torque flat at its largest
    (or smallest) value over runs of samples, where the torque the model predicts goes on:
    fitted, those samples bias the parameters. The torque may carry sensor noise added before
    or after the clip, or be quantised. Per joint whose torque takes more than
    :data:`CLIP_LEVELS` values, with z the torque's running median over 5 samples (spikes and
    noise damped), q_0 its quantum (the smallest step between its values) and sigma its noise
    standard deviation (the median absolute second difference x 1.4826 / sqrt 6, the MAD's
    consistency factor for a normal law: Rousseeuw & Croux, "Alternatives to the median
    absolute deviation", J. Amer. Statist. Assoc. 88, 1993), per extreme:

    - a first level v: the median of the z within w / 2 of z's extreme, w the larger of q_0
      and :data:`CLIP_NOISE` sigma (the recording's noise band);
    - the resolution u: the larger of q_0 and CLIP_NOISE x the noise near v (the median of the
      second differences where z is within w / 2 of v: 0 on a clip without noise or with the
      noise before it, whatever the rest);
    - the approach is cut: with b half the band (u / 2 where u < w / 2, a plateau flatter than
      the recording's noise allows; else the larger of u and w, halved) and v taken again as
      the median of the z within b of z's extreme, per stretch of z above v - K b that reaches
      within b of v and ends inside the recording (K = :data:`CLIP_APPROACH`), T_1 the time z
      spends within b of v and T_2 the time it spends between b and K b below v (z joined
      linearly between samples, times in samples). A peak whose depth below its top grows as
      |t - t_0|^p spends T_1 / T_2 = 1 / ((d_2 / d_1)^(1/p) - 1) there, d_1 and d_2 the band's
      depths below the top (Laplace's method: the time a smooth function spends within d of
      its maximum scales as d^(1/p), de Bruijn, "Asymptotic Methods in Analysis", 1958,
      ch. 4). v lies at most b below the top, so that d_2 / d_1 >= (K + 1) / 2 and any peak
      of order p up to :data:`CLIP_ORDER` gives T_1 / T_2 <= 1 / (((K + 1) / 2)^(1/CLIP_ORDER)
      - 1) = 6.8, whatever its width, height or noise band. A clip of a torque passing its
      limit with slope s gives (L s / b + 2) / (2 (K - 1)) for a plateau lasting L: its slope
      does not go to zero before the plateau. The extreme is clipped where the stretch longest
      within b of v has T_1 > 6.8 (T_2 + 1), one sample's allowance for the joining. A clip the
      torque passes by a few noise deviations only approaches its level as slowly as an
      honest peak of that order and is not told from one;
    - the clipped samples, those within u / 2 of v, hold at most :data:`CLIP_SHARE` of the
      samples in which the joint moves the way most of them move: a torque held flat through
      most of a stroke is Coulomb friction (a joint's torque a square wave of its velocity's
      sign, as real recordings show), not a limit;
    - one run of them holds at least :data:`CLIP_RUN` samples during which the joint's own
      position changes (not the joint held at rest, dithering over a few levels).

    Parameters
    ----------
    q : ndarray, shape (N, n)
        Positions [rad or m], sorted by time.
    tau : ndarray, shape (N, n)
        Recorded torques [N m or N] (or currents [A]).

    Returns
    -------
    ndarray of bool, shape (N, n)
        True at the clipped samples.

    Examples
    --------
    >>> t = np.linspace(0, 4, 400)
    >>> tau = np.column_stack([np.clip(np.sin(t * 3), -0.7, 0.7), np.sin(t * 3)])
    >>> mask = clipped_samples(np.column_stack([t, t]), tau)
    >>> np.unique(tau[mask[:, 0], 0]).tolist(), bool(mask[:, 1].any())
    ([-0.7, 0.7], False)
    """
    from scipy import ndimage

    q, tau = np.asarray(q, float), np.asarray(tau, float)
    out = np.zeros(tau.shape, bool)
    levels, noises = _resolution(tau)
    bound = 1.0 / (((CLIP_APPROACH + 1.0) / 2.0) ** (1.0 / CLIP_ORDER) - 1.0)
    for j in range(tau.shape[1]):
        x, noise, steps = tau[:, j], noises[:, j], levels[np.isfinite(levels[:, j]), j]
        if steps.size < CLIP_LEVELS:
            continue
        dq, z = np.diff(q[:, j], prepend=q[0, j]), ndimage.median_filter(x, 5, mode="nearest")
        w = max(steps.min(), CLIP_NOISE * np.median(noise))
        for y, sx in ((z, x), (-z, -x)):
            v = np.median(y[y > y.max() - w / 2])
            u = max(steps.min(), CLIP_NOISE * np.median(noise[np.abs(y - v) < w / 2]))
            b = u / 2 if u < w / 2 else max(w, u) / 2
            v = np.median(y[y > y.max() - b])
            at = np.abs(sx - v) < u / 2
            way = dq > 0 if 2 * np.count_nonzero(dq[at] > 0) >= at.sum() else dq < 0
            top, below = _time_above(y, v, b, CLIP_APPROACH * b)
            k = np.argmax(top) if top.size else 0       # the stretch longest near v
            if (not top.size or top[k] <= bound * (below[k] + 1.0)
                    or np.count_nonzero(at & way) > CLIP_SHARE * np.count_nonzero(way)):
                continue
            if any(b - a >= CLIP_RUN and dq[a + 1:b].any() for a, b in _runs(at)):
                out[at, j] = True
    return out


def _time_above(y, v, near, far):
    """Per stretch of y, shape (N,), above v - far that reaches above v - near and ends inside
    the recording: the time [samples] y, joined linearly between samples, spends above v - near,
    and between v - far and v - near; two arrays, one value per stretch."""
    times = []
    for a, b in _runs(y > v - far):
        if a > 0 and b < y.size and (y[a:b] > v - near).any():
            lo, hi = np.minimum(y[a - 1:b], y[a:b + 1]), np.maximum(y[a - 1:b], y[a:b + 1])
            with np.errstate(divide="ignore", invalid="ignore"):
                times.append([np.clip(np.where(hi > lo, (hi - v + d) / (hi - lo), hi > v - d),
                                      0, 1).sum() for d in (near, far)])
    top, both = np.reshape(times, (-1, 2)).T
    return top, both - top


def _runs(mask):
    """The runs of True in a boolean array, shape (N,): (start, stop) pairs."""
    edges = np.flatnonzero(np.diff(np.concatenate([[0], mask.view(np.int8), [0]])))
    return list(zip(edges[::2], edges[1::2]))


def extreme_samples(tau: npt.NDArray[np.float64]) -> npt.NDArray[np.bool_]:
    """The samples at a coarsely quantised torque's extreme levels: within half its quantum of
    its largest or smallest value, where it takes fewer than :data:`CLIP_COARSE` values.

    A clip holds the torque at one of these levels; fitted, they pull the model towards it, so
    a fit that is to judge them (:func:`model_clipped`) leaves them out.

    Parameters
    ----------
    tau : ndarray, shape (N, n)
        Recorded torques [N m or N] (or currents [A]).

    Returns
    -------
    ndarray of bool, shape (N, n)
        True within q_0 / 2 of each column's maximum or minimum, q_0 the smallest step between
        its values (none of a constant torque, nor of one of :data:`CLIP_COARSE` values or more).

    Examples
    --------
    >>> extreme_samples(np.array([[0.0], [0.5], [1.0], [1.0], [0.5]]))[:, 0].tolist()
    [True, False, True, True, False]
    """
    steps = _resolution(tau)[0]
    half = 0.5 * np.nan_to_num(steps.min(axis=0, initial=np.inf), posinf=0.0)
    return (((tau > tau.max(axis=0) - half) | (tau < tau.min(axis=0) + half))
            & coarse_columns(tau))


def coarse_columns(tau: npt.NDArray[np.float64],
                   below: int = CLIP_COARSE) -> npt.NDArray[np.bool_]:
    """The torques quantised to fewer than ``below`` values: by default :data:`CLIP_COARSE`,
    those a fitted model judges for clipping (:func:`model_clipped`, :func:`confirmed_clips`);
    below :data:`CLIP_FEW`, those too coarse for either judgement to leave samples out.

    Parameters
    ----------
    tau : ndarray, shape (N, n)
        Recorded torques [N m or N] (or currents [A]).
    below : int
        The fewest values of a column not counted.

    Returns
    -------
    ndarray of bool, shape (n,)
        True where a column takes fewer than ``below`` distinct values (steps below 1e-9 of
        its range not counted as steps).

    Examples
    --------
    >>> coarse_columns(np.column_stack([np.arange(30) % 3, np.arange(30)])).tolist()
    [True, False]
    """
    return np.asarray(np.isfinite(_resolution(np.asarray(tau, float))[0]).sum(axis=0) + 1
                      < below, bool)


def confirmed_clips(q: npt.NDArray[np.float64], tau: npt.NDArray[np.float64],
                    clipped: npt.NDArray[np.bool_],
                    predicted: npt.NDArray[np.float64]) -> npt.NDArray[np.bool_]:
    """:func:`clipped_samples`' samples on a coarsely quantised torque, kept only at an extreme
    which a fitted model goes beyond.

    On a torque of fewer than :data:`CLIP_COARSE` levels, a flat-topped honest peak (two
    maxima within a step of each other, the dip between them rounded to the same level) holds
    its extreme level as long, against the level below, as a clip does (analysis/clip_levels.py:
    the PUMA 560's joint 5 over an ADC twice its range, 20 % of its samples, taken for clipped by
    a count of the samples at the level), so that a rule on the levels alone may not tell them
    apart; the model can: an honest peak rounds to within
    half a step of its level, and the model predicts it so. Per column of fewer than
    CLIP_COARSE levels and per extreme (the clipped samples above, then below, the column's
    mean), with v the median of the clipped samples there and q_0 the quantum: the extreme's
    clipped samples are kept where the predicted torque lies beyond v by more than q_0 / 2 at
    :data:`CLIP_RUN` of them in a row during which the joint's position changes (a limit holds
    every run at its level, also those whose own excess the rounding hides); otherwise none is.
    A finer torque's clipped samples are kept as they are.

    Parameters
    ----------
    q : ndarray, shape (N, n)
        Positions [rad or m], sorted by time.
    tau : ndarray, shape (N, n)
        Recorded torques [N m or N] (or currents [A]).
    clipped : ndarray of bool, shape (N, n)
        :func:`clipped_samples` of the recording.
    predicted : ndarray, shape (N, n)
        A fitted model's torque at the same samples [N m or N], from a fit without the
        samples at the extreme levels; NaN where not predicted (never beyond).

    Returns
    -------
    ndarray of bool, shape (N, n)
        The clipped samples kept.

    Examples
    --------
    >>> t = np.linspace(0, 4, 400)
    >>> honest = (np.round(5 * np.sin(3 * t)) / 5)[:, None]
    >>> clipped = np.abs(honest) == 1.0        # the top and bottom levels, taken for a clip
    >>> confirmed_clips(t[:, None], honest, clipped, np.sin(3 * t)[:, None]).any()
    np.False_
    >>> kept = confirmed_clips(t[:, None], honest, clipped, 1.3 * np.sin(3 * t)[:, None])
    >>> bool(np.array_equal(kept, clipped))    # a model beyond the levels: a clip
    True
    """
    out = np.array(clipped, bool)
    tau, predicted = np.asarray(tau, float), np.asarray(predicted, float)
    half = 0.5 * np.nan_to_num(_resolution(tau)[0].min(axis=0, initial=np.inf), posinf=0.0)
    dq = np.diff(q, axis=0, prepend=q[:1])
    for j in np.flatnonzero(coarse_columns(tau)):
        top = tau[:, j] > tau[:, j].mean()
        for side, sign in ((top, 1.0), (~top, -1.0)):
            at = out[:, j] & side
            if not at.any():
                continue
            v = np.median(sign * tau[at, j])
            with np.errstate(invalid="ignore"):
                beyond = at & (sign * predicted[:, j] > v + half[j])
            out[side, j] &= any(b - a >= CLIP_RUN and dq[a + 1:b, j].any()
                                for a, b in _runs(beyond))
    return out


def model_clipped(q: npt.NDArray[np.float64], tau: npt.NDArray[np.float64],
                  predicted: npt.NDArray[np.float64],
                  spread: npt.NDArray[np.float64]) -> npt.NDArray[np.bool_]:
    """The samples at which a joint's torque is clipped, found against a fitted model.

    On a torque quantised to a few levels a shallow clip and an honest peak both hold the
    extreme level over runs of samples (:func:`clipped_samples` cannot tell them apart); the
    model tells them apart: an honest torque at the level v lies within q_0 / 2 of it (q_0 its
    quantum), and so does the model's, while under a clip the model's torque goes on beyond.
    Per joint of fewer than :data:`CLIP_COARSE` levels and per extreme, a run of samples at the
    extreme level (:func:`extreme_samples`) is clipped when it holds :data:`CLIP_RUN` samples
    in a row, during which the joint's position changes, at which the predicted torque lies
    beyond v by more than q_0 / 2 + :data:`CLIP_SIGMAS` x the joint's residual standard
    deviation.

    Parameters
    ----------
    q : ndarray, shape (N, n)
        Positions [rad or m], sorted by time.
    tau : ndarray, shape (N, n)
        Recorded torques [N m or N].
    predicted : ndarray, shape (N, n)
        The fitted model's torque at the same samples [N m or N], from a fit without the
        extreme samples; NaN where not predicted (never clipped).
    spread : ndarray, shape (n,)
        The fit's residual standard deviation per joint [N m or N].

    Returns
    -------
    ndarray of bool, shape (N, n)
        True at the samples of the clipped runs.

    Examples
    --------
    >>> t = np.linspace(0, 4, 400)
    >>> tau = np.round(5 * np.sin(3 * t)) / 5
    >>> clip = np.clip(tau, -0.8, 0.8)[:, None]
    >>> model_clipped(t[:, None], clip, np.sin(3 * t)[:, None], np.array([0.02]))[:, 0].any()
    np.True_
    >>> model_clipped(t[:, None], tau[:, None], np.sin(3 * t)[:, None], np.array([0.02])).any()
    np.False_
    """
    out = np.zeros(tau.shape, bool)
    half = 0.5 * np.nan_to_num(_resolution(tau)[0].min(axis=0, initial=np.inf), posinf=0.0)
    dq = np.diff(q, axis=0, prepend=q[:1])
    for x, y in ((tau, predicted), (-tau, -predicted)):
        v = x.max(axis=0)
        at = (x > v - half) & extreme_samples(tau)
        beyond = at & (y > v + half + CLIP_SIGMAS * np.asarray(spread, float))
        for j in range(tau.shape[1]):
            hits = [a for a, b in _runs(beyond[:, j]) if b - a >= CLIP_RUN and dq[a + 1:b, j].any()]
            for a, b in _runs(at[:, j]):
                out[a:b, j] |= any(a <= c < b for c in hits)
    return out
