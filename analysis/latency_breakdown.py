"""Where the main job's time goes, phase by phase, as multiples of a bare import.

    python analysis/latency_breakdown.py [--runs R]

``analysis/benchmark.py --latency-only`` gives the main job over a bare import as one ratio.
This script splits that job (``gd-analyze puma560 data/puma560_trajectory.csv``, HTML, PDF
and figure files) into its phases, so that a limit on the ratio can be weighed against what
the job does. Each round runs, in a fresh interpreter each and in rotated order:

* the bare import ``import numpy, scipy, xarray, matplotlib.pyplot, pinocchio`` (the
  reference of ``benchmark.py``);
* the main job through ``gd_analyze.cli.run``, as the console script runs it, in an
  interpreter that first imports the bare set (timed), then every other module the job loads
  (timed; the list is taken from a warm-up run), and then runs the job with timers around
  its phase functions (the functions are wrapped, not changed: the job takes its one code
  path). Generation-2 garbage collections are timed by a ``gc.callbacks`` observer.

Per phase it prints the median time [s] and the median, min and max of its ratio to the
bare import of the same round, as one JSON line (``--table`` adds a readable table). The
phases of the job add up to its wall time; ``gc_generation_2`` is inside them (the phase
running when a collection starts pays for it), and so are the last three rows, parts of
``report_documents``: the HTML and the figure files on the main thread, the PDF on a worker
thread at the same time (the figures' own PDFs are typeset on a worker thread while the next
figure is drawn: the wait for the last is in ``report_other``). Children run with this checkout's ``src``
first on ``PYTHONPATH``, in a temporary folder (never importing from the current folder).
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
from benchmark import BARE_IMPORT  # the reference of benchmark.py, one definition

ROOT = Path(__file__).resolve().parents[1]
JOB = ["puma560", str(ROOT / "data" / "puma560_trajectory.csv"), "-q"]

#: (module, function or Class.method, label): timed with their calls nested as given.
TIMED = (
    ("gd_analyze.jobs.run", "run_analysis", "run_analysis"),
    ("gd_analyze.jobs.analyze", "analyze_to_file", "analyze_to_file"),
    ("gd_analyze.jobs.analyze", "_verify_sample", "verify"),
    ("gd_analyze.simplify.form_choice", "deploy", "simplified_model"),
    ("gd_analyze.report.main", "write_report", "write_report"),
    ("gd_analyze.store.schema", "open_results", "report_read_results"),
    ("gd_analyze.report.drawing", "html_document", "report_html"),
    ("gd_analyze.report.drawing", "figure_svg", "report_figures_draw_page"),
    ("gd_analyze.report.drawing", "write_documents", "report_documents"),
    ("gd_analyze.report.typeset", "write_pdf", "report_pdf"),
    ("gd_analyze.report.drawing", "write_figure_files", "report_figure_files"),
)
#: Timed inside ``report_documents``, not phases of their own: the PDF is typeset on a worker
#: thread while the HTML, the figure files and the tables are written.
INSIDE_DOCUMENTS = ("report_html", "report_pdf", "report_figure_files")

_CHILD = r"""
import gc, importlib, json, sys, time
sys.modules["dask"] = None    # what cli.run does for the main job (cli._without), first
t0 = time.perf_counter()
import numpy, scipy, xarray, matplotlib.pyplot, pinocchio
t1 = time.perf_counter()
import gd_analyze.cli as cli
for name in MODULES:
    try:
        importlib.import_module(name)
    except Exception:                    # a module that cannot load alone: loaded by the job
        pass
t2 = time.perf_counter()
acc = {}
def timed(f, label):
    def g(*args, **kwargs):
        s = time.perf_counter()
        try:
            return f(*args, **kwargs)
        finally:
            acc[label] = acc.get(label, 0.0) + time.perf_counter() - s
    g.__wrapped__ = f
    return g
def install(f, new):
    for m in list(sys.modules.values()):
        if m is not None and getattr(m, "__name__", "").startswith("gd_analyze"):
            for k, v in list(vars(m).items()):
                if v is f:
                    setattr(m, k, new)
for mod, name, label in TIMED:
    m = importlib.import_module(mod)
    if "." in name:
        cls, meth = name.split(".")
        c = getattr(m, cls)
        setattr(c, meth, timed(getattr(c, meth), label))
    else:
        f = getattr(m, name)
        install(f, timed(f, label))
import gd_analyze.report.main as rm
makers = rm.figure_makers
def figure_makers(*args, **kwargs):
    return {k: timed(v, "report_figures_make_" + ("column" if k.endswith("_column") else "page"))
            for k, v in makers(*args, **kwargs).items()}
rm.figure_makers = figure_makers
gcs = [0.0, 0.0, 0]
def observe(phase, info):
    if info["generation"] == 2:
        if phase == "start":
            gcs[1] = time.perf_counter()
        else:
            gcs[0] += time.perf_counter() - gcs[1]
            gcs[2] += 1
gc.callbacks.append(observe)
sys.argv = ["gd-analyze"] + ARGV
t3 = time.perf_counter()
try:
    cli.run()
    code = 0
except SystemExit as exc:
    code = exc.code
t4 = time.perf_counter()
print(json.dumps({"code": code, "imports_bare_set": t1 - t0, "imports_rest": t2 - t1,
                  "job": t4 - t3, "total": t4 - t0, "gc_generation_2": gcs[0],
                  "gc_generation_2_count": gcs[2], "phases": acc,
                  "modules": [k for k, v in sys.modules.items() if v is not None]}))
