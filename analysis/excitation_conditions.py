"""The excitation trajectory's scaled condition number against random Fourier trajectories.

    python analysis/excitation_conditions.py [--robots puma560,panda,ur5] [--randoms 8]
        [--starts 2] [--maxiter 40] [--durations 10] [--harmonics 5] [--diagnose]

For each arm, plans the default excitation (``gd-analyze plan ROBOT --excitation``: 5
harmonics, one 10 s period, 2 random starts of SLSQP) and draws R random Fourier trajectories
with the same harmonics and base frequency, each joint scaled to the same limits
(:func:`gd_analyze.trajectory.excitation.random_excitation`, seeds 1000..). Condition numbers of the
column-scaled base regressor with drive columns are taken on 400 samples of a period.

``--durations`` and ``--harmonics`` take comma-separated lists: every arm is planned for each
pair (T one period of w_f = 2 pi / T), and the random trajectories drawn with the same harmonics
and w_f, so that the ratio can be read against the timing and the number of harmonics.

Prints one JSON line per arm and pair: the optimised condition number, the random ones' median, minimum
and maximum, the ratio median / optimised, the planning's wall and CPU time [s], and the load
average before and after (the wall time depends on the machine's load; the CPU time less so).
With ``--diagnose``, also each joint's mean |qd| / rms qd (the correlation of its viscous and
Coulomb columns), the columns with the largest weights in the singular vectors of the
largest and smallest singular values of the optimised trajectory's scaled regressor, and the
condition number after leaving out, one by one, the 8 columns whose removal lowers it most
(how far the spectrum is spread over the columns).
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
    from gd_analyze.model.robots import load_robot
    from gd_analyze.trajectory.excitation import (
        excitation_condition,
        plan_excitation,
        random_excitation,
    )

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--robots", default="puma560,panda,ur5")
    parser.add_argument("--randoms", type=int, default=8)
    parser.add_argument("--starts", type=int, default=2, help="SLSQP random starts")
    parser.add_argument("--maxiter", type=int, default=40, help="SLSQP iterations per start")
    parser.add_argument("--durations", default="10",
                        help="comma-separated excitation periods T [s]")
    parser.add_argument("--harmonics", default="5", help="comma-separated harmonics K")
    parser.add_argument("--diagnose", action="store_true",
                        help="print the Coulomb correlations and extreme singular vectors")
    args = parser.parse_args(argv)
    for name in args.robots.split(","):
        robot = load_robot(name)
        for T in (float(v) for v in args.durations.split(",")):
            for K in (int(v) for v in args.harmonics.split(",")):
                ex = _measure(args, name, robot, T, K, excitation_condition, plan_excitation,
                              random_excitation)
                if args.diagnose:
                    print(json.dumps({"robot": name, **_diagnosis(robot, ex)}), flush=True)
    return 0


def _measure(args, name, robot, T, K, excitation_condition, plan_excitation, random_excitation):
    """Plan one excitation, draw the random ones, print one JSON line; the excitation."""
    load = os.getloadavg()[0]
    wall, cpu = time.perf_counter(), time.process_time()
    ex = plan_excitation(robot, duration=T, harmonics=K, starts=args.starts,
                         maxiter=args.maxiter)
    wall, cpu = time.perf_counter() - wall, time.process_time() - cpu
    ours = excitation_condition(robot, ex.columns, ex.series, samples=400)
    randoms = [excitation_condition(robot, ex.columns, random_excitation(
        robot, ex.series.harmonics, ex.series.wf, 1000 + k), samples=400)
        for k in range(args.randoms)]
    print(json.dumps({
        "robot": name, "joints": robot.n, "columns": ex.columns.count,
        "duration_s": T, "harmonics": K, "starts": args.starts, "maxiter": args.maxiter,
        "optimised": round(ours, 3), "random_median": round(float(np.median(randoms)), 3),
        "random_min": round(min(randoms), 3), "random_max": round(max(randoms), 3),
        "ratio_median": round(float(np.median(randoms)) / ours, 2),
        "ratio_min": round(min(randoms) / ours, 2),
        "wall_s": round(wall, 1), "cpu_s": round(cpu, 1),
        "load_before": round(load, 2), "load_after": round(os.getloadavg()[0], 2)}),
        flush=True)
    return ex


def _diagnosis(robot, ex, samples=400, weights=5):
    """mean |qd| / rms qd per joint, and the heaviest columns of the extreme singular vectors."""
    from gd_analyze.symbolic.drive_regressor import identification_regressor

    t = (np.arange(samples) + 0.5) * (ex.series.period / samples)
    q, qd, qdd = ex.series.evaluate(t)
    Y = identification_regressor(robot, q, qd, qdd, ex.columns).reshape(-1, ex.columns.count)
    _, s, Vt = np.linalg.svd(Y / np.linalg.norm(Y, axis=0), full_matrices=False)
    names = ex.columns.names()

    def heaviest(v):
        return {names[i]: round(float(v[i]), 2) for i in np.argsort(-np.abs(v))[:weights]}

    def cond(cols):
        sv = np.linalg.svd(Ws[:, cols], compute_uv=False)
        return float(sv[0] / sv[-1])

    Ws = Y / np.linalg.norm(Y, axis=0)
    kept, left_out = list(range(len(names))), []
    for _ in range(8):      # the columns whose removal lowers the condition number most
        worst = min(kept, key=lambda i: cond([c for c in kept if c != i]))
        kept.remove(worst)
        left_out.append([names[worst], round(cond(kept), 3)])
    return {"left_out_one_by_one": left_out,
            "mean_abs_qd_over_rms": np.round(np.abs(qd).mean(0)
                                             / np.sqrt((qd ** 2).mean(0)), 3).tolist(),
            "sigma_max": round(float(s[0]), 3), "sigma_min": round(float(s[-1]), 3),
            "largest": heaviest(Vt[0]), "smallest": heaviest(Vt[-1])}


if __name__ == "__main__":
    sys.exit(main())
