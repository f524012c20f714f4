"""The whole main job against the number of joints: wall time and peak memory, with and
without the report, each run in a fresh process with a cold derivation cache.

For random chains of n joints (``analysis/scaling.py``'s ``random_robot`` with position limits
of +-2.5 rad, +-0.3 m for the prismatic joints, 2 rad/s, 4 rad/s^2, written as a robot file by
:func:`gd_analyze.model.robot_file.robot_toml`) and a 31-point sinusoidal trajectory inside the
region, this script runs ``gd-analyze ROBOT.toml TRAJ.csv`` (``python -m gd_analyze.cli``),
once with its report and once with ``--no-report``, each in its own process with
``GD_ANALYZE_CACHE_DIR`` a new empty folder, and reads the process's peak resident memory
(``os.wait4``). It prints the load averages, a Markdown table (wall time, peak memory,
which screen chose the exact recursive model: "sampled" where the sampled pre-screen skipped
the region's certification, "proved" where the pairs searched under the proved bounds saved
too little for the pruned model to be built, "no" where neither did; and the deployed
model's operations against the exact recursive model's) and the growth exponents p of
t ~ n^p (least squares over the ns, and between the last two).

Usage::

    python analysis/main_job_scaling.py [--ns 3,6,9,12,15] [--rounds 1] [--src DIR]
        [--arm ROBOT.urdf:TRAJ.csv ...] [--fuzz N:SEED ...] [--compare DIR] [--report-only]

``--src`` runs the jobs on another checkout's ``src`` folder (put first on PYTHONPATH), e.g.
to measure the code before a change beside the code after it. ``--compare DIR`` runs every
job both on this checkout and on ``DIR`` (another checkout's ``src``), interleaved in each
round (the other side first in odd rounds, this side first in even ones), and prints, per
input and side, the median [min, max] of the rounds' wall and CPU times (the child's user +
system time from ``os.wait4``) and peak memory. ``--arm`` adds a given robot file (URDF or
TOML) with its trajectory; ``--fuzz N:SEED`` a random URDF arm of N joints
(:func:`fuzz_urdf`: revolute, continuous and prismatic joints on oblique or principal axes,
fixed joints in between) with the trajectory ``gd-analyze plan`` makes for it. With ``--arm``
or ``--fuzz`` and no ``--ns``, no random chain is run. ``--report-only`` skips the
``--no-report`` jobs.
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


def fuzz_urdf(n, seed):
    """A random URDF arm of n joints (the text).

    Per joint, from ``numpy.random.default_rng(seed)``: revolute, continuous or prismatic (1
    in 4); an axis along a principal direction (60 %) or oblique; a placement with a random
    offset and, half the time, a random orientation; a link of 0.2 to 5 kg with a random
    centre of mass and a positive definite inertia; position limits (revolute: a random range
    around 0 up to +-3 rad; prismatic: -0.2 to 0.3 m), velocity limits of 1 to 3 rad/s; and, 3
    times in 10, a fixed joint to a massless link after it.

    Parameters
    ----------
    n : int
        Moving joints.
    seed : int

    Returns
    -------
    str
        The URDF.
    """
    rng = np.random.default_rng(seed)
    lines = [f'<robot name="fuzz{seed}">', '<link name="base"/>']
    parent = "base"
    for k in range(n):
        kind = rng.choice(["revolute", "revolute", "continuous", "prismatic"])
        ax = rng.normal(size=3)
        if rng.random() < 0.6:
            ax = np.eye(3)[rng.integers(3)] * rng.choice([-1, 1])
        ax /= np.linalg.norm(ax)
        xyz = rng.normal(scale=0.15, size=3)
        rpy = rng.uniform(-np.pi, np.pi, 3) * (rng.random() < 0.5)
        m, c = rng.uniform(0.2, 5), rng.normal(scale=0.05, size=3)
        A = rng.normal(size=(3, 3))
        inertia = A @ A.T * 0.01 + np.eye(3) * 1e-3
        name = f"l{k + 1}"
        lines.append(
            f'<link name="{name}"><inertial><origin xyz="{c[0]} {c[1]} {c[2]}" rpy="0 0 0"/>'
            f'<mass value="{m}"/><inertia ixx="{inertia[0, 0]}" ixy="{inertia[0, 1]}" '
            f'ixz="{inertia[0, 2]}" iyy="{inertia[1, 1]}" iyz="{inertia[1, 2]}" '
            f'izz="{inertia[2, 2]}"/></inertial></link>')
        if kind == "prismatic":
            lim = '<limit lower="-0.2" upper="0.3" effort="100" velocity="0.5"/>'
        elif kind == "continuous":
            lim = '<limit effort="100" velocity="2.0"/>'
        else:
            lo, hi = rng.uniform(-3, -0.5), rng.uniform(0.5, 3)
            lim = (f'<limit lower="{lo}" upper="{hi}" effort="100" '
                   f'velocity="{rng.uniform(1, 3)}"/>')
        lines.append(
            f'<joint name="j{k + 1}" type="{kind}"><parent link="{parent}"/>'
            f'<child link="{name}"/><origin xyz="{xyz[0]} {xyz[1]} {xyz[2]}" '
            f'rpy="{rpy[0]} {rpy[1]} {rpy[2]}"/><axis xyz="{ax[0]} {ax[1]} {ax[2]}"/>{lim}'
            '</joint>')
        parent = name
        if rng.random() < 0.3:
            lines.append(f'<link name="{name}_f"/><joint name="f{k + 1}" type="fixed">'
                         f'<parent link="{parent}"/><child link="{name}_f"/>'
                         '<origin xyz="0 0 0.05" rpy="0 0.3 0"/></joint>')
            parent = f"{name}_f"
    lines.append("</robot>")
    return "\n".join(lines)


def write_fuzz(n, seed, folder):
    """The fuzz arm's URDF and the trajectory ``gd-analyze plan`` makes for it."""
    urdf = folder / f"fuzz-{n}-{seed}.urdf"
    urdf.write_text(fuzz_urdf(n, seed))
    csv = folder / f"fuzz-{n}-{seed}.csv"
    subprocess.run([sys.executable, "-m", "gd_analyze.cli", "plan", str(urdf), "-o", str(csv)],
                   check=True, stdout=subprocess.DEVNULL)
    return urdf, csv


