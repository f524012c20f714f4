"""Peak memory of ``gd-analyze plan`` (quintic, or with ``--excitation``) against the number
of set points N.

    python analysis/plan_memory.py [--robot NAME] [--excitation] [--setpoints N ...]
                                   [--repeats R] [--src DIR]

Each run is a fresh process, ``/usr/bin/time -v python -m gd_analyze.cli plan ROBOT
--setpoints N -o FILE`` (FILE in a temporary folder, removed after each run), whose "Maximum
resident set size" is the peak RSS. ``--src DIR`` runs another checkout's ``src`` (first on
PYTHONPATH), to measure the code before a change. Prints one JSON line per N: the median,
lowest and highest peak RSS [MiB] and wall time [s] over the repeats, and the file's size
[bytes].
"""

from __future__ import annotations

import argparse
import json
import os
import re
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

SRC = Path(__file__).resolve().parent.parent / "src"


def run(robot, n, excitation, src):
    """One plan in a fresh process: (peak RSS [MiB], wall time [s], CSV size [bytes])."""
    env = dict(os.environ, PYTHONPATH=str(src))
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "plan.csv"
        cmd = ["/usr/bin/time", "-v", sys.executable, "-m", "gd_analyze.cli", "plan", robot,
               "--setpoints", str(n), "-o", str(out)] + (["--excitation"] if excitation else [])
        t0 = time.perf_counter()
        done = subprocess.run(cmd, capture_output=True, text=True, env=env)
        wall = time.perf_counter() - t0
        if done.returncode != 0:
            raise SystemExit(f"plan failed ({done.returncode}): {done.stderr[-2000:]}")
        kb = re.search(r"Maximum resident set size \(kbytes\): (\d+)", done.stderr)
        return int(kb.group(1)) / 1024, wall, out.stat().st_size


def main(argv=None):
    """Measure and print one JSON line per number of set points.

    Parameters
    ----------
    argv : list of str, optional
        Command-line arguments.
    """
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--robot", default="puma560")
    p.add_argument("--excitation", action="store_true")
    p.add_argument("--setpoints", type=int, nargs="+", default=[1_000_000, 10_000_000])
    p.add_argument("--repeats", type=int, default=1)
    p.add_argument("--src", default=str(SRC), help="the src folder run")
    args = p.parse_args(argv)
    for n in args.setpoints:
        runs = [run(args.robot, n, args.excitation, args.src) for _ in range(args.repeats)]
        rss, wall = [r[0] for r in runs], [r[1] for r in runs]
        print(json.dumps({"robot": args.robot, "excitation": args.excitation, "setpoints": n,
                          "src": args.src, "repeats": args.repeats,
                          "peak_rss_mib": {"median": round(statistics.median(rss), 1),
                                           "min": round(min(rss), 1), "max": round(max(rss), 1)},
                          "wall_s": {"median": round(statistics.median(wall), 1),
                                     "min": round(min(wall), 1), "max": round(max(wall), 1)},
                          "csv_bytes": runs[0][2], "load": os.getloadavg()[0]}), flush=True)


if __name__ == "__main__":
    main()
