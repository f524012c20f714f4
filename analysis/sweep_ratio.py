"""A sweep of K random PUMA 560 trajectories against a Pinocchio loop over the same states,
interleaved.

    python analysis/sweep_ratio.py [-k 1000] [--runs R] [--workers W] [--baseline SRC]

Times, in interleaved rounds with the same number of runs on each side (a, b, b, a, ...;
default 3 each):

  (a) the sweep `python -m gd_analyze.cli sweep puma560 --random K -o OUT --no-report -q
      [--workers W]`, a fresh process per run as a user runs the console script (planning,
      the dask LocalCluster, the ranking of every trajectory on it, the merged model of the
      budget rule with its region guarantee and its check on every swept and held-out
      trajectory, sweep.h5 and the model files), under a small parent that prints its
      children's peak resident set size (ru_maxrss) and CPU time (user + system);
  (b) Pinocchio crba + nonLinearEffects + computeGeneralizedGravity in a Python loop over the
      same states (the K swept trajectories and the held-out ones, planned here with the
      sweep's own seeds; analysis/benchmark.py's ``pinocchio_loop``), in this process.

The sweep runs with a derivation cache of its own, filled by one untimed warm-up run (reported
apart), as a user's later runs do, with Python's default settings (a ``PYTHONDONTWRITEBYTECODE``
in the caller's environment is dropped, so that the warm-up leaves gd_analyze's byte-code as a
user's first run does). ``--baseline SRC`` also times another checkout's sweep (its ``src``
folder first on ``PYTHONPATH``, its own warm-up) in the same rounds, against the same loop,
the order of the sides rotated each round.

Prints one JSON line: per side the median wall and CPU times [s], the per-round ratios a / b
of wall and CPU time (median and [min, max]), the sweep's peak RSS per run [MiB], and the
1-minute load average before and after every run. Then ``within_ratio_limit: true`` or
``false`` (the median wall ratio against 8).

    python analysis/sweep_ratio.py --in-process [-k 1000] [--runs R] [--warm-arm stanford]
                                   [--baseline SRC] [--processes P]

``--in-process`` times the sweep in one warm Python process instead, as a program that calls
the command line's ``main`` runs it: the derivation cache (a folder of its own) is filled by a
child's PUMA 560 sweep first; then this process imports the package and runs one untimed sweep
of another arm (``--warm-arm``, K trajectories), so that the imports and numba's kernels are
loaded but the PUMA 560's per-process memos are cold; then R rounds, each (a)
``gd_analyze.cli.main(["sweep", "puma560", "--random", K, "--seed", S, "-o", OUT,
"--no-report", "-q"])`` with a new seed S per round, as the console script runs it, against
(b) ``pinocchio_loop`` over that round's states (its K swept and 20 held-out trajectories),
the order of (a) and (b) alternating by round, wall time (``time.perf_counter``) and CPU time
(``time.process_time``, all threads) of each. It prints one JSON line: the first PUMA 560
sweep of the process apart (its ratios a / b), and the later ones as the median and
[min, max] of their per-round ratios, wall and CPU, with the load. With ``--baseline SRC`` it
runs P processes of each side (default 2), this checkout's ``src`` and SRC first on
``PYTHONPATH`` in turn (this script in each, the order rotated per pair), and prints both
sides' figures (the first sweeps' ratios over the processes, the later ones' over all their
rounds) and the ratio of the two sides' medians.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

from benchmark import pinocchio_loop  # noqa: E402
from million_ratio import _range, run_child  # noqa: E402

#: The median wall-time ratio allowed.
RATIO_LIMIT = 8.0
#: The sweep's default held-out trajectories and their seed offset (cli/commands.py).
HELD_OUT, HELD_OUT_SEED = 20, 1_000_003


def main(argv=None):
    """Measure and print one JSON line and the verdict line.

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
    p.add_argument("-k", type=int, default=1000, help="swept trajectories")
    p.add_argument("--runs", type=int, default=3)
    p.add_argument("--workers", type=int, default=None, help="LocalCluster workers")
    p.add_argument("--baseline", metavar="SRC", default=None,
                   help="another checkout's src folder, timed in the same rounds")
    p.add_argument("--in-process", action="store_true",
                   help="the sweeps in one warm process (module docstring)")
    p.add_argument("--warm-arm", default="stanford",
                   help="the arm of the in-process warm-up sweep")
    p.add_argument("--processes", type=int, default=2,
                   help="with --in-process --baseline: processes per side")
    args = p.parse_args(argv)
    if args.in_process:
        result = alternated(args) if args.baseline else in_process(args)
        print(json.dumps(result))
        return 0
    from gd_analyze import load_robot
    from gd_analyze.trajectory.planning import random_trajectories

    robot = load_robot("puma560")
    states = random_trajectories(robot, args.k, seed=0) + \
        random_trajectories(robot, HELD_OUT, seed=HELD_OUT_SEED)
    q = np.concatenate([t.q for t in states])
    qd = np.concatenate([t.qd for t in states])
    loads = [os.getloadavg()[0]]
    with tempfile.TemporaryDirectory() as tmp:
        command = [sys.executable, "-m", "gd_analyze.cli", "sweep", "puma560", "--random",
                   str(args.k), "-o", str(Path(tmp) / "out"), "--no-report", "-q"]
        if args.workers:
            command += ["--workers", str(args.workers)]

        env = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}
        env.pop("GD_ANALYZE_NO_CACHE", None)
        env["GD_ANALYZE_CACHE_DIR"] = str(Path(tmp) / "cache")

        def job(src=None):
            return run_child(command, env if src is None else {**env, "PYTHONPATH": os.pathsep.join(
                [str(Path(src).resolve())] + [v for v in [env.get("PYTHONPATH")] if v])})

        def loop():
            t0, c0 = time.perf_counter(), time.process_time()
            pinocchio_loop(robot, q, qd)
            return time.perf_counter() - t0, time.process_time() - c0

        first_wall, _, first_rss = job()
        loads.append(os.getloadavg()[0])
        jobs, loops, bases = [], [], []
        sides = [(job, jobs), (loop, loops)]
        if args.baseline:
            job(args.baseline)                  # its own warm-up: its code, its cache keys
            loads.append(os.getloadavg()[0])
            sides.append((lambda: job(args.baseline), bases))
        for k in range(args.runs):
            for side in sides[k % len(sides):] + sides[:k % len(sides)]:
                side[1].append(side[0]())
                loads.append(os.getloadavg()[0])
    wall = [a[0] / b[0] for a, b in zip(jobs, loops)]
    cpu = [a[1] / b[1] for a, b in zip(jobs, loops)]
    result = {
        "trajectories": args.k, "held_out": HELD_OUT, "states": int(q.shape[0]),
        "runs": args.runs, "workers": args.workers or os.cpu_count(),
        "sweep_over_pinocchio_loop_wall": _range(wall),
        "sweep_over_pinocchio_loop_cpu": _range(cpu),
        "sweep_wall_s": _range([a[0] for a in jobs]),
        "sweep_cpu_s": _range([a[1] for a in jobs]),
        "pinocchio_loop_wall_s": _range([b[0] for b in loops]),
        "pinocchio_loop_cpu_s": _range([b[1] for b in loops]),
        "first_run_empty_cache_s": first_wall,
        "sweep_peak_rss_mib": max([a[2] for a in jobs] + [first_rss]),
        "ratio_limit": RATIO_LIMIT,
        "load_average_1min": {"min": min(loads), "max": max(loads), "each": loads},
    }
    if args.baseline:
        result.update({
            "baseline_src": str(Path(args.baseline).resolve()),
            "baseline_over_pinocchio_loop_wall": _range([a[0] / b[0]
                                                         for a, b in zip(bases, loops)]),
            "baseline_over_pinocchio_loop_cpu": _range([a[1] / b[1]
                                                        for a, b in zip(bases, loops)]),
            "baseline_wall_s": _range([a[0] for a in bases]),
            "sweep_over_baseline_wall": _range([a[0] / b[0] for a, b in zip(jobs, bases)])})
    print(json.dumps(result))
    print(f"within_ratio_limit: {'true' if np.median(wall) <= RATIO_LIMIT else 'false'}")
    return 0


