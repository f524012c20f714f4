"""Work the test suite repeats in one process, timed on this checkout and on a reference one.

    python analysis/repeated_costs.py --baseline <other checkout>/src [--rounds 3] [--reps 5]

Each round runs one fresh interpreter per side (this checkout's ``src`` first in odd rounds,
the reference first in even ones), with that side's ``src`` first on ``PYTHONPATH``. The child
runs the PUMA 560's main job once with its report in a temporary folder (warm-up: imports,
numba's kernels, the fonts, the first Jinja2 environment), then times with
``time.process_time`` (CPU time of the whole process, worker threads included):

* ``open_loaded``, ``open_lazy``: ``store.schema.open_results`` of that job's ``results.h5``,
  loaded (file closed) and lazy (opened, then closed), ``reps`` times each, per open;
* ``render_html``: the report's HTML rendered again from the context the job's report gave
  ``report.common.render_template`` (the template compiled per report, or once a process);
* ``blas_limit``: ``estimation.estimate.least_squares`` of a small synthetic factor (12
  parameters, 6 joints), ``20 * reps`` times, per call: each call enters the one-BLAS-thread
  limit once (a ``threadpoolctl.ThreadpoolController`` made per entry, or once a process).

Prints one JSON line: per measure and side the median [min, max] over the rounds [s], the ratio
this / reference of the medians and its range over the rounds (each round's own ratio), and the
load average before and after.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
MEASURES = ("open_loaded", "open_lazy", "render_html", "blas_limit")

_CHILD = r"""
import json, os, sys, tempfile, time
import numpy as np
from gd_analyze.cli import main
import gd_analyze.report.common as common
from gd_analyze.store.schema import open_results
from gd_analyze.estimation.estimate import joint_factors, least_squares

reps = int(sys.argv[2])
seen = []
render = common.render_template
def recording(name, context, env_globals=None):
    seen.append((name, context, env_globals))
    return render(name, context, env_globals)
common.render_template = recording
import gd_analyze.report.drawing as drawing
drawing.render_template = recording
out = {}
with tempfile.TemporaryDirectory() as tmp:
    assert main(["puma560", sys.argv[1], "-o", os.path.join(tmp, "run"), "-q"]) == 0
    h5 = os.path.join(tmp, "run", "results.h5")
    t = time.process_time()
    for _ in range(reps):
        open_results(h5)
    out["open_loaded"] = (time.process_time() - t) / reps
    t = time.process_time()
    for _ in range(reps):
        open_results(h5, lazy=True).close()
    out["open_lazy"] = (time.process_time() - t) / reps
name, context, env_globals = seen[-1]
t = time.process_time()
html = render(name, context, env_globals)
out["render_html"] = time.process_time() - t
rng = np.random.default_rng(0)
N, n, p = 400, 6, 12
Y = rng.normal(size=(N, n, p))
factors = joint_factors(Y, Y @ rng.normal(size=p), np.ones((N, n), bool))
t = time.process_time()
for _ in range(20 * reps):
    least_squares(factors, np.zeros(p))
out["blas_limit"] = (time.process_time() - t) / (20 * reps)
print(json.dumps(out))
"""


def run_once(src: Path, reps: int) -> dict[str, float]:
    """One child on ``src``: the measures of the module docstring [s]."""
    env = {**os.environ, "PYTHONPATH": str(src), "MPLBACKEND": "Agg"}
    done = subprocess.run([sys.executable, "-c", _CHILD,
                           str(ROOT / "data" / "puma560_trajectory.csv"), str(reps)],
                          env=env, capture_output=True, text=True, check=True,
                          cwd=Path(os.sep))
    return json.loads(done.stdout.strip().splitlines()[-1])


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--baseline", required=True, type=Path,
                        help="the reference checkout's src folder")
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--reps", type=int, default=5)
    args = parser.parse_args(argv)
    where = {"this": ROOT / "src", "baseline": args.baseline.resolve()}
    load = [round(x, 2) for x in os.getloadavg()]
    runs: dict[str, list[dict[str, float]]] = {"this": [], "baseline": []}
    for k in range(args.rounds):
        for side in (("this", "baseline") if k % 2 == 0 else ("baseline", "this")):
            runs[side].append(run_once(where[side], args.reps))
    out: dict[str, object] = {}
    for m in MEASURES:
        med = {s: statistics.median(r[m] for r in runs[s]) for s in runs}
        per_round = [a[m] / b[m] for a, b in zip(runs["this"], runs["baseline"])]
        out[m] = {**{s: [round(med[s], 4), round(min(r[m] for r in runs[s]), 4),
                         round(max(r[m] for r in runs[s]), 4)] for s in runs},
                  "ratio": round(med["this"] / med["baseline"], 3),
                  "ratio_range": [round(min(per_round), 3), round(max(per_round), 3)]}
    out["rounds"] = args.rounds
    out["load"] = [load, [round(x, 2) for x in os.getloadavg()]]
    print(json.dumps(out))


if __name__ == "__main__":
    main()
