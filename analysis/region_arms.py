"""The region guarantee on every serial arm of example-robot-data.

For each arm (the built-in PUMA 560 and every URDF the main job accepts, as
``analysis/real_arms.py`` finds them, plus NAME:TIP arms given with --arms), in one process:

1. the exact customized recursive Newton-Euler model's count (``recursive_program``);
2. the trajectory model at EPS: pruned on the default planned trajectory's peaks
   (``recursive_model``), its count, and its worst error sampled over the joint-limit region
   relative to s_i there (``region_sampled_error``): what a user gets off the trajectory;
3. the region model at EPS: pruned on bounds proved over the region
   (``simplify.deploy.region_model``), its count, the certification's wall time (sampling, scale
   search and branch and bound, into an empty derivation cache; then read back from it, with its
   self-check), the ratio of its
   proved bound to its sampled error per joint (worst joint), and the median and largest ratio
   of proved to sampled peak over the pairs that contribute.

Counts are multiplications + additions. Prints the load averages and a Markdown table.

Usage::

    python analysis/region_arms.py [--arms NAME[:TIP],...] [--tolerance EPS] [--only-listed]
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

#: Arms with several chains in their URDF: the arm's tip (the table of the region guarantee).
EXTRA = ("baxter:left_gripper", "tiago_no_hand:arm_7_link", "solo12:FL_LOWER_LEG")


def _ops(cost):
    return int(cost["multiplications"]) + int(cost["additions"])


def row(name, robot, eps):
    """One arm's figures as a dict (or the reason it has none)."""
    from gd_analyze.certify.region import joint_region, missing_limits
    from gd_analyze.dynamics.base_parameters import base_parameters
    from gd_analyze.model.limits import acceleration_limits
    from gd_analyze.simplify import deploy
    from gd_analyze.store.certification_cache import certification
    from gd_analyze.symbolic.pruning import pruned_program
    from gd_analyze.symbolic.recursive import recursive_program
    from gd_analyze.symbolic.recursive_model import recursive_model
    from gd_analyze.trajectory.planning import default_motion, plan_quintic

    why = missing_limits(robot)
    if why:
        return {"arm": name, "n": robot.n, "note": why}
    base = base_parameters(robot)
    exact = _ops(recursive_program(robot, base.values).cost())
    traj = plan_quintic(robot, *default_motion(robot))
    region = joint_region(robot, acceleration_limits(robot)[0])
    t0 = time.perf_counter()
    pb = certification(robot, base, region, samples=deploy.REGION_SAMPLES)
    seconds = time.perf_counter() - t0
    t0 = time.perf_counter()
    certification(robot, base, region, samples=deploy.REGION_SAMPLES)
    cached = time.perf_counter() - t0
    rec_t = recursive_model(robot, traj.q, traj.qd, traj.qdd, eps, base=base)
    g_t = deploy.trajectory_guarantee(robot, base, rec_t, eps, region=region)
    rec_r, g_r = deploy.region_model(robot, base, region, eps)
    live = pb.sampled > 1e-12 * pb.scale[None, None, :]
    ratio = pb.bound[live] / pb.sampled[live]
    with np.errstate(divide="ignore", invalid="ignore"):
        joint_ratio = np.where(g_r.sampled_error > 0, g_r.bound / g_r.sampled_error, np.nan)
    return {"arm": name, "n": robot.n, "exact": exact,
            "trajectory": _ops(pruned_program(robot, base, rec_t.dropped).cost()),
            "trajectory_region_error": 100 * float(np.nanmax(g_t.region_sampled_error)),
            "region": _ops(pruned_program(robot, base, rec_r.dropped).cost()),
            "region_error": 100 * float(np.max(g_r.sampled_error / g_r.scale)),
            "bound_over_sampled": float(np.nanmax(joint_ratio)) if np.isfinite(
                joint_ratio).any() else float("nan"),
            "pair_ratio_median": float(np.median(ratio)) if ratio.size else float("nan"),
            "pair_ratio_max": float(ratio.max()) if ratio.size else float("nan"),
            "seconds": seconds, "cached": cached, "boxes": pb.boxes, "note": ""}


def main(argv=None):
    """Print the table.

    Parameters
    ----------
    argv : list of str, optional
        Command-line arguments.
    """
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--arms", default="", help="NAME[:TIP],... of example-robot-data")
    p.add_argument("--tolerance", type=float, default=0.01)
    p.add_argument("--only-listed", action="store_true",
                   help="only the --arms given (not the PUMA and every accepted arm)")
    args = p.parse_args(argv)
    with tempfile.TemporaryDirectory() as folder:    # an empty derivation cache of our own
        os.environ.pop("GD_ANALYZE_NO_CACHE", None)
        os.environ["GD_ANALYZE_CACHE_DIR"] = folder
        _table(args)


def _table(args):
    """Print the table for the parsed arguments."""
    import real_arms

    from gd_analyze import load_robot
    from gd_analyze.model.urdf import load_urdf

    listed = [a for a in args.arms.split(",") if a]
    chosen, skipped = real_arms.discover(listed if args.only_listed else None)
    if not args.only_listed:
        extra, more = real_arms.discover(list(EXTRA) + listed)
        chosen += extra
        skipped += more
    arms = [] if args.only_listed else [("puma560", load_robot("puma560"))]
    for name, path, tip, _ in chosen:
        arms.append((f"{name}:{tip}" if tip else name, load_urdf(path, tip=tip)))
    print(f"load averages {os.getloadavg()}; EPS = {args.tolerance:g}")
    print("| arm | n | exact | trajectory model | its sampled error over R | region model | "
          "region model's sampled error | proved bound / sampled error | pair bound / sampled "
          "(median, max) | certification [s] (boxes) | from the cache [s] |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for name, robot in arms:
        r = row(name, robot, args.tolerance)
        if r["note"]:
            print(f"| {name} | {r['n']} | {r['note']} |||||||||")
            continue
        print(f"| {name} | {r['n']} | {r['exact']} | {r['trajectory']} | "
              f"{r['trajectory_region_error']:.3g} % | {r['region']} | {r['region_error']:.3g} % "
              f"| {r['bound_over_sampled']:.3g} | {r['pair_ratio_median']:.3g}, "
              f"{r['pair_ratio_max']:.3g} | {r['seconds']:.1f} ({r['boxes']}) | "
              f"{r['cached']:.2f} |", flush=True)
    for name, why in skipped:
        print(f"skipped {name}: {why}", file=sys.stderr)


if __name__ == "__main__":
    main()
