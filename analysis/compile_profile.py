"""Where a first run's numba compilation goes: per kernel and per compiler pass.

    python analysis/compile_profile.py [--robot puma560] [--src SRC] [--top 20]

Copies ``SRC`` (default this checkout's ``src``) into a new temporary folder, so that numba's
cache starts empty, and runs the main job ``ROBOT data/ROBOT_trajectory.csv -q --no-report``
in this process with that copy first on ``sys.path`` and a new empty derivation cache: a first
run after an install. numba's event API (``numba.core.event``) reports every compilation
(``numba:compile``: one per dispatcher and signature), every compiler pass
(``numba:run_pass``) and every call into LLVM (``numba:llvm_lock``); each is timed by the
CPU time of its own thread (``time.thread_time``; the job compiles in threads too), the
events nested in it subtracted where a time is said to be exclusive.

Prints one JSON line: the job's wall and CPU time [s]; the compilation's CPU time [s] (the
top-level compilations' inclusive times); per compiled function (module.qualname) its
number of compilations, their signatures where more than one, and their inclusive CPU time
[s] (a kernel's includes the helpers it compiles first); per pass its exclusive CPU time
[s] (``LLVM in PASS``: the LLVM calls made within that pass); and the 1-minute load
average at the start and the end.
"""

from __future__ import annotations

import argparse
import collections
import json
import os
import runpy
import shutil
import sys
import tempfile
import threading
import time
from pathlib import Path

from numba.core import event

ROOT = Path(__file__).resolve().parents[1]


class _Recorder(event.Listener):
    """A numba event listener: per thread a stack of open events, their times summed."""

    def __init__(self) -> None:
        super().__init__()
        self.local = threading.local()
        self.lock = threading.Lock()
        self.compiles: dict[str, list] = collections.defaultdict(lambda: [0, 0.0, []])
        self.top = 0.0
        self.passes: dict[str, float] = collections.defaultdict(float)

    def _stack(self) -> list:
        if not hasattr(self.local, "stack"):
            self.local.stack = []
        return self.local.stack

    def on_start(self, ev) -> None:
        self._stack().append([ev.kind, ev.data, time.thread_time(), 0.0])

    def on_end(self, ev) -> None:
        stack = self._stack()
        kind, data, t0, nested = stack.pop()
        spent = time.thread_time() - t0
        if stack:
            stack[-1][3] += spent
        with self.lock:
            if kind == "numba:compile":
                fn = data["dispatcher"].py_func
                entry = self.compiles[f"{fn.__module__}.{fn.__qualname__}"]
                entry[0] += 1
                entry[1] += spent
                entry[2].append(str(data["args"]))
                if not any(e[0] == "numba:compile" for e in stack):
                    self.top += spent
            elif kind == "numba:run_pass":
                self.passes[data["name"].split(" [")[0]] += spent - nested
            elif kind == "numba:llvm_lock":
                outer = [e for e in stack if e[0] == "numba:run_pass"]
                name = outer[-1][1]["name"].split(" [")[0] if outer else "no pass"
                self.passes[f"LLVM in {name}"] += spent - nested


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--robot", default="puma560")
    parser.add_argument("--src", type=Path, default=ROOT / "src")
    parser.add_argument("--top", type=int, default=20, help="the functions listed")
    args = parser.parse_args(argv)
    load = [os.getloadavg()[0]]
    tmp = Path(tempfile.mkdtemp(prefix="gd-compile-profile-"))
    try:
        src = tmp / "src"
        shutil.copytree(args.src, src, ignore=shutil.ignore_patterns("__pycache__", "*.egg-info"))
        os.environ.update(GD_ANALYZE_CACHE_DIR=str(tmp / "cache"), MPLBACKEND="Agg")
        os.environ.pop("GD_ANALYZE_NO_CACHE", None)
        sys.path.insert(0, str(src))
        recorder = _Recorder()
        for kind in ("numba:compile", "numba:run_pass", "numba:llvm_lock"):
            event.register(kind, recorder)
        sys.argv = ["gd-analyze", args.robot,
                    str(ROOT / "data" / f"{args.robot}_trajectory.csv"), "-o", str(tmp / "out"),
                    "-q", "--no-report"]
        wall, cpu = time.perf_counter(), time.process_time()
        try:
            runpy.run_module("gd_analyze.cli", run_name="__main__")
        except SystemExit as stop:
            if stop.code not in (None, 0):
                raise
        wall, cpu = time.perf_counter() - wall, time.process_time() - cpu
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    load.append(os.getloadavg()[0])
    ranked = sorted(recorder.compiles.items(), key=lambda kv: -kv[1][1])
    print(json.dumps({
        "robot": args.robot, "job_wall_s": round(wall, 2), "job_cpu_s": round(cpu, 2),
        "compile_cpu_s": round(recorder.top, 2),
        "compilations": sum(v[0] for v in recorder.compiles.values()),
        "functions": {name: {"compiled": v[0], "cpu_s": round(v[1], 2),
                             **({"signatures": v[2]} if v[0] > 1 else {})}
                      for name, v in ranked[:args.top]},
        "passes_cpu_s": {k: round(v, 2) for k, v in
                         sorted(recorder.passes.items(), key=lambda kv: -kv[1]) if v >= 0.05},
        "load_average": [round(v, 2) for v in load]}))


if __name__ == "__main__":
    main()
