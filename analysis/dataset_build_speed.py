"""Time of building the jobs' in-memory datasets, this checkout against another.

    python analysis/dataset_build_speed.py --baseline DIR [--rounds 5] [--calls 20]
        [--robots puma560,stanford,puma560-drives]

What is timed is the dataset building the jobs do between their computations and the file:
``store.datasets.with_setpoints`` (the main job's per-set-point variables added to the
summary dataset). For each robot, a child process on this checkout's ``src`` and one on
``--baseline DIR`` (another checkout's ``src``), each first on ``PYTHONPATH``, alternate
round by round (the order swapped each round, so both see the same load). A child runs the
main job's analysis once (``analyze`` on the robot's shipped trajectory, no verification, no
formulations), keeps the arguments its ``with_setpoints`` call got, then times ``--calls``
calls of it with those arguments (``time.perf_counter``; the median is the child's figure).
It also prints a digest of the dataset built (SHA-256 of its variables' names, dims, values,
attributes and encodings in order, the ``history`` attribute left out: it holds the time):
the two sides must build the same dataset.

Prints the load averages before and after, then one JSON line per robot: per side the median
[min, max] over the rounds [ms], this side over the baseline per round, median [min, max],
and whether the digests are equal.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent

_CHILD = r"""
import hashlib, json, sys, time
import numpy as np
from gd_analyze import load_robot
from gd_analyze.jobs import analyze as job
from gd_analyze.jobs.options import AnalysisOptions
from gd_analyze.trajectory.trajectory import read_trajectory

name, csv, calls = sys.argv[1], sys.argv[2], int(sys.argv[3])
robot = load_robot(name)
trajectory = read_trajectory(csv, robot.n)
kept = []
original = job.with_setpoints

def spy(*args):
    kept.append(args)
    return original(*args)

job.with_setpoints = spy
job.analyze(robot, trajectory, AnalysisOptions(verify=False, formulations=False))
times = []
for _ in range(calls):
    t0 = time.perf_counter()
    ds = original(*kept[0])
    times.append(time.perf_counter() - t0)
digest = hashlib.sha256()
for key, v in ds.variables.items():
    attrs = {k: str(a) for k, a in v.attrs.items()}
    digest.update(repr((key, v.dims, v.dtype.str, sorted(v.encoding.items()), attrs)).encode())
    digest.update(np.ascontiguousarray(v.values).tobytes() if v.dtype.kind != "O"
                  else repr(v.values.tolist()).encode())
digest.update(repr((list(ds.dims), {k: str(a) for k, a in ds.attrs.items()
                                    if k != "history"})).encode())
print(json.dumps({"median_s": float(np.median(times)), "digest": digest.hexdigest()}))
"""


def _child(src: Path, robot: str, csv: Path, calls: int) -> dict:
    env = dict(os.environ, PYTHONPATH=str(src))
    done = subprocess.run([sys.executable, "-c", _CHILD, robot, str(csv), str(calls)], env=env,
                          capture_output=True, text=True, check=True, cwd=ROOT)
    return json.loads(done.stdout.strip().splitlines()[-1])


def _summary(values: list[float]) -> list[float]:
    return [round(statistics.median(values), 3), round(min(values), 3), round(max(values), 3)]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--baseline", required=True, help="the other checkout's src folder")
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument("--calls", type=int, default=20)
    parser.add_argument("--robots", default="puma560,stanford,puma560-drives")
    args = parser.parse_args()
    sides = {"this": ROOT / "src", "baseline": Path(args.baseline).resolve()}
    print(json.dumps({"load_before": os.getloadavg()}))
    for robot in args.robots.split(","):
        csv = ROOT / "data" / f"{robot.split('-')[0]}_trajectory.csv"
        ms = {side: [] for side in sides}
        digests = {side: set() for side in sides}
        for r in range(args.rounds):
            order = list(sides) if r % 2 == 0 else list(sides)[::-1]
            for side in order:
                got = _child(sides[side], robot, csv, args.calls)
                ms[side].append(1e3 * got["median_s"])
                digests[side].add(got["digest"])
        ratios = [a / b for a, b in zip(ms["this"], ms["baseline"])]
        print(json.dumps({"robot": robot, "this_ms": _summary(ms["this"]),
                          "baseline_ms": _summary(ms["baseline"]), "ratio": _summary(ratios),
                          "same_dataset": len(digests["this"] | digests["baseline"]) == 1}))
    print(json.dumps({"load_after": os.getloadavg()}))


if __name__ == "__main__":
    main()
