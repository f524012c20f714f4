"""The region model's operation counts of the PUMA 560, the Panda and the UR5.

For each arm, in one process with an empty derivation cache of its own: the exact recursive
model's count, the region model's count at EPS (``simplify.deploy.region_model``: pruned on
bounds proved over the joint-limit region), the pairs proved identically zero, the
certification's wall time (:func:`gd_analyze.certify.certify.certify`), the wall time
of ``region_model`` after it (its own certification into the empty cache, the choice of the
pairs with their joint sums, and the sampled error), and the largest proved bound / sampled
error over the joints. Counts are multiplications + additions. Prints the
load averages first.

Usage::

    python analysis/region_costs.py [--tolerance EPS] [--arms puma560,panda,ur5]
"""

from __future__ import annotations

import argparse
import os
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))


def _ops(cost):
    return int(cost["multiplications"]) + int(cost["additions"])


def _robot(name):
    import real_arms

    from gd_analyze import load_robot
    from gd_analyze.model.urdf import load_urdf

    if name == "puma560":
        return load_robot("puma560")
    arm = name if ":" in name or name not in real_arms.KNOWN_TIPS else \
        f"{name}:{real_arms.KNOWN_TIPS[name]}"
    chosen, skipped = real_arms.discover([arm])
    if not chosen:
        return load_robot(name)         # a built-in arm (ur5: example-robot-data's ur5_robot)
    _, path, tip, _ = chosen[0]
    return load_urdf(path, tip=tip)


def row(name, eps):
    """One arm's figures as a dict."""
    from gd_analyze.certify.certify import certify
    from gd_analyze.certify.region import joint_region
    from gd_analyze.dynamics.base_parameters import base_parameters
    from gd_analyze.model.limits import acceleration_limits
    from gd_analyze.simplify import deploy
    from gd_analyze.symbolic.pruning import pruned_program
    from gd_analyze.symbolic.recursive import recursive_program

    robot = _robot(name)
    base = base_parameters(robot)
    region = joint_region(robot, acceleration_limits(robot)[0])
    t0 = time.perf_counter()
    pb = certify(robot, base, region, samples=deploy.REGION_SAMPLES)
    seconds = time.perf_counter() - t0
    t0 = time.perf_counter()
    rec, g = deploy.region_model(robot, base, region, eps)
    model_seconds = time.perf_counter() - t0
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = np.where(g.sampled_error > 0, g.bound / g.sampled_error, np.nan)
    zero = int(getattr(pb, "zero", np.zeros(1, bool)).sum())
    return {"arm": name, "n": robot.n,
            "exact": _ops(recursive_program(robot, base.values).cost()),
            "region": _ops(pruned_program(robot, base, rec.dropped).cost()),
            "dropped": int(rec.dropped.sum()), "zero": zero,
            "ratio": float(np.nanmax(ratio)) if np.isfinite(ratio).any() else float("nan"),
            "seconds": seconds, "boxes": pb.boxes, "model_seconds": model_seconds}


def main(argv=None):
    """Print the table.

    Parameters
    ----------
    argv : list of str, optional
        Command-line arguments.
    """
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--arms", default="puma560,panda,ur5")
    p.add_argument("--tolerance", type=float, default=0.01)
    args = p.parse_args(argv)
    with tempfile.TemporaryDirectory() as folder:    # an empty derivation cache of our own
        os.environ.pop("GD_ANALYZE_NO_CACHE", None)
        os.environ["GD_ANALYZE_CACHE_DIR"] = folder
        print(f"load averages {os.getloadavg()}; EPS = {args.tolerance:g}")
        print("| arm | n | exact | region model | pairs dropped | pairs proved zero | "
              "proved bound / sampled error (worst joint) | certification [s] (boxes) | "
              "region model [s] |")
        print("|---|---|---|---|---|---|---|---|---|")
        for name in args.arms.split(","):
            r = row(name, args.tolerance)
            print(f"| {r['arm']} | {r['n']} | {r['exact']} | {r['region']} | {r['dropped']} | "
                  f"{r['zero']} | {r['ratio']:.3g} | {r['seconds']:.1f} ({r['boxes']}) | "
                  f"{r['model_seconds']:.1f} |",
                  flush=True)


if __name__ == "__main__":
    main()
