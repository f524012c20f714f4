"""Identification: synthetic recovery on every built-in arm, the held-out table on the real
data the repository holds (data/tiago), and the time and memory of 20,000 samples of 7 joints.

Run from the repository's root (takes a few minutes)::

    .venv/bin/python analysis/identify_arms.py [--skip-performance | --performance-only]

1. Synthetic (Pinocchio oracle, tests/identify_recordings.py): a true arm (the robot file with
   other masses, centres of mass and inertias, viscous and Coulomb friction and offsets),
   a 25 s finite Fourier series on an irregular clock (0.7 to 8.8 ms steps) to fit and a
   10 s one held out; noise-free with the file's qd and qdd and no filter (the largest error
   on the held-out motion relative to its peak |tau|), noise-free from positions only
   through the default preprocessing (held-out total relative error), and 1 % noise
   (fraction of base parameters within 1 and 3 standard deviations, pooled over three noise
   realisations).
2. Real: TIAGo (data/tiago, FIGAROH, Apache-2.0): fit on tiago_fit.csv, validate on
   tiago_validate.csv; the held-out total relative error of the identified model and of the
   URDF as shipped (example-robot-data's tiago.urdf).
3. Performance: one recording of 20,000 samples of the Panda's 7 joints (positions and
   torques only, default preprocessing), ``gd.identify`` against ``numpy.linalg.lstsq`` on
   the same regressor (the stacked identification regressor, built beforehand), interleaved,
   each run in its own process: median and range of the wall time, and the peak RSS.
"""

import json
import os
import pathlib
import subprocess
import sys
import tempfile

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "tests"))

from identify_recordings import (  # noqa: E402
    ERD,
    builtin_urdf,
    fourier,
    irregular_clock,
    truth_for,
)

from gd_analyze import load_robot  # noqa: E402
from gd_analyze.dynamics.base_parameters import base_parameters, base_regressor, random_states
from gd_analyze.jobs.identify import IdentifyOptions, identify  # noqa: E402
from gd_analyze.model.robots import builtin_robots  # noqa: E402
from gd_analyze.trajectory.trajectory import recording_from_arrays  # noqa: E402

URDF_BUILTINS = {"panda", "ur5"}
REPEATS = 3
#: Noise realisations pooled for the coverage (a two-link arm has 6 base parameters only).
NOISE_SEEDS = (3, 4, 5)


def _record(truth, n, seconds, seed, noise=0.0, derivatives=True):
    t = irregular_clock(seconds, seed)
    q, qd, qdd = fourier(n, t, seed=seed)
    tau_true = truth.torque(q, qd, qdd)
    tau = tau_true
    if noise:
        tau = tau + noise * tau.std(axis=0) * np.random.default_rng(seed + 7).normal(
            size=tau.shape)
    return recording_from_arrays(t, q, tau, qd if derivatives else None,
                                 qdd if derivatives else None, source=f"rec{seed}"), tau_true


def _true_beta(robot, truth, base):
    q, qd, qdd = random_states(robot, 400, seed=11)
    rigid = truth.torque(q, qd, qdd) - truth.viscous * qd - truth.coulomb * np.sign(qd) \
        - truth.offset
    Y, _ = base_regressor(robot, q, qd, qdd, base)
    return np.linalg.lstsq(Y.reshape(-1, Y.shape[2]), rigid.reshape(-1), rcond=None)[0]


def synthetic():
    rows = []
    for name in builtin_robots():
        robot = load_robot(name)
        truth = truth_for(robot, urdf=builtin_urdf(name) if name in URDF_BUILTINS else None)
        train, _ = _record(truth, robot.n, 25, 2)
        held, tau_true = _record(truth, robot.n, 10, 5)
        res = identify(robot, [train], validate=[held], options=IdentifyOptions(cutoff=None))
        fit = res.recordings[1]
        exact = float(np.abs(fit.tau_predicted - tau_true).max() / np.abs(tau_true).max())
        prior = fit.errors("prior")[2]
        train_p, _ = _record(truth, robot.n, 25, 2, derivatives=False)
        held_p, _ = _record(truth, robot.n, 10, 5, derivatives=False)
        res_p = identify(robot, [train_p], validate=[held_p])
        filtered = res_p.recordings[1].errors()[2]
        base = base_parameters(robot)
        beta = _true_beta(robot, truth, base)
        z = []
        for seed in NOISE_SEEDS:
            noisy, _ = _record(truth, robot.n, 40, seed, noise=0.01)
            res_n = identify(robot, [noisy], options=IdentifyOptions(cutoff=None))
            z.append(np.abs(res_n.parameters.value[:base.rank] - beta)
                     / res_n.parameters.std[:base.rank])
        z = np.concatenate(z)
        rows.append((name, robot.n, len(res.parameters.names), res.rank,
                     res.condition_number, exact, filtered, prior, float(np.mean(z <= 1)),
                     float(np.mean(z <= 3))))
    print("## Synthetic recovery (Pinocchio oracle)\n")
    print("| arm | n | parameters | rank | condition number | held-out max error / peak "
          "tau (exact derivatives, no filter) | held-out total rel. error (positions only, "
          "default filter) | robot file as shipped | 1-sigma coverage (1 % noise) | "
          "3-sigma coverage |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        print(f"| {r[0]} | {r[1]} | {r[2]} | {r[3]} | {r[4]:.1f} | {r[5]:.1e} | {r[6]:.3%} | "
              f"{r[7]:.1%} | {r[8]:.0%} | {r[9]:.0%} |")
    print()


