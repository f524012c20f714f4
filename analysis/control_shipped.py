"""Closed-loop check of the simplified model on the shipped PUMA 560 trajectory.

    python analysis/control_shipped.py [--wn 20] [--zeta 1] [--offset 0] [--out DIR]

Builds the simplified model the main job produces
(``gd_analyze.jobs.analyze.analyze(load_robot("puma560"), read_trajectory(...)).model``), then
integrates the full-model arm along ``data/puma560_trajectory.csv`` under three controllers
(Fu, Gonzalez & Lee 1987, Ch. 5 computed torque with the full model and with the simplified
model of Sec. 3.4.1; PD + gravity compensation), starting on the trajectory unless an offset is
given. Prints one JSON line:

- ``tracking``: per controller, peak and RMS |q_d - q| per joint [rad], at the 31 set points
  and on the 2001-point fine grid;
- ``tau_difference``: peak and RMS per joint of tau(simplified controller) - tau(full
  controller) [N m], on the fine grid;
- ``cost``: multiplications and additions per set point (counted on the project's counting
  scalar) and batched microseconds per set point of the full model (``gd_terms`` + tau), of the
  full model in the fused evaluator, and of the simplified model in the fused evaluator.

With ``--out DIR`` it also writes DIR/simplified_model.json, DIR/control.h5 and the control
report (DIR/control_report.html, DIR/control_report.pdf).
"""

from __future__ import annotations

import argparse
import json
import tempfile
import time
from pathlib import Path

from gd_analyze import load_robot
from gd_analyze.files import file_sha256
from gd_analyze.jobs.analyze import analyze
from gd_analyze.jobs.control import CONTROL_FILE, DEFAULT_WN, DEFAULT_ZETA, run_control
from gd_analyze.store.control_dataset import write_control_dataset
from gd_analyze.store.model_file import save_model
from gd_analyze.trajectory.trajectory import read_trajectory

ROOT = Path(__file__).resolve().parents[1]
SHIPPED = ROOT / "data" / "puma560_trajectory.csv"


def _round(obj, digits=4):
    if isinstance(obj, float):
        return float(f"{obj:.{digits}g}")
    if isinstance(obj, dict):
        return {k: _round(v, digits) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_round(v, digits) for v in obj]
    return obj


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--wn", type=float, default=DEFAULT_WN, help="rad/s (default 20)")
    parser.add_argument("--zeta", type=float, default=DEFAULT_ZETA, help="(default 1)")
    parser.add_argument("--offset", type=float, default=0.0,
                        help="initial position error on every joint [rad] (default 0)")
    parser.add_argument("--out", type=Path, default=None,
                        help="also write the model, control.h5 and the control report here")
    args = parser.parse_args(argv)

    t0 = time.perf_counter()
    robot = load_robot("puma560")
    trajectory = read_trajectory(SHIPPED, n_joints=robot.n)
    model = analyze(robot, trajectory).model
    with tempfile.TemporaryDirectory() as tmp:
        outdir = args.out or Path(tmp)
        outdir.mkdir(parents=True, exist_ok=True)
        model_path = outdir / "simplified_model.json"
        save_model(model, model_path)
        result = run_control(model, trajectory, wn=args.wn, zeta=args.zeta,
                             q0_offset=args.offset, model_path=model_path,
                             model_sha256=file_sha256(model_path))
        if args.out:
            from gd_analyze.report.control import write_control_report

            write_control_dataset(result, outdir / CONTROL_FILE)
            write_control_report(outdir / CONTROL_FILE, outdir)
    s = result.summary()
    cost = s["cost"]
    out = {
        "robot": robot.name, "trajectory": SHIPPED.name, "setpoints": trajectory.n_setpoints,
        "wn_rad_s": args.wn, "zeta": args.zeta, "q0_offset_rad": args.offset,
        "solver": f"{result.provenance['method']} rtol={result.provenance['rtol']:g} "
                  f"atol={result.provenance['atol']:g}",
        "grid_samples": int(result.t.size),
        "tracking_rad": s["tracking"], "nfev": s["nfev"],
        "tau_difference_Nm": s["tau_difference"],
        "max_peak_error_rad": {c: max(f["peak_grid"]) for c, f in s["tracking"].items()},
        "cost": {
            "evaluators": cost["evaluators"],
            "multiplications": cost["multiplications"], "additions": cost["additions"],
            "dropped_parts": f"{cost['dropped']} of {cost['parts']}",
        },
        "kept": model.choices,
        "wall_s": time.perf_counter() - t0,
    }
    print(json.dumps(_round(out)))


if __name__ == "__main__":
    main()
