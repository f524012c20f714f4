"""The main job on the serial arms of example-robot-data: costs, errors against Pinocchio, time, memory.

For every serial arm shipped with the ``example-robot-data`` package (its URDF files, found
through the installed distribution's file list; an arm is a URDF with one chain the main job
accepts, or a NAME:TIP given with --arms, e.g. a quadruped's leg), the script

1. plans the default trajectory with ``gd-analyze plan URDF -o traj.csv`` (31 set points;
   ``--duration 2 --ignore-limits`` for an arm without velocity limits, as its error says);
2. runs the main job ``gd-analyze URDF traj.csv -o OUT --tolerance EPS`` as a child process
   (explicit-model cache disabled unless --cache), measuring its wall time and peak resident
   memory (``os.wait4``: the child's own maximum RSS, including the processes it waited for);
3. reads ``simplified_model.json``: the deployed ``form`` (recursive or explicit), its ``cost``
   (the EPS model), and from ``costs`` the exact recursive model and Newton-Euler as
   implemented; counts are multiplications + additions (sin and cos beside them);
4. evaluates the emitted ``simplified_model.py`` (numpy only) and ``simplified_model.c``
   (compiled with ``cc -O2 -shared -fPIC``, timed, called through ctypes one set point at a
   time) along the trajectory against Pinocchio's rnea on the URDF itself
   (``pinocchio.buildModelFromUrdf``, the chain's joints driven, every other joint at its
   neutral position and at rest): the worst per-joint peak |tau - tau_rnea| / peak |tau_rnea_i|,
   and against the bound the file states (``bound``, EPS x s_i [N m or N]): the worst
   peak |tau - tau_rnea|_i / bound_i, at most 1 (the acceptance criterion; s_i is the
   largest |tau_i| found over the region by default, so an error can exceed EPS x the
   trajectory's peak);
5. builds the exact model (EPS = 0) in-process, ``recursive_program(load_robot(URDF, base,
   tip))``, and compares it with rnea in the same way on 200 random states
   (``base_parameters.random_states``).

It prints the machine's load averages, a Markdown table, and one PASS/FAIL line per acceptance
criterion naming the arms that fail it.

Usage::

    python analysis/real_arms.py [--arms NAME[:TIP],...] [--timeout S] [--tolerance EPS]
                                 [--cache] [--no-report] [--list]
"""

from __future__ import annotations

import argparse
import ctypes
import json
import os
import platform
import re
import shutil
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
            # a stem two packages share (anymal_b's and anymal_c's anymal.urdf): the second is
            # named with its package folder, stem@package
            out[path.stem if path.stem not in out else f"{path.stem}@{path.parts[-3]}"] = path
    return dict(sorted(out.items()))


def load_chain(path, tip=None):
    """The chain the main job would use, or the one-line reason it refuses the URDF."""
    from gd_analyze.errors import InputError
    from gd_analyze.model.urdf import read_urdf_chain

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


#: States of the exact-model check (EPS = 0) and their seed.
EXACT_STATES, EXACT_SEED = 200, 0

#: The C compiler command of the deployed model (the machine's cc), flags of the issue.
CC = ["cc", "-O2", "-shared", "-fPIC"]


def relative_error(tau, ref):
    """Worst per-joint peak |tau - ref| / peak |ref_i|; inf for non-finite values or a zero joint."""
    scale = np.abs(ref).max(axis=0)
    if not (np.isfinite(tau).all() and np.isfinite(ref).all() and (scale > 0).all()):
        return float("inf")
    return float((np.abs(tau - ref).max(axis=0) / scale).max())


def bound_ratio(tau, ref, bound):
    """Worst per-joint peak |tau - ref| / (bound_i + 1e-9 peak |ref_i|): at most 1 where the
    model keeps the error bound its file states (bound [N m or N], 0 for an exact model, which
    is then held to round-off); inf for non-finite values or a missing bound."""
    bound = np.asarray(bound if bound is not None else [], float)
    if bound.shape != (ref.shape[1],) or not (np.isfinite(tau).all() and np.isfinite(bound).all()):
        return float("inf")
    allowed = bound + 1e-9 * np.maximum(np.abs(ref).max(axis=0), 1.0)
    return float((np.abs(tau - ref).max(axis=0) / allowed).max())


