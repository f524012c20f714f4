"""Test cases timed on this checkout and on a reference checkout, in interleaved rounds.

    python analysis/test_case_time.py --baseline /tmp/old/ [--rounds 3] NODEID [NODEID ...]

Each round runs ``python -m pytest -q -p no:cacheprovider NODEID ...`` once in each checkout,
in a fresh process (this one first in odd rounds, the reference first in even ones), with
``PYTHONPATH`` its own ``src`` and ``MPLBACKEND=Agg``: one test session each, so a fixture
built once a session (``tests/conftest.py``'s ``built_once``) is built in every run, on both
sides alike. Measured per run: the process's CPU time (user + sys of pytest and the processes
it waited for, ``os.wait4``), its wall time, and the cases' own call time (pytest's JUnit XML
with ``junit_duration_report=call``: without setup and teardown, where the session's
fixtures are built).

Prints one JSON line: per side the median [min, max] of each measure, and the ratio this /
reference of the medians. A failed run is reported, not timed.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
import xml.etree.ElementTree as ET  # noqa: N817  the standard library's parser of pytest's file
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def run_once(checkout: Path, nodeids: list[str]) -> dict[str, float]:
    """One pytest session of ``nodeids`` in ``checkout``.

    Parameters
    ----------
    checkout : Path
        A worktree of the project (its ``src`` and ``tests``).
    nodeids : list of str
        pytest node ids, relative to the checkout.

    Returns
    -------
    dict of str to float
        ``cpu`` [s] (user + sys of the session and its children), ``wall`` [s], ``call`` [s]
        (the cases' summed call time) and ``code`` (pytest's exit code).
    """
    env = {**os.environ, "PYTHONPATH": str(checkout / "src"), "MPLBACKEND": "Agg"}
    with tempfile.TemporaryDirectory() as tmp:
        xml = Path(tmp) / "run.xml"
        start = time.perf_counter()
        child = subprocess.Popen([sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider",
                                  "-o", "junit_duration_report=call", f"--junitxml={xml}",
                                  *nodeids], cwd=checkout, env=env,
                                 stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        _, status, usage = os.wait4(child.pid, 0)
        wall = time.perf_counter() - start
        child.returncode = os.waitstatus_to_exitcode(status)
        call = sum(float(c.get("time", 0.0))
                   for c in ET.parse(xml).getroot().iter("testcase")) if xml.is_file() else 0.0
    return {"cpu": usage.ru_utime + usage.ru_stime, "wall": wall, "call": call,
            "code": float(child.returncode)}


def _summary(runs: list[dict[str, float]]) -> dict[str, list[float]]:
    return {k: [round(statistics.median(r[k] for r in runs), 2),
                round(min(r[k] for r in runs), 2), round(max(r[k] for r in runs), 2)]
            for k in ("cpu", "wall", "call")}


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("nodeids", nargs="+", help="pytest node ids")
    parser.add_argument("--baseline", required=True, type=Path,
                        help="the reference checkout (a worktree of another commit)")
    parser.add_argument("--rounds", type=int, default=3)
    args = parser.parse_args(argv)
    sides: dict[str, list[dict[str, float]]] = {"this": [], "baseline": []}
    where = {"this": ROOT, "baseline": args.baseline.resolve()}
    failed = []
    for k in range(args.rounds):
        for side in (("this", "baseline") if k % 2 == 0 else ("baseline", "this")):
            run = run_once(where[side], args.nodeids)
            (sides[side] if run["code"] == 0 else failed).append(run)
            if run["code"]:
                failed[-1]["side"] = side           # type: ignore[assignment]
    out = {side: _summary(runs) for side, runs in sides.items() if runs}
    if len(out) == 2:
        out["ratio"] = {k: round(out["this"][k][0] / out["baseline"][k][0], 3)
                        for k in ("cpu", "wall", "call") if out["baseline"][k][0]}
    out["failed"] = failed
    out["load"] = [round(x, 2) for x in os.getloadavg()]
    print(json.dumps(out))


if __name__ == "__main__":
    main()
