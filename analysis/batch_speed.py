"""Time the emitted C's batch entry point against its single-state call and Pinocchio's rnea.

For each robot (default the PUMA 560 and the Panda) the script builds the model of the emitted
files (``SimplifiedModel.sources``) at each EPS (default 0, the exact customized recursive
Newton-Euler model on base parameters, and 0.01, pruned on 60 random states), writes its C and
compiles it as the header's comment says for the batch functions (``cc -std=c99 -O3
-march=native``, no -ffast-math: GCC's vectoriser calls glibc's libmvec sin and cos), together
with a second file (another translation unit, so nothing is inlined: a user's call) that calls
``PREFIXtau`` once per state in a loop. On N random states (default 10^6, q within the joint
limits, qd and qdd within the robot's limits: :func:`gd_analyze.dynamics.base_parameters
.random_states`) it times, in R interleaved rounds (the order rotated from round to round):

- ``single``: ``PREFIXtau`` called state after state (the C loop above);
- ``batch``: one call of ``PREFIXtau_batch(N, q, qd, qdd, tau)``;
- ``rnea``: Pinocchio's C++ ``rnea`` over the same states, ``rneaInParallel`` with one thread
  (the installed wheel's build, batched in C++, no Python per state).

Times are CPU time of this process (``time.process_time``) per state; the script prints each
one's median and range over the rounds, and the per-round ratios single / batch (the batch
speed-up) and batch / rnea, median and range. Checks (exit 1 if one fails): the batch torques
equal the single-state ones to 1e-13 of peak |tau_i| per joint, and at EPS = 0 Pinocchio's to
1e-10. The load average is printed at the start and the end: the machine is shared.

Usage: python analysis/batch_speed.py [--states N] [--runs R] [--eps EPS [EPS ...]]
       [--robots NAME [NAME ...]]
"""

import argparse
import ctypes
import os
import platform
import re
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import pinocchio as pin

from gd_analyze import SimplifiedModel, load_robot
from gd_analyze.dynamics.base_parameters import random_states
from gd_analyze.dynamics.pinocchio import pinocchio_model
from gd_analyze.ranking.labels import element_labels
from gd_analyze.symbolic.recursive_model import recursive_model

DP = ctypes.POINTER(ctypes.c_double)
#: The batch call against the single-state call, relative to peak |tau_i|.
BATCH_TOLERANCE = 1e-13
#: The exact model against rnea, relative to peak |tau_i|.
EXACT_TOLERANCE = 1e-10
PREFIX = "m_"
LOOP = """
#include "simplified_model.h"

void loop_single(long n, const double *q, const double *qd, const double *qdd, double *tau)
{
    long k;
    for (k = 0; k < n; ++k)
        m_tau(q + m_N_JOINTS * k, qd + m_N_JOINTS * k, qdd + m_N_JOINTS * k,
              tau + m_N_JOINTS * k);
}
"""


def build(robot, eps):
    """The model of the emitted files: the recursive model pruned within EPS on 60 random
    states (exact at EPS = 0)."""
    q, qd, qdd = random_states(robot, 60, 4)
    rec = recursive_model(robot, q, qd, qdd, eps)
    return SimplifiedModel(robot=robot, choices={k: "both" for k in element_labels(robot.n)},
                           dominance_threshold=0.9, negligible_threshold=0.01, rule="budget",
                           tolerance=eps, recursive=rec)


def compile_model(model, folder):
    """Write the model's files, compile them with the header's batch line; the two calls."""
    for file, text in model.sources(prefix=PREFIX).items():
        (folder / file).write_text(text, encoding="utf-8")
    header = (folder / "simplified_model.h").read_text()
    line = re.search(r"^ \*     (cc .*) \(link with -lm\)$", header, re.M).group(1).split()
    (folder / "loop.c").write_text(LOOP)
    flags = line[1:-2] + ["-fPIC"]
    objs = []
    for src in ("simplified_model.c", "loop.c"):
        objs.append(str(folder / (src[:-2] + ".o")))
        subprocess.run(["cc", *flags, "-c", str(folder / src), "-o", objs[-1]], check=True,
                       cwd=folder)
    lib = folder / "libmodel.so"
    subprocess.run(["cc", "-shared", "-o", str(lib), *objs, "-lm"], check=True)
    undefined = subprocess.run(["nm", "-u", objs[0]], check=True, capture_output=True,
                               text=True).stdout.split()
    handle = ctypes.CDLL(str(lib))
    fns = {"single": handle.loop_single, "batch": handle[PREFIX + "tau_batch"]}
    for fn in fns.values():
        fn.argtypes, fn.restype = [ctypes.c_long, DP, DP, DP, DP], None
    return fns, " ".join(line), sorted(s for s in undefined if s.startswith("_ZGV"))


