"""A sweep of K random PUMA 560 trajectories against a Pinocchio loop over the same states,
interleaved.

    python analysis/sweep_ratio.py [-k 1000] [--runs R] [--workers W] [--baseline SRC]

Times, in interleaved rounds with the same number of runs on each side (a, b, b, a, ...;
default 3 each):

  (a) the sweep `python -m gd_analyze.cli sweep puma560 --random K -o OUT --no-report -q
      [--workers W]`, a fresh process per run as a user runs the console script (planning,
      the dask LocalCluster, the ranking of every trajectory on it, the merged model of the
      budget rule with its region guarantee and its check on every swept and held-out
      trajectory, sweep.h5 and the model files), under a small parent that prints its
      children's peak resident set size (ru_maxrss) and CPU time (user + system);
  (b) Pinocchio crba + nonLinearEffects + computeGeneralizedGravity in a Python loop over the
      same states (the K swept trajectories and the held-out ones, planned here with the
      sweep's own seeds; analysis/benchmark.py's ``pinocchio_loop``), in this process.

The sweep runs with a derivation cache of its own, filled by one untimed warm-up run (reported
apart), as a user's later runs do, with Python's default settings (a ``PYTHONDONTWRITEBYTECODE``
in the caller's environment is dropped, so that the warm-up leaves gd_analyze's byte-code as a
user's first run does). ``--baseline SRC`` also times another checkout's sweep (its ``src``
folder first on ``PYTHONPATH``, its own warm-up) in the same rounds, against the same loop,
the order of the sides rotated each round.

Prints one JSON line: per side the median wall and CPU times [s], the per-round ratios a / b
of wall and CPU time (median and [min, max]), the sweep's peak RSS per run [MiB], and the
1-minute load average before and after every run. Then ``within_ratio_limit: true`` or
``false`` (the median wall ratio against 8).
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

from benchmark import pinocchio_loop  # noqa: E402
from million_ratio import _range, run_child  # noqa: E402

#: The median wall-time ratio allowed.
RATIO_LIMIT = 8.0
#: The sweep's default held-out trajectories and their seed offset (cli/sweep_command.py).
HELD_OUT, HELD_OUT_SEED = 20, 1_000_003


def main(argv=None):
    """Measure and print one JSON line and the verdict line.

    Parameters
    ----------
    argv : list of str, optional
        Command-line arguments.

    Returns
    -------
    int
        0.
    """
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("-k", type=int, default=1000, help="swept trajectories")
    p.add_argument("--runs", type=int, default=3)
    p.add_argument("--workers", type=int, default=None, help="LocalCluster workers")
    p.add_argument("--baseline", metavar="SRC", default=None,
                   help="another checkout's src folder, timed in the same rounds")
    args = p.parse_args(argv)
    from gd_analyze import load_robot
    from gd_analyze.trajectory.planning import random_trajectories

    robot = load_robot("puma560")
    states = random_trajectories(robot, args.k, seed=0) + \
        random_trajectories(robot, HELD_OUT, seed=HELD_OUT_SEED)
    q = np.concatenate([t.q for t in states])
    qd = np.concatenate([t.qd for t in states])
    loads = [os.getloadavg()[0]]
    with tempfile.TemporaryDirectory() as tmp:
        command = [sys.executable, "-m", "gd_analyze.cli", "sweep", "puma560", "--random",
                   str(args.k), "-o", str(Path(tmp) / "out"), "--no-report", "-q"]
        if args.workers:
            command += ["--workers", str(args.workers)]

        env = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}
        env.pop("GD_ANALYZE_NO_CACHE", None)
        env["GD_ANALYZE_CACHE_DIR"] = str(Path(tmp) / "cache")

        def job(src=None):
            return run_child(command, env if src is None else {**env, "PYTHONPATH": os.pathsep.join(
                [str(Path(src).resolve())] + [v for v in [env.get("PYTHONPATH")] if v])})

        def loop():
            t0, c0 = time.perf_counter(), time.process_time()
            pinocchio_loop(robot, q, qd)
            return time.perf_counter() - t0, time.process_time() - c0

        first_wall, _, first_rss = job()
        loads.append(os.getloadavg()[0])
        jobs, loops, bases = [], [], []
        sides = [(job, jobs), (loop, loops)]
        if args.baseline:
            job(args.baseline)                  # its own warm-up: its code, its cache keys
            loads.append(os.getloadavg()[0])
            sides.append((lambda: job(args.baseline), bases))
        for k in range(args.runs):
            for side in sides[k % len(sides):] + sides[:k % len(sides)]:
                side[1].append(side[0]())
                loads.append(os.getloadavg()[0])
    wall = [a[0] / b[0] for a, b in zip(jobs, loops)]
    cpu = [a[1] / b[1] for a, b in zip(jobs, loops)]
    result = {
        "trajectories": args.k, "held_out": HELD_OUT, "states": int(q.shape[0]),
        "runs": args.runs, "workers": args.workers or os.cpu_count(),
        "sweep_over_pinocchio_loop_wall": _range(wall),
        "sweep_over_pinocchio_loop_cpu": _range(cpu),
        "sweep_wall_s": _range([a[0] for a in jobs]),
        "sweep_cpu_s": _range([a[1] for a in jobs]),
        "pinocchio_loop_wall_s": _range([b[0] for b in loops]),
        "pinocchio_loop_cpu_s": _range([b[1] for b in loops]),
        "first_run_empty_cache_s": first_wall,
        "sweep_peak_rss_mib": max([a[2] for a in jobs] + [first_rss]),
        "ratio_limit": RATIO_LIMIT,
        "load_average_1min": {"min": min(loads), "max": max(loads), "each": loads},
    }
    if args.baseline:
        result.update({
            "baseline_src": str(Path(args.baseline).resolve()),
            "baseline_over_pinocchio_loop_wall": _range([a[0] / b[0]
                                                         for a, b in zip(bases, loops)]),
            "baseline_over_pinocchio_loop_cpu": _range([a[1] / b[1]
                                                        for a, b in zip(bases, loops)]),
            "baseline_wall_s": _range([a[0] for a in bases]),
            "sweep_over_baseline_wall": _range([a[0] / b[0] for a, b in zip(jobs, bases)])})
    print(json.dumps(result))
    print(f"within_ratio_limit: {'true' if np.median(wall) <= RATIO_LIMIT else 'false'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