def run_job(toml, csv, out, report, src=""):
    """One main job in a fresh process with a cold cache: (wall [s], peak RSS [MiB], spec);
    its CPU time (user + system) [s] is ``run_job.cpu`` after the call."""
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
        run_job.cpu = usage.ru_utime + usage.ru_stime
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
    parser.add_argument("--ns", default=None)
    parser.add_argument("--rounds", type=int, default=1)
    parser.add_argument("--src", default="", help="another checkout's src folder")
    parser.add_argument("--arm", action="append", default=[], help="ROBOT:TRAJ.csv")
    parser.add_argument("--fuzz", action="append", default=[], help="N:SEED")
    parser.add_argument("--compare", default="", help="another checkout's src folder, "
                        "run interleaved beside this one")
    parser.add_argument("--report-only", action="store_true")
    args = parser.parse_args(argv)
    if args.compare or args.arm or args.fuzz:
        return compare(args)
    ns = [int(v) for v in (args.ns or "3,6,9,12,15").split(",") if v]
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
                    rows[n]["skipped"] = _screened(screen)
                    rows[n]["ops"] = sum(int(spec["cost"][k]) for k in
                                         ("multiplications", "additions"))
                    exact = spec["costs"]["exact recursive"]
                    rows[n]["exact"] = int(exact["multiplications"]) + int(exact["additions"])
                    loads.append(os.getloadavg())
                    print(f"  round {r + 1} n = {n} {'with' if report else 'without'} report: "
                          f"{wall:.1f} s, {mib:.0f} MiB, load {loads[-1][0]:.2f}", flush=True)
    print(f"| n | main job [s] | peak [MiB] | --no-report [s] | peak [MiB] | exact model "
          f"by a screen | operations (exact) |  (median of {args.rounds} round(s))")
    print("|---|---|---|---|---|---|---|")
    for n in ns:
        row = rows[n]
        print(f"| {n} | {np.median(row['report']):.1f} | {np.median(row['report_mib']):.0f} | "
              f"{np.median(row['bare']):.1f} | {np.median(row['bare_mib']):.0f} | "
              f"{row['skipped']} | {row['ops']:,} ({row['exact']:,}) |")
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


