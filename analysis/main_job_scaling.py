"""The whole main job against the number of joints: wall time and peak memory, with and
without the report, each run in a fresh process with a cold derivation cache.

For random chains of n joints (``analysis/scaling.py``'s ``random_robot`` with position limits
of +-2.5 rad, +-0.3 m for the prismatic joints, 2 rad/s, 4 rad/s^2, written as a robot file by
:func:`gd_analyze.model.robot_file.robot_toml`) and a 31-point sinusoidal trajectory inside the
region, this script runs ``gd-analyze ROBOT.toml TRAJ.csv`` (``python -m gd_analyze.cli``),
once with its report and once with ``--no-report``, each in its own process with
``GD_ANALYZE_CACHE_DIR`` a new empty folder, and reads the process's peak resident memory
(``os.wait4``). It prints the load averages, a Markdown table (wall time, peak memory,
whether the region's certification was skipped by the sampled pre-screen, and the deployed
model's operations against the exact recursive model's) and the growth exponents p of
t ~ n^p (least squares over the ns, and between the last two).

Usage::

    python analysis/main_job_scaling.py [--ns 3,6,9,12,15] [--rounds 1] [--src DIR]

``--src`` runs the jobs on another checkout's ``src`` folder (put first on PYTHONPATH), e.g.
to measure the code before a change beside the code after it.
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
from scaling import exponents, random_robot  # noqa: E402  (the chains of the scaling study)


def write_inputs(n, folder):
    """The chain's robot file and a trajectory inside its region; returns both paths."""
    from gd_analyze.model.robot_file import robot_toml

    robot = random_robot(n, limits=True)
    toml = folder / f"random-{n}.toml"
    toml.write_text(robot_toml(robot, [f"random chain of {n} joints (analysis/scaling.py)"]))
    t = np.linspace(0.0, 3.0, 31)
    rng = np.random.default_rng(1)
    w, phase = rng.uniform(0.5, 1.0, n), rng.uniform(0.0, 6.0, n)
    amp = np.where(np.asarray(robot.prismatic, bool), 0.1, 0.8)      # within +-0.3 m, 2.5 rad
    arg = w * t[:, None] + phase
    q, qd, qdd = amp * np.sin(arg), amp * w * np.cos(arg), -amp * w ** 2 * np.sin(arg)
    header = ["t"] + [f"{k}{j + 1}" for k in ("q", "qd", "qdd") for j in range(n)]
    csv = folder / f"random-{n}.csv"
    np.savetxt(csv, np.column_stack([t, q, qd, qdd]), delimiter=",", header=",".join(header),
               comments="")
    return toml, csv


def run_job(toml, csv, out, report, src=""):
    """One main job in a fresh process with a cold cache: (wall [s], peak RSS [MiB], spec)."""
    with tempfile.TemporaryDirectory() as cache:
        env = dict(os.environ, GD_ANALYZE_CACHE_DIR=cache)
        if src:
            env["PYTHONPATH"] = os.pathsep.join([src, env.get("PYTHONPATH", "")]).rstrip(
                os.pathsep)
        env.pop("GD_ANALYZE_NO_CACHE", None)
        cmd = [sys.executable, "-m", "gd_analyze.cli", str(toml), str(csv), "-o", str(out),
               "-q"] + ([] if report else ["--no-report"])
        t0 = time.perf_counter()
        proc = subprocess.Popen(cmd, env=env, stdout=subprocess.DEVNULL,
                                stderr=subprocess.PIPE)
        _, status, usage = os.wait4(proc.pid, 0)
        wall = time.perf_counter() - t0
        err = proc.stderr.read().decode() if proc.stderr else ""
        proc.returncode = os.waitstatus_to_exitcode(status)
    if proc.returncode not in (0,):
        raise SystemExit(f"{toml.name}: exit {proc.returncode}: {err.strip()[-400:]}")
    spec = json.loads((out / "simplified_model.json").read_text())
    return wall, usage.ru_maxrss / 1024, spec


def main(argv=None):
    """Run the measurement and print the table.

    Parameters
    ----------
    argv : list of str, optional

    Returns
    -------
    int
        0.
    """
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--ns", default="3,6,9,12,15")
    parser.add_argument("--rounds", type=int, default=1)
    parser.add_argument("--src", default="", help="another checkout's src folder")
    args = parser.parse_args(argv)
    ns = [int(v) for v in args.ns.split(",") if v]
    loads = [os.getloadavg()]
    print("load averages at the start:", " ".join(f"{v:.2f}" for v in loads[0]), flush=True)
    rows = {n: {"report": [], "report_mib": [], "bare": [], "bare_mib": []} for n in ns}
    with tempfile.TemporaryDirectory() as folder:
        folder = Path(folder)
        inputs = {n: write_inputs(n, folder) for n in ns}
        for r in range(args.rounds):
            for n in ns:
                for report, key in ((False, "bare"), (True, "report")):
                    wall, mib, spec = run_job(*inputs[n], folder / f"out-{n}-{key}", report,
                                             args.src)
                    rows[n][key].append(wall)
                    rows[n][key + "_mib"].append(mib)
                    screen = spec.get("provenance", {}).get("region_screen")
                    rows[n]["skipped"] = bool(screen and screen["skipped"])
                    rows[n]["ops"] = sum(int(spec["cost"][k]) for k in
                                         ("multiplications", "additions"))
                    exact = spec["costs"]["exact recursive"]
                    rows[n]["exact"] = int(exact["multiplications"]) + int(exact["additions"])
                    loads.append(os.getloadavg())
                    print(f"  round {r + 1} n = {n} {'with' if report else 'without'} report: "
                          f"{wall:.1f} s, {mib:.0f} MiB, load {loads[-1][0]:.2f}", flush=True)
    print(f"| n | main job [s] | peak [MiB] | --no-report [s] | peak [MiB] | certification "
          f"skipped | operations (exact) |  (median of {args.rounds} round(s))")
    print("|---|---|---|---|---|---|---|")
    for n in ns:
        row = rows[n]
        print(f"| {n} | {np.median(row['report']):.1f} | {np.median(row['report_mib']):.0f} | "
              f"{np.median(row['bare']):.1f} | {np.median(row['bare_mib']):.0f} | "
              f"{'yes' if row['skipped'] else 'no'} | {row['ops']:,} ({row['exact']:,}) |")
    if len(ns) >= 2:
        for key in ("report", "bare", "report_mib"):
            values = [np.median(rows[n][key]) for n in ns]
            fit, _ = exponents(ns, values)
            last, _ = exponents(ns[-2:], values[-2:])
            print(f"growth exponent of {key}: n^{fit:.2f} (least squares over n = "
                  f"{ns[0]}..{ns[-1]}), n^{last:.2f} (n = {ns[-2]} to {ns[-1]})")
    one = np.array([x[0] for x in loads])
    print(f"load (1-minute) during the run: {one.min():.2f} to {one.max():.2f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
