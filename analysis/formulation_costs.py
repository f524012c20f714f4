"""Wall time per set point of the L-E, N-E and G-D formulations, beside Pinocchio.

Each formulation is timed two ways on the same random states of a robot (default: PUMA 560):

- batched: all N = 2000 set points in one call (NumPy vectorised over set points);
- looped: one call per set point, over 200 set points (Python and NumPy call overhead shows).

Pinocchio (C++) is always called once per set point; the G-D terms are those of ``gd_terms``
(its numba-compiled kernel). "tau" times the inverse dynamics (joint
torques from q, qd, qdd); "D, h, c" times the dynamic coefficients. The script then prints the
operation counts per set point, measured as implemented (gd_analyze.dynamics.opcount), beside Table 3.5
of Fu, Gonzalez & Lee (1987). It runs in well under two minutes.

Usage::

    python analysis/formulation_costs.py [ROBOT] [--batch N] [--loop N]
"""

from __future__ import annotations

import argparse
import time

import numpy as np
import pinocchio as pin

from gd_analyze import gd_terms, load_robot
from gd_analyze.dynamics.lagrange_euler import le_terms
from gd_analyze.dynamics.newton_euler import ne_tau, ne_terms
from gd_analyze.dynamics.opcount import table
from gd_analyze.dynamics.pinocchio import pinocchio_model


def best_time(fn, repeat=3):
    """Smallest wall time of ``repeat`` calls of fn() [s]."""
    best = np.inf
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t0)
    return best


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("robot", nargs="?", default="puma560")
    parser.add_argument("--batch", type=int, default=2000, help="set points per batched call")
    parser.add_argument("--loop", type=int, default=200, help="set points timed one at a time")
    args = parser.parse_args(argv)

    robot = load_robot(args.robot)
    n = robot.n
    rng = np.random.default_rng(0)
    q, qd, qdd = (rng.uniform(-2, 2, (args.batch, n)) for _ in range(3))
    model = pinocchio_model(robot)
    data = model.createData()
    zero = np.zeros(n)

    def pin_tau(q, qd, qdd):
        for k in range(len(q)):
            pin.rnea(model, data, q[k], qd[k], qdd[k])

    def pin_terms(q, qd, qdd):
        for k in range(len(q)):
            pin.crba(model, data, q[k])
            g = pin.computeGeneralizedGravity(model, data, q[k])
            pin.rnea(model, data, q[k], qd[k], zero) - g

    def gd(q, qd, qdd):
        return gd_terms(robot, q, qd)

    gd(q[:2], qd[:2], qdd[:2])                              # numba: compile before timing
    cases = {
        ("L-E", "tau"): lambda q, qd, qdd: le_terms(robot, q, qd).tau(qdd),
        ("N-E", "tau"): lambda q, qd, qdd: ne_tau(robot, q, qd, qdd),
        ("G-D compiled", "tau"): lambda q, qd, qdd: gd(q, qd, qdd).tau(qdd),
        ("Pinocchio rnea", "tau"): pin_tau,
        ("L-E", "D, h, c"): lambda q, qd, qdd: le_terms(robot, q, qd),
        ("N-E probing", "D, h, c"): lambda q, qd, qdd: ne_terms(robot, q, qd),
        ("G-D compiled", "D, h, c"): gd,
        ("Pinocchio crba+rnea", "D, h, c"): pin_terms,
    }
    L = min(args.loop, args.batch)
    print(f"{robot.name} (n = {n}): wall time per set point [us]")
    print(f"{'method':<21} {'computes':<8} {'batched N=' + str(args.batch):>14} "
          f"{'looped N=' + str(L):>13}")
    for (name, what), fn in cases.items():
        batched = best_time(lambda: fn(q, qd, qdd)) / args.batch
        if name.startswith("Pinocchio"):
            looped = best_time(lambda: fn(q[:L], qd[:L], qdd[:L])) / L
        else:
            looped = best_time(lambda: [fn(q[k], qd[k], qdd[k]) for k in range(L)]) / L
        print(f"{name:<21} {what:<8} {1e6 * batched:>14.1f} {1e6 * looped:>13.1f}")

    print()
    print("Operations per set point: measured as implemented (gd_analyze.dynamics.opcount)")
    print("and Table 3.5 of Fu, Gonzalez & Lee (1987) ('T3.5')")
    print(table(10).to_string())


if __name__ == "__main__":
    main()
