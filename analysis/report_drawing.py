"""CPU time of writing the main and the sweep report, this checkout against another's code.

    python analysis/report_drawing.py [--baseline SRC] [--rounds R] [--reports main,sweep]

Makes the PUMA 560's ``results.h5`` (the main job on the shipped trajectory, ``--no-report``)
and ``sweep.h5`` (``sweep puma560 --random 20 --seed 0 --no-report``) once, with this
checkout's code, in a temporary folder. Then, in each of R rounds (default 3) and for each
report, it writes that report from those files in a fresh interpreter with this checkout's
``src`` and with ``SRC`` (default ``/work/main/src``) on ``PYTHONPATH``, the two in turn (which
goes first alternates between rounds). Each child imports the report writer, calls
``gc.freeze()`` as the console script does after its imports, and writes the report twice
into new folders: the first as a command does (once per process), the second as a test
session does (caches of the first kept). It times each by the process' CPU time (all
threads: Typst's too; wall time is unsteady on a shared machine), and the main thread's CPU
time inside ``report.drawing.figure_svg`` (drawing the figures to SVG, their text measured
and raised; the main report's figure PDFs are typeset on a worker thread meanwhile).

Prints one JSON line: per report, per side (``this``, ``baseline``) and per call (``first``,
``again``) the median and [min, max] of the total and of the drawing [s], and the median of
the per-round ratio this / baseline of the total with its range.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]

#: The writer of each report, ``writer(input file, output folder)``, as the child imports it.
WRITERS = {"main": "from gd_analyze.report.main import write_report as write",
           "sweep": "from gd_analyze.report.sweep import write_sweep_report as write"}

_CHILD = r"""
import gc, json, sys, time
{writer}
import gd_analyze.report.drawing as drawing
drawn = [0.0]
svg = drawing.figure_svg
def timed(*args, **kwargs):
    t = time.thread_time()
    try:
        return svg(*args, **kwargs)
    finally:
        drawn[0] += time.thread_time() - t
drawing.figure_svg = timed
gc.freeze()
out = []
for k in range(2):
    drawn[0] = 0.0
    t = time.process_time()
    write(sys.argv[1], sys.argv[2] + str(k))
    out.append((time.process_time() - t, drawn[0]))
print(json.dumps(out))
"""


def _run(command: list[str], src: str | os.PathLike[str], cwd: str) -> str:
    """Run a child with ``src`` first on PYTHONPATH; its standard output.

    Raises
    ------
    RuntimeError
        If the child exits with an error.
    """
    env = {**os.environ, "PYTHONPATH": str(src)}
    done = subprocess.run(command, capture_output=True, text=True, env=env, cwd=cwd)
    if done.returncode != 0:
        raise RuntimeError(f"{' '.join(command[:4])} exited {done.returncode} "
                           f"(PYTHONPATH={src}): {done.stderr[-2000:]}")
    return done.stdout


def inputs(folder: Path) -> dict[str, Path]:
    """Make the reports' input files with this checkout's code.

    Parameters
    ----------
    folder : pathlib.Path
        Where they go (``main/results.h5``, ``sweep/sweep.h5``).

    Returns
    -------
    dict of str to pathlib.Path
        The file of each report in :data:`WRITERS`.
    """
    cli = [sys.executable, "-m", "gd_analyze.cli"]
    src, cwd = ROOT / "src", str(folder)
    _run(cli + ["puma560", str(ROOT / "data" / "puma560_trajectory.csv"), "-o",
                str(folder / "main"), "-q", "--no-report"], src, cwd)
    _run(cli + ["sweep", "puma560", "--random", "20", "--seed", "0", "-o",
                str(folder / "sweep"), "-q", "--no-report"], src, cwd)
    return {"main": folder / "main" / "results.h5", "sweep": folder / "sweep" / "sweep.h5"}


def write_times(report: str, path: Path, src: str | os.PathLike[str], out: Path
                ) -> list[tuple[float, float]]:
    """Write one report twice in a fresh interpreter with ``src`` on PYTHONPATH.

    Parameters
    ----------
    report : {"main", "sweep"}
        The report (:data:`WRITERS`).
    path : pathlib.Path
        Its input file.
    src : str or os.PathLike
        The code's ``src`` folder.
    out : pathlib.Path
        Output folders' stem (``out0``, ``out1``).

    Returns
    -------
    list of (float, float)
        Per call (first, again): the CPU time of the call and of its drawing [s].

    Raises
    ------
    RuntimeError
        If the child fails.
    """
    text = _run([sys.executable, "-c", _CHILD.format(writer=WRITERS[report]), str(path),
                 str(out)], src, str(out.parent))
    return [tuple(x) for x in json.loads(text.strip().splitlines()[-1])]


def _stat(values: list[float]) -> list[float]:
    """Median, min and max, rounded to ms."""
    v = np.asarray(values, float)
    return [round(float(np.median(v)), 3), round(float(v.min()), 3), round(float(v.max()), 3)]


def main(argv: list[str] | None = None) -> dict:
    """Time the reports, interleaved; print and return the summary (see the module).

    Parameters
    ----------
    argv : list of str, optional
        ``--baseline``, ``--rounds``, ``--reports`` (the process' arguments if not given).

    Returns
    -------
    dict
        ``{report: {"this": ..., "baseline": ..., "ratio": ...}}`` and ``load_average``
        (the one-minute load average before and after).

    Raises
    ------
    RuntimeError
        If a child fails.
    """
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--baseline", default="/work/main/src", help="the other code's src")
    p.add_argument("--rounds", type=int, default=3)
    p.add_argument("--reports", default="main,sweep")
    a = p.parse_args(argv)
    reports = a.reports.split(",")
    sides = {"this": ROOT / "src", "baseline": Path(a.baseline)}
    load = [os.getloadavg()[0]]
    with tempfile.TemporaryDirectory() as tmp:
        files = inputs(Path(tmp))
        times: dict = {r: {s: [] for s in sides} for r in reports}
        for k in range(a.rounds):
            for report in reports:
                order = list(sides) if k % 2 == 0 else list(sides)[::-1]
                for side in order:
                    out = Path(tmp) / f"{report}-{side}-{k}" / "out"
                    out.parent.mkdir()
                    times[report][side].append(write_times(report, files[report],
                                                           sides[side], out))
    load.append(os.getloadavg()[0])
    result: dict = {"load_average": [round(x, 2) for x in load]}
    for report, by_side in times.items():
        result[report] = {}
        for side, runs in by_side.items():
            result[report][side] = {
                call: {"total_s": _stat([r[c][0] for r in runs]),
                       "drawing_s": _stat([r[c][1] for r in runs])}
                for c, call in enumerate(("first", "again"))}
        result[report]["ratio"] = {
            call: _stat([t[c][0] / b[c][0] for t, b in zip(by_side["this"],
                                                           by_side["baseline"])])
            for c, call in enumerate(("first", "again"))}
    print(json.dumps(result))
    return result


if __name__ == "__main__":
    main()