def real():
    urdf = ERD / "tiago_description/robots/tiago.urdf"
    robot = load_robot(str(urdf), tip="arm_7_link")
    data = ROOT / "data" / "tiago"
    print("## Real recording: TIAGo (data/tiago; fit on tiago_fit.csv, validate on "
          "tiago_validate.csv)\n")
    print("| setting | condition number | identified, held out | URDF as shipped, held out |")
    print("|---|---|---|---|")
    for label, options in (("default", IdentifyOptions()),
                           ("--consistent", IdentifyOptions(consistent=True))):
        res = identify(robot, [data / "tiago_fit.csv"], validate=[data / "tiago_validate.csv"],
                       options=options)
        held = res.recordings[1]
        print(f"| {label} | {res.condition_number:.1f} | {held.errors()[2]:.1%} | "
              f"{held.errors('prior')[2]:.0%} |")
        print(f"\n{label}: per joint held-out relative error "
              + ", ".join(f"{v:.2f}" for v in held.errors()[1]) + "\n")


CHILD = r"""
import json, resource, sys, time
import numpy as np
sys.path.insert(0, {tests!r})
from gd_analyze import load_robot
from gd_analyze.trajectory.trajectory import read_recording
from gd_analyze.jobs.identify import identify
kind, path = sys.argv[1], sys.argv[2]
robot = load_robot("panda")
def cpu():
    r = resource.getrusage(resource.RUSAGE_SELF)
    return r.ru_utime + r.ru_stime
if kind == "identify":
    c0 = cpu()
    t0 = time.perf_counter()
    res = identify(robot, [path])
    elapsed = time.perf_counter() - t0
    cpu_s = cpu() - c0
else:
    from gd_analyze.estimation.preprocess import preprocess
    from gd_analyze.dynamics.base_parameters import base_parameters
    from gd_analyze.symbolic.drive_regressor import (
        IdentificationColumns,
        identification_regressor,
    )
    rec = read_recording(path, robot.n)
    pre = preprocess(rec.t, rec.q, rec.tau)
    k = pre.keep
    columns = IdentificationColumns.keeping_all(base_parameters(robot), robot.n,
                                                ("viscous", "coulomb", "offset"))
    Y = identification_regressor(robot, pre.q[k], pre.qd[k], pre.qdd[k], columns)
    A, y = Y.reshape(-1, Y.shape[2]), pre.tau[k].reshape(-1)
    c0 = cpu()
    t0 = time.perf_counter()
    np.linalg.lstsq(A, y, rcond=None)
    elapsed = time.perf_counter() - t0
    cpu_s = cpu() - c0
print(json.dumps({{"seconds": elapsed, "cpu_seconds": cpu_s,
                  "peak_mib": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024}}))
"""


def performance():
    from identify_recordings import write_recording

    robot = load_robot("panda")
    truth = truth_for(robot, urdf=builtin_urdf("panda"))
    folder = pathlib.Path(tempfile.mkdtemp())
    t = irregular_clock(200.0, 9)[:20000]
    q, qd, qdd = fourier(robot.n, t, seed=9)
    tau = truth.torque(q, qd, qdd)
    tau = tau + 0.01 * tau.std(axis=0) * np.random.default_rng(1).normal(size=tau.shape)
    path = write_recording(folder / "panda20000.csv", t, q, tau)
    code = CHILD.format(tests=str(ROOT / "tests"))
    runs = {"identify": [], "lstsq": []}
    for _ in range(REPEATS):
        for kind in runs:
            out = subprocess.run([sys.executable, "-c", code, kind, str(path)], check=True,
                                 capture_output=True, text=True).stdout
            runs[kind].append(json.loads(out.strip().splitlines()[-1]))
    print(f"## Performance: {t.size} samples of 7 joints (Panda), {REPEATS} interleaved runs "
          f"each\n")
    load = os.getloadavg()[0]
    print(f"(load average {load:.1f} on {os.cpu_count()} cores at the start)\n")
    print("| job | median wall [s] | range [s] | median CPU [s] | peak RSS [MiB] |")
    print("|---|---|---|---|---|")
    for kind, label in (("identify", "gd.identify (read, preprocess, regressor, OLS+WLS)"),
                        ("lstsq", "numpy.linalg.lstsq on the same regressor (solve only)")):
        s = [r["seconds"] for r in runs[kind]]
        m = max(r["peak_mib"] for r in runs[kind])
        c = np.median([r["cpu_seconds"] for r in runs[kind]])
        print(f"| {label} | {np.median(s):.2f} | {min(s):.2f} to {max(s):.2f} | {c:.2f} | "
              f"{m:.0f} |")
    print()


if __name__ == "__main__":
    if "--performance-only" not in sys.argv:
        synthetic()
        real()
    if "--skip-performance" not in sys.argv:
        performance()
