"""The dominance ranking of Sec. 3.4.1 over 1,000 random PUMA 560 trajectories, on dask.

    python analysis/sweep_1000.py [-o OUTDIR] [-k 1000] [--seed 0] [--workers N] [--batch B]
                                  [--payload-sweep 0:2.5:0.5]

Plans K random rest-to-rest quintic PUMA 560 trajectories (start and goal uniform inside the
joint limits, shortest duration within the velocity and acceleration limits, 31 set points as in
Sec. 3.4.1), ranks each on a dask LocalCluster (one process and one thread per worker, default
one worker per core), merges the simplified models conservatively, and writes ``sweep.h5`` and
``sweep_report.html``/``.pdf`` to OUTDIR (default: a new temporary folder). With
``--payload-sweep`` it also ranks the shipped trajectory for a range of payloads and adds that to
the report.

Prints one JSON line: wall times (total, cluster + computation, writing, report), the cluster
(workers, batch size, tasks), per element the fraction of trajectories in each class and the
min/median/max share_tran, the fraction that agrees with the class the chapter reports for its
PUMA 560 trajectory, the merged model's choices and its torque error over all trajectories.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from gd_analyze.store.model_file import save_model

ROOT = Path(__file__).resolve().parents[1]


def _r(x, digits=4):
    x = float(x)
    return None if not np.isfinite(x) else float(f"{x:.{digits}g}")


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("-o", "--outdir", default=None, help="output folder (default: temp)")
    parser.add_argument("-k", type=int, default=1000, help="number of trajectories")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--workers", type=int, default=None,
                        help="local workers (default: os.cpu_count())")
    parser.add_argument("--batch", type=int, default=None, help="trajectories per task")
    parser.add_argument("--payload-sweep", default=None, metavar="START:STOP:STEP",
                        help="also rank the shipped trajectory for these payloads [kg]")
    args = parser.parse_args(argv)

    from gd_analyze import load_robot
    from gd_analyze.cli import parse_range
    from gd_analyze.jobs.payload import payload_sweep
    from gd_analyze.jobs.sweep import run_sweep
    from gd_analyze.jobs.sweep_merged import merged_model
    from gd_analyze.ranking.ranking import CHAPTER_DOMINANCE, CLASSES
    from gd_analyze.report.sweep import write_sweep_report
    from gd_analyze.store.schema import write_dataset
    from gd_analyze.trajectory.planning import random_trajectories

    t_start = time.perf_counter()
    outdir = Path(args.outdir) if args.outdir else Path(tempfile.mkdtemp(prefix="gd-sweep-"))
    outdir.mkdir(parents=True, exist_ok=True)
    robot = load_robot("puma560")

    t0 = time.perf_counter()
    trajectories = random_trajectories(robot, args.k, seed=args.seed)
    t_generate = time.perf_counter() - t0

    t0 = time.perf_counter()
    ds = run_sweep(robot, trajectories, n_workers=args.workers, batch=args.batch,
                   settings={"command": " ".join(["analysis/sweep_1000.py", *sys.argv[1:]])})
    t_sweep = time.perf_counter() - t0

    t0 = time.perf_counter()
    sweep_path = outdir / "sweep.h5"
    write_dataset(ds, sweep_path)
    model = merged_model(robot, ds)
    save_model(model, outdir / "merged_model.json")
    payload_path = None
    if args.payload_sweep:
        from gd_analyze.trajectory.trajectory import read_trajectory

        shipped = read_trajectory(ROOT / "data" / "puma560_trajectory.csv", robot.n)
        payload_path = outdir / "payload_sweep.h5"
        write_dataset(payload_sweep(robot, shipped, parse_range(args.payload_sweep)),
                    payload_path)
    t_write = time.perf_counter() - t0

    t0 = time.perf_counter()
    reports = write_sweep_report(sweep_path, outdir, payload=payload_path)
    t_report = time.perf_counter() - t0

    labels = [str(v) for v in ds["element"].values]
    frac = ds["class_fraction"].values
    dom = ds["dominance"].values
    envelope = {}
    for m, label in enumerate(labels):
        entry = {cls: _r(frac[m, c]) for c, cls in enumerate(CLASSES)}
        entry.update(share_min=_r(ds["share_tran_min"].values[m]),
                     share_median=_r(ds["share_tran_median"].values[m]),
                     share_max=_r(ds["share_tran_max"].values[m]),
                     chapter=CHAPTER_DOMINANCE.get(label),
                     chapter_agreement=_r(np.mean(dom[:, m] == CHAPTER_DOMINANCE.get(label))))
        envelope[label] = entry
    v = model.validation
    line = {
        "robot": robot.name, "trajectories": int(ds.sizes["trajectory"]), "seed": args.seed,
        "setpoints_total": int(ds.attrs["setpoints_total"]),
        "cpu_count": os.cpu_count(), "n_workers": int(ds.attrs["n_workers"]),
        "batch_size": int(ds.attrs["batch_size"]), "n_tasks": int(ds.attrs["n_tasks"]),
        "elapsed_s": round(time.perf_counter() - t_start, 3),
        "generate_s": round(t_generate, 3),
        "sweep_s": round(t_sweep, 3),
        "sweep_compute_s": float(ds.attrs["compute_s"]),
        "write_s": round(t_write, 3), "report_s": round(t_report, 3),
        "merged_choices": dict(model.choices),
        "merged_counts": {c: sum(ch == c for ch in model.choices.values())
                          for c in ("tran", "rot", "both", "none")},
        "merged_error_peak_Nm": [_r(x) for x in v["peak_abs_error"]],
        "merged_error_relative_peak": [_r(x) for x in v["relative_peak_error"]],
        "merged_error_relative_rms": [_r(x) for x in v["relative_rms_error"]],
        "peak_tau_Nm": [_r(x) for x in v["peak_tau"]],
        "own_error_relative_peak_max": [
            _r(np.nanmax(ds["tau_error_relative_peak"].values[:, j]))
            for j in range(robot.n)],
        "envelope": envelope,
        "files": [str(sweep_path), str(outdir / "merged_model.json"),
                  *(str(p) for p in reports)]
        + ([str(payload_path)] if payload_path else []),
    }
    print(json.dumps(line))
    return 0


if __name__ == "__main__":
    sys.exit(main())
