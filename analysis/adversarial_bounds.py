"""An adversarial search for a state of the region that breaks a region model's proved bound.

The main job proves, by interval arithmetic rounded outward, that its region model's torque
error stays within ``guarantee.bound`` at every state of the region, and that its D_s is
positive definite there (``inertia_check.lower_bound``). The tests check 100,000 uniform
states; this script looks where the error peaks instead. For each arm, EPS and region it
runs the main job (``gd-analyze ROBOT TRAJ.csv --tolerance EPS --no-report --no-verify``, each
in its own process), reads the model file back by ``gd_analyze.load_model`` (which proves the
bound again), and compares the emitted ``simplified_model.py`` with Pinocchio's ``rnea``
(plus the drives' friction, ``viscous qd + coulomb sign(qd) + torque_offset``) at the same
state:

(a) vertices: the error is affine in qdd, so its largest |e_i| over the acceleration box is
    exactly ``|e_i(q, qd, 0)| + sum_j |D_s - D|_ij qdd_max_j``; qd at every vertex of its box
    (every sign pattern up to 7 joints, 256 random ones above), q uniform, at the joint-limit
    corners and on the faces (each joint at a limit with probability 1/2);
(b) from the worst states of (a) (the ``--starts`` best per joint, 1,000 at most), a local
    maximisation of error_i / bound_i over (q, qd) in the box, qdd eliminated as above:
    projected finite-difference gradient ascent on all starts at once, the best 5 per joint
    then polished by ``scipy.optimize.minimize`` (L-BFGS-B with bounds);
(c) the least eigenvalue of the emitted D_s over q: uniform, corner and face positions, then
    the same local minimisation from the 200 least; it must stay at or above the proved
    ``lower_bound`` (> 0), and above 0 where the model says it is not proved (no floor
    under D: the Stanford arm).

Each reported ratio is recomputed at its state by a direct call of the emitted ``tau`` and
Pinocchio's ``rnea`` (qdd at the vertex that maximises the error). A violation is a ratio above
``1 + 1e-9`` beyond the round-off floor the guarantee states (64 eps of the largest s_i), or
an eigenvalue below the proved bound.

Usage::

    python analysis/adversarial_bounds.py [--arms puma560,stanford,panda,ur5,puma560-drives,
        puma560@wall,stanford@wall,panda@wall,ur5@wall,ur5@payload,ur5@wrap,puma560@odd]
        [--fuzz 4:5,5:7,6:2,7:3,8:2,9:1] [--eps 0.01,0.05] [--narrow ARM,...] [--positions 4000]
        [--starts 100] [--iterations 60] [--work DIR] [--seed 0]

An arm ``NAME@wall`` is mounted with ``--base-rpy 20,70,10`` (gravity oblique to every
axis), ``NAME@payload`` carries a 3 kg load off the flange's axis, ``NAME@wrap`` limits every
joint to 100:300 deg (across +-180 deg: the UR5's full-turn joints), ``puma560@odd`` limits
joint 6 to 150:250 deg and joint 5's velocity to 0.01 deg/s. ``--narrow`` adds, for those arms, a narrowed region (the middle half of each joint's range,
-90:90 deg for a full-turn joint, half the velocity and acceleration limits) at each EPS.
``--fuzz N:SEED`` adds ``analysis/main_job_scaling.py``'s random URDF arm (revolute,
continuous and prismatic joints, offsets, oblique axes) with the trajectory ``gd-analyze plan``
makes for it. The main jobs' folders are kept under ``--work`` and reused on a second run
(each model file is proved again on reading).

Prints the load averages, one line per configuration as it finishes, then a Markdown table:
per arm, EPS and region, the largest error_i / bound_i found per joint (``-`` where the bound
is 0: there the error over the round-off floor is shown in brackets), where the worst came
from (vertex search or local maximisation), the least eigenvalue of D_s found against the
proved lower bound, and the seconds taken; the model files that ``load_model`` refused, with
its reason (such a file is audited all the same, its robot read from the file and mounted as
it says); then PASS, or FAIL with each violating state.
"""

from __future__ import annotations

import argparse
import importlib.util
import json
import os
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(Path(__file__).resolve().parent))
from main_job_scaling import fuzz_urdf  # noqa: E402  (the random URDF arms)

