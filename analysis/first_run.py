"""The main job's first run after installing, against the runs after it: what compiling the
numba kernels costs a user once.

    python analysis/first_run.py [--rounds 3] [--robot puma560] [--report] [--baseline SRC]

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
warm) / median first; and the 1-minute load average at the start and the end. With
``--baseline SRC`` (another checkout's ``src``) each round runs that code's three jobs too, the
two sides in turn (which goes first alternates), and the line adds the baseline's figures and
the per-round ratio of the first run's CPU time, this / baseline, median and range.
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


def _round(source: Path, robot: str, report: bool) -> dict[str, tuple[float, float]]:
    """One round on a fresh copy of the ``source`` folder (a ``src``): each kind in turn."""
    out = {}
    with tempfile.TemporaryDirectory(prefix="gd-first-run-") as tmp:
        src = Path(tmp) / "src"
        shutil.copytree(source, src, ignore=shutil.ignore_patterns("__pycache__", "*.egg-info"))
        cache = Path(tmp) / "cache"
        for k, kind in enumerate(KINDS):
            if kind == "kernels_cold":
                _numba_cache_removed(src)
            out[kind] = _job(src, cache, Path(tmp) / f"out{k}", robot, report)
    return out


def _summary(rounds: list[dict[str, tuple[float, float]]]) -> dict[str, object]:
    """Per kind the median wall time, its range and the median CPU time; the compile share."""
    wall = {k: [r[k][0] for r in rounds] for k in KINDS}
    out: dict[str, object] = {
        k: {"median_wall_s": round(statistics.median(wall[k]), 2),
            "range_wall_s": [round(min(wall[k]), 2), round(max(wall[k]), 2)],
            "median_cpu_s": round(statistics.median(r[k][1] for r in rounds), 2)}
        for k in KINDS}
    med = {k: statistics.median(wall[k]) for k in KINDS}
    out["compile_share_of_first"] = round((med["kernels_cold"] - med["warm"]) / med["first"], 3)
    return out


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--robot", default="puma560")
    parser.add_argument("--report", action="store_true", help="run the jobs with their report")
    parser.add_argument("--baseline", type=Path, default=None,
                        help="another checkout's src, run in the same rounds, alternating")
    args = parser.parse_args(argv)
    sides = {"this": ROOT / "src", **({"baseline": args.baseline} if args.baseline else {})}
    rounds: dict[str, list[dict[str, tuple[float, float]]]] = {s: [] for s in sides}
    load = [os.getloadavg()[0]]
    for r in range(args.rounds):
        for side in (list(sides) if r % 2 == 0 else list(sides)[::-1]):
            rounds[side].append(_round(sides[side], args.robot, args.report))
    load.append(os.getloadavg()[0])
    result: dict[str, object] = {"robot": args.robot, "report": args.report,
                                 "rounds": args.rounds, **_summary(rounds["this"])}
    if args.baseline:
        result["baseline"] = _summary(rounds["baseline"])
        ratios = sorted(a["first"][1] / b["first"][1]
                        for a, b in zip(rounds["this"], rounds["baseline"]))
        result["first_cpu_this_over_baseline"] = {
            "median": round(statistics.median(ratios), 3),
            "range": [round(ratios[0], 3), round(ratios[-1], 3)]}
    result["load_average"] = [round(v, 2) for v in load]
    print(json.dumps(result))


if __name__ == "__main__":
    main()
