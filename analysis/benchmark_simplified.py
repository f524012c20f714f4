"""Time the compiled exact and EPS models against Pinocchio rnea, side by side, per robot.

For each robot (default the PUMA 560 and the Panda, on their shipped trajectories
data/<robot>_trajectory.csv) two models are emitted as C (``gd_tau``) and compiled
with ``cc -O2 -shared -fPIC`` together with a batch loop over set points:

- the exact customized recursive Newton-Euler model on base parameters
  (:func:`gd_analyze.symbolic.recursive.recursive_program`);
- the model the main job deploys at EPS (``analyze(robot, trajectory, AnalysisOptions(verify=False, formulations=False)).model``:
  the cheapest simplified model within the error budget on the trajectory).

They are timed on the same N random set points (q within the joint limits, else +-pi; qd within
+-qd_max; qdd within the acceleration limits of :func:`gd_analyze.model.limits.acceleration_limits`)
against Pinocchio ``rneaInParallel`` with one thread (batched in C++) and ``rnea`` called in a
Python loop over the same N set points. Runs are interleaved, R rounds, each round one run of
each of the four (the order rotated from round to round), so each side gets R runs. The script
prints each model's counted operations (``Program.cost()``), each time per set point (median
and range over the rounds) and the ratios to ``rneaInParallel`` (median and range of the
per-round ratios). Each compiled model's output of its last timed run is checked against
``rnea`` on the same set points (largest error relative to peak |tau_i|): the exact model must
agree to 1e-10 (else exit 1); the EPS model is built for the trajectory, not for these random
states, so its error is only printed. The load average is printed at the start and the end:
timings on a shared machine are noisy.

Usage: python analysis/benchmark_simplified.py [--setpoints N] [--runs R] [--eps EPS]
       [--robots NAME [NAME ...]]
"""

import argparse
import ctypes
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import pinocchio as pin

from gd_analyze import load_robot
from gd_analyze.dynamics.pinocchio import pinocchio_model
from gd_analyze.jobs.analyze import analyze
from gd_analyze.jobs.options import AnalysisOptions, SimplifyOptions
from gd_analyze.model.limits import acceleration_limits
from gd_analyze.symbolic.emit import emit_c
from gd_analyze.symbolic.recursive import recursive_program
from gd_analyze.symbolic.safe_text import comment_safe
from gd_analyze.trajectory.trajectory import read_trajectory

ROOT = Path(__file__).resolve().parents[1]
#: Largest relative disagreement of the exact compiled model with rnea.
EXACT_TOLERANCE = 1e-10
BATCH = """
void gd_simplified_batch(long count, const double *q, const double *qd, const double *qdd,
                         double *tau)
{{
    for (long k = 0; k < count; ++k)
        gd_tau(q + {n} * k, qd + {n} * k, qdd + {n} * k, tau + {n} * k);
}}
"""
DP = ctypes.POINTER(ctypes.c_double)


def compile_batch(source, n, folder, name):
    """Compile C source of ``gd_tau`` plus a batch loop; return the batch function."""
    c_file, lib = folder / f"{name}.c", folder / f"lib{name}.so"
    c_file.write_text(source + BATCH.format(n=n))
    subprocess.run(["cc", "-O2", "-shared", "-fPIC", "-o", str(lib), str(c_file), "-lm"],
                   check=True)
    fn = ctypes.CDLL(str(lib)).gd_simplified_batch
    fn.argtypes, fn.restype = [ctypes.c_long, DP, DP, DP, DP], None
    return fn


def random_set_points(robot, count, seed=0):
    """q, qd, qdd of shape (count, n) within the robot's limits (C-contiguous)."""
    rng = np.random.default_rng(seed)
    lo = np.where(np.isfinite(robot.q_min), robot.q_min, -np.pi)
    hi = np.where(np.isfinite(robot.q_max), robot.q_max, np.pi)
    qdd_max, qdd_source = acceleration_limits(robot)
    n = robot.n
    q = rng.uniform(lo, hi, (count, n))
    qd = rng.uniform(-1, 1, (count, n)) * robot.qd_max
    qdd = rng.uniform(-1, 1, (count, n)) * qdd_max
    return q, qd, qdd, qdd_source


def fmt_cost(c):
    return (f"{c['multiplications']} mult, {c['additions']} add, {c['sin']} sin, "
            f"{c['cos']} cos")


