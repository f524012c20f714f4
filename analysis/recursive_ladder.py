"""The recursive simplified model of a robot: its costs beside the anchors, its ladder.

Prints, for each robot asked for (default the PUMA 560 and the Panda, on their shipped
trajectories):

1. the base parameters (their number) and the exact customized recursive Newton-Euler model's
   counted operations (multiplications, additions, sin, cos), with the published anchors for
   the PUMA 560: a customized recursive N-E 338, OpenSYMORO with base parameters 541 (641
   without), Armstrong, Khatib & Burdick's (1986) full explicit 1,165 and 1 % simplified 305; and
   for every robot the project's Newton-Euler as implemented and Table 3.5's;
2. the ladder for EPS in {0, 0.001, 0.01, 0.05}: the pruned recursive model's operations, its
   guaranteed bound and its measured worst per-joint error on the analysed trajectory (both
   relative to each joint's peak |tau|), and its worst error on K other planned trajectories
   (NOT guaranteed).

Errors are against Pinocchio rnea. The explicit model's ladder is
``analysis/simplified_ladder.py``.

Usage: python analysis/recursive_ladder.py [--robots puma560,panda] [--held-out K] [--seed S]
       [--torque-floor TAU]
"""

import argparse
import time
from pathlib import Path

import numpy as np
import pinocchio as pin

from gd_analyze.dynamics.base_parameters import base_parameters
from gd_analyze.dynamics.opcount import book_counts, operation_counts
from gd_analyze.dynamics.pinocchio import pinocchio_model
from gd_analyze.model.robots import load_robot
from gd_analyze.symbolic.emit import python_function
from gd_analyze.symbolic.recursive import recursive_program
from gd_analyze.symbolic.recursive_model import recursive_model
from gd_analyze.trajectory.planning import random_trajectories
from gd_analyze.trajectory.trajectory import read_trajectory

ROOT = Path(__file__).resolve().parents[1]
LADDER = (0.0, 0.001, 0.01, 0.05)
#: The published anchors for the PUMA 560 (multiplications + additions).
ANCHORS = {"customized recursive N-E": 338,
           "OpenSYMORO, base parameters": 541, "OpenSYMORO, standard parameters": 641,
           "AKB 1986 full explicit": 1165, "AKB 1986 simplified (1 %)": 305}


def rnea(model, data, q, qd, qdd):
    return np.array([pin.rnea(model, data, a, b, c) for a, b, c in zip(q, qd, qdd)])


def worst(tau_fn, trajs, pmodel, pdata):
    """max over joints of peak |tau_s - tau| / peak |tau|, over the trajectories together."""
    peak_err = peak_tau = 0.0
    for q, qd, qdd in trajs:
        ref = rnea(pmodel, pdata, q, qd, qdd)
        peak_err = np.maximum(peak_err, np.abs(tau_fn(q, qd, qdd) - ref).max(axis=0))
        peak_tau = np.maximum(peak_tau, np.abs(ref).max(axis=0))
    return float((peak_err / peak_tau).max())


def ops(c):
    return int(c["multiplications"]) + int(c["additions"])


def one(name, args):
    robot = load_robot(name)
    traj = read_trajectory(ROOT / "data" / f"{name}_trajectory.csv", robot.n)
    q, qd, qdd = traj.q, traj.qd, traj.qdd
    t0 = time.perf_counter()
    base = base_parameters(robot)
    exact = recursive_program(robot, base.values).cost()
    t_exact = time.perf_counter() - t0
    print(f"{name}: {robot.n} joints, {base.rank} base parameters; exact recursive model "
          f"{ops(exact):,} operations ({exact['multiplications']} mult + "
          f"{exact['additions']} add; {exact['sin']} sin, {exact['cos']} cos), built in "
          f"{t_exact:.2f} s")
    ne = operation_counts(robot.n)["newton-euler"]
    book = book_counts(robot.n)["newton-euler"]
    print(f"  anchors: project N-E as implemented {ops(ne):,}; Table 3.5 N-E {ops(book):,}")
    if name == "puma560":
        for label, v in ANCHORS.items():
            print(f"  anchors: {label} {v:,}")
    pmodel = pinocchio_model(robot)
    pdata = pmodel.createData()
    held = [(t.q, t.qd, t.qdd) for t in random_trajectories(robot, args.held_out,
                                                            seed=args.seed)]
    scale = np.maximum(np.abs(rnea(pmodel, pdata, q, qd, qdd)).max(axis=0), args.torque_floor)
    print(f"  ladder on {traj.source and Path(traj.source).name} ({traj.n_setpoints} set "
          f"points), torque floor {args.torque_floor:g}:")
    print(f"  {'EPS':>7}{'mult':>7}{'add':>7}{'total':>7}{'sin+cos':>9}{'dropped':>9}"
          f"{'bound':>11}{'worst, analysed':>17}{f'worst, {len(held)} others':>20}")
    for eps in LADDER:
        rec = recursive_model(robot, q, qd, qdd, eps, args.torque_floor, base=base)
        prog = rec.program(robot)
        c = prog.cost()
        fn = python_function(prog)
        w = worst(fn, [(q, qd, qdd)], pmodel, pdata)
        wh = worst(fn, held, pmodel, pdata)
        bound = float((rec.bound / np.where(scale > 0, scale, np.inf)).max())
        print(f"  {eps:>7g}{c['multiplications']:>7}{c['additions']:>7}{ops(c):>7}"
              f"{c['sin'] + c['cos']:>9}{int(rec.dropped.sum()):>9}{bound:>11.2e}"
              f"{w:>17.2e}{wh:>13.2e} (not guaranteed)")
    print()


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--robots", default="puma560,panda")
    ap.add_argument("--held-out", type=int, default=100)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--torque-floor", type=float, default=0.0)
    args = ap.parse_args()
    for name in args.robots.split(","):
        one(name.strip(), args)


if __name__ == "__main__":
    main()
