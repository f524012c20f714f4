"""What the Python API's check of its states for NaN and inf costs against the call it guards.

    python analysis/input_check_cost.py [--setpoints N] [--regressor-setpoints M] [--rounds R]

On N random PUMA 560 states (``random_states``, default 10^6) it times, in R interleaved rounds
(default 5), ``gd_terms(robot, q, qd)`` into buffers allocated once (the whole call, its check
included) and the check alone as ``as_states`` runs it (the sum of q, and of qd, finite);
and on M states (default 10^5: the base regressor of 10^6 states is 1.7 GB)
``regressor(robot, q, qd, qdd)`` against the check of q, qd and qdd. Prints one JSON line: each
time's median and [min, max] [s], and the check's share of its call (per round, median and
range), with the load average at the start and the end (the machine is shared).
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import time

import numpy as np


def check(*arrays):
    """The check ``as_states`` makes on each array (its sum finite, else each value)."""
    for x in arrays:
        assert np.isfinite(x.sum()) or np.isfinite(x).all()


def timed(call):
    """Seconds of one call (wall clock)."""
    t0 = time.perf_counter()
    call()
    return time.perf_counter() - t0


def summary(values):
    """Median and [min, max]."""
    return {"median": float(np.median(values)), "range": [min(values), max(values)]}


def main(argv=None):
    """Measure and print one JSON line.

    Parameters
    ----------
    argv : list of str, optional
        Command-line arguments.
    """
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--setpoints", type=int, default=1_000_000)
    p.add_argument("--regressor-setpoints", type=int, default=100_000)
    p.add_argument("--rounds", type=int, default=5)
    args = p.parse_args(argv)
    import gd_analyze as gd
    from gd_analyze.dynamics.base_parameters import base_parameters, base_regressor, random_states
    from gd_analyze.dynamics.dalembert import allocate_terms

    load = [os.getloadavg()]
    robot = gd.load_robot("puma560")
    q, qd, qdd = random_states(robot, args.setpoints, seed=1)
    out = allocate_terms(*q.shape)
    M = args.regressor_setpoints
    base = base_parameters(robot)
    gd.gd_terms(robot, q[:10], qd[:10])                     # the compiled kernel loaded
    pairs = {"gd_terms": (lambda: gd.gd_terms(robot, q, qd, out=out), lambda: check(q, qd)),
             "regressor": (lambda: base_regressor(robot, q[:M], qd[:M], qdd[:M], base),
                           lambda: check(q[:M], qd[:M], qdd[:M]))}
    times = {f"{k}_{part}": [] for k in pairs for part in ("call", "check")}
    for r in range(args.rounds):
        for key, (call, chk) in pairs.items():
            order = [("call", call), ("check", chk)]
            for part, f in order[::(-1) ** r]:
                times[f"{key}_{part}"].append(timed(f))
    load.append(os.getloadavg())
    result = {"setpoints": args.setpoints, "regressor_setpoints": M, "rounds": args.rounds,
              "load_average": load}
    for key in pairs:
        result[f"{key}_s"] = summary(times[f"{key}_call"])
        result[f"{key}_check_s"] = summary(times[f"{key}_check"])
        result[f"{key}_check_share"] = summary(
            [c / a for c, a in zip(times[f"{key}_check"], times[f"{key}_call"])])
    print(json.dumps(result))
    return 0


if __name__ == "__main__":
    sys.exit(main())
