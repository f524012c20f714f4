"""The excitation trajectory's scaled condition number against random Fourier trajectories.

    python analysis/excitation_conditions.py [--robots puma560,panda,ur5] [--randoms 8]
        [--starts 2] [--maxiter 40]

For each arm, plans the default excitation (``gd-analyze plan ROBOT --excitation``: 5
harmonics, one 10 s period, 2 random starts of SLSQP) and draws R random Fourier trajectories
with the same harmonics and base frequency, each joint scaled to the same limits
(:func:`gd_analyze.io.excitation.random_excitation`, seeds 1000..). Condition numbers of the
column-scaled base regressor with drive columns are taken on 400 samples of a period.

Prints one JSON line per arm: the optimised condition number, the random ones' median, minimum
and maximum, the ratio median / optimised, the planning's wall and CPU time [s], and the load
average before and after (the wall time depends on the machine's load; the CPU time less so).
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import time

import numpy as np


def main(argv=None):
    """Measure and print."""
    from gd_analyze.io.excitation import excitation_condition, plan_excitation, random_excitation
    from gd_analyze.io.robots import load_robot

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--robots", default="puma560,panda,ur5")
    parser.add_argument("--randoms", type=int, default=8)
    parser.add_argument("--starts", type=int, default=2, help="SLSQP random starts")
    parser.add_argument("--maxiter", type=int, default=40, help="SLSQP iterations per start")
    args = parser.parse_args(argv)
    for name in args.robots.split(","):
        robot = load_robot(name)
        load = os.getloadavg()[0]
        wall, cpu = time.perf_counter(), time.process_time()
        ex = plan_excitation(robot, starts=args.starts, maxiter=args.maxiter)
        wall, cpu = time.perf_counter() - wall, time.process_time() - cpu
        ours = excitation_condition(robot, ex.columns, ex.series, samples=400)
        randoms = [excitation_condition(robot, ex.columns, random_excitation(
            robot, ex.series.harmonics, ex.series.wf, 1000 + k), samples=400)
            for k in range(args.randoms)]
        print(json.dumps({
            "robot": name, "joints": robot.n, "columns": ex.columns.count,
            "starts": args.starts, "maxiter": args.maxiter,
            "optimised": round(ours, 3), "random_median": round(float(np.median(randoms)), 3),
            "random_min": round(min(randoms), 3), "random_max": round(max(randoms), 3),
            "ratio_median": round(float(np.median(randoms)) / ours, 2),
            "ratio_min": round(min(randoms) / ours, 2),
            "wall_s": round(wall, 1), "cpu_s": round(cpu, 1),
            "load_before": round(load, 2), "load_after": round(os.getloadavg()[0], 2)}),
            flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
