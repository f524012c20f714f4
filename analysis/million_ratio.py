"""The main job on a long PUMA 560 trajectory against a Pinocchio loop, interleaved.

    python analysis/million_ratio.py [--setpoints N] [--runs R]

Plans the default PUMA 560 motion with N set points (default 1,000,000) by
`gd-analyze plan puma560 -o FILE --setpoints N`, then times, in interleaved rounds with the same
number of runs on each side (a, b, b, a, ...; default 3 each):

  (a) the main job `python -m gd_analyze.cli puma560 FILE -o OUT --no-report -q`, a fresh
      process per run, as a user runs the console script (reading the CSV, the G-D terms,
      verification, ranking, simplified model, results.h5 and the model files; the same OUT
      each run, as a user runs it again), under a small parent that prints its child's peak
      resident set size (ru_maxrss) and CPU time (user + system, every thread);
  (b) Pinocchio crba + nonLinearEffects + computeGeneralizedGravity in a Python loop over the
      same N states, keeping the results (analysis/benchmark.py's ``pinocchio_loop``), in this
      process (its CPU time by ``time.process_time``).

The job runs with a derivation cache of its own, filled by one untimed warm-up run (the
user's first run of the arm, reported apart as ``first_run_empty_cache_s``): the timed runs
read the explicit model and the region certification from it, as a user's later runs do.

Prints one JSON line: per side the median wall and CPU times [s]; the per-round ratios a / b
of wall time and of CPU time, each as the median with its range [min, max]; the first run's
time [s]; the job's peak RSS per run and the largest [MiB] against the 1 GiB limit; this
process's own peak RSS (the loop's arrays and the trajectory) [MiB]; and the 1-minute load
average before and after every run (its range). Then two lines, ``within_memory_limit: true``
or ``false`` and ``within_ratio_limit: true`` or ``false`` (the median wall ratio against 3).
Exit status 0 when the job's peak RSS stayed under the limit in every run, 1 otherwise (the
time ratio depends on the machine's load; the memory does not). Ratios, not absolute times,
carry over between machines; on a shared machine prefer the CPU-time ratio and the memory.
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

from benchmark import pinocchio_loop  # noqa: E402

#: The job's peak resident set size allowed [MiB].
LIMIT_MIB = 1024
#: The median wall-time ratio allowed.
RATIO_LIMIT = 3.0


def _range(values):
    """Median and [min, max] of a list of numbers."""
    v = np.asarray(values, float)
    return {"median": float(np.median(v)), "min": float(v.min()), "max": float(v.max())}


def run_child(command, env=None):
    """Run ``command`` (in environment ``env``, default this one) under a small parent that
    reports its children's peak RSS and CPU time (the job's alone); returns (wall [s], CPU [s],
    peak RSS [MiB])."""
    wrapper = [sys.executable, "-c", "import resource, subprocess, sys; "
               f"subprocess.run({command!r}, check=True, capture_output=True); "
               "u = resource.getrusage(resource.RUSAGE_CHILDREN); "
               "print(u.ru_maxrss / 1024, u.ru_utime + u.ru_stime)"]
    t0 = time.perf_counter()
    out = subprocess.run(wrapper, check=True, capture_output=True, text=True, env=env).stdout
    wall = time.perf_counter() - t0
    rss, cpu = (float(v) for v in out.split()[-2:])
    return wall, cpu, rss


def main(argv=None):
    """Measure, print one JSON line and the two verdict lines.

    Parameters
    ----------
    argv : list of str, optional
        Command-line arguments.

    Returns
    -------
    int
        0 if the job's peak RSS stayed within :data:`LIMIT_MIB` in every run, else 1.
    """
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--setpoints", type=int, default=1_000_000)
    p.add_argument("--runs", type=int, default=3)
    args = p.parse_args(argv)
    from gd_analyze import load_robot
    from gd_analyze.trajectory.trajectory import read_trajectory

    loads = [os.getloadavg()[0]]
    with tempfile.TemporaryDirectory() as tmp:
        csv = Path(tmp) / "long.csv"
        subprocess.run([sys.executable, "-m", "gd_analyze.cli", "plan", "puma560", "-o",
                        str(csv), "--setpoints", str(args.setpoints)], check=True,
                       capture_output=True)
        robot = load_robot("puma560")
        traj = read_trajectory(csv, robot.n)
        command = [sys.executable, "-m", "gd_analyze.cli", "puma560", str(csv), "-o",
                   str(Path(tmp) / "out"), "--no-report", "-q"]
        def job():             # a small parent per run: the job's own peak RSS and CPU time
            return run_child(command)

        def loop():
            t0, c0 = time.perf_counter(), time.process_time()
            pinocchio_loop(robot, traj.q, traj.qd)
            return time.perf_counter() - t0, time.process_time() - c0

        # warm-up, timed apart: a user's first run of the arm fills an empty derivation cache
        # of our own (explicit model, region certification), numba's cache and byte-code
        os.environ.pop("GD_ANALYZE_NO_CACHE", None)
        os.environ["GD_ANALYZE_CACHE_DIR"] = str(Path(tmp) / "cache")
        first_wall, _, first_rss = job()
        loads.append(os.getloadavg()[0])
        jobs, loops = [], []
        for k in range(args.runs):
            for side in ((job, jobs), (loop, loops))[:: 1 if k % 2 == 0 else -1]:
                side[1].append(side[0]())
                loads.append(os.getloadavg()[0])
    wall = [a[0] / b[0] for a, b in zip(jobs, loops)]
    cpu = [a[1] / b[1] for a, b in zip(jobs, loops)]
    peaks = [a[2] for a in jobs] + [first_rss]
    rss = max(peaks)
    result = {
        "setpoints": args.setpoints, "runs": args.runs,
        "main_job_over_pinocchio_loop_wall": _range(wall),
        "main_job_over_pinocchio_loop_cpu": _range(cpu),
        "main_job_wall_s": _range([a[0] for a in jobs]),
        "main_job_cpu_s": _range([a[1] for a in jobs]),
        "pinocchio_loop_wall_s": _range([b[0] for b in loops]),
        "pinocchio_loop_cpu_s": _range([b[1] for b in loops]),
        "first_run_empty_cache_s": first_wall,
        "main_job_peak_rss_mib": rss, "main_job_peak_rss_each_mib": peaks,
        "this_process_peak_rss_mib": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024,
        "limit_mib": LIMIT_MIB, "ratio_limit": RATIO_LIMIT,
        "load_average_1min": {"min": min(loads), "max": max(loads), "each": loads},
    }
    within = rss <= LIMIT_MIB
    print(json.dumps(result))
    print(f"within_memory_limit: {'true' if within else 'false'}")
    print(f"within_ratio_limit: {'true' if np.median(wall) <= RATIO_LIMIT else 'false'}")
    return 0 if within else 1


if __name__ == "__main__":
    sys.exit(main())