def python_model(outdir):
    """tau(q, qd, qdd) of the emitted simplified_model.py (our own output, numpy only)."""
    ns = {"__name__": "simplified_model"}
    exec((outdir / "simplified_model.py").read_text(encoding="utf-8"), ns)
    return ns["tau"]


def c_model(outdir, n, build):
    """Compile simplified_model.c with ``cc -O2 -shared -fPIC``: (tau function, compile time [s]).

    The function evaluates the set points one by one through ctypes; shape (N, n) -> (N, n).
    """
    lib = build / "simplified_model.so"
    t0 = time.perf_counter()
    done = subprocess.run(CC + ["-o", str(lib), str(outdir / "simplified_model.c"), "-lm"],
                          capture_output=True, text=True)
    seconds = time.perf_counter() - t0
    if done.returncode != 0:
        raise RuntimeError(f"cc failed: {done.stderr.strip().splitlines()[-1:]}")
    prefix = re.search(r"void (\w*)tau\(", (outdir / "simplified_model.h").read_text()).group(1)
    fn = getattr(ctypes.CDLL(str(lib)), prefix + "tau")
    ptr = ctypes.POINTER(ctypes.c_double)
    fn.argtypes, fn.restype = [ptr] * 4, None

    def tau(q, qd, qdd):
        q, qd, qdd = (np.ascontiguousarray(x, dtype=float) for x in (q, qd, qdd))
        out = np.empty_like(q)
        row = np.empty(n)
        for k in range(q.shape[0]):
            fn(q[k].ctypes.data_as(ptr), qd[k].ctypes.data_as(ptr), qdd[k].ctypes.data_as(ptr),
               row.ctypes.data_as(ptr))
            out[k] = row
        return out

    return tau, seconds


def exact_model_error(path, tip, chain):
    """The exact recursive model (EPS = 0) against rnea on random states: worst relative error."""
    from gd_analyze.dynamics.base_parameters import random_states
    from gd_analyze.model.robots import load_robot
    from gd_analyze.symbolic.emit import python_function
    from gd_analyze.symbolic.recursive import recursive_program

    robot = load_robot(str(path), None, tip)                    # as the CLI: robot, --base, --tip
    q, qd, qdd = random_states(robot, EXACT_STATES, EXACT_SEED)
    tau = np.asarray(python_function(recursive_program(robot))(q, qd, qdd), float)
    return relative_error(tau, rnea_torques(path, chain.joint_names, q, qd, qdd))


def model_errors(row, outdir, path, chain, csv, build, bound=None):
    """Errors of the emitted Python and C models along the trajectory (relative to the
    trajectory's peaks, and to the file's ``bound``), and the compile time."""
    from gd_analyze.trajectory.trajectory import read_trajectory

    traj = read_trajectory(csv, n_joints=len(chain.joint_names))
    ref = rnea_torques(path, chain.joint_names, traj.q, traj.qd, traj.qdd)
    py = np.asarray(python_model(outdir)(traj.q, traj.qd, traj.qdd), float)
    row["error_py"] = relative_error(py, ref)
    row["peak_tau"] = np.abs(ref).max(axis=0)
    row["joint_errors_py"] = np.abs(py - ref).max(axis=0) / row["peak_tau"]
    fn, row["compile_s"] = c_model(outdir, len(chain.joint_names), build)
    c = fn(traj.q, traj.qd, traj.qdd)
    row["error_c"] = relative_error(c, ref)
    row["over_bound"] = max(bound_ratio(py, ref, bound), bound_ratio(c, ref, bound))
    row["joint_errors_c"] = np.abs(c - ref).max(axis=0) / row["peak_tau"]
    row["c_vs_py"] = relative_error(c, py) if np.isfinite(py).all() else float("inf")


