"""Wall and CPU time of ``gd-analyze control`` (``--no-report``), this checkout against another.

    python analysis/control_speed.py --baseline DIR [--rounds 3] [--arms puma560,chain10]

For each arm, the main job runs once, untimed, to write its simplified model: the PUMA 560 on
``data/puma560_trajectory.csv``, and ``chainN`` the random chain of N joints of
``analysis/main_job_scaling.py`` (``write_inputs``) on its 31-point trajectory. Each round
then runs ``python -m gd_analyze.cli control MODEL TRAJECTORY -o OUT --no-report -q`` in a
fresh process on this checkout's ``src`` and on ``--baseline DIR`` (another checkout's ``src``),
each first on ``PYTHONPATH``, in alternating order, and reads the child's wall time, CPU time
(user + system) and peak resident memory (``os.wait4``). Both sides share one derivation
cache (filled by the untimed run). Prints the load averages, then one JSON line per arm: per
side the median [min, max] of wall, CPU and peak RSS [MiB], and this side's wall and CPU over
the baseline's, per round, median [min, max]. Both sides' ``control.h5`` are compared: the
line says whether their tracking errors are bit for bit the same.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent


def _run(src, args, env):
    """(wall [s], CPU [s], peak RSS [MiB]) of one child on ``src``."""
    env = dict(env, PYTHONPATH=str(src))
    t0 = time.perf_counter()
    proc = subprocess.Popen([sys.executable, "-m", "gd_analyze.cli", *args], env=env,
                            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    _, status, usage = os.wait4(proc.pid, 0)
    wall = time.perf_counter() - t0
    if os.waitstatus_to_exitcode(status) != 0:
        raise SystemExit(f"{src}: {' '.join(args)} failed: {proc.stderr.read().decode()[-400:]}")
    return wall, usage.ru_utime + usage.ru_stime, usage.ru_maxrss / 1024


def _inputs(arm, folder, env, src):
    """(model file, trajectory) of an arm, its main job run once on ``src``."""
    if arm == "puma560":
        robot, traj = "puma560", str(ROOT / "data" / "puma560_trajectory.csv")
    else:
        sys.path.insert(0, str(HERE))
        from main_job_scaling import write_inputs

        robot, traj = (str(p) for p in write_inputs(int(arm.removeprefix("chain")), folder))
    _run(src, [robot, traj, "-o", str(folder / "main"), "--no-report", "-q"], env)
    return str(folder / "main" / "simplified_model.json"), traj


def _stats(values):
    return [statistics.median(values), min(values), max(values)]


def _errors(path):
    """The runs stored in a control.h5 (q, qd, tau, the errors, the evaluations), as bytes."""
    import h5py

    with h5py.File(path, "r") as f:
        return b"".join(f[k][()].tobytes() for k in ("q", "qd", "tau", "error", "nfev",
                                                      "tau_difference"))


def main(argv=None):
    """Measure and print.

    Parameters
    ----------
    argv : list of str, optional
        Command-line arguments.
    """
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--baseline", required=True, help="another checkout's src folder")
    p.add_argument("--rounds", type=int, default=3)
    p.add_argument("--arms", default="puma560,chain10")
    args = p.parse_args(argv)
    this = ROOT / "src"
    print(f"load averages at the start: {os.getloadavg()}", flush=True)
    with tempfile.TemporaryDirectory() as tmp:
        env = dict(os.environ, GD_ANALYZE_CACHE_DIR=str(Path(tmp) / "cache"))
        for arm in args.arms.split(","):
            folder = Path(tmp) / arm
            folder.mkdir()
            model, traj = _inputs(arm, folder, env, this)
            sides = {"this": (this, []), "baseline": (Path(args.baseline), [])}
            for r in range(args.rounds):
                order = ["this", "baseline"] if r % 2 == 0 else ["baseline", "this"]
                for side in order:
                    src, runs = sides[side]
                    runs.append(_run(src, ["control", model, traj, "-o",
                                           str(folder / side), "--no-report", "-q"], env))
            t, b = sides["this"][1], sides["baseline"][1]
            same = _errors(folder / "this" / "control.h5") == _errors(
                folder / "baseline" / "control.h5")
            print(json.dumps({
                "arm": arm, "rounds": args.rounds,
                "this": {"wall_s": _stats([x[0] for x in t]), "cpu_s": _stats([x[1] for x in t]),
                         "peak_rss_mib": _stats([x[2] for x in t])},
                "baseline": {"wall_s": _stats([x[0] for x in b]),
                             "cpu_s": _stats([x[1] for x in b]),
                             "peak_rss_mib": _stats([x[2] for x in b])},
                "wall_ratio": _stats([x[0] / y[0] for x, y in zip(t, b)]),
                "cpu_ratio": _stats([x[1] / y[1] for x, y in zip(t, b)]),
                "runs_identical": same}), flush=True)
    print(f"load averages at the end: {os.getloadavg()}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
