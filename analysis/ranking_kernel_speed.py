"""The ranking kernel alone, before and after a change, on 10^6 set points.

    PYTHONPATH=src python analysis/ranking_kernel_speed.py [--before REV] [--robot puma560]
                                                          [--setpoints 1000000] [--rounds 9]

Times :func:`gd_analyze.ranking.kernels.ranking_kernel` of this checkout ("after") against
the same kernel of git revision REV ("before": its ``src/gd_analyze/ranking/kernels.py``,
imported from a temporary copy; any of the kernel's three layouts: the running sums and peaks
as arrays of their own, one statistics array, or the statistics of a chunk's segments). Both are fed the same G-D terms and torques of N random
set points of the robot (made ahead, chunk by chunk), in the main job's chunks of
``STREAM_CHUNK`` rows, each kernel compiled (or loaded from numba's cache) before the rounds.
The rounds are interleaved (before, after, after, before, ...); prints one JSON line: each
side's median time [s] with its [min, max], the per-round ratio after / before (median
[min, max]), the ratio of the fastest rounds (the least disturbed by other processes on a
loaded machine) and the 1-minute load average at the start and the end.
"""

from __future__ import annotations

import argparse
import importlib.util
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
KERNELS = "src/gd_analyze/ranking/kernels.py"


def _range(values):
    v = np.asarray(values, float)
    return {"median": float(np.median(v)), "min": float(v.min()), "max": float(v.max())}


def load_before(rev, folder):
    """The kernels module of git revision ``rev``, imported from a copy in ``folder``."""
    text = subprocess.run(["git", "-C", str(ROOT), "show", f"{rev}:{KERNELS}"], check=True,
                          capture_output=True, text=True).stdout
    path = Path(folder) / "ranking_kernels_before.py"
    path.write_text(text)
    # named inside the package: its relative imports (the statistics' rows) resolve there
    spec = importlib.util.spec_from_file_location("gd_analyze.ranking.ranking_kernels_before",
                                                  path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def inputs(robot, N, chunk, seed=0):
    """The chunks' (D_tran, D_rot, h_tran, h_rot, tau) of N random set points, and the
    armature (zeros without drives)."""
    from gd_analyze import gd_terms

    rng = np.random.default_rng(seed)
    lo, hi = np.asarray(robot.q_min, float), np.asarray(robot.q_max, float)
    lo, hi = np.where(np.isfinite(lo), lo, -np.pi), np.where(np.isfinite(hi), hi, np.pi)
    chunks, armature = [], np.zeros(robot.n)
    for a in range(0, N, chunk):
        b = min(a + chunk, N)
        q = rng.uniform(lo, hi, (b - a, robot.n))
        qd = rng.uniform(-2.0, 2.0, (b - a, robot.n))
        qdd = rng.uniform(-5.0, 5.0, (b - a, robot.n))
        t = gd_terms(robot, q, qd)
        c = np.ascontiguousarray
        chunks.append((c(t.D_tran), c(t.D_rot), c(t.h_tran), c(t.h_rot), c(t.tau(qdd))))
        if t.armature is not None:
            armature = np.asarray(t.armature, float)
    return chunks, armature


def runner(kernels, n, armature):
    """call(chunks) -> None: a fresh accumulator's arrays fed every chunk by ``kernels``, in
    the layout its ``ranking_kernel`` takes (told by its number of arguments): five running
    sums and peaks of their own (14), one statistics array (10), or the statistics of the
    chunk's segments, here one segment per chunk (11)."""
    from gd_analyze.ranking.statistics import ROWS

    m = n * (n + 1) // 2 + n
    iu = np.triu_indices(n)
    arm = np.zeros(m)
    arm[:iu[0].size] = np.where(iu[0] == iu[1], armature[iu[0]], 0.0)
    arguments = kernels.ranking_kernel.py_func.__code__.co_argcount

    def call(chunks):
        scale_D, peak_tau = np.zeros(iu[0].size), np.zeros(n)
        if arguments == 14:
            sums_peaks = [np.zeros(m) for _ in range(5)]
            for ch in chunks:
                kernels.ranking_kernel(*ch, arm, armature, *sums_peaks, scale_D, peak_tau)
        elif arguments == 10:
            stats = np.zeros((len(ROWS), m))
            for ch in chunks:
                kernels.ranking_kernel(*ch, arm, armature, stats, scale_D, peak_tau)
        else:
            stats = np.zeros((1, len(ROWS), m))
            for ch in chunks:
                bounds = np.array([0, ch[2].shape[0]], np.int64)
                kernels.ranking_kernel(*ch, arm, armature, bounds, stats, scale_D[None],
                                       peak_tau[None])
    return call


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--before", default="ca03a5d",
                        help="git revision of the kernel before the change")
    parser.add_argument("--robot", default="puma560")
    parser.add_argument("--setpoints", type=int, default=1_000_000)
    parser.add_argument("--rounds", type=int, default=9)
    args = parser.parse_args(argv)

    from gd_analyze import load_robot
    from gd_analyze.jobs.analyze import STREAM_CHUNK
    from gd_analyze.ranking import kernels as after

    robot = load_robot(args.robot)
    chunks, armature = inputs(robot, args.setpoints, STREAM_CHUNK)
    with tempfile.TemporaryDirectory() as folder:
        before = load_before(args.before, folder)
        calls = {"before": runner(before, robot.n, armature),
                 "after": runner(after, robot.n, armature)}
        for call in calls.values():             # compile or load, outside the rounds
            call(chunks[:1])
        load = [os.getloadavg()[0]]
        times = {"before": [], "after": []}
        for k in range(args.rounds):
            for side in (("before", "after") if k % 2 == 0 else ("after", "before")):
                t0 = time.perf_counter()
                calls[side](chunks)
                times[side].append(time.perf_counter() - t0)
        load.append(os.getloadavg()[0])
    ratio = np.asarray(times["after"]) / np.asarray(times["before"])
    print(json.dumps({"robot": robot.name, "setpoints": args.setpoints,
                      "chunk": STREAM_CHUNK, "rounds": args.rounds, "before_rev": args.before,
                      "before_s": _range(times["before"]), "after_s": _range(times["after"]),
                      "after_over_before": _range(ratio),
                      "fastest_after_over_fastest_before":
                          min(times["after"]) / min(times["before"]),
                      "load_1min": load}))
    return 0


if __name__ == "__main__":
    sys.exit(main())
