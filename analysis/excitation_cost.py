"""The excitation's planning cost and result, this tree's against another source tree's.

    python analysis/excitation_cost.py --compare OLD_SRC [--robots puma560,panda,ur5]
        [--repeats 3] [--randoms 8] [--seeds 0]

For each arm, plans the default excitation (``gd-analyze plan ROBOT --excitation``: 5
harmonics, one 10 s period, 2 random starts) with this tree's ``src`` and with ``OLD_SRC`` (a
checkout's ``src`` folder, e.g. ``/work/main/src``; ``--old`` is the same option), each run in
a process of its own, the two interleaved (old, new, new, old, ...) so that both see the same
load. ``--seeds`` (comma-separated) plans with each seed of the random starts in every round:
the optimum reached depends on rounding along the optimiser's path, so a change that alters
the rounding is judged on the conditions of several seeds, not of one. A run measures the CPU time [s] of :func:`plan_excitation` (the process's, from the call
to its return: the robot's regressor columns included, as a user waits for them), its wall
time, the process's peak resident memory [MiB], and the optimum's scaled condition number on
400 samples of a period against R random Fourier trajectories with the same harmonics, base
frequency and limits (:func:`random_excitation`, seeds 1000.., the tests' reference).

Prints one JSON line per run, then one per arm and tree: the median and range of the CPU and
wall times over all its runs, the peak memory, each seed's condition number and their median,
the random ones' median and the ratio (to the median condition), and the load average
(``os.getloadavg``) before and after; then per arm the ratio of the CPU time medians, old /
new.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
NEW_SRC = HERE.parent / "src"


def child(name, randoms, seed):
    """One planning in this process: print its JSON line."""
    import resource
    import time

    import numpy as np

    from gd_analyze.model.robots import load_robot
    from gd_analyze.trajectory.excitation import (
        excitation_condition,
        plan_excitation,
        random_excitation,
    )

    robot = load_robot(name)
    wall, cpu = time.perf_counter(), time.process_time()
    ex = plan_excitation(robot, seed=seed)
    wall, cpu = time.perf_counter() - wall, time.process_time() - cpu
    ours = excitation_condition(robot, ex.columns, ex.series, samples=400)
    others = [excitation_condition(robot, ex.columns, random_excitation(
        robot, ex.series.harmonics, ex.series.wf, 1000 + k), samples=400)
        for k in range(randoms)]
    print(json.dumps({"cpu_s": cpu, "wall_s": wall, "condition": ours,
                      "random_median": float(np.median(others)),
                      "peak_mib": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024}))


def run(src, name, randoms, seed):
    """One planning in a process of its own with ``src`` first on the path."""
    env = dict(os.environ, PYTHONPATH=str(src))
    out = subprocess.run([sys.executable, __file__, "--child", name, "--randoms", str(randoms),
                          "--seed", str(seed)],
                         env=env, capture_output=True, text=True, check=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def main(argv=None):
    """Measure and print."""
    import numpy as np

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--compare", "--old", dest="old", help="the other tree's src folder")
    parser.add_argument("--robots", default="puma560,panda,ur5")
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--randoms", type=int, default=8)
    parser.add_argument("--seeds", default="0", help="comma-separated seeds of the starts")
    parser.add_argument("--seed", type=int, default=0, help=argparse.SUPPRESS)
    parser.add_argument("--child", help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    if args.child:
        child(args.child, args.randoms, args.seed)
        return 0
    if not args.old:
        parser.error("--compare is required")
    trees = {"old": Path(args.old).resolve(), "new": NEW_SRC}
    seeds = [int(v) for v in args.seeds.split(",")]
    for name in args.robots.split(","):
        runs = {tree: [] for tree in trees}
        load = os.getloadavg()[0]
        for k in range(args.repeats):
            for seed in seeds:
                order = list(trees.items())
                for tree, src in (order if (k + seed) % 2 == 0 else order[::-1]):
                    one = run(src, name, args.randoms, seed)
                    one.update(robot=name, tree=tree, repeat=k, seed=seed,
                               load=os.getloadavg()[0])
                    print(json.dumps({key: round(v, 3) if isinstance(v, float) else v
                                      for key, v in one.items()}), flush=True)
                    runs[tree].append(one)
        medians = {}
        for tree, rs in runs.items():
            cpu = [r["cpu_s"] for r in rs]
            wall = [r["wall_s"] for r in rs]
            conds = {seed: [r["condition"] for r in rs if r["seed"] == seed] for seed in seeds}
            cond = float(np.median([c[0] for c in conds.values()]))
            medians[tree] = float(np.median(cpu))
            print(json.dumps({
                "robot": name, "tree": tree, "runs": len(rs),
                "cpu_s_median": round(medians[tree], 2),
                "cpu_s_range": [round(min(cpu), 2), round(max(cpu), 2)],
                "wall_s_median": round(float(np.median(wall)), 2),
                "wall_s_range": [round(min(wall), 2), round(max(wall), 2)],
                "peak_mib_max": round(max(r["peak_mib"] for r in rs), 1),
                "conditions_by_seed": {s: round(c[0], 3) for s, c in conds.items()},
                "condition_median": round(cond, 3),
                "conditions_equal_across_runs": all(len(set(c)) == 1 for c in conds.values()),
                "random_median": round(rs[0]["random_median"], 3),
                "ratio": round(rs[0]["random_median"] / cond, 2),
                "load_before": round(load, 2), "load_after": round(os.getloadavg()[0], 2)}),
                flush=True)
        if len(medians) == 2:
            print(json.dumps({"robot": name, "cpu_median_old_over_new":
                              round(medians["old"] / medians["new"], 2)}), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
