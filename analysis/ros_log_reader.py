"""Reading a ``rostopic echo -p /joint_states`` log against reading the same recording numbered.

    python analysis/ros_log_reader.py [--rows N] [--joints n] [--rounds R]

Writes one recording of N rows and n joints (random values, a 1 kHz clock, another
publisher's row every 1,000 rows) twice: as ROS 1's ``rostopic echo -p`` writes a JointState
topic (``tests/identify_recordings.write_echo_log``: ns stamps, the joints named in each row in
another order, a gripper joint beside them) and as ``t,q1..,tau1..,qd1..``. Each round reads,
in a fresh interpreter each and in rotated order, the numbered file (the reference), the log
by the pandas path, and the log cell by cell (``_echoed_frame`` switched off: the reader
before the pandas path); each run's wall time of ``read_recording`` and the process's peak
RSS. Prints one JSON line: per side the median [min, max] time [s] and peak [MiB], and the
ratio of each log reader's median time to the numbered file's; the runs check that the three
give the same arrays (a fingerprint of q, qd and tau).
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests"))

CHILD = r"""
import hashlib, json, resource, sys, time, warnings
import numpy as np
from gd_analyze.trajectory import trajectory as tr
if sys.argv[2] == "cells":
    tr._echoed_frame = lambda *a, **k: None
warnings.simplefilter("ignore")
n = int(sys.argv[3])
t0 = time.perf_counter()
rec = tr.read_recording(sys.argv[1], n, joint_names=[f"j{k}" for k in range(n)])
wall = time.perf_counter() - t0
print(json.dumps({"s": wall, "mib": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024,
                  "sha": hashlib.sha256(np.hstack([rec.q, rec.qd, rec.tau]).tobytes()).hexdigest()}))
"""


def main() -> None:
    from identify_recordings import write_echo_log, write_recording

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rows", type=int, default=200_000)
    ap.add_argument("--joints", type=int, default=7)
    ap.add_argument("--rounds", type=int, default=3)
    args = ap.parse_args()
    rng = np.random.default_rng(0)
    n, rows = args.joints, args.rows
    fields = {k: rng.normal(size=(rows, n)) for k in ("position", "velocity", "effort")}
    env = {**os.environ, "PYTHONPATH": str(ROOT / "src")}
    with tempfile.TemporaryDirectory() as tmp:
        log, numbered = Path(tmp) / "log.csv", Path(tmp) / "numbered.csv"
        t = write_echo_log(log, 0.001 * np.arange(rows), fields, [f"j{k}" for k in range(n)],
                           other_rows=range(500, rows, 1000))
        write_recording(numbered, t, fields["position"], fields["effort"], fields["velocity"])
        sides = {"numbered": (numbered, "pandas"), "log_pandas": (log, "pandas"),
                 "log_cells": (log, "cells")}
        runs: dict[str, list] = {k: [] for k in sides}
        for r in range(args.rounds):
            order = list(sides)[r % 3:] + list(sides)[:r % 3]
            for name in order:
                path, how = sides[name]
                done = subprocess.run([sys.executable, "-c", CHILD, str(path), how, str(n)],
                                      capture_output=True, text=True, env=env, check=True)
                runs[name].append(json.loads(done.stdout.strip().splitlines()[-1]))
        shas = {run["sha"] for side in runs.values() for run in side}
        out: dict = {"rows": rows, "joints": n, "rounds": args.rounds,
                     "same_arrays": len(shas) == 1, "load_average": os.getloadavg()[:2],
                     "file_mb": {k: round(p.stat().st_size / 1e6, 1)
                                 for k, p in (("log", log), ("numbered", numbered))}}
        base = statistics.median(run["s"] for run in runs["numbered"])
        for name, side in runs.items():
            s, mib = [run["s"] for run in side], [run["mib"] for run in side]
            out[name] = {"s": [round(statistics.median(s), 3), round(min(s), 3),
                               round(max(s), 3)],
                         "peak_mib": [round(statistics.median(mib)), round(min(mib)),
                                      round(max(mib))],
                         "time_over_numbered": round(statistics.median(s) / base, 2)}
    print(json.dumps(out))


if __name__ == "__main__":
    main()
