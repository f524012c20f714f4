"""Speed of the G-D terms against Pinocchio, measured side by side in one process.

    python analysis/benchmark.py [--setpoints N] [--runs R] [--no-latency]

For N random PUMA 560 states (default 100,000) it times
  (a) gd_analyze.gd_terms -> D_tran, D_rot, h_tran, h_rot, c (batched);
  (b) Pinocchio crba + nonLinearEffects + computeGeneralizedGravity in a Python loop that
      keeps the results (and, as the most demanding reference, the same calls discarding them);
  (c) the Pinocchio split: crba + nonLinearEffects on the zero-rotational-inertia model and on
      the zero-mass model (4 calls) plus computeGeneralizedGravity, in a Python loop;
  (d) separately (batched_rnea_comparison): gd_terms writing into buffers allocated once,
      against Pinocchio's batched C++ RNEA (pin.rneaInParallel, one thread, tau only), runs
      interleaved, the same number on each side (--runs), median and [min, max];
checks that (a) agrees with (b) and (c), and times the main job
`gd-analyze puma560 data/puma560_trajectory.csv` (HDF5, HTML, PDF) against a bare
`python -c "import numpy, scipy, xarray, matplotlib.pyplot, pinocchio"`.

Prints one JSON line: microseconds per set point for a, b, c, the ratios a/b and a/c, the
main-job latency ratio, and the peak resident memory. Ratios, not absolute times, are what
carry over between machines.
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]


def best_of(fn, repeat):
    """Best wall time of `repeat` calls [s], and the last result."""
    best, out = np.inf, None
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - t0)
    return best, out


def pinocchio_loop(robot, q, qd):
    import pinocchio as pin

    from gd_analyze.formulations.pinocchio import pinocchio_model

    model = pinocchio_model(robot)
    data = model.createData()
    free = model.copy()
    free.gravity = pin.Motion.Zero()
    fdata = free.createData()
    N, n = q.shape
    D, h, c = np.empty((N, n, n)), np.empty((N, n)), np.empty((N, n))
    for k in range(N):
        D[k] = pin.crba(free, fdata, q[k])
        h[k] = pin.nonLinearEffects(free, fdata, q[k], qd[k])
        c[k] = pin.computeGeneralizedGravity(model, data, q[k])
    return D, h, c


def pinocchio_calls_only(robot, q, qd):
    """(b) without keeping the results: the fastest a Python loop over Pinocchio can be."""
    import pinocchio as pin

    from gd_analyze.formulations.pinocchio import pinocchio_model

    model = pinocchio_model(robot)
    data = model.createData()
    free = model.copy()
    free.gravity = pin.Motion.Zero()
    fdata = free.createData()
    crba, nle, grav = pin.crba, pin.nonLinearEffects, pin.computeGeneralizedGravity
    for k in range(q.shape[0]):
        crba(free, fdata, q[k])
        nle(free, fdata, q[k], qd[k])
        grav(model, data, q[k])


def pinocchio_split(robot, q, qd):
    import pinocchio as pin

    from gd_analyze.formulations.pinocchio import pinocchio_model

    models = []
    for part in ("tran", "rot"):
        m = pinocchio_model(robot, part)
        m.gravity = pin.Motion.Zero()
        models.append((m, m.createData()))
    full = pinocchio_model(robot)
    fdata = full.createData()
    (mt, dt), (mr, dr) = models
    N, n = q.shape
    Dt, Dr = np.empty((N, n, n)), np.empty((N, n, n))
    ht, hr, c = np.empty((N, n)), np.empty((N, n)), np.empty((N, n))
    for k in range(N):
        Dt[k] = pin.crba(mt, dt, q[k])
        ht[k] = pin.nonLinearEffects(mt, dt, q[k], qd[k])
        Dr[k] = pin.crba(mr, dr, q[k])
        hr[k] = pin.nonLinearEffects(mr, dr, q[k], qd[k])
        c[k] = pin.computeGeneralizedGravity(full, fdata, q[k])
    return Dt, Dr, ht, hr, c


def batched_rnea_comparison(robot, q, qd, qdd, runs):
    """(d) G-D terms into reused buffers against Pinocchio's batched C++ RNEA (tau only).

    Both sides run ``runs`` times, interleaved (a, d, a, d, ...), on the same N states:
    gd_analyze.gd_terms(engine="compiled", out=buffers allocated once) and
    pin.rneaInParallel(1 thread, a ModelPool of one model, column-major q, qd, qdd, tau).
    Returns the median and [min, max] per set point [us] of each, their ratio, and the largest
    relative difference of G-D's tau = D qdd + h + c from RNEA's tau.
    """
    import pinocchio as pin

    from gd_analyze import gd_terms
    from gd_analyze.core.dalembert import allocate_terms
    from gd_analyze.formulations.pinocchio import pinocchio_model

    N, n = q.shape
    buf = allocate_terms(N, n)
    pool = pin.ModelPool(pinocchio_model(robot), 1)
    Q, V, A = (np.asfortranarray(x.T) for x in (q, qd, qdd))
    tau = np.zeros((n, N), order="F")

    def gd():
        return gd_terms(robot, q, qd, engine="compiled", out=buf)

    def rnea():
        pin.rneaInParallel(1, pool, Q, V, A, tau)

    gd(), rnea()                                   # warm: kernel loaded, buffers touched
    disagreement = float(np.abs(gd().tau(qdd) - tau.T).max() / np.abs(tau).max())
    t_gd, t_rnea = [], []
    for _ in range(runs):
        for fn, acc in ((gd, t_gd), (rnea, t_rnea)):
            t0 = time.perf_counter()
            fn()
            acc.append((time.perf_counter() - t0) * 1e6 / N)
    return {"runs": runs, "gd_terms_reused_buffers_us": float(np.median(t_gd)),
            "gd_range_us": [min(t_gd), max(t_gd)],
            "rnea_in_parallel_1_thread_us": float(np.median(t_rnea)),
            "rnea_range_us": [min(t_rnea), max(t_rnea)],
            "ratio_gd_over_rnea_batched": float(np.median(t_gd) / np.median(t_rnea)),
            "tau_rel_disagreement": disagreement}


def _upper(D):
    """crba fills the upper triangle only: mirror it."""
    return np.triu(D) + np.swapaxes(np.triu(D, 1), 1, 2)


def latency(repeat=3):
    """Main job wall time over bare-import wall time, best of `repeat` each [s, s, ratio]."""
    exe = Path(sys.executable).parent / "gd-analyze"
    bare = [sys.executable, "-c", "import numpy, scipy, xarray, matplotlib.pyplot, pinocchio"]
    with tempfile.TemporaryDirectory() as tmp:
        job = [str(exe), "puma560", str(ROOT / "data" / "puma560_trajectory.csv"), "-o", tmp,
               "-q"]
        subprocess.run(job, check=True, capture_output=True)        # warm the caches once
        t_bare = best_of(lambda: subprocess.run(bare, check=True), repeat)[0]
        t_job = best_of(lambda: subprocess.run(job, check=True, capture_output=True), repeat)[0]
    return t_job, t_bare, t_job / t_bare


def main(argv=None):
    """Run the benchmark and print one JSON line.

    Parameters
    ----------
    argv : list of str, optional
        Command-line arguments.
    """
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--setpoints", type=int, default=100_000)
    parser.add_argument("--no-latency", action="store_true", help="skip the main-job timing")
    parser.add_argument("--runs", type=int, default=7,
                        help="interleaved runs of (d), each side (default 7)")
    args = parser.parse_args(argv)

    from gd_analyze import gd_terms, load_robot
    from gd_analyze.formulations.pinocchio import relative_error

    robot = load_robot("puma560")
    N = args.setpoints
    rng = np.random.default_rng(2026)
    q = rng.uniform(robot.q_min, robot.q_max, (N, robot.n))
    qd = rng.uniform(-robot.qd_max, robot.qd_max, (N, robot.n))

    t0 = time.perf_counter()
    gd_terms(robot, q[:10], qd[:10], engine="compiled")       # load or compile the kernel
    first_call = time.perf_counter() - t0
    t_a, terms = best_of(lambda: gd_terms(robot, q, qd), 3)
    t_b, (D, h, c) = best_of(lambda: pinocchio_loop(robot, q, qd), 1)
    t_b0, _ = best_of(lambda: pinocchio_calls_only(robot, q, qd), 2)
    t_c, (Dt, Dr, ht, hr, c2) = best_of(lambda: pinocchio_split(robot, q, qd), 1)
    t_np, _ = best_of(lambda: gd_terms(robot, q[:20000], qd[:20000], engine="numpy"), 1)

    qdd = rng.uniform(-robot.qdd_max, robot.qdd_max, (N, robot.n))
    batched = batched_rnea_comparison(robot, q, qd, qdd, args.runs)

    agreement = {
        "D_vs_crba": relative_error(terms.D, _upper(D)),
        "h_vs_nonLinearEffects": relative_error(terms.h, h),
        "c_vs_computeGeneralizedGravity": relative_error(terms.c, c),
        "D_tran_vs_split": relative_error(terms.D_tran, _upper(Dt)),
        "D_rot_vs_split": relative_error(terms.D_rot, _upper(Dr)),
        "h_tran_vs_split": relative_error(terms.h_tran, ht),
        "h_rot_vs_split": relative_error(terms.h_rot, hr),
    }
    us = 1e6 / N
    result = {
        "setpoints": N,
        "a_gd_terms_us": t_a * us,
        "b_pinocchio_D_h_c_us": t_b * us,
        "c_pinocchio_split_us": t_c * us,
        "ratio_a_over_b": t_a / t_b,
        "ratio_a_over_c": t_a / t_c,
        "b_calls_only_us": t_b0 * us,
        "ratio_a_over_b_calls_only": t_a / t_b0,
        "numpy_engine_us": t_np * 1e6 / 20000,
        "ratio_numpy_engine_over_b": (t_np / 20000) / (t_b / N),
        "kernel_first_call_s": first_call,
        "d_rnea_batched": batched,
        "max_rel_disagreement": max(max(agreement.values()), batched["tau_rel_disagreement"]),
        "agreement": agreement,
    }
    if not args.no_latency:
        t_job, t_bare, ratio = latency()
        result.update(main_job_s=t_job, bare_import_s=t_bare, ratio_main_job_over_import=ratio)
    result["peak_rss_mib"] = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    print(json.dumps(result))
    if result["max_rel_disagreement"] > 1e-10:
        print("benchmark: results disagree with Pinocchio", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    os.environ.setdefault("MPLBACKEND", "Agg")
    sys.exit(main())
