"""Region certification against the number of joints: cold, and read back from the cache.

For random chains of n joints (``analysis/scaling.py``'s ``random_robot`` with position limits
of +-2.5 rad, +-0.3 m for the prismatic joints, 2 rad/s, 4 rad/s^2) and, optionally, named arms,
this script times in rounds, interleaved over n (every n once per round, so that a change of
load hits all of them alike):

1. a certification into an empty derivation cache (sampling, the scale's local maximisation,
   the sampled peaks and the branch and bound: ``store/certification_cache.py``);
2. the same certification read back from that cache: the region's samples drawn first (their
   positions, channel values and sampled peaks, as the main job draws them before it,
   ``simplify/region_memo.py``; timed apart as "of which sampling"), then the scale's self-check,
   the tree of boxes checked to tile the region and the enclosures its witnesses name derived
   again (no search),

each in its own process (the compiled kernels warmed up first), with the process's peak
resident memory and CPU time. It checks that the bounds read back equal the fresh ones bit for bit, and
prints the load averages, a Markdown table of the median and [min, max] over the rounds, and
the growth exponents p of t ~ n^p (least squares over the chains, and between the last two n).

Usage::

    python analysis/certification_readback.py [--ns 3,6,9,12,15] [--rounds 3] [--arms puma560]
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
from scaling import exponents, random_robot  # noqa: E402  (the chains of the scaling study)


def _robot(name):
    from gd_analyze import load_robot

    if name.startswith("random-"):
        return random_robot(int(name.split("-")[1]), limits=True)
    return load_robot(name)


def child(name, phase):
    """One certification in this process; prints one JSON line."""
    from gd_analyze.certify.certify import certify, pair_peaks_at
    from gd_analyze.certify.region import channel_values, sample_positions
    from gd_analyze.dynamics.base_parameters import base_parameters
    from gd_analyze.simplify.deploy import REGION_SAMPLES, robot_region
    from gd_analyze.store.certification_cache import certification

    robot = _robot(name)
    base = base_parameters(robot)
    region, missing = robot_region(robot)
    if region is None:
        raise SystemExit(f"{name}: {missing}")
    certify(robot, base, region, samples=20, max_boxes=4)          # compile the kernels
    t0, c0 = time.perf_counter(), time.process_time()
    drawn, sampling = None, 0.0
    if phase == "back":     # the samples first, as the main job draws them (region_memo)
        cols = np.flatnonzero(base.independent.reshape(-1))
        q = sample_positions(region, REGION_SAMPLES)
        V = channel_values(robot, q, cols)
        drawn = (q, V, pair_peaks_at(V, np.asarray(base.beta, float), region.qd_max,
                                     region.qdd_max))
        sampling = time.perf_counter() - t0
    pb = certification(robot, base, region, samples=REGION_SAMPLES, drawn=drawn)
    seconds, cpu = time.perf_counter() - t0, time.process_time() - c0
    digest = {"bound": pb.bound.tolist(), "leaves_max": pb.leaves.max(axis=2).tolist()}
    print(json.dumps({"n": robot.n, "seconds": seconds, "cpu": cpu, "sampling": sampling,
                      "boxes": int(pb.boxes),
                      "peak_mib": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024,
                      "digest": digest}))


def _run(name, phase, cache):
    env = dict(os.environ, GD_ANALYZE_CACHE_DIR=str(cache))
    env.pop("GD_ANALYZE_NO_CACHE", None)
    out = subprocess.run([sys.executable, __file__, "--child", name, "--phase", phase],
                         env=env, check=True, capture_output=True, text=True).stdout
    return json.loads(out.strip().splitlines()[-1])


def _cell(values, fmt):
    return f"{np.median(values):{fmt}} [{min(values):{fmt}}, {max(values):{fmt}}]"


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--ns", default="3,6,9,12,15")
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--arms", default="", help="named arms besides the chains")
    parser.add_argument("--child", help=argparse.SUPPRESS)
    parser.add_argument("--phase", help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    if args.child:
        child(args.child, args.phase)
        return 0
    names = [f"random-{n}" for n in args.ns.split(",") if n] + \
        [a for a in args.arms.split(",") if a]
    load = [os.getloadavg()]
    print("load averages at the start:", " ".join(f"{v:.2f}" for v in load[0]), flush=True)
    rows = {name: {"fresh": [], "back": [], "fresh_mib": [], "back_mib": [], "equal": True,
                   "fresh_cpu": [], "back_cpu": [], "sampling": []}
            for name in names}
    with tempfile.TemporaryDirectory() as folder:
        for r in range(args.rounds):
            for name in names:
                cache = Path(folder) / f"{name}-{r}"
                fresh = _run(name, "fresh", cache)
                back = _run(name, "back", cache)
                row = rows[name]
                row.update(n=fresh["n"], boxes=fresh["boxes"])
                row["fresh"].append(fresh["seconds"])
                row["back"].append(back["seconds"])
                row["fresh_mib"].append(fresh["peak_mib"])
                row["back_mib"].append(back["peak_mib"])
                row["fresh_cpu"].append(fresh["cpu"])
                row["back_cpu"].append(back["cpu"])
                row["sampling"].append(back["sampling"])
                row["equal"] &= fresh["digest"] == back["digest"]
                print(f"  round {r + 1} {name}: fresh {fresh['seconds']:.2f} s (CPU "
                      f"{fresh['cpu']:.2f} s), read back {back['seconds']:.2f} s (CPU "
                      f"{back['cpu']:.2f} s, sampling {back['sampling']:.2f} s), load "
                      f"{os.getloadavg()[0]:.2f}", flush=True)
                load.append(os.getloadavg())
    print(f"| arm | n | boxes | certification [s] | read back [s] | of which sampling [s] | "
          f"CPU: certification [s] | CPU: read back [s] | peak [MiB] | "
          f"read-back peak [MiB] | bounds equal |  ({args.rounds} rounds: median [min, max])")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for name, row in rows.items():
        print(f"| {name} | {row['n']} | {row['boxes']} | {_cell(row['fresh'], '.2f')} | "
              f"{_cell(row['back'], '.2f')} | {_cell(row['sampling'], '.2f')} | "
              f"{_cell(row['fresh_cpu'], '.2f')} | {_cell(row['back_cpu'], '.2f')} | "
              f"{_cell(row['fresh_mib'], '.0f')} | "
              f"{_cell(row['back_mib'], '.0f')} | {'yes' if row['equal'] else 'NO'} |")
    chains = [rows[n] for n in names if n.startswith("random-")]
    if len(chains) >= 2:
        ns = [c["n"] for c in chains]
        for what in ("fresh", "back", "sampling", "fresh_mib"):
            fit, two = exponents(ns, [np.median(c[what]) for c in chains])
            print(f"growth exponent of {what}: n^{fit:.2f} (least squares over n = "
                  f"{ns[0]}..{ns[-1]}), n^{two:.2f} (n = {ns[-2]} to {ns[-1]})")
    loads = np.array([x[0] for x in load])
    print(f"load (1-minute) during the run: {loads.min():.2f} to {loads.max():.2f}")
    return 0 if all(row["equal"] for row in rows.values()) else 1


if __name__ == "__main__":
    sys.exit(main())
