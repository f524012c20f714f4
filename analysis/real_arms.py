"""The main job on the serial arms of example-robot-data: costs, error against Pinocchio, time, memory.

For every serial arm shipped with the ``example-robot-data`` package (its URDF files, found
through the installed distribution's file list; an arm is a URDF with one chain the main job
accepts, or a NAME:TIP given with --arms, e.g. a quadruped's leg), the script

1. plans the default trajectory with ``gd-analyze plan URDF -o traj.csv`` (31 set points);
2. runs the main job ``gd-analyze URDF traj.csv -o OUT --tolerance EPS`` as a child process
   (explicit-model cache disabled unless --cache), measuring its wall time and peak resident
   memory (``os.wait4``: the child's own maximum RSS, including the processes it waited for);
3. reads ``simplified_model.json``: ``exact_recursive_cost`` if the model has one, else n/a;
   ``cost`` (the simplified model at EPS: multiplications + additions + sin + cos, and the
   split); and the Newton-Euler count as implemented from the cost table in ``results.h5``;
4. evaluates the emitted ``simplified_model.py`` (numpy only) along the trajectory against
   Pinocchio's rnea on the URDF itself (``pinocchio.buildModelFromUrdf``, the chain's joints
   driven by the trajectory, every other joint at its neutral position): the worst per-joint
   peak |tau_py - tau_rnea| / peak |tau_rnea_i|.

It prints a Markdown table. Arms with 7 joints take minutes each (their explicit expansion).

Usage::

    python analysis/real_arms.py [--arms NAME[:TIP],...] [--timeout S] [--tolerance EPS]
                                 [--cache] [--list]
"""

from __future__ import annotations

import argparse
import json
import os
import signal
import subprocess
import sys
import tempfile
import time
from importlib import metadata
from pathlib import Path

import numpy as np


#: Arms of example-robot-data whose URDF has several chains: the tip of the arm by default.
KNOWN_TIPS = {"panda": "panda_hand"}


def erd_urdfs():
    """name -> URDF path of every URDF file of the installed example-robot-data."""
    try:
        dist = metadata.distribution("example-robot-data")
    except metadata.PackageNotFoundError:
        sys.exit("example-robot-data is not installed (pip install example-robot-data)")
    out = {}
    for f in dist.files or []:
        if str(f).endswith(".urdf") and "/robots/" in str(f):
            path = Path(dist.locate_file(f))
            out.setdefault(path.stem, path)
    return dict(sorted(out.items()))


def load_chain(path, tip=None):
    """The chain the main job would use, or the one-line reason it refuses the URDF."""
    from gd_analyze.errors import InputError
    from gd_analyze.io.urdf import read_urdf_chain

    try:
        chain = read_urdf_chain(path, tip=tip)
    except InputError as exc:
        return None, str(exc).split(": ", 1)[-1]
    if len(chain.joint_names) < 1:
        return None, "no moving joint"
    return chain, ""


def discover(names=None):
    """(name, path, tip, chain) of the arms to run, and (name, reason) of the URDFs left out."""
    urdfs = erd_urdfs()
    chosen, skipped = [], []
    wanted = [tuple((a.split(":", 1) + [None])[:2]) for a in names] if names else \
        [(k, KNOWN_TIPS.get(k)) for k in urdfs]
    for name, tip in wanted:
        if name not in urdfs:
            skipped.append((name, "not a URDF of example-robot-data"))
            continue
        chain, why = load_chain(urdfs[name], tip)
        if chain is None:
            skipped.append((name, why))
        else:
            chosen.append((name, urdfs[name], tip, chain))
    return chosen, skipped