def _screened(screen):
    """The table's column: "sampled" where the sampled pre-screen skipped the certification,
    "proved" where the pairs searched under the proved bounds saved too little for the
    pruned model to be built (the exact one deployed), "no" where neither screen chose the
    exact model."""
    if not (screen and screen["skipped"]):
        return "no"
    return "proved" if screen.get("proved") else "sampled"


def _stats(values):
    return f"{np.median(values):.1f} [{min(values):.1f}, {max(values):.1f}]"


def compare(args):
    """The jobs of ``--arm``, ``--fuzz`` and ``--ns`` on this checkout and, interleaved, on
    ``--compare``'s; prints the table (median [min, max] over the rounds) and the loads.

    Parameters
    ----------
    args : argparse.Namespace

    Returns
    -------
    int
        0.
    """
    here = str(Path(__file__).resolve().parent.parent / "src")
    sides = [("this", here)] + ([("other", args.compare)] if args.compare else [])
    loads = [os.getloadavg()]
    print("load averages at the start:", " ".join(f"{v:.2f}" for v in loads[0]), flush=True)
    modes = [(True, "report")] + ([] if args.report_only else [(False, "bare")])
    with tempfile.TemporaryDirectory() as folder:
        folder = Path(folder)
        inputs = {}
        for n in [int(v) for v in (args.ns or "").split(",") if v]:
            inputs[f"chain {n}"] = write_inputs(n, folder)
        for item in args.arm:
            robot, traj = item.rsplit(":", 1)
            inputs[f"{Path(robot).parent.name}/{Path(robot).name}"] = (Path(robot).resolve(),
                                                                     Path(traj).resolve())
        for item in args.fuzz:
            n, seed = (int(v) for v in item.split(":"))
            inputs[f"fuzz {n}:{seed}"] = write_fuzz(n, seed, folder)
        rows: dict = {}
        for r in range(args.rounds):
            for name, (robot, traj) in inputs.items():
                for side, src in (sides if r % 2 else sides[::-1]):
                    for report, key in modes:
                        out = folder / f"out-{len(rows)}"
                        wall, mib, spec = run_job(robot, traj, out, report, src)
                        row = rows.setdefault((name, side, key), {"wall": [], "cpu": [],
                                                                  "mib": []})
                        row["wall"].append(wall)
                        row["cpu"].append(run_job.cpu)
                        row["mib"].append(mib)
                        row["ops"] = sum(int(spec["cost"][k]) for k in
                                         ("multiplications", "additions"))
                        exact = spec["costs"]["exact recursive"]
                        row["exact"] = int(exact["multiplications"]) + int(exact["additions"])
                        screen = spec.get("provenance", {}).get("region_screen")
                        row["skipped"] = _screened(screen)
                        loads.append(os.getloadavg())
                        print(f"  round {r + 1} {name} {side} {key}: wall {wall:.1f} s, CPU "
                              f"{run_job.cpu:.1f} s, {mib:.0f} MiB, load {loads[-1][0]:.2f}",
                              flush=True)
    print(f"| arm | code | job | wall [s] | CPU [s] | peak [MiB] | exact model by a screen | "
          f"operations (exact) |  (median [min, max] of {args.rounds} round(s))")
    print("|---|---|---|---|---|---|---|---|")
    for (name, side, key), row in rows.items():
        print(f"| {name} | {side} | {'with report' if key == 'report' else '--no-report'} | "
              f"{_stats(row['wall'])} | {_stats(row['cpu'])} | {_stats(row['mib'])} | "
              f"{row['skipped']} | {row['ops']:,} ({row['exact']:,}) |")
    one = np.array([x[0] for x in loads])
    print(f"load (1-minute) during the run: {one.min():.2f} to {one.max():.2f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
