"""The simplified explicit model of a robot (default the PUMA 560): cost table, tolerance ladder.

Prints
1. the derivation time of the explicit model (no cache) and the program build time;
2. the cost table (multiplications, additions, sin/cos calls) of the full explicit model, the
   simplified model at EPS = 0.001, 0.01, 0.05, the chapter-rule model, the project's G-D, N-E
   and L-E as implemented, Table 3.5 and Armstrong, Khatib & Burdick (1986);
3. the ladder for EPS in {0, 0.001, 0.01, 0.05}: operations, worst per-joint error on the analysed
   trajectory (guaranteed <= EPS) and on 100 other planned trajectories (NOT guaranteed).

Errors are peak |tau_s - tau_rnea| / peak |tau_rnea| per joint, against Pinocchio rnea.

Usage: python analysis/simplified_ladder.py [TRAJECTORY.csv] [--robot NAME] [--held-out K]
       [--seed S] [--torque-floor TAU]   (the trajectory defaults to data/<robot>_trajectory.csv)
"""

import argparse
import os
import time
from pathlib import Path

import numpy as np
import pinocchio as pin

from gd_analyze import load_robot
from gd_analyze.dynamics.dalembert import gd_terms
from gd_analyze.dynamics.pinocchio import pinocchio_model
from gd_analyze.jobs.simplified_dataset import cost_rows
from gd_analyze.ranking.ranking import rank_dominance
from gd_analyze.simplify.explicit_model import LADDER, build_model, collect_peaks
from gd_analyze.store.explicit_cache import explicit_terms
from gd_analyze.trajectory.planning import random_trajectories
from gd_analyze.trajectory.trajectory import read_trajectory

ROOT = Path(__file__).resolve().parents[1]


def rnea(model, data, q, qd, qdd):
    return np.array([pin.rnea(model, data, a, b, c) for a, b, c in zip(q, qd, qdd)])


def worst(model_s, trajs, pmodel, pdata):
    """max over joints of peak |tau_s - tau| / peak |tau| over the trajectories together."""
    peak_err = np.zeros(model_s.robot.n)
    peak_tau = np.zeros(model_s.robot.n)
    for tr in trajs:
        ref = rnea(pmodel, pdata, tr.q, tr.qd, tr.qdd)
        err = np.abs(model_s.torque(tr.q, tr.qd, tr.qdd) - ref).max(axis=0)
        peak_err = np.maximum(peak_err, err)
        peak_tau = np.maximum(peak_tau, np.abs(ref).max(axis=0))
    return float((peak_err / peak_tau).max())


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("trajectory", nargs="?", default=None)
    ap.add_argument("--robot", default="puma560")
    ap.add_argument("--held-out", type=int, default=100)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--torque-floor", type=float, default=0.0,
                    help="least joint-torque scale TAU [N m] of the budget (as the CLI's)")
    args = ap.parse_args()
    robot = load_robot(args.robot)
    if args.trajectory is None:
        args.trajectory = str(ROOT / "data" / f"{args.robot}_trajectory.csv")
    traj = read_trajectory(args.trajectory, robot.n)
    os.environ["GD_ANALYZE_NO_CACHE"] = "1"
    terms, t_derive = explicit_terms(robot)
    q, qd, qdd = traj.q, traj.qd, traj.qdd
    t = gd_terms(robot, q, qd)
    ranking = rank_dominance(t.D_tran, t.D_rot, t.h_tran, t.h_rot, t.tau(qdd))
    t0 = time.perf_counter()
    peaks = collect_peaks(robot, terms, q, qd, qdd)
    floor = args.torque_floor
    model, _ = build_model(robot, terms, peaks, tolerance=0.01, ranking=ranking,
                           torque_floor=floor)
    t_build = time.perf_counter() - t0
    print(f"derivation of the explicit {robot.name} model (no cache): {t_derive:.2f} s; "
          f"peaks, selection and program at EPS = 0.01: {t_build:.2f} s "
          f"({len(terms)} terms in the full model); timings under contention on a shared "
          "machine")
    chapter, _ = build_model(robot, terms, peaks, rule="chapter",
                             chapter_choices=ranking.choices(), ranking=ranking)
    pmodel = pinocchio_model(robot)
    pdata = pmodel.createData()
    held = random_trajectories(robot, args.held_out, seed=args.seed)
    rows = []
    for eps in LADDER:
        m, _ = build_model(robot, terms, peaks, tolerance=eps, torque_floor=floor)
        rows.append((eps, m, worst(m, [traj], pmodel, pdata), worst(m, held, pmodel, pdata)))
    ladder_rows = [{"tolerance": eps, **m.cost} for eps, m, *_ in rows]
    table = cost_rows(robot.n, model, other=chapter, ladder_rows=ladder_rows)
    print()
    print(f"{f'model ({robot.name})':<44}{'mult':>8}{'add':>8}{'total':>8}{'sin+cos':>9}")
    trig = {f"explicit, budget EPS={eps:g}": m.cost["sin"] + m.cost["cos"]
            for eps, m, *_ in rows}
    trig["explicit, full"] = trig["explicit, budget EPS=0"]
    trig["explicit, chapter"] = chapter.cost["sin"] + chapter.cost["cos"]
    for label, (mu, ad, tot) in table.items():
        if "(this model)" in label:
            continue
        fmt = (lambda v: f"{v:>8.0f}" if np.isfinite(v) else f"{'-':>8}")
        tr = trig.get(label)
        print(f"{label:<44}{fmt(mu)}{fmt(ad)}{fmt(tot)}{tr if tr is not None else '':>9}")
    print(f"(project N-E and Table 3.5 take sin/cos of the n joint angles as inputs: "
          f"{robot.n} + {robot.n})")
    print()
    print(f"tolerance ladder on {Path(args.trajectory).name} "
          f"({traj.n_setpoints} set points), torque floor {floor:g} N m, errors against "
          f"Pinocchio rnea (relative to each joint's peak |tau|)")
    print(f"{'EPS':>7}{'mult':>7}{'add':>7}{'total':>7}{'sin+cos':>9}{'worst, analysed':>17}"
          f"{f'worst, {len(held)} others':>20}")
    for eps, m, w, wh in rows:
        c = m.cost
        print(f"{eps:>7g}{c['multiplications']:>7}{c['additions']:>7}"
              f"{c['multiplications'] + c['additions']:>7}{c['sin'] + c['cos']:>9}"
              f"{w:>17.2e}{wh:>13.2e} (not guaranteed)")


if __name__ == "__main__":
    main()
