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

Every comparison is timed interleaved (a, b, b, a, ...) with the same number of runs on each
side (--runs, default 5; --latency-runs rounds for the main job, default 5; --baseline SRC
adds another checkout's main job, e.g. /work/main/src, to the same rounds). Prints one JSON
line: microseconds per set point (medians) for a, b, c, and for each comparison the median of
the per-pair ratios with its range (min, max). Ratios, not absolute times, are what carry over
between machines.
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


def interleaved(fa, fb, runs):
    """Time two callables side by side: a, b, a, b, ... (b first on odd runs), ``runs`` each.

    Returns
    -------
    dict
        ``median_ratio`` (median of the per-pair ratios t_a / t_b), ``min_ratio``,
        ``max_ratio``, ``runs``, ``median_a_s`` and ``median_b_s``; the last results under
        ``"results"`` (a, b).
    """
    ta, tb, out = [], [], [None, None]
    for k in range(runs):
        order = ((0, fa, ta), (1, fb, tb)) if k % 2 == 0 else ((1, fb, tb), (0, fa, ta))
        for slot, fn, times in order:
            t0 = time.perf_counter()
            out[slot] = fn()
            times.append(time.perf_counter() - t0)
    ratios = np.asarray(ta) / np.asarray(tb)
    return {"median_ratio": float(np.median(ratios)), "min_ratio": float(ratios.min()),
            "max_ratio": float(ratios.max()), "runs": runs,
            "median_a_s": float(np.median(ta)), "median_b_s": float(np.median(tb)),
            "results": tuple(out)}


def _summary(r):
    return {k: v for k, v in r.items() if k != "results"}


def pinocchio_loop(robot, q, qd):
    import pinocchio as pin

    from gd_analyze.dynamics.pinocchio import pinocchio_model

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

    from gd_analyze.dynamics.pinocchio import pinocchio_model

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

    from gd_analyze.dynamics.pinocchio import pinocchio_model

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

    Both sides run ``runs`` times, interleaved (:func:`interleaved`), on the same N states:
    gd_analyze.gd_terms(out=buffers allocated once) and
    pin.rneaInParallel(1 thread, a ModelPool of one model, column-major q, qd, qdd, tau).
    Returns the median per set point [us] of each, the median of the per-pair ratios with its
    range, and the largest relative difference of G-D's tau = D qdd + h + c from RNEA's tau.
    """
    import pinocchio as pin

    from gd_analyze import gd_terms
    from gd_analyze.dynamics.dalembert import allocate_terms
    from gd_analyze.dynamics.pinocchio import pinocchio_model

    N, n = q.shape
    buf = allocate_terms(N, n)
    pool = pin.ModelPool(pinocchio_model(robot), 1)
    Q, V, A = (np.asfortranarray(x.T) for x in (q, qd, qdd))
    tau = np.zeros((n, N), order="F")

    def gd():
        return gd_terms(robot, q, qd, out=buf)

    def rnea():
        pin.rneaInParallel(1, pool, Q, V, A, tau)

    gd(), rnea()                                   # warm: kernel loaded, buffers touched
    disagreement = float(np.abs(gd().tau(qdd) - tau.T).max() / np.abs(tau).max())
    r = interleaved(gd, rnea, runs)
    return {"runs": runs, "gd_terms_reused_buffers_us": r["median_a_s"] * 1e6 / N,
            "rnea_in_parallel_1_thread_us": r["median_b_s"] * 1e6 / N,
            "gd_over_rnea_batched": _summary(r),
            "tau_rel_disagreement": disagreement}


def _upper(D):
    """crba fills the upper triangle only: mirror it."""
    return np.triu(D) + np.swapaxes(np.triu(D, 1), 1, 2)


BARE_IMPORT = "import numpy, scipy, xarray, matplotlib.pyplot, pinocchio"


def rounds(fns, runs):
    """Time several callables in rounds, each once per round, the order rotated each round.

    Parameters
    ----------
    fns : list of callable
        The last one is the reference every other is divided by, within its round.
    runs : int
        Rounds.

    Returns
    -------
    list of dict
        One per callable but the last: ``median_ratio``, ``min_ratio``, ``max_ratio`` (its
        time over the reference's of the same round), ``runs``, ``median_a_s`` (its median
        time) and ``median_b_s`` (the reference's). Where the callables run child processes,
        also ``median_cpu_a_s`` and ``median_cpu_b_s``: the children's CPU time (user +
        system) per run, steadier than wall time on a shared machine.
    """
    times = [[] for _ in fns]
    cpu = [[] for _ in fns]
    m = len(fns)
    for k in range(runs):
        for j in range(m):
            slot = (j + k) % m
            r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
            t0 = time.perf_counter()
            fns[slot]()
            times[slot].append(time.perf_counter() - t0)
            r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
            cpu[slot].append(r1.ru_utime - r0.ru_utime + r1.ru_stime - r0.ru_stime)
    ref = np.asarray(times[-1])
    out = []
    for t, c in zip(times[:-1], cpu[:-1]):
        ratios = np.asarray(t) / ref
        out.append({"median_ratio": float(np.median(ratios)), "min_ratio": float(ratios.min()),
                    "max_ratio": float(ratios.max()), "runs": runs,
                    "median_a_s": float(np.median(t)), "median_b_s": float(np.median(ref))})
        if min(c) > 0:                          # child processes: their CPU time too
            out[-1].update(median_cpu_a_s=float(np.median(c)),
                           median_cpu_b_s=float(np.median(cpu[-1])))
    return out


def _job(command, env):
    done = subprocess.run(command, capture_output=True, text=True, env=env)
    if done.returncode != 0:
        raise RuntimeError(f"{' '.join(command)} exited {done.returncode} "
                           f"(PYTHONPATH={env.get('PYTHONPATH')}): {done.stderr[-2000:]}")
    return done


def latency(runs=5, baseline=None):
    """The main job on the shipped trajectory against a bare import, in interleaved rounds.

    The main job is ``python -m gd_analyze.cli puma560 data/puma560_trajectory.csv -o TMP -q``
    (HDF5, JSON, the model's sources, HTML, PDF and the figure files), run with this
    checkout's ``src`` first on ``PYTHONPATH``; the reference is ``python -c "import numpy,
    scipy, xarray, matplotlib.pyplot, pinocchio"``. One warm-up run of each first (file
    caches), then ``runs`` rounds, the order rotated each round. Every side runs with
    Python's default settings: a ``PYTHONDONTWRITEBYTECODE`` in the caller's environment is
    dropped, so the warm-up leaves the byte-code of gd_analyze as any first run (or a
    non-editable install) does.

    Parameters
    ----------
    runs : int, optional
        Rounds.
    baseline : str or os.PathLike, optional
        Another checkout's ``src`` folder (e.g. the main branch's): its main job is timed in
        the same rounds, with that folder first on ``PYTHONPATH``, against the same bare
        import.

    Returns
    -------
    dict
        ``job``: as :func:`rounds`, the job over the bare import; ``job_no_report``: the
        same with ``--no-report``; ``baseline`` (with its report) likewise, if given; ``load_average``: the one-minute load average before and after.
    """
    env = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}
    env["MPLBACKEND"] = "Agg"           # default Python settings: the warm-up writes .pyc
    bare = [sys.executable, "-c", BARE_IMPORT]
    srcs = [ROOT / "src"] + ([Path(baseline).resolve()] if baseline else [])
    load = [os.getloadavg()[0]]
    with tempfile.TemporaryDirectory() as tmp:
        fns = []
        for k, src in enumerate(srcs):
            job = [sys.executable, "-m", "gd_analyze.cli", "puma560",
                   str(ROOT / "data" / "puma560_trajectory.csv"), "-o", f"{tmp}/out{k}", "-q"]
            side = {**env, "PYTHONPATH": os.pathsep.join(
                [str(src)] + [p for p in [env.get("PYTHONPATH")] if p])}
            # this checkout's job with its report, then without (limits 4 and 2.5)
            jobs = [job] + ([job[:-2] + [f"{tmp}/plain{k}", "-q", "--no-report"]]
                            if k == 0 else [])
            for one in jobs:
                _job(one, side)                             # warm up
                fns.append(lambda one=one, side=side: _job(one, side))
        subprocess.run(bare, check=True, env=env)
        fns.append(lambda: subprocess.run(bare, check=True, env=env))
        result = rounds(fns, runs)
    load.append(os.getloadavg()[0])
    out = {"job": result[0], "job_no_report": result[1], "load_average": load}
    if baseline:
        out["baseline"] = result[2]
        out["baseline_src"] = str(srcs[1])
    return out


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
    parser.add_argument("--runs", type=int, default=5,
                        help="interleaved runs per side of each comparison, (d) included "
                             "(default 5)")
    parser.add_argument("--latency-runs", type=int, default=5,
                        help="interleaved pairs of the main job and the bare import (default 5)")
    parser.add_argument("--latency-only", action="store_true",
                        help="only the main job against the bare import")
    parser.add_argument("--baseline", metavar="SRC",
                        help="also time the main job of another checkout's src folder (e.g. "
                             "/work/main/src) in the same rounds")
    args = parser.parse_args(argv)

    if args.latency_only:
        print(json.dumps({"main_job_over_bare_import": latency(args.latency_runs,
                                                               args.baseline)}))
        return 0

    from gd_analyze import gd_terms, load_robot
    from gd_analyze.dynamics.pinocchio import relative_error

    robot = load_robot("puma560")
    N = args.setpoints
    rng = np.random.default_rng(2026)
    q = rng.uniform(robot.q_min, robot.q_max, (N, robot.n))
    qd = rng.uniform(-robot.qd_max, robot.qd_max, (N, robot.n))

    t0 = time.perf_counter()
    gd_terms(robot, q[:10], qd[:10])                         # load or compile the kernel
    first_call = time.perf_counter() - t0
    runs = args.runs
    ab = interleaved(lambda: gd_terms(robot, q, qd), lambda: pinocchio_loop(robot, q, qd), runs)
    ab0 = interleaved(lambda: gd_terms(robot, q, qd),
                      lambda: pinocchio_calls_only(robot, q, qd), runs)
    ac = interleaved(lambda: gd_terms(robot, q, qd), lambda: pinocchio_split(robot, q, qd),
                     runs)
    terms = ab["results"][0]
    D, h, c = ab["results"][1]
    Dt, Dr, ht, hr, c2 = ac["results"][1]

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
        "runs_per_side": runs,
        "a_gd_terms_us": ab["median_a_s"] * us,
        "b_pinocchio_D_h_c_us": ab["median_b_s"] * us,
        "b_calls_only_us": ab0["median_b_s"] * us,
        "c_pinocchio_split_us": ac["median_b_s"] * us,
        "gd_terms_over_pinocchio_loop": _summary(ab),
        "gd_terms_over_pinocchio_calls_only": _summary(ab0),
        "gd_terms_over_pinocchio_split": _summary(ac),
        "kernel_first_call_s": first_call,
        "d_rnea_batched": batched,
        "max_rel_disagreement": max(max(agreement.values()), batched["tau_rel_disagreement"]),
        "agreement": agreement,
    }
    if not args.no_latency:
        result["main_job_over_bare_import"] = latency(args.latency_runs, args.baseline)
    result["peak_rss_mib"] = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    print(json.dumps(result))
    if result["max_rel_disagreement"] > 1e-10:
        print("benchmark: results disagree with Pinocchio", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    os.environ.setdefault("MPLBACKEND", "Agg")
    sys.exit(main())