def stats(values):
    v = np.asarray(values)
    return f"{np.median(v):8.3f} [{v.min():.3f}, {v.max():.3f}]"


def bench(name, eps, args, folder):
    """Build, check and time one model; False if a check fails."""
    robot = load_robot(name)
    n, N = robot.n, args.states
    t0 = time.perf_counter()
    model = build(robot, eps)
    fns, line, vector = compile_model(model, folder)
    built = time.perf_counter() - t0
    q, qd, qdd = (np.ascontiguousarray(x) for x in random_states(robot, N, 7))
    ptrs = [x.ctypes.data_as(DP) for x in (q, qd, qdd)]
    tau = {k: np.full((N, n), np.nan) for k in fns}
    pmodel = pinocchio_model(robot)
    pool = pin.ModelPool(pmodel, 1)
    qT, qdT, qddT = (np.asfortranarray(x.T) for x in (q, qd, qdd))
    tauT = np.empty((n, N), order="F")

    runners = {k: (lambda f=f, out=tau[k]: f(N, *ptrs, out.ctypes.data_as(DP)))
               for k, f in fns.items()}
    runners["rnea"] = lambda: pin.rneaInParallel(1, pool, qT, qdT, qddT, tauT)
    order = list(runners)
    times = {k: [] for k in order}
    for r in range(args.runs):
        for k in order[r % len(order):] + order[:r % len(order)]:
            t = time.process_time()
            runners[k]()
            times[k].append((time.process_time() - t) / N * 1e9)

    peak = np.abs(tau["single"]).max(axis=0)
    err_batch = float((np.abs(tau["batch"] - tau["single"]) / peak).max())
    err_rnea = float((np.abs(tau["batch"] - tauT.T) / peak).max())
    ok = bool(np.isfinite(tau["batch"]).all()) and err_batch <= BATCH_TOLERANCE
    if eps == 0:
        ok = ok and err_rnea <= EXACT_TOLERANCE
    cost = model.functions().programs["tau"].cost()
    print(f"\n{name}, EPS = {eps:g}: tau {cost['multiplications']} mult, "
          f"{cost['additions']} add, {cost['sin']} sin, {cost['cos']} cos "
          f"(built and compiled in {built:.1f} s)")
    print(f"  compiled: {line}; vector sin/cos called: {', '.join(vector) or 'none'}")
    print(f"  max |batch - single| / peak |tau_i| = {err_batch:.1e} (<= {BATCH_TOLERANCE:g}); "
          f"max |batch - rnea| / peak |tau_i| = {err_rnea:.1e}"
          + (f" (<= {EXACT_TOLERANCE:g})" if eps == 0 else " (pruned model)"))
    print(f"  {'CPU ns per state, median [range]':<44}")
    labels = {"single": "PREFIXtau, a C loop", "batch": "PREFIXtau_batch",
              "rnea": "Pinocchio rnea (rneaInParallel, 1 thread)"}
    for k in order:
        print(f"    {labels[k]:<42} {stats(times[k])}")
    speed = np.array(times["single"]) / np.array(times["batch"])
    print(f"    speed-up single / batch, per round        {stats(speed)}")
    print(f"    batch / rnea, per round                   "
          f"{stats(np.array(times['batch']) / np.array(times['rnea']))}")
    print(f"    single / rnea, per round                  "
          f"{stats(np.array(times['single']) / np.array(times['rnea']))}")
    if not ok:
        print("  CHECK FAILED", file=sys.stderr)
    return ok


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--states", type=int, default=1_000_000)
    ap.add_argument("--runs", type=int, default=7)
    ap.add_argument("--eps", type=float, nargs="+", default=[0.0, 0.01])
    ap.add_argument("--robots", nargs="+", default=["puma560", "panda"])
    args = ap.parse_args()
    cc = subprocess.run(["cc", "--version"], capture_output=True, text=True).stdout
    print(f"{args.states} states, {args.runs} interleaved rounds; {platform.machine()}, "
          f"{cc.splitlines()[0] if cc else 'cc'}, pinocchio {pin.__version__}; "
          f"load average {os.getloadavg()[0]:.2f}")
    ok = True
    with tempfile.TemporaryDirectory(prefix="gd-batch-") as tmp:
        for name in args.robots:
            for eps in args.eps:
                folder = Path(tmp) / f"{name}_{eps:g}"
                folder.mkdir()
                ok = bench(name, eps, args, folder) and ok
    print(f"\nload average at the end {os.getloadavg()[0]:.2f}")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