def run_child(cmd, timeout, env):
    """Run a command; (exit code or None on timeout, wall time [s], peak RSS [MiB], stderr)."""
    with tempfile.TemporaryFile() as err:
        t0 = time.perf_counter()
        proc = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=err, env=env,
                                start_new_session=True, cwd=tempfile.gettempdir())
        while True:
            pid, status, usage = os.wait4(proc.pid, os.WNOHANG)
            if pid:
                break
            if time.perf_counter() - t0 > timeout:
                os.killpg(proc.pid, signal.SIGKILL)          # the job and its workers only
                pid, status, usage = os.wait4(proc.pid, 0)
                proc.returncode = -9
                err.seek(0)
                return None, time.perf_counter() - t0, usage.ru_maxrss / 1024, ""
            time.sleep(0.05)
        wall = time.perf_counter() - t0
        proc.returncode = os.waitstatus_to_exitcode(status)
        err.seek(0)
        text = err.read().decode(errors="replace").strip().splitlines()
    return proc.returncode, wall, usage.ru_maxrss / 1024, text[-1] if text else ""


def rnea_torques(path, joint_names, q, qd, qdd):
    """Pinocchio rnea on the URDF itself, shape (N, n) [N m]: the chain's joints at (q, qd, qdd),
    the others at their neutral position and at rest."""
    import pinocchio as pin

    model = pin.buildModelFromUrdf(str(path))
    data = model.createData()
    ids = [model.getJointId(name) for name in joint_names]
    iv = [model.idx_vs[j] for j in ids]
    out = np.empty_like(q)
    for k in range(q.shape[0]):
        qf = pin.neutral(model)
        for j, value in zip(ids, q[k]):
            a = model.idx_qs[j]
            if model.nqs[j] == 2:                      # continuous joint: (cos, sin)
                qf[a:a + 2] = np.cos(value), np.sin(value)
            else:
                qf[a] = value
        vf, af = np.zeros(model.nv), np.zeros(model.nv)
        vf[iv], af[iv] = qd[k], qdd[k]
        out[k] = pin.rnea(model, data, qf, vf, af)[iv]
    return out


def python_model_error(outdir, path, chain, csv):
    """Worst per-joint peak |tau_py - tau_rnea| / peak |tau_rnea_i| along the trajectory."""
    from gd_analyze.io.trajectory import read_trajectory

    traj = read_trajectory(csv, n_joints=len(chain.joint_names))
    ns = {"__name__": "simplified_model"}
    exec((outdir / "simplified_model.py").read_text(encoding="utf-8"), ns)   # our own output
    tau = np.asarray(ns["tau"](traj.q, traj.qd, traj.qdd), float)
    ref = rnea_torques(path, chain.joint_names, traj.q, traj.qd, traj.qdd)
    scale = np.abs(ref).max(axis=0)
    if not (np.isfinite(tau).all() and (scale > 0).all()):
        return float("inf")
    return float((np.abs(tau - ref).max(axis=0) / scale).max())


def newton_euler_cost(results):
    """Multiplications + additions of N-E as implemented, from the cost table of results.h5."""
    import xarray as xr

    with xr.open_dataset(results, engine="h5netcdf") as ds:
        if "cost_model" not in ds.coords:
            return None
        labels = [str(v) for v in ds["cost_model"].values]
        key = "project N-E as implemented"
        if key not in labels:
            return None
        k = labels.index(key)
        return int(ds["cost_multiplications"].values[k]), int(ds["cost_additions"].values[k])


