"""The main job's first run after installing, against the runs after it: what compiling the
numba kernels costs a user once.

    python analysis/first_run.py [--rounds 3] [--robot puma560] [--report]

Each round copies this checkout's ``src`` into a new temporary folder, so that numba's cache
(``__pycache__/*.nbi``, ``*.nbc`` beside the kernels' sources, as an install has it) starts
empty, and runs ``python -m gd_analyze.cli ROBOT data/ROBOT_trajectory.csv -q --no-report``
(``--report``: with its report) three times in fresh processes, with that copy first on
``PYTHONPATH``:

- ``first``: numba's cache empty and the derivation cache (``GD_ANALYZE_CACHE_DIR``) a new
  empty folder: a first run after ``pip install``;
- ``kernels_cold``: the derivation cache kept from ``first``, numba's cache removed again: the
  kernels' compilation alone;
- ``warm``: both caches kept: every later run.

The copies' byte-code is written by the first run, as an install's is. Prints one JSON line:
per kind, the median wall time [s] with its [min, max] over the rounds and the median CPU time
of the child (user + system, ``os.wait4``) [s]; the compile share, (median kernels_cold - median
warm) / median first; and the 1-minute load average at the start and the end.
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
KINDS = ("first", "kernels_cold", "warm")


def _numba_cache_removed(src: Path) -> None:
    """Remove numba's cache files under ``src``."""
    for pattern in ("*.nbi", "*.nbc"):
        for path in src.rglob(pattern):
            path.unlink()


def _job(src: Path, cache: Path, out: Path, robot: str, report: bool) -> tuple[float, float]:
    """One main job in a fresh process: (wall [s], child CPU [s])."""
    env = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}
    env.update(PYTHONPATH=str(src), GD_ANALYZE_CACHE_DIR=str(cache), MPLBACKEND="Agg")
    env.pop("GD_ANALYZE_NO_CACHE", None)
    command = [sys.executable, "-m", "gd_analyze.cli", robot,
               str(ROOT / "data" / f"{robot}_trajectory.csv"), "-o", str(out), "-q",
               *([] if report else ["--no-report"])]
    t0 = time.perf_counter()
    proc = subprocess.Popen(command, env=env, stdout=subprocess.DEVNULL,
                            stderr=subprocess.PIPE)
    _, status, usage = os.wait4(proc.pid, 0)
    wall = time.perf_counter() - t0
    if os.waitstatus_to_exitcode(status) != 0:
        err = proc.stderr.read().decode() if proc.stderr else ""
        raise SystemExit(f"{' '.join(command)}: exit {os.waitstatus_to_exitcode(status)}: "
                         f"{err.strip()[-400:]}")
    return wall, usage.ru_utime + usage.ru_stime


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--robot", default="puma560")
    parser.add_argument("--report", action="store_true", help="run the jobs with their report")
    args = parser.parse_args(argv)
    times: dict[str, list[tuple[float, float]]] = {k: [] for k in KINDS}
    load = [os.getloadavg()[0]]
    for _ in range(args.rounds):
        with tempfile.TemporaryDirectory(prefix="gd-first-run-") as tmp:
            src = Path(tmp) / "src"
            shutil.copytree(ROOT / "src", src,
                            ignore=shutil.ignore_patterns("__pycache__", "*.egg-info"))
            cache = Path(tmp) / "cache"
            for k, kind in enumerate(KINDS):
                if kind == "kernels_cold":
                    _numba_cache_removed(src)
                times[kind].append(_job(src, cache, Path(tmp) / f"out{k}", args.robot,
                                        args.report))
    load.append(os.getloadavg()[0])
    wall = {k: [w for w, _ in v] for k, v in times.items()}
    out = {k: {"median_wall_s": round(statistics.median(wall[k]), 2),
               "range_wall_s": [round(min(wall[k]), 2), round(max(wall[k]), 2)],
               "median_cpu_s": round(statistics.median(c for _, c in times[k]), 2)}
           for k in KINDS}
    med = {k: statistics.median(wall[k]) for k in KINDS}
    print(json.dumps({"robot": args.robot, "report": args.report, "rounds": args.rounds,
                      **out,
                      "compile_share_of_first": round((med["kernels_cold"] - med["warm"])
                                                      / med["first"], 3),
                      "load_average": [round(v, 2) for v in load]}))


if __name__ == "__main__":
    main()
