"""Identification against the recording's length: wall time and peak memory of
``gd-analyze identify`` on long recordings, this checkout against another, interleaved.

For each length N, a recording of the Panda's 7 joints at 1 kHz (positions and torques only;
a slow multi-sine inside the joint limits; the torque from Pinocchio's ``rnea`` with viscous
and Coulomb friction and noise) is written once as CSV. Each round runs, in a fresh process
each and in alternating order, ``python -m gd_analyze.cli identify panda REC.csv -o OUT
--no-report`` on this checkout's ``src`` and on ``--compare DIR`` (another checkout's
``src``), each first on ``PYTHONPATH`` (with ``--levels L`` the torques quantised to L
levels over their ranges, which identify's check of clipping against the model fits twice
for), and reads the child's wall time, CPU time and peak
resident memory (``os.wait4``). Prints the load averages, then one JSON line per length and
side: median [min, max] of the rounds' wall and CPU time [s] and peak RSS [MiB], and the
ratio of this side's wall time to the other side's in the same round.

Usage::

    python analysis/identify_memory.py [--samples 30000,100000,300000] [--rounds 2]
        [--compare DIR] [--levels L]
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

HERE = Path(__file__).resolve().parent.parent / "src"


def write_recording(N: int, path: Path, levels: int | None = None) -> None:
    """A recording of N samples at 1 kHz, written as ``t,q1..q7,tau1..tau7``; with ``levels``,
    each torque rounded to that many levels over its range (an ADC)."""
    import pinocchio as pin

    import gd_analyze as gd
    from gd_analyze.dynamics.pinocchio import pinocchio_model

    robot = gd.load_robot("panda")
    model = pinocchio_model(robot)
    data = model.createData()
    n = robot.n
    t = np.arange(N) / 1000.0
    lo, hi = np.asarray(robot.q_min, float), np.asarray(robot.q_max, float)
    w = 2 * np.pi * np.array([0.11, 0.13, 0.17, 0.19, 0.23, 0.29, 0.31])[:n]
    amp = 0.3 * (hi - lo) / 2
    q = (lo + hi) / 2 + amp * np.sin(w * t[:, None])
    qd = amp * w * np.cos(w * t[:, None])
    qdd = -amp * w * w * np.sin(w * t[:, None])
    tau = np.array([pin.rnea(model, data, *x) for x in zip(q, qd, qdd)])
    rng = np.random.default_rng(0)
    tau += 0.5 * qd + 0.8 * np.sign(qd) + 0.05 * rng.standard_normal(tau.shape)
    if levels:
        step = np.ptp(tau, axis=0) / (levels - 1)
        tau = tau.min(axis=0) + np.round((tau - tau.min(axis=0)) / step) * step
    header = ",".join(["t"] + [f"q{j + 1}" for j in range(n)] + [f"tau{j + 1}" for j in range(n)])
    np.savetxt(path, np.column_stack([t, q + 1e-5 * rng.standard_normal(q.shape), tau]),
               delimiter=",", header=header, comments="", fmt="%.9g")


def run(src: Path, recording: Path, out: Path) -> dict:
    """One identification in a fresh process; its wall and CPU time [s] and peak RSS [MiB]."""
    env = dict(os.environ, PYTHONPATH=str(src))
    start = time.perf_counter()
    proc = subprocess.Popen([sys.executable, "-m", "gd_analyze.cli", "identify", "panda",
                             str(recording), "-o", str(out), "--no-report", "-q"], env=env,
                            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, cwd=out.parent)
    _, status, usage = os.wait4(proc.pid, 0)
    wall = time.perf_counter() - start
    err = proc.stderr.read().decode() if proc.stderr else ""
    if os.waitstatus_to_exitcode(status) != 0:
        raise SystemExit(f"identify failed on {src}: {err.strip()}")
    return {"wall": wall, "cpu": usage.ru_utime + usage.ru_stime,
            "rss": usage.ru_maxrss / 1024}


def summary(values: list[float]) -> list[float]:
    """Median, min and max."""
    return [float(np.median(values)), float(min(values)), float(max(values))]


def main() -> None:
    """Parse the arguments, run the rounds, print the JSON lines."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--samples", default="30000,100000,300000")
    parser.add_argument("--rounds", type=int, default=2)
    parser.add_argument("--compare", type=Path, default=None)
    parser.add_argument("--levels", type=int, default=None,
                        help="quantise each torque to this many levels over its range")
    args = parser.parse_args()
    print("load averages at the start:", " ".join(f"{x:.2f}" for x in os.getloadavg()))
    sides = {"this": HERE} | ({"other": args.compare.resolve()} if args.compare else {})
    with tempfile.TemporaryDirectory() as tmp:
        for N in (int(x) for x in args.samples.split(",")):
            recording = Path(tmp) / f"panda-{N}.csv"
            write_recording(N, recording, args.levels)
            got: dict[str, list[dict]] = {k: [] for k in sides}
            for r in range(args.rounds):
                order = list(sides) if r % 2 == 0 else list(sides)[::-1]
                for side in order:
                    got[side].append(run(sides[side], recording, Path(tmp) / f"out-{side}-{r}"))
            for side, runs in got.items():
                line = {"samples": N, "side": side, "src": str(sides[side]),
                        **{k: summary([x[k] for x in runs]) for k in ("wall", "cpu", "rss")}}
                if side == "this" and "other" in got:
                    line["wall_ratio_to_other"] = summary(
                        [a["wall"] / b["wall"] for a, b in zip(runs, got["other"])])
                print(json.dumps(line))
    print("load averages at the end:", " ".join(f"{x:.2f}" for x in os.getloadavg()))


if __name__ == "__main__":
    main()