def in_process(args):
    """The in-process rounds (module docstring): a dict of the figures."""
    with tempfile.TemporaryDirectory() as tmp:
        os.environ.pop("GD_ANALYZE_NO_CACHE", None)
        os.environ["GD_ANALYZE_CACHE_DIR"] = str(Path(tmp) / "cache")
        sweep = ["sweep", "puma560", "--random", str(args.k), "--no-report", "-q"]
        t0 = time.perf_counter()
        subprocess.run([sys.executable, "-m", "gd_analyze.cli", *sweep, "-o",
                        str(Path(tmp) / "fill")], check=True, capture_output=True)
        fill = time.perf_counter() - t0
        import gd_analyze
        from gd_analyze import load_robot
        from gd_analyze.cli import main as cli_main
        from gd_analyze.trajectory.planning import random_trajectories

        loads = [os.getloadavg()[0]]
        t0 = time.perf_counter()
        assert cli_main(["sweep", args.warm_arm, "--random", str(args.k), "-o",
                         str(Path(tmp) / "warm"), "--no-report", "-q"]) == 0
        warm = time.perf_counter() - t0
        robot = load_robot("puma560")
        loads.append(os.getloadavg()[0])
        rounds = []
        for r in range(args.runs):
            seed = 1000 + r
            states = random_trajectories(robot, args.k, seed=seed) + \
                random_trajectories(robot, HELD_OUT, seed=seed + HELD_OUT_SEED)
            q = np.concatenate([t.q for t in states])
            qd = np.concatenate([t.qd for t in states])
            if r == 0:
                pinocchio_loop(robot, q[:10], qd[:10])      # its import, untimed
            out = str(Path(tmp) / f"round{r}")

            def job(seed=seed, out=out):
                assert cli_main([*sweep, "--seed", str(seed), "-o", out]) == 0

            timed = {}
            for side, call in (("sweep", job), ("loop", lambda q=q, qd=qd: pinocchio_loop(
                    robot, q, qd)))[::1 if r % 2 == 0 else -1]:
                t0, c0 = time.perf_counter(), time.process_time()
                call()
                timed[side] = (time.perf_counter() - t0, time.process_time() - c0)
                loads.append(os.getloadavg()[0])
            rounds.append(timed)
    wall = [t["sweep"][0] / t["loop"][0] for t in rounds]
    cpu = [t["sweep"][1] / t["loop"][1] for t in rounds]
    later = slice(1, None)
    return {
        "src": str(Path(gd_analyze.__file__).parents[1]), "trajectories": args.k,
        "held_out": HELD_OUT, "states": int(q.shape[0]), "rounds": args.runs,
        "warm_arm": args.warm_arm, "warm_up_s": warm, "cache_fill_child_s": fill,
        "first_sweep": {"wall_s": rounds[0]["sweep"][0], "cpu_s": rounds[0]["sweep"][1],
                        "over_loop_wall": wall[0], "over_loop_cpu": cpu[0]},
        "later_sweeps": None if args.runs < 2 else {
            "wall_s": _range([t["sweep"][0] for t in rounds[later]]),
            "cpu_s": _range([t["sweep"][1] for t in rounds[later]]),
            "over_loop_wall": _range(wall[later]), "over_loop_cpu": _range(cpu[later]),
            "over_loop_wall_each": wall[later], "over_loop_cpu_each": cpu[later]},
        "pinocchio_loop_wall_s": _range([t["loop"][0] for t in rounds]),
        "pinocchio_loop_cpu_s": _range([t["loop"][1] for t in rounds]),
        "load_average_1min": {"min": min(loads), "max": max(loads), "each": loads},
    }


