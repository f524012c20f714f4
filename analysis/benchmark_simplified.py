"""Time the compiled simplified PUMA 560 model against Pinocchio rnea, side by side.

The simplified model (budget rule, EPS = 0.01, on the shipped trajectory) is emitted as C, compiled
with ``cc -O2 -shared -fPIC`` together with a batch loop, and called once through ctypes for
100,000 set points. Against it:

- Pinocchio ``rnea`` called in a Python loop over the same set points;
- Pinocchio ``rneaInParallel`` with one thread, batched in C++.

Runs are interleaved (C, loop, batched, C, loop, batched, ...), the same set points and count on
each side; the script prints the median and the range of each ratio.

Usage: python analysis/benchmark_simplified.py [--setpoints N] [--runs R] [--eps EPS]
"""

import argparse
import ctypes
import subprocess
import tempfile
import time
from pathlib import Path

import numpy as np
import pinocchio as pin

from gd_analyze import load_robot
from gd_analyze.formulations.pinocchio import pinocchio_model
from gd_analyze.io.explicit_cache import explicit_terms
from gd_analyze.io.trajectory import read_trajectory
from gd_analyze.workflows.simplify import build_model, collect_peaks

ROOT = Path(__file__).resolve().parents[1]
BATCH = """
void gd_simplified_batch(long count, const double *q, const double *qd, const double *qdd,
                         double *tau)
{
    for (long k = 0; k < count; ++k)
        gd_simplified_tau(q + 6 * k, qd + 6 * k, qdd + 6 * k, tau + 6 * k);
}
"""


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--setpoints", type=int, default=100_000)
    ap.add_argument("--runs", type=int, default=7)
    ap.add_argument("--eps", type=float, default=0.01)
    args = ap.parse_args()
    robot = load_robot("puma560")
    traj = read_trajectory(ROOT / "data" / "puma560_trajectory.csv", 6)
    terms, _ = explicit_terms(robot)
    peaks = collect_peaks(robot, terms, traj.q, traj.qd, traj.qdd)
    model, _ = build_model(robot, terms, peaks, tolerance=args.eps)
    cost = model.cost
    tmp = Path(tempfile.mkdtemp(prefix="gd-bench-"))
    (tmp / "simplified_model.c").write_text(model.c_source() + BATCH)
    lib = tmp / "libsimplified.so"
    subprocess.run(["cc", "-O2", "-shared", "-fPIC", "-o", str(lib),
                    str(tmp / "simplified_model.c"), "-lm"], check=True)
    dll = ctypes.CDLL(str(lib))
    dp = ctypes.POINTER(ctypes.c_double)
    batch = dll.gd_simplified_batch
    batch.argtypes, batch.restype = [ctypes.c_long, dp, dp, dp, dp], None

    rng = np.random.default_rng(0)
    N = args.setpoints
    q = rng.uniform(robot.q_min, robot.q_max, (N, 6))
    qd = rng.uniform(-robot.qd_max, robot.qd_max, (N, 6))
    qdd = rng.uniform(-robot.qdd_max, robot.qdd_max, (N, 6))
    tau_c = np.empty((N, 6))
    pmodel = pinocchio_model(robot)
    pdata = pmodel.createData()
    pool = pin.ModelPool(pmodel, 1)
    qT, qdT, qddT = (np.asfortranarray(x.T) for x in (q, qd, qdd))
    tauT = np.empty((6, N), order="F")

    def run_c():
        batch(N, *(np.ascontiguousarray(x).ctypes.data_as(dp) for x in (q, qd, qdd)),
              tau_c.ctypes.data_as(dp))

    def run_loop():
        for k in range(N):
            pin.rnea(pmodel, pdata, q[k], qd[k], qdd[k])

    def run_batched():
        pin.rneaInParallel(1, pool, qT, qdT, qddT, tauT)

    times = {"c": [], "loop": [], "batched": []}
    for _ in range(args.runs):
        for name, fn in (("c", run_c), ("loop", run_loop), ("batched", run_batched)):
            t0 = time.perf_counter()
            fn()
            times[name].append(time.perf_counter() - t0)
    ref = tauT.T
    scale = np.abs(ref).max(axis=0)
    print(f"simplified PUMA 560 model, EPS = {args.eps:g}: {cost['multiplications']} mult, "
          f"{cost['additions']} add, {cost['sin']} sin, {cost['cos']} cos per set point")
    import os

    print(f"{N} random set points within the joint limits, {args.runs} interleaved runs; "
          f"load average {os.getloadavg()[0]:.2f} on {os.cpu_count()} cores at the start")
    print(f"largest |tau_c - rnea| / peak |rnea| per joint on these states (not guaranteed off "
          f"the trajectory): {np.array2string(np.abs(tau_c - ref).max(axis=0) / scale, precision=2)}")
    c = np.array(times["c"])
    for name, label in (("loop", "rnea in a Python loop"),
                        ("batched", "rneaInParallel, 1 thread")):
        r = np.array(times[name]) / c
        print(f"{label:<28} / compiled C: median {np.median(r):8.2f}  range "
              f"[{r.min():.2f}, {r.max():.2f}]   (per set point: C "
              f"{np.median(c) / N * 1e9:.0f} ns, {name} {np.median(times[name]) / N * 1e9:.0f} ns)")


if __name__ == "__main__":
    main()