TRAJECTORIES = {"puma560": "puma560_trajectory.csv", "puma560-drives": "puma560_trajectory.csv",
                "stanford": "stanford_trajectory.csv", "panda": "panda_trajectory.csv",
                "ur5": "ur5_trajectory.csv"}
ROBOTS = {"ur5": str(ROOT / "data" / "robots" / "ur5.urdf")}
#: Mountings and loads (``ARM@VARIANT``): the main job's options.
VARIANTS = {"wall": ["--base-rpy", "20,70,10"],
            "payload": ["--payload", "3", "--payload-com", "0.05,0.02,0.1",
                        "--payload-inertia", "0.01,0.02,0.015"],
            "wrap": ["--q-limits", "100:300"],
            "odd": ["--q-limits", "-160:160,-45:225,-225:45,-110:170,-100:100,150:250",
                    "--qd-max", "100,95,100,150,0.01,110"]}
TOLERANCE = 1e-9          # relative slack beyond which a ratio above 1 is a violation
POLISHED = 5             # starts per joint polished by L-BFGS-B after the ascent


# ---------------------------------------------------------------------------------------------
# building the models

def _inputs(arm: str, work: Path) -> tuple[str, str]:
    """The robot argument and the trajectory of an arm name or a fuzz ``N:SEED``."""
    if ":" in arm:
        n, seed = (int(x) for x in arm.split(":"))
        urdf, csv = work / f"fuzz-{n}-{seed}.urdf", work / f"fuzz-{n}-{seed}.csv"
        if not csv.exists():
            urdf.write_text(fuzz_urdf(n, seed))
            subprocess.run([sys.executable, "-m", "gd_analyze.cli", "plan", str(urdf), "-o",
                            str(csv)], check=True, stdout=subprocess.DEVNULL)
        return str(urdf), str(csv)
    return ROBOTS.get(arm, arm), str(ROOT / "data" / TRAJECTORIES[arm])


def _narrowed(spec: dict) -> list[str]:
    """The options of the narrowed region of a default region model's file."""
    g = spec["guarantee"]["region"]
    prismatic = g["prismatic"]
    lims, qd, qdd = [], [], []
    for j, q in enumerate(g["q"]):
        unit = 1.0 if prismatic[j] else 180.0 / np.pi
        if isinstance(q, str):
            lo, hi = -90.0, 90.0
        else:
            mid, half = (q[0] + q[1]) / 2, (q[1] - q[0]) / 4
            lo, hi = (mid - half) * unit, (mid + half) * unit
        lims.append(f"{lo:.6f}:{hi:.6f}")
        qd.append(f"{g['qd_max'][j] * unit / 2:.6f}")
        qdd.append(f"{g['qdd_max'][j] * unit / 2:.6f}")
    return ["--q-limits", ",".join(lims), "--qd-max", ",".join(qd), "--qdd-max", ",".join(qdd)]