def run_arm(name, path, tip, chain, work, args, env):
    """One arm: plan, main job, figures. A dict of the table's cells."""
    cli = [sys.executable, "-P", "-m", "gd_analyze.cli"]
    chain_opt = ["--tip", tip] if tip else []
    csv = work / f"{name}.csv"
    row = {"arm": name + (f":{tip}" if tip else ""), "joints": len(chain.joint_names)}
    code, _, _, err = run_child(cli + ["plan", str(path), "-o", str(csv), *chain_opt],
                                args.timeout, env)
    if code != 0:
        return {**row, "note": f"plan failed: {err}" if code is not None else "plan timed out"}
    out = work / name
    code, wall, rss, err = run_child(cli + [str(path), str(csv), "-o", str(out), "--tolerance",
                                            str(args.tolerance), *chain_opt,
                                            *(["--no-report"] if args.no_report else [])],
                                     args.timeout, env)
    row.update(time_s=wall, rss_mib=rss)
    if code is None:
        return {**row, "note": f"main job timed out after {args.timeout:g} s"}
    if code not in (0, 1):
        return {**row, "note": f"main job exit {code}: {err}"}
    spec = json.loads((out / "simplified_model.json").read_text(encoding="utf-8"))
    row["exact"] = spec.get("exact_recursive_cost")
    row["cost"] = spec.get("cost")
    row["ne"] = newton_euler_cost(out / "results.h5")
    row["error"] = python_model_error(out, path, chain, csv)
    row["note"] = "verification failed (exit 1)" if code == 1 else ""
    return row


def _cost(c):
    if not c:
        return "n/a"
    if isinstance(c, (int, float)):
        return f"{int(c):,}"
    total = sum(int(c.get(k, 0)) for k in ("multiplications", "additions", "sin", "cos"))
    return (f"{total:,} ({c.get('multiplications', 0):,} mul + {c.get('additions', 0):,} add "
            f"+ {c.get('sin', 0)} sin + {c.get('cos', 0)} cos)")


def table(rows, eps):
    head = ["arm", "joints", "exact recursive cost", f"EPS={eps:g} model cost",
            "Newton-Euler cost", "worst error vs rnea", "main job [s]", "peak RSS [MiB]", "note"]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for r in rows:
        ne = r.get("ne")
        lines.append("| " + " | ".join([
            r["arm"], str(r["joints"]), _cost(r.get("exact")), _cost(r.get("cost")),
            f"{sum(ne):,} ({ne[0]:,} mul + {ne[1]:,} add)" if ne else "n/a",
            f"{r['error']:.2e}" if "error" in r else "n/a",
            f"{r['time_s']:.1f}" if "time_s" in r else "n/a",
            f"{r['rss_mib']:.0f}" if "rss_mib" in r else "n/a",
            r.get("note", "")]) + " |")
    return "\n".join(lines)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--arms", help="comma-separated NAME or NAME:TIP (URDF file stems of "
                                       "example-robot-data; default: every serial arm)")
    parser.add_argument("--timeout", type=float, default=600.0,
                        help="seconds per arm and step (default 600)")
    parser.add_argument("--tolerance", type=float, default=0.01, help="EPS (default 0.01)")
    parser.add_argument("--cache", action="store_true",
                        help="let the main job use the explicit-model cache (default: cold)")
    parser.add_argument("--no-report", action="store_true", help="main job without its report")
    parser.add_argument("--list", action="store_true", help="list the arms found and stop")
    args = parser.parse_args(argv)
    arms, skipped = discover(args.arms.split(",") if args.arms else None)
    if args.list or not arms:
        for name, path, tip, chain in arms:
            print(f"{name}{':' + tip if tip else ''}: {len(chain.joint_names)} joints ({path})")
        for name, why in skipped:
            print(f"skipped {name}: {why}")
        return 0 if arms else 2
    env = dict(os.environ)
    if not args.cache:
        env["GD_ANALYZE_NO_CACHE"] = "1"
    rows = []
    with tempfile.TemporaryDirectory(prefix="real_arms_") as tmp:
        for name, path, tip, chain in arms:
            print(f"{name}: {len(chain.joint_names)} joints ...", file=sys.stderr, flush=True)
            rows.append(run_arm(name, path, tip, chain, Path(tmp), args, env))
    print(table(rows, args.tolerance))
    if skipped and not args.arms:
        print(f"\nNot serial arms the main job accepts: "
              + "; ".join(f"{n} ({why})" for n, why in skipped))
    return 0


if __name__ == "__main__":
    sys.exit(main())
