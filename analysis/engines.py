"""Which engine per hot loop: the compiled (numba) kernel against its array (numpy) copy.

    python analysis/engines.py --src CHECKOUT/src [--arms puma560 panda]
                               [--sizes 1000 10000 100000 1000000]
                               [--rounds 3] [--max-seconds 30] [--loops ...]
                               [--first-call-runs 5]
                               [--main-setpoints 31 1000000] [--main-runs 1]

(1) Every hot loop that has two engines, timed on the same inputs with each engine in
interleaved rounds (a, b, b, a, ...), on PUMA 560 and Panda, at N set points (or positions):
median time [s] with its [min, max], the per-round ratio numba / numpy (median [min, max]),
and the peak of the memory traced by tracemalloc during one separate call of each engine
[MiB] (numpy's allocations; the compiled kernels write into buffers their caller allocates,
which are traced too). The compiled kernel is loaded before the rounds (its first-call cost
is (2)). A size is skipped where the array code would take more than --max-seconds a call
(linear from the size before). The loops:

  gd_terms            G-D terms, ``gd_terms(engine=...)`` (dynamics/kernels.gd_kernel)
  ranking             ``RankingAccumulator.update`` (selection/kernels.ranking_kernel)
  part_peaks          ``PartPeaks.update`` (selection/kernels.part_peaks_kernel)
  inertia_check       ``check_inertia`` (selection/kernels.inertia_block/screen_kernel)
  contribution_peaks  ``contribution_peaks`` (symbolic/regressor_compiled)
  atom_peaks          ``term_peaks`` of the explicit model (symbolic/term_kernels)
  channel_values      ``channel_values`` of the region (symbolic/regressor_compiled)

(2) numba's first-call cost, which a job pays once: a fresh interpreter that has imported
gd_analyze and its inputs imports numba and loads every compiled kernel from numba's cache
(``cache=True``; one untimed warm-up fills it), against the same interpreter doing nothing
more (rounds interleaved; the difference of the medians, and each side's median).

(3) The main job end to end, ``python -m gd_analyze.cli puma560 FILE -o OUT --no-report -q``
in a fresh process per run, under three rules for every kernel (the size rule's threshold set
before the job starts): ``auto`` (the shipped rule, compiled from 2,000 set points on),
``numba`` (compiled always), ``numpy`` (array code always); wall and CPU time and peak RSS
per run, the rounds interleaved, on the shipped 31-set-point trajectory and on planned ones
of the given lengths. Ratios against ``auto`` in the same round.

The rule that decides (printed with the results): a loop keeps one engine when that engine is
not slower than the other by more than 1.3 times at any measured size, first-call cost
included where the job pays it; numba alone is taken for the whole package only when the main
job with every kernel compiled stays within 1.3 times of the shipped rule on the short job and
at 10^6 set points, numpy alone only when the array code does at 10^6 (and its memory stays
under 1 GiB). Otherwise the size rule stays. Prints one JSON line per measurement, then a
Markdown table and the verdicts.

The package now keeps the compiled kernels only (the verdict of this script); the array copies
left for the tests' oracles, so the script measures a checkout from before (--src: its
``src`` folder, put first on the module path of this process and of every child; e.g. the
commit before the change, 3a5980f). Without --src, or on a checkout without the two engines,
it says so in one line and exits with status 2.
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
import tracemalloc
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
SHIPPED = ROOT / "data" / "puma560_trajectory.csv"
LOOPS = ("gd_terms", "ranking", "part_peaks", "inertia_check", "contribution_peaks",
         "atom_peaks", "channel_values")
#: A loop's engine is "within" when not slower than the other by more than this factor.
WITHIN = 1.3
#: The main job's memory limit [MiB].
LIMIT_MIB = 1024


def _range(values):
    v = np.asarray(values, float)
    return {"median": float(np.median(v)), "min": float(v.min()), "max": float(v.max())}


def _states(robot, N, seed=0):
    rng = np.random.default_rng(seed)
    lo, hi = np.asarray(robot.q_min, float), np.asarray(robot.q_max, float)
    lo, hi = np.where(np.isfinite(lo), lo, -np.pi), np.where(np.isfinite(hi), hi, np.pi)
    q = rng.uniform(lo, hi, (N, robot.n))
    qd = rng.uniform(-1, 1, (N, robot.n)) * 2.0
    qdd = rng.uniform(-1, 1, (N, robot.n)) * 5.0
    return q, qd, qdd


def loop_calls(name, robot, N):
    """(call(engine) -> None) for one loop on N set points of ``robot``, inputs made ahead."""
    from gd_analyze import gd_terms

    q, qd, qdd = _states(robot, N)
    if name == "gd_terms":
        return lambda e: gd_terms(robot, q, qd, engine=e)
    if name in ("ranking", "part_peaks"):
        from gd_analyze.ranking.ranking import RankingAccumulator
        from gd_analyze.simplify.budget import PartPeaks

        t = gd_terms(robot, q, qd)
        tau = t.tau(qdd)
        if name == "ranking":
            return lambda e: RankingAccumulator(robot.n).update(
                t.D_tran, t.D_rot, t.h_tran, t.h_rot, tau, armature=t.armature, engine=e)
        return lambda e: PartPeaks(robot.n).update(t.D_tran, t.D_rot, t.h_tran, t.h_rot, qdd,
                                                   tau, engine=e)
    if name == "inertia_check":
        from gd_analyze.certify.positive_definite import check_inertia

        K = min(N, 20_000)                  # D at K positions, read cyclically (memory)
        D = gd_terms(robot, q[:K], qd[:K]).D
        index = np.arange(N, dtype=float)[:, None]
        return lambda e: check_inertia(lambda qq: D[qq[:, 0].astype(np.int64) % K], index,
                                       engine=e)
    from gd_analyze.dynamics.base_parameters import base_parameters

    if name == "contribution_peaks":
        from gd_analyze.dynamics.regressor_kernels import contribution_peaks

        base = base_parameters(robot)
        return lambda e: contribution_peaks(robot, base, q, qd, qdd, engine=e)
    if name == "channel_values":
        from gd_analyze.certify.region import channel_values

        cols = np.flatnonzero(base_parameters(robot).independent.reshape(-1))
        return lambda e: channel_values(robot, q, cols, engine=e)
    if name == "atom_peaks":
        from gd_analyze.store.explicit_cache import explicit_terms
        from gd_analyze.symbolic.explicit import term_peaks

        terms, _ = explicit_terms(robot)
        offset = np.zeros(robot.n)
        return lambda e: term_peaks(terms, offset, q, qd, qdd, prismatic=robot.prismatic,
                                    engine=e)
    raise ValueError(f"unknown loop {name!r}")


def time_loop(name, robot, N, rounds):
    """Interleaved rounds of the two engines on one loop; one dict."""
    call = loop_calls(name, robot, N)
    call("compiled")                        # load (or compile) the kernels before timing
    times = {"compiled": [], "numpy": []}
    for k in range(rounds):
        for e in (("compiled", "numpy") if k % 2 == 0 else ("numpy", "compiled")):
            t0 = time.perf_counter()
            call(e)
            times[e].append(time.perf_counter() - t0)
    memory = {}
    if N <= 100_000:                        # tracemalloc slows the array code down
        for e in ("compiled", "numpy"):
            tracemalloc.start()
            call(e)
            memory[e] = tracemalloc.get_traced_memory()[1] / 2 ** 20
            tracemalloc.stop()
    ratio = np.asarray(times["compiled"]) / np.asarray(times["numpy"])
    return {"loop": name, "arm": robot.name, "N": N, "rounds": rounds,
            "numba_s": _range(times["compiled"]), "numpy_s": _range(times["numpy"]),
            "numba_over_numpy": _range(ratio), "peak_traced_mib": memory,
            "load": os.getloadavg()[0]}


def first_call(runs):
    """numba's import and the first call of the G-D kernel in a fresh interpreter, against the
    same interpreter running the array code (interleaved); then, in the numba interpreter, the
    first calls of two more kernels (ranking and part peaks: their cache loads)."""
    code = ("import sys, time\nimport numpy as np\nfrom gd_analyze import load_robot, gd_terms\n"
            "robot = load_robot('puma560'); q = np.zeros((4, robot.n))\n"
            "t0 = time.perf_counter()\n"
            "if sys.argv[1] == 'numba':\n"
            "    gd_terms(robot, q, q, engine='compiled')\n"
            "else:\n"
            "    gd_terms(robot, q, q, engine='numpy')\n"
            "t1 = time.perf_counter()\n"
            "if sys.argv[1] == 'numba':\n"
            "    from gd_analyze.ranking import kernels as sk\n"
            "    from gd_analyze.symbolic import regressor_compiled, term_kernels\n"
            "    from gd_analyze.ranking.ranking import RankingAccumulator\n"
            "    from gd_analyze.simplify.budget import PartPeaks\n"
            "    t = gd_terms(robot, q, q, engine='compiled')\n"
            "    RankingAccumulator(robot.n).update(t.D_tran, t.D_rot, t.h_tran, t.h_rot, q,"
            " engine='compiled')\n"
            "    PartPeaks(robot.n).update(t.D_tran, t.D_rot, t.h_tran, t.h_rot, q, q,"
            " engine='compiled')\n"
            "print(t1 - t0, time.perf_counter() - t1)\n")
    subprocess.run([sys.executable, "-c", code, "numba"], check=True, capture_output=True)
    out = {"numba": [], "numpy": [], "numba_more_kernels": []}
    for k in range(runs):
        for side in (("numba", "numpy") if k % 2 == 0 else ("numpy", "numba")):
            r = subprocess.run([sys.executable, "-c", code, side], check=True,
                               capture_output=True, text=True).stdout.split()
            out[side].append(float(r[0]))
            if side == "numba":
                out["numba_more_kernels"].append(float(r[1]))
    return {"measure": "first_call", "runs": runs,
            "numba_import_and_gd_kernel_load_s": _range(out["numba"]),
            "numpy_gd_terms_first_call_s": _range(out["numpy"]),
            "two_more_kernels_load_s": _range(out["numba_more_kernels"]),
            "load": os.getloadavg()[0]}


JOB = ("import sys\nfrom gd_analyze.dynamics import dalembert\n"
       "dalembert.compiled_engine.__defaults__ = (int(sys.argv[1]),)\n"
       "from gd_analyze.cli import main\nsys.exit(main(sys.argv[2:]))\n")
POLICIES = {"auto": None, "numba": 0, "numpy": 10 ** 18}


def run_job(policy, csv, out):
    """One main job in a fresh process under ``policy``: (wall [s], CPU [s], peak RSS [MiB])."""
    from gd_analyze.dynamics.dalembert import COMPILED_MIN_SETPOINTS

    threshold = POLICIES[policy]
    threshold = COMPILED_MIN_SETPOINTS if threshold is None else threshold
    cmd = [sys.executable, "-c", JOB, str(threshold), "puma560", str(csv), "-o", str(out),
           "--no-report", "-q"]
    wrapper = [sys.executable, "-c", "import resource, subprocess, sys; "
               f"subprocess.run({cmd!r}, check=True, capture_output=True); "
               "u = resource.getrusage(resource.RUSAGE_CHILDREN); "
               "print(u.ru_maxrss / 1024, u.ru_utime + u.ru_stime)"]
    t0 = time.perf_counter()
    res = subprocess.run(wrapper, check=True, capture_output=True, text=True).stdout
    wall = time.perf_counter() - t0
    rss, cpu = (float(v) for v in res.split()[-2:])
    return wall, cpu, rss


def main_job(setpoints, runs, tmp):
    """The main job under the three rules on one trajectory; one dict."""
    if setpoints == 31:
        csv = SHIPPED
    else:
        csv = Path(tmp) / f"plan{setpoints}.csv"
        subprocess.run([sys.executable, "-m", "gd_analyze.cli", "plan", "puma560", "-o",
                        str(csv), "--setpoints", str(setpoints)], check=True,
                       capture_output=True)
    out = Path(tmp) / "out"
    run_job("auto", csv, out)               # warm-up: derivation cache and byte-code
    res = {p: [] for p in POLICIES}
    order = list(POLICIES)
    for k in range(runs):
        for p in order[k % 3:] + order[:k % 3]:
            res[p].append(run_job(p, csv, out))
    summary = {"measure": "main_job", "setpoints": setpoints, "runs": runs,
               "load": os.getloadavg()[0]}
    for p, rows in res.items():
        summary[p] = {"wall_s": _range([r[0] for r in rows]),
                      "cpu_s": _range([r[1] for r in rows]),
                      "peak_rss_mib": max(r[2] for r in rows)}
        if p != "auto":
            summary[p]["wall_over_auto"] = _range(
                [a[0] / b[0] for a, b in zip(rows, res["auto"])])
            summary[p]["cpu_over_auto"] = _range(
                [a[1] / b[1] for a, b in zip(rows, res["auto"])])
    return summary


def _fmt(r):
    return f"{r['median']:.3g} [{r['min']:.3g}, {r['max']:.3g}]"


def table(rows):
    """Markdown table of the per-loop rows."""
    lines = ["| loop | arm | N | numba [s] | numpy [s] | numba / numpy | peak traced MiB "
             "(numba, numpy) |", "|---|---|---|---|---|---|---|"]
    for r in rows:
        m = r["peak_traced_mib"]
        mem = f"{m['compiled']:.1f}, {m['numpy']:.1f}" if m else "-"
        lines.append(f"| {r['loop']} | {r['arm']} | {r['N']:,} | {_fmt(r['numba_s'])} | "
                     f"{_fmt(r['numpy_s'])} | {_fmt(r['numba_over_numpy'])} | {mem} |")
    return "\n".join(lines)


def verdicts(rows):
    """Per loop: which engine the rule keeps, from its rows (both arms, every size)."""
    out = {}
    for name in dict.fromkeys(r["loop"] for r in rows):
        ratios = [r["numba_over_numpy"]["median"] for r in rows if r["loop"] == name]
        if max(ratios) <= WITHIN and min(ratios) < 1:
            out[name] = "numba (never slower than numpy by more than 1.3 times)"
        elif min(ratios) >= 1 / WITHIN and max(ratios) > 1:
            out[name] = "numpy (never slower than numba by more than 1.3 times)"
        else:
            out[name] = (f"neither alone: numba/numpy from {min(ratios):.3g} to "
                         f"{max(ratios):.3g} over the sizes")
    return out


def main(argv=None):
    """Measure and print; returns 0.

    Parameters
    ----------
    argv : list of str, optional
        Command-line arguments.

    Returns
    -------
    int
        0.
    """
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--arms", nargs="+", default=["puma560", "panda"])
    p.add_argument("--sizes", nargs="*", type=int, default=[1000, 10000, 100000, 1000000])
    p.add_argument("--rounds", type=int, default=3)
    p.add_argument("--max-seconds", type=float, default=30.0,
                   help="skip a size where the array code would take longer a call")
    p.add_argument("--loops", nargs="+", default=list(LOOPS), choices=LOOPS)
    p.add_argument("--first-call-runs", type=int, default=5)
    p.add_argument("--main-setpoints", nargs="*", type=int, default=[31, 1_000_000])
    p.add_argument("--main-runs", type=int, default=1)
    p.add_argument("--src", help="the src folder of a checkout that has both engines")
    args = p.parse_args(argv)
    if args.src:
        sys.path.insert(0, str(Path(args.src).resolve()))
        os.environ["PYTHONPATH"] = os.pathsep.join(
            [str(Path(args.src).resolve())] + [x for x in [os.environ.get("PYTHONPATH")] if x])
    from gd_analyze import load_robot
    from gd_analyze.dynamics import dalembert

    if not hasattr(dalembert, "compiled_engine"):
        print(f"error: {Path(dalembert.__file__).parents[3]} has one engine per loop; "
              "give --src the src folder of a checkout with both (e.g. commit 3a5980f)",
              file=sys.stderr)
        return 2

    print(json.dumps({"command": " ".join([Path(sys.argv[0]).name] + (argv or sys.argv[1:])),
                      "load_start": os.getloadavg()}), flush=True)
    rows = []
    for arm in args.arms:
        robot = load_robot(arm)
        for name in args.loops:
            last = None                     # (N, numpy median [s]) of the size before
            for N in args.sizes:
                if last and last[1] * N / last[0] > args.max_seconds:
                    print(json.dumps({"loop": name, "arm": arm, "N": N, "skipped":
                                      f"numpy would take about {last[1] * N / last[0]:.0f} s "
                                      "a call (linear from the size before)"}), flush=True)
                    continue
                row = time_loop(name, robot, N, args.rounds)
                rows.append(row)
                last = (N, row["numpy_s"]["median"])
                print(json.dumps(row), flush=True)
    if args.first_call_runs:
        print(json.dumps(first_call(args.first_call_runs)), flush=True)
    with tempfile.TemporaryDirectory() as tmp:
        os.environ["GD_ANALYZE_CACHE_DIR"] = str(Path(tmp) / "cache")
        for N in args.main_setpoints:
            print(json.dumps(main_job(N, args.main_runs, tmp)), flush=True)
    if rows:
        print(table(rows))
        for name, v in verdicts(rows).items():
            print(f"verdict {name}: {v}")
    print(json.dumps({"load_end": os.getloadavg(),
                      "this_process_peak_rss_mib":
                      resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024}))
    return 0


if __name__ == "__main__":
    sys.exit(main())