"""


def _child_code(modules, argv):
    return (f"MODULES = {modules!r}\nARGV = {argv!r}\nTIMED = {TIMED!r}\n" + _CHILD)


def _env():
    env = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}
    env["MPLBACKEND"] = "Agg"
    env["PYTHONPATH"] = os.pathsep.join([str(ROOT / "src")] + [p for p in
                                                              [env.get("PYTHONPATH")] if p])
    return env


def _run_child(code, cwd, env):
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          cwd=cwd, env=env)
    if done.returncode != 0:
        raise RuntimeError(f"the timed job failed: {done.stderr[-2000:]}")
    out = json.loads(done.stdout.strip().splitlines()[-1])
    if out["code"] != 0:
        raise RuntimeError(f"the main job exited {out['code']}: {done.stderr[-2000:]}")
    return out


def phases(record):
    """Exclusive phase times [s] of one timed job, adding up to its wall time.

    Parameters
    ----------
    record : dict
        A child's JSON record.

    Returns
    -------
    dict of str to float
    """
    p = record["phases"]
    get = p.get
    fig = {k: v for k, v in p.items() if k.startswith("report_figures_")}
    report_parts = (sum(get(k, 0.0) for k in ("report_read_results", "report_documents"))
                    + sum(fig.values()))
    out = {
        "imports_bare_set": record["imports_bare_set"],
        "imports_rest": record["imports_rest"],
        "dynamics_ranking_storage": get("analyze_to_file", 0.0) - get("verify", 0.0)
        - get("simplified_model", 0.0),
        "verification_pinocchio": get("verify", 0.0),
        "simplified_model": get("simplified_model", 0.0),
        "model_files": get("run_analysis", 0.0) - get("analyze_to_file", 0.0)
        - get("write_report", 0.0),
        "report_read_results": get("report_read_results", 0.0),
        **{k: fig.get(k, 0.0) for k in ("report_figures_make_page", "report_figures_draw_page",
                                        "report_figures_make_column")},
        "report_documents": get("report_documents", 0.0),
        "report_other": get("write_report", 0.0) - report_parts,
        "cli_and_staging": record["job"] - get("run_analysis", 0.0),
    }
    out["total"] = record["total"]
    out["gc_generation_2"] = record["gc_generation_2"]
    out.update({k: get(k, 0.0) for k in INSIDE_DOCUMENTS})       # not added: inside a phase
    return out


def breakdown(runs=5):
    """Time the bare import and the phase-timed main job in interleaved rounds.

    Parameters
    ----------
    runs : int, optional
        Rounds (each: one bare import and one job, the order alternating).

    Returns
    -------
    dict
        ``phases``: per phase ``median_s`` and ``median_ratio``, ``min_ratio``,
        ``max_ratio`` (over the bare import of the same round); ``bare_import_s`` (median);
        ``gc_generation_2_count`` (median); ``load_average`` before and after.

    Raises
    ------
    RuntimeError
        If the job fails.
    """
    env = _env()
    load = [os.getloadavg()[0]]
    with tempfile.TemporaryDirectory() as tmp:
        argv = JOB + ["-o", f"{tmp}/out"]
        warm = _run_child(_child_code([], argv), tmp, env)
        modules = [m for m in warm["modules"] if not m.startswith("__")]
        code = _child_code(modules, argv)
        _run_child(code, tmp, env)                      # warm-up with the preimports
        bare_cmd = [sys.executable, "-c", BARE_IMPORT]
        bare, jobs = [], []
        for k in range(runs):
            order = (0, 1) if k % 2 == 0 else (1, 0)
            for side in order:
                if side == 0:
                    t0 = time.perf_counter()
                    subprocess.run(bare_cmd, check=True, env=env, cwd=tmp)
                    bare.append(time.perf_counter() - t0)
                else:
                    jobs.append(_run_child(code, tmp, env))
    load.append(os.getloadavg()[0])
    bare = np.asarray(bare)
    table = [phases(j) for j in jobs]
    out = {}
    for name in table[0]:
        t = np.asarray([row[name] for row in table])
        r = t / bare
        out[name] = {"median_s": float(np.median(t)), "median_ratio": float(np.median(r)),
                     "min_ratio": float(r.min()), "max_ratio": float(r.max())}
    return {"phases": out, "bare_import_s": float(np.median(bare)), "runs": runs,
            "gc_generation_2_count": float(np.median([j["gc_generation_2_count"]
                                                       for j in jobs])),
            "load_average": load}


def main(argv=None):
    """Run the breakdown and print one JSON line (and a table with ``--table``).

    Parameters
    ----------
    argv : list of str, optional
        Command-line arguments.
    """
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--runs", type=int, default=5, help="interleaved rounds (default 5)")
    parser.add_argument("--table", action="store_true", help="also print a readable table")
    args = parser.parse_args(argv)
    result = breakdown(args.runs)
    print(json.dumps(result))
    if args.table:
        print(f"{'phase':32s} {'median [s]':>10s} {'x bare':>7s} {'range':>15s}")
        for name, v in result["phases"].items():
            print(f"{name:32s} {v['median_s']:10.3f} {v['median_ratio']:7.2f} "
                  f"[{v['min_ratio']:.2f}, {v['max_ratio']:.2f}]")
        print(f"bare import {result['bare_import_s']:.3f} s; load {result['load_average']}")


if __name__ == "__main__":
    main()
