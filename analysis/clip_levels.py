"""Clipped torques quantised to few levels: the share of the clipped samples that
``clipped_samples`` finds, and its false detections on honest recordings.

Recordings (Pinocchio oracle, tests/identify_recordings.py): the PUMA 560 and the two-link arm,
the true arm (other masses and inertias, friction, offsets), a 25 s finite Fourier series on an
irregular clock (0.7 to 8.8 ms steps). For each joint in turn, its torque clipped at 85 % of
its peak |tau| (a drive's limit), then, optionally, sensor noise of 1 % of each joint's
standard deviation added, then every joint quantised to L levels, L in 10, 12, 14, 17, 20:
an ADC spanning the joint's recorded range [min, max] in L - 1 equal steps (``clipped``:
the range of the clipped torque, so that the limit is the top level; ``wide``: the range of
the torque before the clip, a sensor's range wider than the drive's limit, the limit then
within a step). Per case: the share of the clipped samples (|tau| >= the limit before
quantising) marked on the clipped joint, the joints marked that are not clipped, and the
statistics a count rule on the quantised torque sees (:func:`run_ratios`) at the clipped
extreme: the samples at the extreme level over those one level below, and the largest ratio of
one run at the extreme level to the two stretches one level below on its sides (a smooth,
parabolic peak gives at most 1 / (sqrt 2 - 1) = 2.41 for either).

Honest recordings, with the same levels, noise-free and with the 1 % noise: the torque
unclipped, and the PUMA 560 with 100 x its Coulomb friction (the wrist's torques square
waves of the joints' directions); and the TIAGo recordings shipped in data/tiago as they are:
the joints marked (none expected), and the largest of the same two statistics over their
joints and extremes.

With ``--whole``: what ``gd.identify`` itself leaves out of the fit, the model-free rule and
the check against the fitted model together (the clip mask it hands to the preprocessing of
each training recording, read by wrapping ``preprocess``; the run stopped before its final
fit), on the PUMA 560 and two-link recordings for levels below 20 (where the model judges): per
clipped case the share of the clipped samples left out and the other joints marked, and on
honest recordings (the torque unclipped over its own range and over an ADC 2, 5 or 10 times as
wide, centred, so that few levels are used; with and without the 1 % noise) the joints marked
with the share of their samples.

With ``--identify``: the consequence for identification. ``gd.identify`` (``consistent``
off) on the PUMA 560 and two-link recordings quantised to each level, unclipped and with each
joint in turn clipped (clipped range), validated on a 10 s noise-free held-out recording: its
total relative error, with the found share beside it.

Usage (the package on ``PYTHONPATH``: this checkout's ``src`` or another's)::

    PYTHONPATH=src python analysis/clip_levels.py [--levels 10,12,14,17,20] [--identify | --whole]
"""

from __future__ import annotations

import argparse
import pathlib
import sys
import time

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "tests"))

from identify_recordings import fourier, irregular_clock, truth_for  # noqa: E402

from gd_analyze import load_robot  # noqa: E402
from gd_analyze.estimation.preprocess import clipped_samples  # noqa: E402
from gd_analyze.trajectory.trajectory import read_recording  # noqa: E402

ARMS = ("puma560", "two-link")


def recording(name: str, friction: float = 1.0) -> tuple[np.ndarray, np.ndarray]:
    """q and Pinocchio's torque of a true arm along a 25 s Fourier series, shape (N, n) each."""
    robot = load_robot(name)
    truth = truth_for(robot, seed=4)
    truth.coulomb = truth.coulomb * friction
    t = irregular_clock(25, 2)
    q, qd, qdd = fourier(robot.n, t, seed=2)
    return q, truth.torque(q, qd, qdd)


