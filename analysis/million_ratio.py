"""The main job on a long PUMA 560 trajectory against a Pinocchio loop, interleaved.

    python analysis/million_ratio.py [--setpoints N] [--runs R]

Plans the default PUMA 560 motion with N set points (default 1,000,000) by
`gd-analyze plan puma560 -o FILE --setpoints N`, then times, in interleaved rounds with the same
number of runs on each side (analysis/benchmark.py's ``interleaved``, default 3):

  (a) the main job `python -m gd_analyze.cli puma560 FILE -o OUT --no-report -q`, a fresh
      process per run, as a user runs the console script (reading the CSV, the G-D terms,
      verification, ranking, simplified model, results.h5 and the model files), under a small
      parent that prints its child's peak resident set size (ru_maxrss);
  (b) Pinocchio crba + nonLinearEffects + computeGeneralizedGravity in a Python loop over the
      same N states, keeping the results (analysis/benchmark.py's ``pinocchio_loop``).

The job runs with a derivation cache of its own, filled by one untimed warm-up run (the
user's first run of the arm, reported apart as ``first_run_empty_cache_s``): the timed runs
read the explicit model and the region certification from it, as a user's later runs do.

Prints one JSON line: the median of the per-pair ratios a / b with its range [min, max], the
medians of each side [s], the first run's time [s], the largest peak RSS of (a) [MiB] against the 1 GiB limit, and the
load average before and after. Ratios, not absolute times, carry over between machines.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from benchmark import _summary, interleaved, pinocchio_loop  # noqa: E402


def main(argv=None):
    """Measure and print one JSON line.

    Parameters
    ----------
    argv : list of str, optional
        Command-line arguments.
    """
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--setpoints", type=int, default=1_000_000)
    p.add_argument("--runs", type=int, default=3)
    args = p.parse_args(argv)
    from gd_analyze import load_robot
    from gd_analyze.io.trajectory import read_trajectory

    load = [os.getloadavg()[0]]
    with tempfile.TemporaryDirectory() as tmp:
        csv = Path(tmp) / "long.csv"
        subprocess.run([sys.executable, "-m", "gd_analyze.cli", "plan", "puma560", "-o",
                        str(csv), "--setpoints", str(args.setpoints)], check=True,
                       capture_output=True)
        robot = load_robot("puma560")
        traj = read_trajectory(csv, robot.n)
        command = [sys.executable, "-m", "gd_analyze.cli", "puma560", str(csv), "-o",
                   str(Path(tmp) / "out"), "--no-report", "-q"]
        # a small parent per run: its children's peak RSS is the job's alone
        wrapper = [sys.executable, "-c", "import resource, subprocess, sys; "
                   f"subprocess.run({command!r}, check=True, capture_output=True); "
                   "print(resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 1024)"]
        peaks = []

        def job():
            out = subprocess.run(wrapper, check=True, capture_output=True, text=True).stdout
            peaks.append(float(out.split()[-1]))

        # warm-up, timed apart: a user's first run of the arm fills an empty derivation cache
        # of our own (explicit model, region certification), numba's cache and byte-code
        os.environ.pop("GD_ANALYZE_NO_CACHE", None)
        os.environ["GD_ANALYZE_CACHE_DIR"] = str(Path(tmp) / "cache")
        t0 = time.perf_counter()
        job()
        first = time.perf_counter() - t0
        r = interleaved(job, lambda: pinocchio_loop(robot, traj.q, traj.qd), args.runs)
    load.append(os.getloadavg()[0])
    rss = max(peaks)
    print(json.dumps({"setpoints": args.setpoints, "main_job_over_pinocchio_loop": _summary(r),
                      "first_run_empty_cache_s": first, "main_job_peak_rss_mib": rss, "limit_mib": 1024,
                      "within_memory_limit": rss <= 1024,
                      "load_average_before_after": load}))
    return 0


if __name__ == "__main__":
    sys.exit(main())
