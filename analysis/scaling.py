"""How the cost of the G-D terms grows with the number of joints n, beside Pinocchio.

    python analysis/scaling.py [--setpoints N] [--runs R] [--ns 12,16,24,32,48]

For random chains of n joints (every third joint prismatic, general placements and full
inertia tensors) it times, interleaved and the same number of runs R on each side,

  (a) gd_analyze.gd_terms -> D_tran, D_rot, h_tran, h_rot, c, written
      into output buffers allocated once and reused (the streaming path);
  (b) Pinocchio's batched C++ RNEA, pin.rneaInParallel with one thread (tau only),

on N random states each, and prints one JSON line: per n the median time per set point [us]
of (a) and (b) with their [min, max] over the runs and the ratio a/b, and the scaling
exponents p of t ~ n^p fitted by least squares on log t over log n (all ns) and between the
first and the last n. Ratios and exponents, not absolute times, carry over between machines.
The earlier measurement of the old kernel (D_tran by an O(n^3) triple loop) was p = 1.82
between n = 12 and 48.
"""

from __future__ import annotations

import argparse
import json
import sys
import time

import numpy as np


def random_robot(n, seed=0, limits=False):
    """A random chain of n joints: general placements, every third joint prismatic; with
    ``limits``, position limits of +-2.5 rad (+-0.3 m), so that it has a joint-limit region
    (analysis/certification_readback.py)."""
    from scipy.spatial.transform import Rotation

    from gd_analyze.model.robot_spec import robot_from_chain

    rng = np.random.default_rng(seed)
    joints = []

    def lim(i):
        return 0.3 if i % 3 == 2 else 2.5
    for i in range(n):
        B = rng.normal(size=(3, 3)) * 0.1
        S = B @ B.T
        joints.append({
            "type": "prismatic" if i % 3 == 2 else "revolute",
            "rotation": Rotation.random(random_state=seed * 1000 + i).as_matrix(),
            "translation": rng.uniform(-0.3, 0.3, 3), "mass": rng.uniform(0.3, 4.0),
            "com": rng.uniform(-0.2, 0.2, 3), "inertia": np.trace(S) * np.eye(3) - S,
            "q_min": -lim(i) if limits else -np.inf, "q_max": lim(i) if limits else np.inf,
            "qd_max": 2.0, "qdd_max": 4.0})
    return robot_from_chain(f"random-{n}", joints, [0.0, 0.0, -9.81])


def measure(n, setpoints, runs, seed=0):
    """Interleaved timings of (a) and (b) for one n; returns a dict."""
    import pinocchio as pin

    from gd_analyze import gd_terms
    from gd_analyze.dynamics.dalembert import allocate_terms
    from gd_analyze.dynamics.pinocchio import pinocchio_model

    robot = random_robot(n, seed)
    rng = np.random.default_rng(seed + n)
    q, qd, qdd = (rng.uniform(-1, 1, (setpoints, n)) for _ in range(3))
    buf = allocate_terms(setpoints, n)
    pool = pin.ModelPool(pinocchio_model(robot), 1)
    Q, V, A = (np.asfortranarray(x.T) for x in (q, qd, qdd))
    tau = np.zeros((n, setpoints), order="F")

    def a():
        return gd_terms(robot, q, qd, out=buf)

    def b():
        pin.rneaInParallel(1, pool, Q, V, A, tau)

    a(), b()                                             # compile or load, warm the buffers
    err = np.abs(a().tau(qdd) - tau.T).max() / np.abs(tau).max()
    ta, tb = [], []
    for _ in range(runs):
        for fn, acc in ((a, ta), (b, tb)):
            t0 = time.perf_counter()
            fn()
            acc.append((time.perf_counter() - t0) / setpoints * 1e6)
    return {"n": n, "gd_us": float(np.median(ta)), "gd_range_us": [min(ta), max(ta)],
            "rnea_batched_us": float(np.median(tb)), "rnea_range_us": [min(tb), max(tb)],
            "ratio_gd_over_rnea": float(np.median(ta) / np.median(tb)),
            "tau_rel_disagreement": float(err)}


def exponents(ns, times):
    """Least-squares slope of log t over log n, and the two-point slope first to last."""
    x, y = np.log(np.asarray(ns, float)), np.log(np.asarray(times, float))
    return float(np.polyfit(x, y, 1)[0]), float((y[-1] - y[0]) / (x[-1] - x[0]))


def main(argv=None):
    """Run the measurement and print one JSON line.

    Parameters
    ----------
    argv : list of str, optional
        Command-line arguments.

    Returns
    -------
    int
        0, or 1 if the two engines disagree on tau beyond 1e-10 relative.
    """
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--setpoints", type=int, default=20_000)
    parser.add_argument("--runs", type=int, default=7)
    parser.add_argument("--ns", default="12,16,24,32,48")
    args = parser.parse_args(argv)
    ns = [int(v) for v in args.ns.split(",")]
    rows = [measure(n, args.setpoints, args.runs) for n in ns]
    fit_gd, two_gd = exponents(ns, [r["gd_us"] for r in rows])
    fit_pin, two_pin = exponents(ns, [r["rnea_batched_us"] for r in rows])
    result = {"setpoints": args.setpoints, "runs": args.runs, "rows": rows,
              "gd_exponent_fit": fit_gd, f"gd_exponent_{ns[0]}_{ns[-1]}": two_gd,
              "rnea_exponent_fit": fit_pin, f"rnea_exponent_{ns[0]}_{ns[-1]}": two_pin,
              "previous_gd_exponent_12_48": 1.82}
    print(json.dumps(result))
    if max(r["tau_rel_disagreement"] for r in rows) > 1e-10:
        print("scaling: G-D and Pinocchio disagree on tau", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
