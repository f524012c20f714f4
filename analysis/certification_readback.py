"""The region certification read back from the derivation cache, against a fresh one (issue 40).

An entry of the certification cache stores no bound: read back, its scale is checked at its
states and against the samples, and the branch and bound runs again on the samples
(``io/certification_cache.py``). This script times, in one process and for each arm, with the
compiled kernels warmed up first:

1. a fresh certification into an empty derivation cache (sampling, the scale's local
   maximisation and the branch and bound);
2. the same certification read back from that cache, twice;

and checks that the bounds read back equal the fresh ones bit for bit. Arms: the built-in PUMA
560 and the 10-joint chain of ``tests/workflows/test_many_joints.py`` (joint limits of +-170 deg,
180 deg/s, 360 deg/s^2). Prints the load averages and a Markdown table.

Usage::

    python analysis/certification_readback.py [--arms puma560,chain-10]
"""

from __future__ import annotations

import argparse
import os
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests" / "workflows"))
from test_many_joints import _chain_toml  # noqa: E402  (the chain the tests run)


def _robot(name, folder):
    from gd_analyze import load_robot

    if name.startswith("chain-"):
        path = Path(folder) / f"{name}.toml"
        path.write_text(_chain_toml(int(name.split("-")[1]), limits=True, last_qd_max=True))
        return load_robot(str(path))
    return load_robot(name)


def measure(name, folder):
    """(n, boxes, fresh [s], read back [s] x 2, equal) for one arm."""
    from gd_analyze.core.selection.certify import certify
    from gd_analyze.core.symbolic.base_parameters import base_parameters
    from gd_analyze.io.certification_cache import certification
    from gd_analyze.workflows.deploy import REGION_SAMPLES, robot_region

    robot = _robot(name, folder)
    base = base_parameters(robot)
    region, missing = robot_region(robot)
    if region is None:
        raise SystemExit(f"{name}: {missing}")
    certify(robot, base, region, samples=20, max_boxes=4)          # compile the kernels
    times, results = [], []
    for _ in range(3):
        t0 = time.perf_counter()
        results.append(certification(robot, base, region, samples=REGION_SAMPLES))
        times.append(time.perf_counter() - t0)
    equal = all(np.array_equal(r.bound, results[0].bound)
                and np.array_equal(r.leaves, results[0].leaves) for r in results[1:])
    return robot.n, results[0].boxes, times[0], times[1], times[2], equal


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--arms", default="puma560,chain-10")
    args = parser.parse_args(argv)
    print("load averages at the start:", " ".join(f"{v:.2f}" for v in os.getloadavg()))
    print("| arm | n | boxes | fresh [s] | read back [s] | again [s] | bounds equal |")
    print("|---|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as folder:
        os.environ.pop("GD_ANALYZE_NO_CACHE", None)
        os.environ["GD_ANALYZE_CACHE_DIR"] = str(Path(folder) / "cache")
        for name in args.arms.split(","):
            n, boxes, fresh, back, again, equal = measure(name, folder)
            print(f"| {name} | {n} | {boxes} | {fresh:.2f} | {back:.2f} | {again:.2f} | "
                  f"{'yes' if equal else 'NO'} |", flush=True)
    print("load averages at the end:", " ".join(f"{v:.2f}" for v in os.getloadavg()))


if __name__ == "__main__":
    main()