def bench_robot(name, args):
    """Build, check and time one robot's models; return False if the exact model disagrees."""
    robot = load_robot(name)
    n, N = robot.n, args.setpoints
    traj = read_trajectory(ROOT / "data" / f"{name}_trajectory.csv", n)
    exact = recursive_program(robot)
    model = analyze(robot, traj, AnalysisOptions(verify=False, formulations=False, simplify=SimplifyOptions(tolerance=args.eps))).model
    deployed = model.program()
    tmp = Path(tempfile.mkdtemp(prefix="gd-bench-"))
    header = {"gd-analyze benchmark": "exact customized recursive Newton-Euler model",
              "robot": comment_safe(robot.name, digest=True),
              "robot file sha256": robot.sha256}
    c_fn = {"exact": compile_batch(emit_c(exact, header), n, tmp, "exact"),
            "eps": compile_batch(emit_c(deployed, header), n, tmp, "eps")}

    q, qd, qdd, qdd_source = random_set_points(robot, N)
    pmodel = pinocchio_model(robot)
    pdata = pmodel.createData()
    pool = pin.ModelPool(pmodel, 1)
    qT, qdT, qddT = (np.asfortranarray(x.T) for x in (q, qd, qdd))
    tauT = np.empty((n, N), order="F")
    tau = {k: np.empty((N, n)) for k in c_fn}
    ptrs = [x.ctypes.data_as(DP) for x in (q, qd, qdd)]
    out_ptr = {k: v.ctypes.data_as(DP) for k, v in tau.items()}
    ref = np.array([pin.rnea(pmodel, pdata, q[k], qd[k], qdd[k]) for k in range(N)])

    def c_runner(key):
        return lambda: c_fn[key](N, *ptrs, out_ptr[key])

    def run_loop():
        for k in range(N):
            pin.rnea(pmodel, pdata, q[k], qd[k], qdd[k])

    def run_batched():
        pin.rneaInParallel(1, pool, qT, qdT, qddT, tauT)

    runners = {"exact": c_runner("exact"), "eps": c_runner("eps"), "batched": run_batched,
               "loop": run_loop}
    for fn in runners.values():                       # warm-up, untimed
        fn()
    order = list(runners)
    times = {k: [] for k in runners}
    for r in range(args.runs):
        for key in order[r % 4:] + order[:r % 4]:
            t0 = time.perf_counter()
            runners[key]()
            times[key].append(time.perf_counter() - t0)
    times = {k: np.array(v) for k, v in times.items()}

    scale = np.abs(ref).max(axis=0)
    err = {k: np.abs(v - ref).max(axis=0) / scale for k, v in tau.items()}
    err["batched"] = np.abs(tauT.T - ref).max(axis=0) / scale
    bad = [k for k, e in err.items() if not np.isfinite(e).all()]
    ok = err["exact"].max() <= EXACT_TOLERANCE and not bad

    labels = {"exact": "exact recursive, C",
              "eps": f"deployed EPS = {args.eps:g} ({model.form}), C",
              "batched": "rneaInParallel, 1 thread", "loop": "rnea, Python loop"}
    print(f"\n== {name}: n = {n}, trajectory data/{name}_trajectory.csv "
          f"({traj.q.shape[0]} set points) ==")
    print(f"{N} random set points (q within the joint limits, qd within qd_max, qdd within "
          f"qdd_max: {qdd_source}); {args.runs} interleaved rounds, one run of each per round")
    print(f"counted operations per set point: exact {fmt_cost(exact.cost())}; "
          f"deployed {fmt_cost(deployed.cost())}")
    for key, label in (("exact", "exact"), ("eps", "deployed"), ("batched", "rneaInParallel")):
        e = err[key]
        print(f"  {label:<15} max |tau - rnea| / peak |rnea_i| = {e.max():.2e}  per joint "
              f"{np.array2string(e, precision=1, separator=' ')}")
    print(f"  exact model within {EXACT_TOLERANCE:g}: {'yes' if ok else 'NO'}; the deployed "
          "model is budgeted on the trajectory, not on these random states")
    print(f"  {'':<34} {'ns per set point':>27}   {'ratio to rneaInParallel':>27}")
    print(f"  {'':<34} {'median':>8} {'range':>18}   {'median':>8} {'range':>18}")
    for key in ("exact", "eps", "batched", "loop"):
        t = times[key] / N * 1e9
        r = times[key] / times["batched"]
        print(f"  {labels[key]:<34} {np.median(t):8.0f} [{t.min():7.0f}, {t.max():7.0f}]   "
              f"{np.median(r):8.3f} [{r.min():7.3f}, {r.max():7.3f}]")
    r = times["eps"] / times["exact"]
    print(f"  deployed / exact (C): median {np.median(r):.3f}, range [{r.min():.3f}, "
          f"{r.max():.3f}]")
    return ok


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--setpoints", type=int, default=100_000, help="N (default 100,000)")
    ap.add_argument("--runs", type=int, default=7, help="interleaved rounds (default 7)")
    ap.add_argument("--eps", type=float, default=0.01, help="EPS of the deployed model")
    ap.add_argument("--robots", nargs="+", default=["puma560", "panda"],
                    help="built-in robots with a trajectory data/<robot>_trajectory.csv")
    args = ap.parse_args()
    if args.setpoints < 1 or args.runs < 1:
        ap.error("--setpoints and --runs must be at least 1")
    for name in args.robots:
        if not (ROOT / "data" / f"{name}_trajectory.csv").is_file():
            ap.error(f"no trajectory data/{name}_trajectory.csv for robot {name!r}")
    cc = subprocess.run(["cc", "--version"], capture_output=True, text=True).stdout
    la = os.getloadavg()
    print(f"load average {la[0]:.2f} {la[1]:.2f} {la[2]:.2f} on {os.cpu_count()} cores at the "
          f"start; "
          f"pinocchio {pin.__version__}; {cc.splitlines()[0] if cc else 'cc'} -O2")
    ok = all([bench_robot(name, args) for name in args.robots])
    la = os.getloadavg()
    print(f"\nload average {la[0]:.2f} {la[1]:.2f} {la[2]:.2f} at the end")
    sys.exit(0 if ok else 1)


if __name__ == "__main__":
    main()