def run_arm(name, path, tip, chain, work, args, env):
    """One arm: plan, main job, figures. A dict of the table's cells."""
    cli = [sys.executable, "-P", "-m", "gd_analyze.cli"]
    chain_opt = ["--tip", tip] if tip else []
    csv = work / f"{name}.csv"
    row = {"arm": name + (f":{tip}" if tip else ""), "joints": len(chain.joint_names)}
    notes = []
    try:
        row["exact_error"] = exact_model_error(path, tip, chain)
    except Exception as exc:                                   # noqa: BLE001 - reported
        notes.append(f"exact model: {type(exc).__name__}: {exc}")
    code, _, _, err = run_child(cli + ["plan", str(path), "-o", str(csv), *chain_opt],
                                args.timeout, env)
    if code == 2 and "--ignore-limits" in err:         # no velocity limit: as the error says
        notes.append("planned with --duration 2 --ignore-limits (no velocity limits)")
        code, _, _, err = run_child(cli + ["plan", str(path), "-o", str(csv), *chain_opt,
                                           "--duration", "2", "--ignore-limits"],
                                    args.timeout, env)
    if code != 0:
        notes.append(f"plan failed: {err}" if code is not None else "plan timed out")
        return {**row, "note": "; ".join(notes)}
    out = work / name
    code, wall, rss, err = run_child(cli + [str(path), str(csv), "-o", str(out), "--tolerance",
                                            str(args.tolerance), *chain_opt,
                                            *(["--no-report"] if args.no_report else [])],
                                     args.timeout, env)
    row.update(time_s=wall, rss_mib=rss)
    if code is None:
        notes.append(f"main job timed out after {args.timeout:g} s")
        return {**row, "note": "; ".join(notes)}
    if code not in (0, 1):
        notes.append(f"main job exit {code}: {err}")
        return {**row, "note": "; ".join(notes)}
    if code == 1:
        notes.append("verification failed (exit 1)")
    spec = json.loads((out / "simplified_model.json").read_text(encoding="utf-8"))
    costs = spec.get("costs") or {}
    # an explicit model's file has no "form" key, only its "explicit_terms"
    form = spec.get("form") or ("explicit" if "explicit_terms" in spec else None)
    row.update(form=form, cost=spec.get("cost"),
               exact=costs.get("exact recursive"), ne=costs.get("newton-euler"))
    full = costs.get("explicit, full")
    if full and row["cost"] and mul_add(full) < mul_add(row["cost"]):
        notes.append(f"the full explicit model (EPS = 0) costs less: {_cost(full)}")
    build = work / f"{name}.build"
    build.mkdir()
    try:
        model_errors(row, out, path, chain, csv, build, spec.get("bound"))
    except Exception as exc:                                   # noqa: BLE001 - reported
        notes.append(f"model check: {type(exc).__name__}: {exc}")
    row["note"] = "; ".join(notes)
    return row


def mul_add(c):
    """Multiplications + additions of a cost dict, or None."""
    return int(c["multiplications"]) + int(c["additions"]) if c else None


def _cost(c):
    if not c:
        return "n/a"
    trig = [f"{c[k]} {k}" for k in ("sin", "cos") if k in c]
    return (f"{mul_add(c):,} ({c['multiplications']:,} mul + {c['additions']:,} add"
            + (f"; {', '.join(trig)}" if trig else "") + ")")


def _num(r, key, fmt):
    return format(r[key], fmt) if key in r else "n/a"


def table(rows, eps):
    head = ["arm", "joints", "form", "exact recursive cost", f"EPS={eps:g} model cost",
            "Newton-Euler cost", "error py vs rnea", "error C vs rnea", "error / bound",
            "exact (EPS=0) error vs rnea", "cc -O2 [s]", "main job [s]", "peak RSS [MiB]", "note"]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for r in rows:
        lines.append("| " + " | ".join([
            r["arm"], str(r["joints"]), r.get("form") or "n/a", _cost(r.get("exact")),
            _cost(r.get("cost")), _cost(r.get("ne")), _num(r, "error_py", ".2e"),
            _num(r, "error_c", ".2e"), _num(r, "over_bound", ".3f"),
            _num(r, "exact_error", ".1e"),
            _num(r, "compile_s", ".2f"), _num(r, "time_s", ".1f"), _num(r, "rss_mib", ".0f"),
            r.get("note", "")]) + " |")
    return "\n".join(lines)


