"""Where interval boxes enclose the regressor's channels more tightly than the balls, and where not.

For one arm, random boxes of joint positions of one width: every column's channels enclosed by
the compiled midpoint-radius balls and by the compiled interval boxes
(``certify.regressor_bounds.channel_enclosures`` with ``arithmetic="ball"`` and ``"box"``; the
certification intersects the two on arms of at most 8 joints).
Prints, over the entries the balls do not prove zero (width above 1e-12), the median of the
boxes' width over the balls', by kind of channel (gravity, inertial, velocity) and by link k
of the column against joint i (k - i = 0..3), and the share of entries the boxes prove zero.

Usage::

    python analysis/enclosure_widths.py [--arm panda] [--boxes 64] [--width 1.0] [--seed 0]
"""

from __future__ import annotations

import argparse
import json

import numpy as np

from gd_analyze import load_robot
from gd_analyze.certify import regressor_bounds as rb


def main(argv=None):
    """Print one JSON line of the ratios.

    Parameters
    ----------
    argv : list of str, optional
        Command-line arguments.
    """
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--arm", default="panda")
    p.add_argument("--boxes", type=int, default=64)
    p.add_argument("--width", type=float, default=1.0)
    p.add_argument("--seed", type=int, default=0)
    args = p.parse_args(argv)
    robot = load_robot(args.arm)
    n = robot.n
    mid = np.random.default_rng(args.seed).uniform(-2.0, 2.0, (args.boxes, n))
    q_lo, q_hi = mid - args.width / 2, mid + args.width / 2
    columns = np.arange(10 * n)
    ball_lo, ball_hi = rb.channel_enclosures(robot, q_lo, q_hi, columns, arithmetic="ball")
    box_lo, box_hi = rb.channel_enclosures(robot, q_lo, q_hi, columns, arithmetic="box")
    ball, box = ball_hi - ball_lo, box_hi - box_lo
    live = ball > 1e-12
    ratio = np.where(live, box / np.where(live, ball, 1.0), np.nan)
    kind = np.array(["gravity"] + ["inertial"] * n + ["velocity"] * (ball.shape[1] - 1 - n))
    out = {"arm": args.arm, "width_rad": args.width, "boxes": args.boxes,
           "median_box_over_ball": {k: float(np.nanmedian(ratio[:, kind == k]))
                                    for k in ("gravity", "inertial", "velocity")},
           "box_proves_zero_share": float(np.mean(box[live] == 0.0))}
    by_link = {}
    for d in range(4):
        mask = np.zeros(ratio.shape, bool)
        for i in range(n):
            mask[:, :, i, columns // 10 == i + d] = True
        by_link[f"k-i={d}"] = float(np.nanmedian(ratio[mask]))
    out["median_box_over_ball_by_link"] = by_link
    print(json.dumps(out))


if __name__ == "__main__":
    main()
