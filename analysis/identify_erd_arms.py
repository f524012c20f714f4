"""``identify`` on the serial arms of example-robot-data: recordings made with Pinocchio from a
changed URDF, identified through the command line, judged on a held-out recording.

    python analysis/identify_erd_arms.py [--arms NAME[:TIP] ...] [--seconds S] [--noise F]

For every serial arm of the installed ``example-robot-data`` (as ``analysis/real_arms.py``
finds them: a URDF with one chain, or NAME:TIP given with --arms, e.g. a humanoid's arm) the
script

1. makes the true arm: the URDF's own Pinocchio model (``pinocchio.buildModelFromUrdf``) with
   every moving body's mass and rotational inertia scaled by 1 + 0.25 u and its centre of
   mass moved by 1 % of its largest coordinate (at least 0.1 mm) in a random direction (u
   uniform in [-1, 1]; a body Pinocchio refuses so changed is kept as it is); viscous and
   Coulomb friction of 1-5 % of each joint's peak rigid torque, offsets of up to 2 %;
2. records it (Pinocchio's rnea, the chain's joints driven, every other joint at its neutral
   position and at rest) along a finite Fourier series (Swevers et al. 1997, 5 harmonics,
   0.1 Hz base) centred in the joint limits and kept within 40 % of each joint's range, at
   100 Hz: S seconds to fit (default 40) and 10 s held out, with Gaussian noise of F (default
   1 %) of each joint's torque standard deviation; written as ``t,q1..,tau1..`` (positions
   and torques only, as a real log);
3. runs ``gd-analyze identify URDF FIT.csv --validate HELD.csv [--tip TIP] --no-report`` as a
   child process (default preprocessing: low-pass filter, numerical derivatives), timing it;
4. reads the total relative torque error ||E||_F / ||T||_F on the held-out recording of the
   identified robot file and of the URDF as shipped, from ``identification.h5`` (the
   recording's group's ``total_relative_error`` and ``prior_total_relative_error``).

It prints the load averages, a Markdown table and one PASS/FAIL line per criterion: every
child exits 0; the identified robot's held-out error is below 1 % and below the URDF's.
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(ROOT / "analysis"), str(ROOT / "tests")]

from identify_recordings import Truth, fourier, write_recording  # noqa: E402
from real_arms import discover  # noqa: E402


def true_arm(path, robot, seed=7):
    """The URDF's Pinocchio model with changed inertial parameters (module docstring)."""
    import pinocchio as pin

    model = pin.buildModelFromUrdf(str(path))
    rng = np.random.default_rng(seed)
    for j in range(1, model.njoints):
        inertia = model.inertias[j]
        mass, moments = (1 + 0.25 * rng.uniform(-1, 1, 2))
        shift = 0.01 * max(float(np.abs(inertia.lever).max()), 0.01) * rng.normal(size=3)
        try:
            model.inertias[j] = pin.Inertia(inertia.mass * mass, inertia.lever + shift,
                                            inertia.inertia * moments)
        except RuntimeError:        # a body with no inertia to speak of: kept
            pass
    return model, [model.getJointId(name) for name in robot.joint_names()]


def motion(robot, seconds, seed):
    """t, q, qd, qdd at 100 Hz: a Fourier series centred in the limits, within 40 % of each
    finite range (prismatic joints without limits: 5 cm)."""
    lo, hi = np.asarray(robot.q_min, float), np.asarray(robot.q_max, float)
    finite = np.isfinite(lo) & np.isfinite(hi)
    centre = np.where(finite, 0.5 * (np.where(finite, lo, 0) + np.where(finite, hi, 0)), 0.0)
    t = 0.01 * np.arange(int(seconds / 0.01))
    q, qd, qdd = fourier(robot.n, t, seed=seed, amplitude=0.5)
    reach = np.abs(q).max(axis=0)
    scale = np.where(finite, np.minimum(1.0, 0.4 * np.where(finite, hi - lo, 0) / reach),
                     np.where(np.asarray(robot.prismatic, bool), 0.05, 1.0))
    return t, centre + q * scale, qd * scale, qdd * scale