def criteria(rows, eps):
    """(text, failing arms) per acceptance criterion; a missing figure fails."""
    def fails(test, subset=None):
        return [r["arm"] for r in rows if (subset is None or subset(r)) and not test(r)]

    def cheaper(r):
        m, e, ne = (mul_add(r.get(k)) for k in ("cost", "exact", "ne"))
        return None not in (m, e, ne) and m < ne and m <= e

    def below(key, limit):
        return lambda r: key in r and np.isfinite(r[key]) and r[key] <= limit

    seven = (lambda r: r["joints"] == 7)
    return [
        ("every arm's EPS model < Newton-Euler and <= exact recursive (mul + add)",
         fails(cheaper)),
        ("every error of the Python and C models vs rnea within the bound its file states "
         f"(EPS = {eps:g} times s_i, the region's or the trajectory's scale; the errors "
         "relative to the trajectory's own peaks are in the table)",
         fails(below("over_bound", 1.0))),
        ("every exact (EPS = 0) error vs rnea <= 1e-10", fails(below("exact_error", 1e-10))),
        ("every cc -O2 compile of simplified_model.c < 10 s",
         fails(lambda r: "compile_s" in r and r["compile_s"] < 10)),
        ("the 7-joint arms' main job <= 15 s and <= 1 GiB peak RSS",
         fails(lambda r: below("time_s", 15)(r) and below("rss_mib", 1024)(r), seven)),
    ]


def progress(r):
    """One line of figures per arm for stderr: C against Python, per-joint errors, peaks."""
    nan = float("nan")
    vec = (lambda key: " ".join(f"{v:.1e}" for v in r.get(key, [])))
    return (f"{r.get('time_s', nan):.1f} s; error py {r.get('error_py', nan):.2e}, "
            f"C {r.get('error_c', nan):.2e}, C vs py {r.get('c_vs_py', nan):.1e}, "
            f"exact {r.get('exact_error', nan):.1e}; per joint (py) [{vec('joint_errors_py')}]; "
            f"peak |tau| [N m] [{vec('peak_tau')}] {r.get('note', '')}")


def header(eps, cache):
    """Lines about the machine and the run: load averages (times are noisy on a shared host)."""
    cc = subprocess.run(["cc", "--version"], capture_output=True, text=True).stdout
    up = subprocess.run(["uptime"], capture_output=True, text=True).stdout.strip()
    return [f"# gd-analyze on the serial arms of example-robot-data (EPS = {eps:g})", "",
            f"- {time.strftime('%Y-%m-%d %H:%M:%S UTC', time.gmtime())}; {platform.node()}, "
            f"{os.cpu_count()} CPUs; Python {platform.python_version()}; "
            f"cc: {(cc.splitlines() or ['?'])[0]}",
            f"- uptime at start: {up}",
            f"- explicit-model cache: {'used' if cache else 'disabled (cold)'}; trajectory: "
            f"`gd-analyze plan` (31 set points); exact check: {EXACT_STATES} random states, "
            f"seed {EXACT_SEED}", ""]


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
    if shutil.which("cc") is None:
        sys.exit("no C compiler 'cc' on PATH")
    print("\n".join(header(args.tolerance, args.cache)), flush=True)
    rows = []
    with tempfile.TemporaryDirectory(prefix="real_arms_") as tmp:
        for name, path, tip, chain in arms:
            print(f"{name}: {len(chain.joint_names)} joints ...", file=sys.stderr, flush=True)
            rows.append(run_arm(name, path, tip, chain, Path(tmp), args, env))
            print("  " + progress(rows[-1]), file=sys.stderr, flush=True)
    print(table(rows, args.tolerance))
    print(f"\nuptime at end: {subprocess.run(['uptime'], capture_output=True, text=True).stdout.strip()}\n")
    for text, failing in criteria(rows, args.tolerance):
        print(f"- {'PASS' if not failing else 'FAIL'}: {text}"
              + (f" -- failing: {', '.join(failing)}" if failing else ""))
    if skipped and not args.arms:
        print("\nNot serial arms the main job accepts: "
              + "; ".join(f"{n} ({why})" for n, why in skipped))
    return 0


if __name__ == "__main__":
    sys.exit(main())