def quantised(x: np.ndarray, levels: int, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    """x, shape (N, n), rounded to ``levels`` values per column spanning [lo, hi]."""
    step = (hi - lo) / (levels - 1)
    return lo + np.clip(np.round((x - lo) / step), 0, levels - 1) * step


def clipped_cases(tau: np.ndarray, noise: np.ndarray, levels: int):
    """Per ADC range (``clipped``, ``wide``) and noise (off, on): (kind, noisy, cases), each
    case (j, limit, y): joint j's torque clipped at ``limit`` (85 % of its peak |tau|), the
    noise added if on, every joint quantised to ``levels`` levels."""
    for kind in ("clipped", "wide"):
        for noisy in (False, True):
            cases = []
            for j in range(tau.shape[1]):
                limit = 0.85 * np.abs(tau[:, j]).max()
                x = tau.copy()
                x[:, j] = np.clip(tau[:, j], -limit, limit)
                x = x + noise if noisy else x
                span = x if kind == "clipped" else tau
                cases.append((j, limit, quantised(x, levels, span.min(axis=0), span.max(axis=0))))
            yield kind, noisy, cases


def run_ratios(x: np.ndarray) -> tuple[float, float]:
    """For a quantised torque x, shape (N,), its running median over 5 samples (as
    ``clipped_samples`` damps noise) at its largest level: the samples there over those one level
    below, and the largest of a run's samples there over the samples one level below just before
    and after it (runs entered and left through that level only)."""
    from scipy import ndimage

    x = ndimage.median_filter(x, 5, mode="nearest")
    values = np.unique(x)
    top, below = x == values[-1], x == values[-2]
    edges = np.flatnonzero(np.diff(np.concatenate([[0], top.view(np.int8), [0]])))
    best = 0.0
    for a, b in zip(edges[::2], edges[1::2]):
        left = a - np.argmin(np.concatenate([below[a - 1::-1], [False]])) if a else a
        right = np.argmin(np.concatenate([below[b:], [False]]))
        if left < a and right:
            best = max(best, (b - a) / (a - left + right))
    return float(top.sum() / max(below.sum(), 1)), best


def consequence(levels: list[int]) -> None:
    """Held-out error of the identification from clipped quantised recordings (``--identify``)."""
    import warnings

    from identify_recordings import truth_for as truth_of

    from gd_analyze.jobs.identify import IdentifyOptions, identify
    from gd_analyze.trajectory.trajectory import recording_from_arrays

    warnings.simplefilter("ignore")
    for name in ARMS:
        robot = load_robot(name)
        truth = truth_of(robot, seed=4)
        th = irregular_clock(10, 5)
        qh, qdh, qddh = fourier(robot.n, th, seed=5)
        held = recording_from_arrays(th, qh, truth.torque(qh, qdh, qddh), source="held")
        q, tau = recording(name)
        t = irregular_clock(25, 2)

        def error(x):
            try:
                res = identify(robot, [recording_from_arrays(t, q, x, source="rec")],
                               validate=[held], options=IdentifyOptions(consistent=False))
            except Exception as exc:           # a failed fit is a result here
                return f"failed ({str(exc)[:60]}...)"
            return f"{res.recordings[1].errors()[2]:.4f}"
        for L in levels:
            cells = []
            for j in range(robot.n):
                limit = 0.85 * np.abs(tau[:, j]).max()
                x = tau.copy()
                x[:, j] = np.clip(tau[:, j], -limit, limit)
                y = quantised(x, L, x.min(axis=0), x.max(axis=0))
                found = clipped_samples(q, y)[np.abs(tau[:, j]) >= limit, j].mean()
                cells.append(f"joint {j + 1} {error(y)} (found {found:.0%})")
            plain = error(quantised(tau, L, tau.min(axis=0), tau.max(axis=0)))
            print(f"identify {name} L={L}: unclipped {plain}; clipped " + "; ".join(cells),
                  flush=True)


#: One entry per first fit of the model's check that failed (``--whole``).
SKIPPED: list = []


class _Stop(Exception):
    """Raised in place of identify's final fit (``--whole``): the clip masks are known."""


def left_out(robot, t: np.ndarray, q: np.ndarray, tau: np.ndarray) -> np.ndarray:
    """The clip mask, shape (N, n), that ``gd.identify`` (``consistent`` off) hands to the
    preprocessing of the training recording its final fit takes (the fit called with 4
    positional arguments, not run): the model-free rule's and the fitted model's samples."""
    import warnings

    import gd_analyze.jobs.identify as job
    from gd_analyze.trajectory.trajectory import recording_from_arrays

    masks, preprocess, fit_robot = {}, job.prep.preprocess, job.fit_robot
    fit_columns = getattr(job, "fit_columns", None)         # None in the code before
    final = []

    def recorded(*args, **kwargs):
        out = preprocess(*args, **kwargs)
        masks[id(out)] = (out, kwargs.get("clipped"))
        return out

    def first(fit):
        def fitted(*args, **kwargs):
            try:
                return fit(*args, **kwargs)
            except Exception:               # the model's check skipped
                SKIPPED.append(1)
                raise
        return fitted

    def stopped(*args, **kwargs):
        if len(args) >= 4:                  # the final fit: fit_robot(prior, pres, drives, c)
            final.append(masks[id(args[1][0])][1])
            raise _Stop
        return first(fit_robot)(*args, **kwargs)
    job.prep.preprocess, job.fit_robot = recorded, stopped
    if fit_columns is not None:
        job.fit_columns = first(fit_columns)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            job.identify(robot, [recording_from_arrays(t, q, tau, source="rec")],
                         options=job.IdentifyOptions(consistent=False))
    except _Stop:
        pass
    finally:
        job.prep.preprocess, job.fit_robot = preprocess, fit_robot
        if fit_columns is not None:
            job.fit_columns = fit_columns
    return np.zeros(tau.shape, bool) if final[0] is None else np.asarray(final[0], bool)


def whole(levels: list[int]) -> None:
    """``--whole``: the clips identify leaves out, the rule's and the model's together."""
    import gd_analyze.jobs.identify as job
    print(f"# identify from {pathlib.Path(job.__file__).resolve()}")
    t = irregular_clock(25, 2)
    for name in ARMS:
        robot = load_robot(name)
        q, tau = recording(name)
        noise = 0.01 * tau.std(axis=0) * np.random.default_rng(3).normal(size=tau.shape)
        n = tau.shape[1]
        for L in [v for v in levels if v < 20]:
            for kind, noisy, cases in clipped_cases(tau, noise, L):
                shares, wrong, skips = [], [], len(SKIPPED)
                for j, limit, y in cases:
                    mask = left_out(robot, t, q, y)
                    shares.append(float(mask[np.abs(tau[:, j]) >= limit, j].mean()))
                    wrong += [k + 1 for k in range(n) if k != j and mask[:, k].any()]
                print(f"{name:9s} L={L:2d} {kind:7s} {'noise' if noisy else 'clean'}: "
                      f"left out {' '.join(f'{s:4.0%}' for s in shares)} "
                      f"(min {min(shares):.0%}); other joints marked {wrong}; model's check "
                      f"skipped (first fit failed) {len(SKIPPED) - skips} of {n}", flush=True)
        for noisy in (False, True):
            x = tau + noise if noisy else tau
            for L in levels:
                for wide in (1, 2, 5, 10):
                    mid, half = 0.5 * (x.max(axis=0) + x.min(axis=0)), 0.5 * wide * np.ptp(x, axis=0)
                    y = quantised(x, L, mid - half, mid + half)
                    skips = len(SKIPPED)
                    mask = left_out(robot, t, q, y)
                    used = [len(np.unique(c)) for c in y.T]
                    print(f"honest {name} {'noise' if noisy else 'clean'} L={L} ADC x{wide} "
                          f"(levels used {used}): marked "
                          + (", ".join(f"joint {k + 1} {mask[:, k].mean():.1%}"
                                       for k in np.flatnonzero(mask.any(axis=0))) or "none")
                          + ("; model's check skipped" if len(SKIPPED) > skips else ""), flush=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--levels", default="10,12,14,17,20")
    parser.add_argument("--identify", action="store_true")
    parser.add_argument("--whole", action="store_true")
    args = parser.parse_args()
    levels = [int(v) for v in args.levels.split(",")]
    if args.whole:
        whole(levels)
        return
    if args.identify:
        consequence(levels)
        return
    import gd_analyze.estimation.preprocess as prep
    print(f"# clipped_samples from {pathlib.Path(prep.__file__).resolve()}")
    timings = []
    for name in ARMS:
        q, tau = recording(name)
        noise = 0.01 * tau.std(axis=0) * np.random.default_rng(3).normal(size=tau.shape)
        n = tau.shape[1]
        for L in levels:
            for kind, noisy, cases in clipped_cases(tau, noise, L):
                shares, wrong, stats = [], [], []
                for j, limit, y in cases:
                    start = time.perf_counter()
                    mask = clipped_samples(q, y)
                    timings.append(time.perf_counter() - start)
                    beyond = np.abs(tau[:, j]) >= limit
                    shares.append(float(mask[beyond, j].mean()))
                    side = 1 if tau[:, j].max() > -tau[:, j].min() else -1
                    stats.append(run_ratios(side * y[:, j]))
                    wrong += [k + 1 for k in range(n) if k != j and mask[:, k].any()]
                print(f"{name:9s} L={L:2d} {kind:7s} {'noise' if noisy else 'clean'}: "
                      f"found {' '.join(f'{s:4.0%}' for s in shares)} (min {min(shares):.0%})"
                      f"; other joints marked {len(wrong)}; ratios "
                      + " ".join(f"{a:.1f}/{b:.1f}" for a, b in stats))
    for name, friction in (("puma560", 1.0), ("two-link", 1.0), ("puma560", 100.0)):
        q, tau = recording(name, friction)
        noise = 0.01 * tau.std(axis=0) * np.random.default_rng(5).normal(size=tau.shape)
        for noisy in (False, True):
            x = tau + noise if noisy else tau
            marked = {L: np.flatnonzero(clipped_samples(
                q, quantised(x, L, x.min(axis=0), x.max(axis=0))).any(axis=0)) + 1
                for L in levels}
            marked["raw"] = np.flatnonzero(clipped_samples(q, x).any(axis=0)) + 1
            largest = []
            for L in levels:
                y = quantised(x, L, x.min(axis=0), x.max(axis=0))
                both = [run_ratios(s * y[:, j]) for j in range(x.shape[1]) for s in (1, -1)]
                largest.append((max(a for a, _ in both), max(b for _, b in both)))
            print(f"honest {name} friction x{friction:g} {'noise' if noisy else 'clean'}: "
                  "joints marked " + "; ".join(f"{k}: {v.tolist()}" for k, v in marked.items())
                  + "; largest ratios " + " ".join(f"L={L} {a:.1f}/{b:.1f}"
                                                   for L, (a, b) in zip(levels, largest)))
    for path in sorted((ROOT / "data" / "tiago").glob("*.csv")):
        rec = read_recording(path)
        start = time.perf_counter()
        mask = clipped_samples(rec.q, rec.tau)
        timings.append(time.perf_counter() - start)
        print(f"TIAGo {path.name}: joints marked {(np.flatnonzero(mask.any(axis=0)) + 1).tolist()}")
    print(f"clipped_samples per call: median {np.median(timings) * 1e3:.1f} ms "
          f"[{min(timings) * 1e3:.1f}, {max(timings) * 1e3:.1f}] over {len(timings)} calls")


if __name__ == "__main__":
    main()
