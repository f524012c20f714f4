"""Reading a region model back: CPU time of ``load_model`` with and without its stored trees.

A region model's bound is checked again whenever its file is read
(``store/model_trust.py``): on the trees of boxes stored with it (``guarantee.tilings``, and
the decomposition's pairs ``guarantee.decomposed_tilings``, each checked to tile the region
and evaluated afresh), else by the quick branch and bound on the dropped pairs and, where
that does not reach the stored bound, the full re-derivation (the region's certification
read back from the derivation cache, the joint sums and their branch and bound). For each
arm this script runs the main job once (``--no-report``, into a temporary folder, the
derivation cache as configured), writes the same model without its ``tilings`` and
``decomposed_tilings`` keys (a file written before them), and times in rounds, each load in
a fresh process after one untimed warm-up load of each file (so the derivation cache holds
what the re-derivation reads):

- ``trees``: the model as written;
- ``no trees``: the model without its trees (the quick proof, then the re-derivation);
- ``baseline``: with ``--baseline SRC``, another checkout (its ``src`` first on
  ``PYTHONPATH``) loading the model without trees.

Each child prints its CPU time (``time.process_time``) of ``gd_analyze.load_model`` alone
(imports excluded) and which proofs ran (counted by wrapping ``model_trust.prove_dropped``
and ``model_trust.reproved_bound``). Prints the load averages and a Markdown table of the
median [min, max] over the rounds.

Usage::

    python analysis/model_readback.py [--arms puma560,panda,ur5] [--rounds 3]
        [--baseline /path/to/other/checkout/src]
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

ROOT = Path(__file__).resolve().parents[1]


def child(path):
    """Load one model file in this process; print one JSON line."""
    from gd_analyze import load_model
    from gd_analyze.store import model_trust

    ran = {"quick": 0, "full": 0}

    def counted(name, key):
        real = getattr(model_trust, name)

        def wrapper(*args, **kwargs):
            ran[key] += 1
            return real(*args, **kwargs)
        setattr(model_trust, name, wrapper)
    counted("prove_dropped", "quick")
    counted("reproved_bound", "full")
    t0 = time.process_time()
    load_model(path)
    print(json.dumps({"cpu": time.process_time() - t0, **ran}))


def _load(path, src=None):
    env = dict(os.environ)
    env.pop("PYTHONDONTWRITEBYTECODE", None)
    if src is not None:
        env["PYTHONPATH"] = str(src) + os.pathsep + env.get("PYTHONPATH", "")
    out = subprocess.run([sys.executable, __file__, "--child", str(path)], env=env,
                         check=True, capture_output=True, text=True, cwd=ROOT).stdout
    return json.loads(out.strip().splitlines()[-1])


def _cell(values):
    return f"{np.median(values):.2f} [{min(values):.2f}, {max(values):.2f}]"


def _path(result):
    return "re-derived" if result["full"] else ("quick proof" if result["quick"] else "trees")


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--arms", default="puma560,panda,ur5")
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--baseline", help="another checkout's src folder")
    parser.add_argument("--child", help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    if args.child:
        child(args.child)
        return 0
    from gd_analyze.cli import main as cli

    load = [os.getloadavg()]
    print("load averages at the start:", " ".join(f"{v:.2f}" for v in load[0]), flush=True)
    arms = [a for a in args.arms.split(",") if a]
    variants = ["trees", "no trees"] + (["baseline"] if args.baseline else [])
    times = {(a, v): [] for a in arms for v in variants}
    paths = {}
    with tempfile.TemporaryDirectory() as folder:
        files = {}
        for arm in arms:
            out = Path(folder) / arm
            traj = ROOT / "data" / f"{arm}_trajectory.csv"
            assert cli([arm, str(traj), "-o", str(out), "--no-report", "-q"]) == 0
            doc = json.loads((out / "simplified_model.json").read_text())
            trees = len(doc["guarantee"].get("tilings", []))
            pairs = len(doc["guarantee"].get("decomposed_tilings", []))
            doc["guarantee"].pop("tilings", None)
            doc["guarantee"].pop("decomposed_tilings", None)
            bare = out / "without_trees.json"
            bare.write_text(json.dumps(doc))
            files[arm] = {"trees": out / "simplified_model.json", "no trees": bare,
                          "baseline": bare}
            print(f"{arm}: {trees} trees and {pairs} pairs of trees stored, "
                  f"{len(doc['guarantee'].get('bound', []))} joints", flush=True)
            for v in variants:          # warm-up: the derivation cache of each code
                _load(files[arm][v], args.baseline if v == "baseline" else None)
        for r in range(args.rounds):
            for arm in arms:
                for v in variants:
                    res = _load(files[arm][v], args.baseline if v == "baseline" else None)
                    times[(arm, v)].append(res["cpu"])
                    paths[(arm, v)] = _path(res)
                load.append(os.getloadavg())
                print(f"  round {r + 1} {arm}: " + ", ".join(
                    f"{v} {times[(arm, v)][-1]:.2f} s ({paths[(arm, v)]})" for v in variants)
                    + f", load {load[-1][0]:.2f}", flush=True)
    print("| arm | " + " | ".join(f"{v}: load_model CPU [s] (proof)" for v in variants)
          + f" |  ({args.rounds} rounds: median [min, max])")
    print("|---|" + "---|" * len(variants))
    for arm in arms:
        print(f"| {arm} | " + " | ".join(f"{_cell(times[(arm, v)])} ({paths[(arm, v)]})"
                                         for v in variants) + " |")
    loads = np.array([x[0] for x in load])
    print(f"load (1-minute) during the run: {loads.min():.2f} to {loads.max():.2f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
