"""The cold main job of real 7-joint arms: this checkout against another, alternated.

A user's first main job on a new arm finds the derivation cache empty: the region is
certified and the region searches (the model's EPS and the tolerance ladder's other rungs)
run in full. For each arm of example-robot-data given (NAME or NAME:TIP, as
``analysis/real_arms.py`` takes them) the script plans the default trajectory once
(``gd-analyze plan``), then runs the main job ``gd-analyze URDF traj.csv -o OUT -q`` as a child
process, with ``GD_ANALYZE_CACHE_DIR`` a new empty folder each run, alternately with this
checkout's ``src`` and the ``--baseline`` one first on ``PYTHONPATH`` (round by round, the
order of the two swapped every round). Per run: wall time, CPU time (user + system of the child
and what it waited for, ``os.wait4``) and peak resident memory. Per arm: median [min, max] of
each and the ratio of the medians (this / baseline), and whether the two checkouts' outputs
agree: ``simplified_model.json`` without its provenance, and every emitted source file, byte
for byte. Prints the load averages before and after.

Usage::

    python analysis/cold_main_job.py --baseline /work/main/src [--arms talos_left_arm,xarm7,
        panda:panda_hand] [--rounds 3] [--no-report]
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import statistics
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

HERE = Path(__file__).resolve().parents[1] / "src"


def _env(src, cache):
    env = dict(os.environ, PYTHONPATH=str(src), GD_ANALYZE_CACHE_DIR=str(cache))
    env.pop("GD_ANALYZE_NO_EXPLICIT_CACHE", None)
    return env


def _outputs(outdir):
    """The model without its provenance, and the emitted sources, for comparison."""
    model = json.loads((outdir / "simplified_model.json").read_text())
    model.pop("provenance", None)
    sources = {p.name: p.read_bytes() for p in sorted(outdir.glob("simplified_model.*"))
               if p.suffix != ".json"}
    return json.dumps(model, sort_keys=True), sources


def _stats(values):
    return statistics.median(values), min(values), max(values)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--baseline", required=True, help="the other checkout's src folder")
    ap.add_argument("--arms", default="talos_left_arm,xarm7,panda:panda_hand")
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--timeout", type=float, default=600.0)
    ap.add_argument("--no-report", action="store_true")
    args = ap.parse_args()
    import real_arms

    chosen, skipped = real_arms.discover(args.arms.split(","))
    for name, why in skipped:
        print(f"{name}: left out ({why})")
    print("load averages:", " ".join(f"{v:.2f}" for v in os.getloadavg()))
    sides = {"this": HERE, "baseline": Path(args.baseline).resolve()}
    work = Path(tempfile.mkdtemp(prefix="cold_main_job-"))
    rows = []
    try:
        for name, path, tip, _ in chosen:
            traj = work / f"{name}.csv"
            tip_opt = ["--tip", tip] if tip else []
            cmd = [sys.executable, "-m", "gd_analyze.cli"]
            code, *_ = real_arms.run_child(cmd + ["plan", str(path), *tip_opt, "-o", str(traj)],
                                           args.timeout, _env(HERE, work / "plan-cache"))
            if code != 0:
                print(f"{name}: plan failed ({code})")
                continue
            runs = {side: [] for side in sides}
            outputs = {}
            for r in range(args.rounds):
                order = list(sides) if r % 2 == 0 else list(sides)[::-1]
                for side in order:
                    cache, out = work / f"cache-{side}-{r}", work / f"out-{side}-{r}"
                    cache.mkdir()
                    job = cmd + [str(path), str(traj), *tip_opt, "-o", str(out), "-q"]
                    if args.no_report:
                        job.append("--no-report")
                    before = os.times()
                    code, wall, peak, last = real_arms.run_child(job, args.timeout,
                                                                 _env(sides[side], cache))
                    after = os.times()
                    cpu = (after.children_user - before.children_user
                           + after.children_system - before.children_system)
                    if code != 0:
                        print(f"{name} {side}: exit {code}: {last}")
                        continue
                    runs[side].append((wall, cpu, peak))
                    outputs.setdefault(side, _outputs(out))
                    print(f"  {name} round {r + 1} {side}: wall {wall:.1f} s, CPU {cpu:.1f} s, "
                          f"peak {peak:.0f} MiB", flush=True)
                    shutil.rmtree(cache)
                    shutil.rmtree(out)
            same = len(outputs) == 2 and outputs["this"] == outputs["baseline"]
            rows.append((name, runs, same))
    finally:
        shutil.rmtree(work, ignore_errors=True)
    print("load averages:", " ".join(f"{v:.2f}" for v in os.getloadavg()))
    print("\n| arm | code | wall [s] | CPU [s] | peak [MiB] | outputs equal |")
    print("|---|---|---|---|---|---|")
    for name, runs, same in rows:
        for side in sides:
            if not runs[side]:
                continue
            cells = [_stats([x[k] for x in runs[side]]) for k in range(3)]
            print(f"| {name} | {side} | " + " | ".join(
                f"{m:.1f} [{lo:.1f}, {hi:.1f}]" if k < 2 else f"{m:,.0f} [{lo:,.0f}, {hi:,.0f}]"
                for k, (m, lo, hi) in enumerate(cells)) + f" | {'yes' if same else 'NO'} |")
        if runs["this"] and runs["baseline"]:
            ratio = [statistics.median(x[k] for x in runs["this"])
                     / statistics.median(x[k] for x in runs["baseline"]) for k in range(2)]
            print(f"| {name} | this / baseline | {ratio[0]:.2f} | {ratio[1]:.2f} | | |")


if __name__ == "__main__":
    main()
