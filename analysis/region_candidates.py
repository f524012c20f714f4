"""Why a region model keeps what it keeps: each kept pair's gain and bound if dropped too.

For one arm at EPS (default the Panda, 0.01), in a process with an empty derivation cache of
its own: the region model's dropped set (``simplify.deploy.region_model``), the bound it
states per joint over the budget EPS s_i and its largest error found at the certification's
sampled states over the same budget (a lower bound of the true maximum), and then, for every live pair it keeps (base
parameter / part: i inertial, v velocity, g gravity), and for every parameter with more
than one live pair kept (all of them at once, e.g. ``XX3/ivg``), the quick operation count
(``symbolic.recursive.parts_count``, no common-subexpression elimination) with that pair
dropped as well, and the bound of that larger set over the budget on its worst joint
(``certify.certify.region_bound``: the pairs' joint sums on the certification's final boxes,
and the branch and bound of the joint sum where the set depends on at most
``certify.certify.JOINT_DIMS`` joints). A pair whose gain is positive and whose bound ratio
is above 1 is one that a tighter enclosure could let go.

``--joint-dims D --joint-boxes B`` set the branch and bound's joint limit and box budget for
the run (an experiment: the tool's own constants are not changed on disk).

Usage::

    python analysis/region_candidates.py [--arm panda] [--tolerance EPS]
        [--joint-dims D] [--joint-boxes B]
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))


def candidates(name, eps):
    """The dropped set's figures and one row per kept live pair, as a dict."""
    from region_costs import _robot

    from gd_analyze.certify.certify import joint_sums, region_bound
    from gd_analyze.certify.region import joint_region, worst_states
    from gd_analyze.dynamics.base_parameters import base_parameters
    from gd_analyze.model.limits import acceleration_limits
    from gd_analyze.simplify import deploy
    from gd_analyze.simplify.region_memo import certified
    from gd_analyze.symbolic.pruning import part_values
    from gd_analyze.symbolic.recursive import parts_count

    robot = _robot(name)
    base = base_parameters(robot)
    region = joint_region(robot, acceleration_limits(robot)[0])
    t0 = time.perf_counter()
    rec, _ = deploy.region_model(robot, base, region, eps)
    pb = certified(robot, base, region)
    budget = eps * np.asarray(pb.scale, float)
    alone = np.all(pb.bound <= budget[None, None, :], axis=2) & ~pb.zero
    dropped = np.asarray(rec.dropped, bool)
    sums = joint_sums(robot, base, region, pb.split_joint, pb.split_at, alone | dropped,
                      pb.zero)
    count = parts_count(robot, part_values(base, dropped))
    bound = region_bound(robot, base, region, pb, dropped, budget, sums)
    found = worst_states(pb.values, np.asarray(base.beta, float)[None, :] * dropped.T,
                         region.qd_max, region.qdd_max)[0].max(axis=0)
    rows = []
    live = (pb.bound > 0).any(axis=2) & ~pb.zero
    names = base.names()
    kept = live & ~dropped
    whole = [(m, kept[m]) for m in np.flatnonzero(kept.sum(axis=1) > 1)]
    single = [(m, np.arange(3) == p) for m, p in zip(*np.nonzero(kept))]
    for m, parts in whole + single:
        trial = dropped.copy()
        trial[m] |= parts
        held = np.all((sums.pairs | sums.zero)[trial & ~pb.zero])
        over = region_bound(robot, base, region, pb, trial, budget,
                            sums if held else None) / budget
        rows.append({"pair": f"{names[m]}/{''.join(np.array(list('ivg'))[parts])}",
                     "gain": count - parts_count(robot, part_values(base, trial)),
                     "ratio": float(np.max(over)), "joint": int(np.argmax(over)) + 1})
    return {"arm": name, "eps": eps, "count": count, "dropped": int(dropped.sum()),
            "bound_over_budget": [round(float(x), 4) for x in bound / budget],
            "sampled_over_budget": [round(float(x), 4) for x in found / budget],
            "seconds": round(time.perf_counter() - t0, 1),
            "rows": sorted(rows, key=lambda r: r["ratio"])}


def main(argv=None):
    """Print the figures.

    Parameters
    ----------
    argv : list of str, optional
        Command-line arguments.
    """
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--arm", default="panda")
    p.add_argument("--tolerance", type=float, default=0.01)
    p.add_argument("--joint-dims", type=int)
    p.add_argument("--joint-boxes", type=int)
    args = p.parse_args(argv)
    from gd_analyze.certify import certify
    from gd_analyze.simplify import deploy
    if args.joint_dims is not None:
        certify.JOINT_DIMS = deploy.JOINT_DIMS = args.joint_dims
    if args.joint_boxes is not None:
        certify.JOINT_BOXES = args.joint_boxes
    with tempfile.TemporaryDirectory() as folder:    # an empty derivation cache of our own
        os.environ.pop("GD_ANALYZE_NO_CACHE", None)
        os.environ["GD_ANALYZE_CACHE_DIR"] = folder
        out = candidates(args.arm, args.tolerance)
    out["joint_dims"], out["joint_boxes"] = certify.JOINT_DIMS, certify.JOINT_BOXES
    out["load"] = [round(x, 2) for x in os.getloadavg()]
    rows = out.pop("rows")
    print(json.dumps(out))
    print("| pairs (parameter/parts) | operations saved with them | bound / budget | joint |")
    print("|---|---|---|---|")
    for r in rows:
        print(f"| {r['pair']} | {r['gain']} | {r['ratio']:.3f} | {r['joint']} |")


if __name__ == "__main__":
    main()