def held_out_errors(folder, name):
    """(identified, robot file as shipped): the held-out recording's total relative error [1]
    (its group's ``total_relative_error`` and ``prior_total_relative_error``)."""
    import h5py

    with h5py.File(folder / "identification.h5", "r") as f:
        attrs = f[name].attrs
        return (float(np.ravel(attrs["total_relative_error"])[0]),
                float(np.ravel(attrs["prior_total_relative_error"])[0]))


def run_arm(name, path, tip, work, seconds, noise):
    """One arm: its recordings, the identify child, the held-out errors."""
    from gd_analyze import load_robot

    robot = load_robot(str(path), tip=tip)
    model, ids = true_arm(path, robot)
    zeros = np.zeros(robot.n)
    rigid_only = Truth(model, ids, zeros, zeros, zeros)
    files = {}
    for role, length, seed in (("fit", seconds, 2), ("held", 10, 5)):
        t, q, qd, qdd = motion(robot, length, seed)
        tau = rigid_only.torque(q, qd, qdd)
        if role == "fit":
            peak = np.abs(tau).max(axis=0) + 1e-6
            rng = np.random.default_rng(11)
            viscous = rng.uniform(0.01, 0.05, robot.n) * peak / np.maximum(np.abs(qd).max(0), 1e-3)
            coulomb = rng.uniform(0.01, 0.05, robot.n) * peak
            offset = rng.uniform(-0.02, 0.02, robot.n) * peak
        tau = tau + viscous * qd + coulomb * np.sign(qd) + offset
        tau = tau + noise * tau.std(axis=0) * np.random.default_rng(seed).normal(size=tau.shape)
        files[role] = write_recording(work / f"{name}_{role}.csv", t, q, tau)
    out = work / f"{name}-identify"
    cmd = [sys.executable, "-m", "gd_analyze", "identify", str(path), str(files["fit"]),
           "--validate", str(files["held"]), "-o", str(out), "--no-report"]
    cmd += ["--tip", tip] if tip else []
    start = time.perf_counter()
    child = subprocess.run(cmd, capture_output=True, text=True,
                           env={**os.environ, "MPLBACKEND": "Agg"})
    row = {"arm": name + (f":{tip}" if tip else ""), "joints": robot.n,
           "seconds": time.perf_counter() - start, "exit": child.returncode}
    if child.returncode == 0:
        row["identified"], row["urdf"] = held_out_errors(out, f"{name}_held")
    else:
        row["error"] = (child.stderr.strip().splitlines() or ["?"])[-1][:160]
    return row


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--arms", nargs="*", help="NAME or NAME:TIP (default: every serial arm)")
    parser.add_argument("--seconds", type=float, default=40.0, help="length of the fit [s]")
    parser.add_argument("--noise", type=float, default=0.01,
                        help="torque noise, a fraction of each joint's standard deviation")
    args = parser.parse_args(argv)
    arms, skipped = discover(args.arms)
    print(f"load averages {os.getloadavg()}; {len(arms)} arms, {len(skipped)} URDFs left out")
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for name, path, tip, _ in arms:
            rows.append(run_arm(name, path, tip, Path(tmp), args.seconds, args.noise))
            r = rows[-1]
            print(f"  {r['arm']}: exit {r['exit']}, {r['seconds']:.1f} s", flush=True)
    print("\n| arm | joints | identify [s] | held-out error, identified | URDF as shipped |")
    print("|---|---|---|---|---|")
    for r in rows:
        errors = (f"{100 * r['identified']:.2f} % | {100 * r['urdf']:.2f} %" if r["exit"] == 0
                  else f"exit {r['exit']}: {r['error']} |")
        print(f"| {r['arm']} | {r['joints']} | {r['seconds']:.1f} | {errors} |")
    failed = [r["arm"] for r in rows if r["exit"] != 0]
    worse = [r["arm"] for r in rows if r["exit"] == 0
             and not (r["identified"] < min(0.01, r["urdf"]))]
    print(f"\n{'PASS' if not failed else 'FAIL'}: every identify exits 0" +
          (f" (not: {', '.join(failed)})" if failed else ""))
    print(f"{'PASS' if not worse else 'FAIL'}: held-out error below 1 % and below the URDF's" +
          (f" (not: {', '.join(worse)})" if worse else ""))
    return 1 if failed or worse else 0


if __name__ == "__main__":
    sys.exit(main())