def alternated(args):
    """``--in-process`` in P processes per side, this checkout's src and the baseline's in
    turn (the order rotated per process pair): both sides' figures."""
    here = Path(__file__).resolve()
    sides = {"this": str(here.parents[1] / "src"), "baseline": str(Path(args.baseline).resolve())}
    runs = {name: [] for name in sides}
    for k in range(args.processes):
        for name in (list(sides) if k % 2 == 0 else list(sides)[::-1]):
            env = {**os.environ, "PYTHONPATH": os.pathsep.join(
                [sides[name]] + [v for v in [os.environ.get("PYTHONPATH")] if v])}
            out = subprocess.run([sys.executable, str(here), "--in-process", "-k", str(args.k),
                                  "--runs", str(args.runs), "--warm-arm", args.warm_arm],
                                 check=True, capture_output=True, text=True, env=env).stdout
            runs[name].append(json.loads(out.strip().splitlines()[-1]))

    def summary(items):
        later = [x for r in items for x in [r["later_sweeps"]] if x]
        return {
            "first_over_loop_wall": _range([r["first_sweep"]["over_loop_wall"] for r in items]),
            "first_over_loop_cpu": _range([r["first_sweep"]["over_loop_cpu"] for r in items]),
            "first_wall_s": _range([r["first_sweep"]["wall_s"] for r in items]),
            "later_over_loop_wall": _range([v for x in later for v in x["over_loop_wall_each"]]),
            "later_over_loop_cpu": _range([v for x in later for v in x["over_loop_cpu_each"]]),
            "later_over_loop_wall_process_medians": [x["over_loop_wall"]["median"]
                                                     for x in later],
            "later_wall_s_process_medians": [x["wall_s"]["median"] for x in later],
            "load_1min": [min(r["load_average_1min"]["min"] for r in items),
                          max(r["load_average_1min"]["max"] for r in items)]}

    out = {"processes_per_side": args.processes, "trajectories": args.k, "rounds": args.runs,
           **{name: summary(items) for name, items in runs.items()}, "runs": runs,
           "sides": sides}
    for key in ("first_over_loop_wall", "later_over_loop_wall"):
        out[f"this_over_baseline_{key}_median"] = \
            out["this"][key]["median"] / out["baseline"][key]["median"]
    return out


if __name__ == "__main__":
    sys.exit(main())