def build(arm: str, eps: float, narrow: bool, work: Path) -> Path:
    """The main job's output folder for an arm, EPS and region (run once, then reused)."""
    arm, _, variant = arm.partition("@")
    robot, csv = _inputs(arm, work)
    label = (f"{arm.replace(':', '-')}" + (f"-{variant}" if variant else "") + f"-{eps:g}"
             + ("-narrow" if narrow else ""))
    out = work / label
    if (out / "simplified_model.json").exists():
        return out
    args = [robot, csv, "--tolerance", f"{eps:g}", "--no-report", "--no-verify", "-q",
            "-o", str(out), *VARIANTS.get(variant, [])]
    if narrow:
        default = build(arm + (f"@{variant}" if variant else ""), eps, False, work)
        args += _narrowed(json.loads((default / "simplified_model.json").read_text()))
    done = subprocess.run([sys.executable, "-m", "gd_analyze.cli", *args],
                          stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    if done.returncode != 0:
        raise SystemExit(f"{label}: the main job exited {done.returncode}: "
                         f"{done.stderr.strip()[-400:]}")
    return out


# ---------------------------------------------------------------------------------------------
# the model against Pinocchio

class Arm:
    """A built model, its proved claims and its oracle.

    Parameters
    ----------
    folder : Path
        A main job's output folder (``simplified_model.json`` and ``simplified_model.py``).
    """

    def __init__(self, folder: Path):
        import pinocchio as pin

        from gd_analyze import InputError, load_model
        from gd_analyze.dynamics.pinocchio import pinocchio_model
        from gd_analyze.model.drives import friction_torque
        from gd_analyze.model.mounting import as_mounted
        from gd_analyze.model.robot_spec import robot_from_dict

        spec = json.loads((folder / "simplified_model.json").read_text())
        self.refused = ""
        try:
            robot = load_model(folder / "simplified_model.json").robot   # proves the bound
        except InputError as e:         # the main job's own file refused: audited all the same
            self.refused = str(e).split(": ", 1)[-1]
            said = spec["mounting"]
            robot = as_mounted(robot_from_dict(spec["robot"]["parameters"]),
                               said["base_rpy_deg"], said["gravity_world"])
        self.n = robot.n
        name = f"emitted_{abs(hash(str(folder)))}"
        where = importlib.util.spec_from_file_location(name, folder / "simplified_model.py")
        assert where is not None and where.loader is not None
        self.emitted = importlib.util.module_from_spec(where)
        where.loader.exec_module(self.emitted)
        self.pin, self.pm = pin, pinocchio_model(robot)
        self.data = self.pm.createData()
        self.friction = lambda qd: friction_torque(robot, qd)
        g = spec["guarantee"]
        assert g["kind"] == "region", "not a region model"
        self.bound, self.scale = np.asarray(g["bound"], float), np.asarray(g["scale"], float)
        self.lo, self.hi = np.asarray(g["q_min"], float), np.asarray(g["q_max"], float)
        self.v, self.a = np.asarray(g["qd_max"], float), np.asarray(g["qdd_max"], float)
        self.floor = 64 * np.finfo(float).eps * self.scale.max()
        check = spec.get("inertia_check") or {}
        self.lower = check.get("lower_bound") if check.get("proved") else None
        self.dropped = int(np.asarray(spec["recursive"]["dropped"], bool).sum()) \
            if spec.get("recursive") else 0

    def exact(self, q, qd, qdd):
        """Pinocchio's rnea plus the drives' friction, shape (N, n)."""
        out = np.array([self.pin.rnea(self.pm, self.data, a, b, c)
                        for a, b, c in zip(q, qd, qdd)])
        f = self.friction(qd)
        return out if f is None else out + f

    def inertia(self, q):
        """Pinocchio's crba (armature included), both triangles, shape (N, n, n)."""
        out = np.array([self.pin.crba(self.pm, self.data, a) for a in q])
        return np.triu(out) + np.swapaxes(np.triu(out, 1), 1, 2)

    def parts(self, q, qd):
        """``(e0, dD)``: tau_s - tau at qdd = 0, shape (N, n), and D_s - D, (N, n, n)."""
        zero = np.zeros_like(q)
        e0 = self.emitted.tau(q, qd, zero) - self.exact(q, qd, zero)
        return e0, self.emitted.inertia(q) - self.inertia(q)

    def worst(self, q, qd):
        """The largest |tau_s - tau| over the acceleration box at (q, qd), shape (N, n)
        (affine in qdd: exact)."""
        e0, dD = self.parts(q, qd)
        return np.abs(e0) + np.abs(dD) @ self.a

    def ratio(self, err):
        """error / bound per joint (error / round-off floor where the bound is 0)."""
        return err / np.where(self.bound > 0, self.bound, self.floor)

    def vertex_qdd(self, q, qd, joint):
        """The acceleration vertex where joint ``joint``'s error is largest at (q, qd)."""
        e0, dD = self.parts(q[None], qd[None])
        s = np.sign(e0[0, joint]) or 1.0
        return s * np.where(dD[0, joint] >= 0, 1.0, -1.0) * self.a

    def direct(self, q, qd, qdd):
        """|tau_s - tau| by one call of the emitted ``tau`` and of rnea, shape (n,)."""
        return np.abs(self.emitted.tau(q[None], qd[None], qdd[None])[0]
                      - self.exact(q[None], qd[None], qdd[None])[0])

    def check_consistency(self, rng):
        """The emitted model is D_s qdd + h_s + c_s and Pinocchio's tau = D qdd + rnea(q, qd,
        0): the error's split is exact (to round-off)."""
        q = rng.uniform(self.lo, self.hi, (20, self.n))
        qd = rng.uniform(-1, 1, (20, self.n)) * self.v
        qdd = rng.uniform(-1, 1, (20, self.n)) * self.a
        e0, dD = self.parts(q, qd)
        err = self.emitted.tau(q, qd, qdd) - self.exact(q, qd, qdd)
        split = e0 + np.einsum("nij,nj->ni", dD, qdd)
        assert np.abs(err - split).max() <= 1e-9 * max(1.0, self.scale.max()), "split"


def _positions(arm: Arm, count: int, rng) -> np.ndarray:
    """Positions of the region: a third uniform, a third on faces (each joint at a limit with
    probability 1/2), a third at corners (every joint at a limit), shape (count, n)."""
    n = arm.n
    q = rng.uniform(arm.lo, arm.hi, (count, n))
    at = np.where(rng.uniform(size=(count, n)) < 0.5, arm.lo, arm.hi)
    face = rng.uniform(size=(count, n)) < 0.5
    k = count // 3
    q[k:2 * k] = np.where(face[k:2 * k], at[k:2 * k], q[k:2 * k])
    q[2 * k:] = at[2 * k:]
    return q


def _patterns(n: int, rng) -> np.ndarray:
    """Velocity sign patterns: every one up to 7 joints, 256 random ones above."""
    if n <= 7:
        return np.array(np.meshgrid(*[[-1.0, 1.0]] * n, indexing="ij")).reshape(n, -1).T
    return rng.choice([-1.0, 1.0], (256, n))


def vertex_search(arm: Arm, positions: int, rng, chunk: int = 100):
    """(a): every position with every velocity vertex, qdd eliminated exactly; returns the
    states ``(q, qd)`` and their ratios, shape (M, n), (M, n), (M, n): the worst pattern
    per position and joint is kept as a separate state only for the joint's best."""
    q = _positions(arm, positions, rng)
    signs = _patterns(arm.n, rng)
    P = len(signs)
    best_q, best_qd, best_r = [], [], []
    for s in range(0, positions, chunk):
        qc = q[s:s + chunk]
        qq = np.repeat(qc, P, axis=0)
        vv = np.tile(signs * arm.v, (len(qc), 1))
        zero = np.zeros_like(qq)
        e0 = (arm.emitted.tau(qq, vv, zero) - arm.exact(qq, vv, zero)).reshape(len(qc), P, -1)
        dD = np.abs(arm.emitted.inertia(qc) - arm.inertia(qc)) @ arm.a       # (chunk, n)
        r = arm.ratio(np.abs(e0) + dD[:, None, :])
        idx = r.argmax(axis=1)                                       # (chunk, n)
        for j in range(arm.n):
            best_q.append(qc)
            best_qd.append(signs[idx[:, j]] * arm.v)
            best_r.append(np.take_along_axis(r[:, :, j], idx[:, j:j + 1], 1)[:, 0])
    # regroup: per joint j, its states
    per = [[] for _ in range(arm.n)]
    for k, (a, b, c) in enumerate(zip(best_q, best_qd, best_r)):
        per[k % arm.n].append((a, b, c))
    out = []
    for j in range(arm.n):
        a = np.concatenate([x[0] for x in per[j]])
        b = np.concatenate([x[1] for x in per[j]])
        c = np.concatenate([x[2] for x in per[j]])
        out.append((a, b, c))
    return out


def _ascent(f, x0, lo, hi, iterations, step0=0.05, h=1e-6):
    """Projected finite-difference gradient ascent on all starts at once.

    ``f(X)`` gives the objective of each row of X, shape (S,) for (S, d); each start keeps
    its own step (a fraction of the box's widths), grown on success, cut on failure."""
    S, d = x0.shape
    width = np.where(hi > lo, hi - lo, 1.0)
    x, fx = x0.copy(), f(x0)
    step = np.full(S, step0)
    for _ in range(iterations):
        eye = np.eye(d) * (h * width)
        plus = np.clip((x[:, None, :] + eye).reshape(-1, d), lo, hi)
        minus = np.clip((x[:, None, :] - eye).reshape(-1, d), lo, hi)
        fp, fm = f(plus).reshape(S, d), f(minus).reshape(S, d)
        dx = (plus - minus).reshape(S, d, d)[:, np.arange(d), np.arange(d)]
        g = np.where(dx > 0, (fp - fm) / np.where(dx > 0, dx, 1.0), 0.0) * width
        norm = np.abs(g).max(axis=1, keepdims=True)
        trial = np.clip(x + step[:, None] * width * g / np.where(norm > 0, norm, 1.0), lo, hi)
        ft = f(trial)
        up = ft > fx
        x[up], fx[up] = trial[up], ft[up]
        step = np.where(up, np.minimum(step * 1.5, 0.5), step * 0.3)
        if (step < 1e-9).all():
            break
    return x, fx


def local_search(arm: Arm, found, starts: int, iterations: int):
    """(b): from the ``starts`` worst states per joint of :func:`vertex_search`, ascent on
    error_j / bound_j over (q, qd), then L-BFGS-B from the 5 best per joint. Returns per
    joint the best ``(ratio, q, qd, qdd)`` found, qdd at its vertex, the ratio recomputed by
    a direct call."""
    from scipy.optimize import minimize

    n = arm.n
    lo = np.concatenate([arm.lo, -arm.v])
    hi = np.concatenate([arm.hi, arm.v])
    best = []
    for j in range(n):
        q, qd, r = found[j]
        order = np.argsort(-r)[:starts]
        x0 = np.concatenate([q[order], qd[order]], axis=1)

        def f(X, j=j):
            return arm.ratio(arm.worst(X[:, :n], X[:, n:]))[:, j]

        x, fx = _ascent(f, x0, lo, hi, iterations)
        top = np.argsort(-fx)[:POLISHED]
        cands = [(fx[k], x[k], "ascent") for k in top]
        cands.append((r[order[0]], x0[0], "vertex"))
        for k in top:
            res = minimize(lambda y, j=j: -f(y[None], j)[0], x[k], method="L-BFGS-B",
                           bounds=list(zip(lo, hi)), options={"maxiter": 100})
            cands.append((-res.fun, np.clip(res.x, lo, hi), "L-BFGS-B"))
        value, xb, how = max(cands, key=lambda c: c[0])
        qb, qdb = xb[:n], xb[n:]
        qddb = arm.vertex_qdd(qb, qdb, j)
        direct = arm.ratio(arm.direct(qb, qdb, qddb))[j]
        best.append((direct, qb, qdb, qddb, how))
    return best


def eigen_search(arm: Arm, positions: int, rng, iterations: int):
    """(c): the least eigenvalue of the emitted D_s over q; returns (lambda, q)."""
    q = _positions(arm, positions, rng)

    def f(X):
        return -np.linalg.eigvalsh(arm.emitted.inertia(X))[:, 0]

    v = f(q)
    order = np.argsort(-v)[:200]
    x, fx = _ascent(f, q[order], arm.lo, arm.hi, iterations)
    k = int(np.argmax(fx))
    return -fx[k], x[k]


# ---------------------------------------------------------------------------------------------
# the report

def audit(folder: Path, args, seed: int) -> dict:
    """(a), (b) and (c) on one built model; the row of the table and the violations."""
    t0 = time.perf_counter()
    rng = np.random.default_rng(seed)
    arm = Arm(folder)
    arm.check_consistency(rng)
    found = vertex_search(arm, args.positions, rng)
    vertex = np.array([f[2].max() for f in found])
    best = local_search(arm, found, args.starts, args.iterations)
    lam, qlam = eigen_search(arm, args.positions, rng, args.iterations)
    violations = []
    for j, (ratio, q, qd, qdd, how) in enumerate(best):
        err = arm.direct(q, qd, qdd)[j]
        if err > arm.bound[j] * (1 + TOLERANCE) + arm.floor:
            violations.append(f"{folder.name} joint {j + 1}: error {err:.6g} > bound "
                              f"{arm.bound[j]:.6g} at q={q.tolist()}, qd={qd.tolist()}, "
                              f"qdd={qdd.tolist()}")
    if not lam > 0 or (arm.lower is not None and not lam >= arm.lower):
        violations.append(f"{folder.name}: lambda_min(D_s) {lam:.6g} below "
                          f"{arm.lower or 0} at q={qlam.tolist()}")
    return {"label": folder.name, "n": arm.n, "dropped": arm.dropped,
            "bound": arm.bound, "ratios": [b[0] for b in best], "how": [b[4] for b in best],
            "vertex": vertex, "lambda": lam, "lower": arm.lower,
            "seconds": time.perf_counter() - t0, "violations": violations,
            "refused": arm.refused}


def _cell(row, j):
    r = row["ratios"][j]
    if row["bound"][j] > 0:
        return f"{r:.6f}"
    return f"- [{r:.2g}]"


def table(rows) -> str:
    """The Markdown table of the audits."""
    lines = ["| model (arm-EPS[-narrow]) | joints | pairs left out | worst error_i / bound_i "
             "by joint (- [error / round-off floor] where the bound is 0) | largest | found by"
             " | vertex search's largest | least lambda(D_s) found / proved lower bound | s |",
             "|---|---|---|---|---|---|---|---|---|"]
    for row in rows:
        pos = [j for j in range(row["n"]) if row["bound"][j] > 0]
        k = max(pos, key=lambda j: row["ratios"][j]) if pos else 0
        largest = f"{row['ratios'][k]:.6f} (joint {k + 1})" if pos else "-"
        vertex = f"{max(row['vertex'][j] for j in pos):.6f}" if pos else "-"
        lower = row["lower"]
        eig = (f"{row['lambda']:.4g} / {lower:.4g} = {row['lambda'] / lower:.3g}"
               if lower else f"{row['lambda']:.4g} / not proved")
        label = row["label"] + (" (refused by load_model)" if row["refused"] else "")
        lines.append(f"| {label} | {row['n']} | {row['dropped']} | "
                     f"{', '.join(_cell(row, j) for j in range(row['n']))} | {largest} | "
                     f"{row['how'][k] if pos else '-'} | {vertex} | {eig} | "
                     f"{row['seconds']:.0f} |")
    return "\n".join(lines)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--arms", default="puma560,stanford,panda,ur5,puma560-drives,"
                    "puma560@wall,stanford@wall,panda@wall,ur5@wall,ur5@payload,ur5@wrap,"
                    "puma560@odd")
    ap.add_argument("--fuzz", default="4:5,5:7,6:2,7:3,8:2,9:1")
    ap.add_argument("--eps", default="0.01,0.05")
    ap.add_argument("--narrow", default="puma560,ur5,6:2")
    ap.add_argument("--positions", type=int, default=4000)
    ap.add_argument("--starts", type=int, default=100)
    ap.add_argument("--iterations", type=int, default=60)
    ap.add_argument("--work", default=str(Path.home() / ".cache" / "gd-adversarial"))
    ap.add_argument("--seed", type=int, default=0)
    args = ap.parse_args(argv)
    work = Path(args.work)
    work.mkdir(parents=True, exist_ok=True)
    arms = [a for a in args.arms.split(",") + args.fuzz.split(",") if a]
    narrow = {a for a in args.narrow.split(",") if a}
    print(f"load averages before: {os.getloadavg()}", flush=True)
    rows = []
    for arm in arms:
        for eps in (float(e) for e in args.eps.split(",")):
            for nar in ([False, True] if arm in narrow else [False]):
                folder = build(arm, eps, nar, work)
                row = audit(folder, args, args.seed)
                rows.append(row)
                if row["refused"]:
                    print(f"{row['label']}: refused by load_model ({row['refused']}); "
                          "audited from the file all the same", flush=True)
                top = max([r for r, b in zip(row['ratios'], row['bound']) if b > 0],
                          default=0.0)
                print(f"{row['label']}: largest ratio {top:.12f}"
                      f", lambda {row['lambda']:.4g} (proved >= {row['lower']}), "
                      f"{row['seconds']:.0f} s", flush=True)
    print(f"load averages after: {os.getloadavg()}\n")
    print(table(rows))
    refused = [row for row in rows if row["refused"]]
    if refused:
        print("\nModel files the main job wrote and load_model refused (audited from the "
              "file all the same):")
        for row in refused:
            print(f"- {row['label']}: {row['refused']}")
    bad = [v for row in rows for v in row["violations"]]
    print()
    print("FAIL" if bad else "PASS: no state found above a proved bound or below the proved "
          "lambda_min(D_s)")
    for v in bad:
        print(v)
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
