"""The proof that D_s is positive definite over the region, on the PUMA 560, Panda, UR5 and
Kinova.

For each arm: its default region model (EPS = 1 %, ``simplify.deploy.build_recursive`` over
the robot's joint-limit region), the proof and restore of
``certify.positive_definite.with_inertia_check`` once (the parameters restored, the
proved lower bound of lambda_min(D_s) [kg m^2], the upper bound of min lambda_min(D) over the
region, their ratio, and the wall time with the restores), then the proof alone of the model
deployed (``prove_inertia``: floor, samples, branch and bound), timed in interleaved rounds
(median and range). Prints the machine's load averages before and after.

Usage::

    python analysis/pd_proof.py [--rounds 5] [--samples 2000]
"""

from __future__ import annotations

import argparse
import importlib.metadata
import os
import time

import numpy as np


def _arms():
    root = importlib.metadata.distribution("example-robot-data").locate_file(
        "cmeel.prefix/share/example-robot-data/robots")
    return {"puma560": "puma560", "panda": "panda", "ur5": "ur5",
            "kinova": str(root / "kinova_description/robots/kinova.urdf")}


def main():
    from gd_analyze import load_robot
    from gd_analyze.certify.positive_definite import prove_inertia, with_inertia_check
    from gd_analyze.dynamics.base_parameters import random_states
    from gd_analyze.simplify.deploy import build_recursive, guarantee_region, restored_rebuild

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--samples", type=int, default=2000)
    args = ap.parse_args()
    print("load averages before:", os.getloadavg())
    deployed = {}
    for name, path in _arms().items():
        robot = load_robot(path)
        region, _, _ = guarantee_region(robot)
        q, qd, qdd = random_states(robot, 40, 1)
        model, _ = build_recursive(robot, q, qd, qdd, 0.01, region=region, sample_region=region)
        t0 = time.perf_counter()
        model = with_inertia_check(model, q, samples=args.samples, rebuild=restored_rebuild(
            q, qd, qdd, region=region, sample_region=region))
        seconds = time.perf_counter() - t0
        c = model.inertia_check
        deployed[name] = (robot, model, region)
        print(f"{name}: n = {robot.n}, proved {c['proved']}, lambda_min(D_s) >= "
              f"{c['lower_bound']:.4g} kg m^2, min lambda_min(D) <= {c['d_upper']:.4g} kg m^2, "
              f"ratio {c['ratio']:.4g}; restored {c['restored'] or 'none'}; "
              f"{c['boxes']} boxes; check with restores {seconds:.2f} s")
    times = {name: [] for name in deployed}
    for _ in range(args.rounds):                     # interleaved: one of each per round
        for name, (robot, model, region) in deployed.items():
            t0 = time.perf_counter()
            proof = prove_inertia(robot, model.recursive.base(robot), model.left_out(),
                                  region.q_min, region.q_max, samples=args.samples)
            times[name].append(time.perf_counter() - t0)
            assert proof.proved
    print(f"\nproof of the deployed D_s alone, {args.rounds} interleaved rounds "
          f"({args.samples} samples):")
    print("| arm | ratio | lambda_min(D_s) >= [kg m^2] | median [s] | range [s] |")
    print("|---|---|---|---|---|")
    for name, t in times.items():
        c = deployed[name][1].inertia_check
        print(f"| {name} | {c['ratio']:.3g} | {c['lower_bound']:.3g} | {np.median(t):.3f} | "
              f"{min(t):.3f} - {max(t):.3f} |")
    print("\nload averages after:", os.getloadavg())


if __name__ == "__main__":
    main()
